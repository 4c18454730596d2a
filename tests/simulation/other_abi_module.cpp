// A model module as an older or newer symdyn would build it: another module
// interface number. symdyn-sim must refuse it before reading anything else.
#include <symdyn/runtime/model_module.hpp>

extern "C" const symdyn::runtime::ModelModule* symdyn_model_module() {
  static symdyn::runtime::ModelModule module;
  module.abi = symdyn::runtime::model_module_abi + 1;
  return &module;
}
