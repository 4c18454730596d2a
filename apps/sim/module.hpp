#pragma once
// Loading a model module (runtime/model_module.hpp) built by
// symdyn_add_model(... SIM_MODULE). The library stays loaded for the life of
// the program: the model's entry points live in it.
#include <filesystem>
#include <string_view>

#include <symdyn/runtime/model.hpp>

namespace symdyn::sim {

// Throws ScenarioError: a missing file, a library that is not a model module,
// one built for another module interface, or one holding another model than
// `expected` (when not empty).
runtime::Model load_model_module(const std::filesystem::path& path, std::string_view expected);

}  // namespace symdyn::sim
