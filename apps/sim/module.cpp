#include "module.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include "scenario.hpp"
#include <symdyn/runtime/model_module.hpp>

namespace symdyn::sim {

runtime::Model load_model_module(const std::filesystem::path& path, std::string_view expected) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw ScenarioError(fmt::format(
        "model module '{}' not found (build it with symdyn_add_model(... SIM_MODULE); a "
        "relative path is taken from the scenario file's directory)",
        path.string()));
  }
  // An absolute path, so that dlopen never searches the library path.
  const std::string absolute = std::filesystem::absolute(path).string();
  void* handle = dlopen(absolute.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    throw ScenarioError(fmt::format("model module '{}' cannot be loaded: {}", path.string(),
                                    why ? why : "unknown"));
  }
  using Entry = const runtime::ModelModule* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, runtime::model_module_entry));
  if (entry == nullptr) {
    dlclose(handle);
    throw ScenarioError(fmt::format("'{}' is not a symdyn model module (no {})", path.string(),
                                    runtime::model_module_entry));
  }
  const runtime::ModelModule* m = entry();
  if (m == nullptr || m->abi != runtime::model_module_abi ||
      m->description_size != sizeof(runtime::ModelDescription)) {
    const int abi = m ? m->abi : -1;
    dlclose(handle);
    throw ScenarioError(fmt::format(
        "model module '{}' was built for module interface {}, this symdyn-sim reads {}: "
        "rebuild the module with this symdyn",
        path.string(), abi, runtime::model_module_abi));
  }
  if (!expected.empty() && expected != m->model) {
    const std::string held = m->model;
    dlclose(handle);
    throw ScenarioError(fmt::format("model module '{}' holds model '{}', the scenario names '{}'",
                                    path.string(), held, expected));
  }
  return runtime::Model(m->describe());  // the handle stays open: the model calls into it
}

}  // namespace symdyn::sim
