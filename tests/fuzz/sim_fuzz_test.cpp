// symdyn-sim's scenario loader and command line under random and mutated
// input. In process: a mutated scenario text either builds and runs (briefly)
// or is refused with one of the runtime's errors (ScenarioError, OptionError,
// ModelError, NumericError), never anything else. As a program: exit code 0,
// 1 or 2, never a signal, a sanitizer report (86) or the time limit (124).
#include <fmt/format.h>
#include <rapidcheck/catch.h>

#include <filesystem>
#include <fstream>

#include "codegen/run_command.hpp"
#include "run.hpp"
#include <symdyn/runtime/errors.hpp>

using namespace symdyn;
using namespace symdyn::testing;

namespace {

// Small valid scenarios that reach every part of the loader.
const std::vector<std::string> kSeeds = {
    R"j({"model": "double_pendulum", "t_end": 0.5})j",
    R"j({"model": {"name": "slider_crank", "variant": "dependent"}, "initial": {"q": {"crank": 0.1}, "qd": {"crank": 3}},
        "t_end": 0.2, "integrator": {"name": "rk4", "step": 0.001}, "output_interval": 0.01,
        "outputs": ["q", "qdd", {"body": "slider", "quantity": "velocity"}, {"name": "e", "value": "total_energy"}],
        "checks": [{"name": "fast", "value": "maximum(crank_dot)", "unit": "rad/s", "band": [0, "1e3 * rtol + 10"]}]})j",
    R"j({"model": "double_pendulum", "t_end": 0.4, "variables": {"tau": 1.5},
        "forces": [{"type": "coordinate_force", "name": "motor", "coordinates": ["theta1"], "value": "tau * sin(3 * t)"},
                   {"type": "point_spring_damper", "name": "s", "a": {"body": "ground", "point": [0, -1, 0]},
                    "b": {"body": "rod2", "point": [0.5, 0, 0]}, "stiffness": 50, "free_length": 1, "damping": 2},
                   {"type": "point_load", "name": "push", "at": {"body": "rod1"}, "force": [0, "-2 * theta1_dot", 0]},
                   {"type": "bushing", "name": "b", "a": {"body": "ground"}, "b": {"body": "rod1"},
                    "rotational_stiffness": [0, 0, 5]},
                   {"type": "coordinate_tracking", "name": "hold", "coordinate": "theta2", "kp": 10, "kd": 1,
                    "reference": "0.1 * step(t - 0.2)", "enabled": false}],
        "events": [{"time": 0.1, "enable": "hold", "set": {"tau": 0}}, {"time": 0.3, "disable": ["motor", "s"]}],
        "outputs": [{"element": "s"}, {"element": "push", "quantity": "fy"}],
        "checks": [{"name": "swing", "value": "drift(theta1) + at(theta2, t_end / 2)", "band": [-10, 10]}]})j",
    R"j({"model": "trike", "t_end": 0.05, "integrator": "dopri5",
        "forces": [{"type": "simple_tyre", "name": "f", "body": "front_wheel"},
                   {"type": "gim_tyre", "name": "g", "body": "left_rear_wheel", "ground": {"normal": [0, 0, 1]}},
                   {"type": "plane_contact", "name": "c", "body": "chassis", "point": [1, 0, 0], "radius": 0.1,
                    "stiffness": 1e4, "regularization": "smooth"}],
        "outputs": [{"element": "g"}, {"element": "c", "quantity": "normal_force"}]})j",
};

// Replacements for a value or a piece of text.
const std::vector<std::string> kTokens = {
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "null",
    "true",
    "[]",
    "{}",
    "[0, 0]",
    "\"\"",
    "\"rod3\"",
    "\"ground\"",
    "\"theta1_ddot\"",
    "\"(((\"",
    "\"1/0\"",
    "\"sqrt(-1)\"",
    "\"end(end(theta1))\"",
    "\"at(theta1, 1e300)\"",
    "\"q9\"",
    "\"pi\"",
    "\"t\"",
    "\"rk4\"",
    "\"cvode\"",
    "\"nope\"",
    "\"gim_tyre\"",
    "\"bushing\"",
    "\"module\"",
    "\"/dev/null\"",
    "\"clamp(t, 1)\"",
    "\"x^y^z\"",
    "\"--\"",
    "\"\\u0000\"",
    "1e-9",
    "0.5",
    "\"maximum(\"",
    "\"model\"",
    "\"enabled\"",
};

// A value of the document replaced by a token, a member dropped or renamed:
// the result still parses, so that the loader's checks are what is tested.
std::string mutated_structure(const std::string& seed) {
  nlohmann::json doc = nlohmann::json::parse(seed);
  const int mutations = *rc::gen::inRange(1, 4);
  for (int m = 0; m < mutations; ++m) {
    nlohmann::json* node = &doc;
    while (!node->empty() && (node->is_object() || node->is_array()) &&
           *rc::gen::inRange(0, 4) != 0) {
      auto it = node->begin();
      std::advance(it,
                   *rc::gen::inRange<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(node->size())));
      node = &*it;
    }
    if (node->is_object() && !node->empty() && *rc::gen::arbitrary<bool>()) {
      auto it = node->begin();
      std::advance(it,
                   *rc::gen::inRange<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(node->size())));
      const std::string key = it.key();
      nlohmann::json value = *it;
      node->erase(key);
      if (*rc::gen::arbitrary<bool>()) (*node)[key.substr(1) + "x"] = value;  // renamed
    } else {
      *node = nlohmann::json::parse(*rc::gen::elementOf(kTokens));
    }
  }
  return doc.dump();
}

