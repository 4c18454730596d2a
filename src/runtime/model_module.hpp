#pragma once
// A model module: a shared library holding one generated model, loadable by a
// program that was not built with it (symdyn-sim scenario.json). It exports
//
//   extern "C" const symdyn::runtime::ModelModule* symdyn_model_module();
//
// symdyn_add_model(... SIM_MODULE) builds one from the emitted struct; the
// entry point is generated, never written by hand. The loader reads `abi` and
// `description_size` before anything else and refuses a module built against
// another layout of ModelDescription (bump model_module_abi when it changes, or
// the layout of an emitted function's arrays: domain_arguments' three values).
// The module needs no symbol of the runtime library: Model::describe<G>() is
// header-only, and the program builds the Model from the description.

#include <cstddef>

#include <symdyn/runtime/model.hpp>

namespace symdyn::runtime {

inline constexpr int model_module_abi = 6;
inline constexpr const char* model_module_entry = "symdyn_model_module";

struct ModelModule {
  int abi = model_module_abi;  // first: read before anything else
  std::size_t description_size = sizeof(ModelDescription);
  const char* model = "";    // G::model
  const char* variant = "";  // G::variant, "" if none
  ModelDescription (*describe)() = nullptr;
};

template <detail::generated_model G>
ModelModule make_model_module() {
  ModelModule m;
  m.model = G::model;
  if constexpr (requires { G::variant; }) m.variant = G::variant;
  m.describe = &Model::describe<G>;
  return m;
}

}  // namespace symdyn::runtime
