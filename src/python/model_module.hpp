#pragma once
// The Python module of one generated model (docs/python.md). Every model's
// module is this one definition, given the model's Model::from<G>; the build
// (cmake/SymdynPython.cmake) writes, per model, the one line
//
//   SYMDYN_PYTHON_MODULE(double_pendulum_absolute)
//
// which defines the module `double_pendulum_absolute` from the emitted struct
// symdyn_generated::double_pendulum_absolute. Uses the runtime only.

#include <pybind11/pybind11.h>

#include <symdyn/runtime/model.hpp>

namespace symdyn::python {

using ModelFactory = runtime::Model (*)();

// Fills the module: the model's constants, class System, the force element
// constructors and the exceptions.
void define_model_module(pybind11::module_& module, ModelFactory make_model);

}  // namespace symdyn::python

#define SYMDYN_PYTHON_MODULE(target)                                                              \
  PYBIND11_MODULE(target, module) {                                                               \
    symdyn::python::define_model_module(module,                                                   \
                                        &symdyn::runtime::Model::from<symdyn_generated::target>); \
  }