std::string mutated(std::string text) {
  if (*rc::gen::inRange(0, 3) != 0) return mutated_structure(text);
  const int mutations = *rc::gen::inRange(1, 3);
  for (int m = 0; m < mutations; ++m) {
    if (text.empty()) break;
    const auto at = *rc::gen::inRange<std::size_t>(0, text.size());
    switch (std::min(*rc::gen::inRange(0, 7), 3)) {  // mostly a value replaced, so that it parses
      // By concatenation: g++ 12 sees a false overlap in std::string::insert and replace
      // (-Wrestrict).
      case 0:
        text = text.substr(0, at) +
               text.substr(std::min(text.size(), at + *rc::gen::inRange<std::size_t>(1, 8)));
        break;  // a cut
      case 1:
        text = text.substr(0, at) + *rc::gen::elementOf(kTokens) + text.substr(at);
        break;
      case 2:
        text[at] = *rc::gen::elementOf(std::string("{}[]\",:0123456789.eE-+ abqtx_\\"));
        break;
      default: {  // a value replaced: from a ':' to the next ',' or '}'
        const auto colon = text.find(':', at);
        if (colon == std::string::npos) break;
        const auto end = text.find_first_of(",}", colon);
        if (end == std::string::npos) break;
        text = text.substr(0, colon + 1) + " " + *rc::gen::elementOf(kTokens) + text.substr(end);
      }
    }
  }
  return text;
}

}  // namespace

TEST_CASE("mutated scenario texts are run or refused with a runtime error", "[fuzz][scenario]") {
  rc::prop("scenario loader", [] {
    const std::string text = mutated(*rc::gen::elementOf(kSeeds));
    RC_LOG() << text;
    try {
      sim::Scenario s = sim::parse_scenario(text, "fuzz.json");
      sim::RunOptions o;
      o.t_end = std::min(s.t_end, 0.05);  // bounded work whatever the text says
      sim::Simulation simulation(s, o);
      if (simulation.expected_rows() < 1e4) {
        const sim::RunResult r = simulation.run();
        RC_TAG("ran");
        RC_ASSERT(r.rows > 0);
      } else {
        RC_TAG("too many rows");
      }
    } catch (const runtime::RuntimeError& e) {
      RC_TAG(std::string(e.what()).find(": /") != std::string::npos ? "refused at a JSON path"
                                                                    : "refused");
    }
  });
}

TEST_CASE("random symdyn-sim command lines exit with 0, 1 or 2 and never crash or hang",
          "[fuzz][sim]") {
  const std::vector<std::string> tokens = {"scenario.json",
                                           "double_pendulum",
                                           "slider_crank",
                                           "nope",
                                           "nope.json",
                                           "--list",
                                           "--variant",
                                           "relative",
                                           "dependent",
                                           "--integrator",
                                           "rk4",
                                           "dop853",
                                           "cvode",
                                           "euler",
                                           "--tolerance",
                                           "--rtol",
                                           "--atol",
                                           "1e-6",
                                           "0",
                                           "-1",
                                           "nan",
                                           "inf",
                                           "--interval",
                                           "0.01",
                                           "1e-300",
                                           "--step",
                                           "--assembled",
                                           "--out",
                                           "out.csv",
                                           "--max-rows",
                                           "10",
                                           "--help",
                                           "--",
                                           "",
                                           "\xff",
                                           "--t-end=0.01"};
  rc::prop("symdyn-sim command line", [&] {
    const auto dir = scratch_directory("sim_fuzz");
    std::ofstream(dir / "scenario.json") << mutated(*rc::gen::elementOf(kSeeds));
    std::vector<std::string> argv{SYMDYN_SIM};
    const int n = *rc::gen::inRange(0, 2) == 0 ? 0 : *rc::gen::inRange(1, 6);
    if (n == 0) argv.push_back("scenario.json");
    for (int i = 0; i < n; ++i) argv.push_back(*rc::gen::elementOf(tokens));
    argv.insert(argv.end(),
                {"--t-end", "0.05"});  // bounded work (a second --t-end is a command-line error)
    const CommandResult r = run_command(argv, 60, dir);
    std::filesystem::remove_all(dir);
    RC_LOG() << fmt::format("{}", fmt::join(argv, " ")) << "\nexit " << r.exit_code
             << "\nstderr: " << r.err;
    RC_TAG(fmt::format("exit {}", r.exit_code));
    RC_ASSERT(r.exit_code >= 0);
    RC_ASSERT(r.exit_code <= 2);
    if (r.exit_code == 2) RC_ASSERT(!r.err.empty());
  });
}
