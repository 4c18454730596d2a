// The reference models built into symdyn-sim (models.md), and the scenario
// files of models/scenarios embedded at build time. A model's variants are
// listed only when their generated header exists (the models arrive one at a
// time, and the big ones are optional).
#include <fmt/format.h>

#include <algorithm>

#include "embedded_scenarios.hpp"
#include "scenario.hpp"

#if __has_include("double_pendulum_absolute.hpp")
#include "double_pendulum_absolute.hpp"
#endif
#if __has_include("double_pendulum_relative.hpp")
#include "double_pendulum_relative.hpp"
#endif
#if __has_include("slider_crank_inline.hpp")
#include "slider_crank_inline.hpp"
#endif
#if __has_include("slider_crank_dependent.hpp")
#include "slider_crank_dependent.hpp"
#endif
#if __has_include("four_bar.hpp")
#include "four_bar.hpp"
#endif
#if __has_include("quarter_car.hpp")
#include "quarter_car.hpp"
#endif
#if __has_include("stewart.hpp")
#include "stewart.hpp"
#endif
#if __has_include("robot3d_absolute.hpp")
#include "robot3d_absolute.hpp"
#endif
#if __has_include("robot3d_relative.hpp")
#include "robot3d_relative.hpp"
#endif
#if __has_include("trike.hpp")
#include "trike.hpp"
#endif
#if __has_include("amru5_inline.hpp")
#include "amru5_inline.hpp"
#endif
#if __has_include("amru5_dependent.hpp")
#include "amru5_dependent.hpp"
#endif

namespace symdyn::sim {

using runtime::Model;

const std::vector<BuiltinModel>& builtin_models() {
  static const std::vector<BuiltinModel> all = [] {
    std::vector<BuiltinModel> m;
#if __has_include("double_pendulum_absolute.hpp")
    m.push_back(
        {"double_pendulum", "absolute", &Model::from<symdyn_generated::double_pendulum_absolute>});
#endif
#if __has_include("double_pendulum_relative.hpp")
    m.push_back(
        {"double_pendulum", "relative", &Model::from<symdyn_generated::double_pendulum_relative>});
#endif
#if __has_include("slider_crank_inline.hpp")
    m.push_back({"slider_crank", "inline", &Model::from<symdyn_generated::slider_crank_inline>});
#endif
#if __has_include("slider_crank_dependent.hpp")
    m.push_back(
        {"slider_crank", "dependent", &Model::from<symdyn_generated::slider_crank_dependent>});
#endif
#if __has_include("four_bar.hpp")
    m.push_back({"four_bar", "closed", &Model::from<symdyn_generated::four_bar>});
#endif
#if __has_include("quarter_car.hpp")
    m.push_back({"quarter_car", "default", &Model::from<symdyn_generated::quarter_car>});
#endif
#if __has_include("stewart.hpp")
    m.push_back({"stewart", "default", &Model::from<symdyn_generated::stewart>});
#endif
#if __has_include("robot3d_absolute.hpp")
    m.push_back({"robot3d", "absolute", &Model::from<symdyn_generated::robot3d_absolute>});
#endif
#if __has_include("robot3d_relative.hpp")
    m.push_back({"robot3d", "relative", &Model::from<symdyn_generated::robot3d_relative>});
#endif
#if __has_include("trike.hpp")
    m.push_back({"trike", "default", &Model::from<symdyn_generated::trike>});
#endif
#if __has_include("amru5_inline.hpp")
    m.push_back({"amru5", "inline", &Model::from<symdyn_generated::amru5_inline>});
#endif
#if __has_include("amru5_dependent.hpp")
    m.push_back({"amru5", "dependent", &Model::from<symdyn_generated::amru5_dependent>});
#endif
    return m;
  }();
  return all;
}

const std::vector<Scenario>& builtin_scenarios() {
  static const std::vector<Scenario> all = [] {
    std::vector<Scenario> out;
    for (const EmbeddedScenario& e : embedded_scenarios()) {
      Scenario s = parse_scenario(e.text, fmt::format("models/scenarios/{}.json", e.name));
      s.name = e.name;
      const auto& models = builtin_models();
      if (std::any_of(models.begin(), models.end(),
                      [&](const BuiltinModel& m) { return m.model == s.model; })) {
        out.push_back(std::move(s));
      }
    }
    std::sort(out.begin(), out.end(),
              [](const Scenario& a, const Scenario& b) { return a.name < b.name; });
    return out;
  }();
  return all;
}

const Scenario& find_builtin(std::string_view name) {
  std::vector<std::string> names;
  for (const Scenario& s : builtin_scenarios()) {
    if (s.name == name) return s;
    names.push_back(s.name);
  }
  throw ScenarioError(
      fmt::format("no scenario for model '{}' (known: {}; or give a scenario file, *.json)", name,
                  fmt::join(names, ", ")));
}

}  // namespace symdyn::sim
