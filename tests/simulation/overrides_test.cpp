// Changes to a scenario by path (apps/sim/overrides.hpp) and the sweep
// engine (serve.hpp): each path lands where the scenario's own value is,
// each bad path is refused naming it, a changed value is checked as the
// file's own would be, and the engine's rows read back exactly.
#include "overrides.hpp"

#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "run.hpp"
#include "serve.hpp"

namespace {

using namespace symdyn;
using Catch::Matchers::Contains;
using nlohmann::json;

const std::string kSpring = R"j({
  "model": "double_pendulum",
  "variables": {"torque": 1},
  "forces": [
    {"type": "point_spring_damper", "name": "spring", "a": {"body": "ground", "point": [0, -2, 0]},
     "b": {"body": "rod2", "point": [0.5, 0, 0]}, "stiffness": 20, "free_length": 1},
    {"type": "coordinate_force", "name": "motor", "coordinates": "theta1", "value": "torque"}
  ],
  "integrator": "dopri5",
  "t_end": 0.5
})j";

sim::Scenario spring() {
  return sim::parse_scenario(kSpring, "spring.json");
}

sim::Scenario changed(const std::vector<sim::Override>& changes) {
  const sim::Scenario s = spring();
  return sim::with_overrides(s, sim::make_model(s), changes);
}

std::string refusal(const std::string& path) {
  const sim::Scenario s = spring();
  try {
    sim::check_override(s, sim::make_model(s), path);
  } catch (const sim::OverrideError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("overrides: each path lands where the scenario's own value is", "[scenario][sweep]") {
  const sim::Scenario s = changed({{"forces.spring.stiffness", 35.0},
                                   {"forces.spring.b.point.1", 0.25},
                                   {"initial.qd.theta2", 2.0},
                                   {"variables.torque", 3.0},
                                   {"integrator.rtol", 1e-9},
                                   {"t_end", 0.25}});
  const json& d = s.document;
  CHECK(d["forces"][0]["stiffness"] == 35.0);
  CHECK(d["forces"][0]["b"]["point"] == json::array({0.5, 0.25, 0}));
  CHECK(d["initial"]["qd"]["theta2"] == 2.0);
  CHECK(d["variables"]["torque"] == 3.0);
  CHECK(d["integrator"] == json{{"name", "dopri5"}, {"rtol", 1e-9}});  // a name becomes an object
  CHECK(s.rtol == 1e-9);
  CHECK(s.t_end == 0.25);
  CHECK(s.origin == "spring.json");
  // The run reads them: a stiffer spring and a later end.
  const sim::RunResult r = sim::run_scenario(s);
  CHECK(r.t_end == 0.25);
  CHECK(r.initial.qd(1) == 2.0);
}

TEST_CASE("overrides: integrator.tolerance replaces the scenario's rtol and atol",
          "[scenario][sweep]") {
  const sim::Scenario base = sim::find_builtin("slider_crank");
  const std::vector<sim::Override> first{{"integrator.rtol", 1e-5}, {"integrator.atol", 1e-4}};
  const sim::Scenario s = sim::with_overrides(base, sim::make_model(base), first);
  const sim::Scenario t =
      sim::with_overrides(s, sim::make_model(s), {{"integrator.tolerance", 1e-7}});
  CHECK(s.rtol == 1e-5);
  CHECK(s.atol == 1e-4);
  CHECK(t.rtol == 1e-7);
  CHECK(t.atol == 1e-7);
}

TEST_CASE("overrides: a path that names nothing is refused, naming it and the valid names",
          "[scenario][sweep][bad_input]") {
  struct Case {
    std::string path, culprit;
  };
  const Case cases[] = {
      {"forces.sprng.stiffness",
       "forces.sprng.stiffness: no force element 'sprng' (elements: spring, motor)"},
      {"forces.spring.stifness",
       "forces.spring.stifness: a point_spring_damper has no member 'stifness' (members: enabled, "
       "a, b, stiffness, "
       "free_length, damping)"},
      {"forces.spring", "forces.spring: expected forces.<element>.<member>"},
      {"forces.spring.b.point.3",
       "forces.spring.b.point.3: forces.spring.b.point has 3 entries: '3' is not an index"},
      {"forces.spring.b.pont", "forces.spring.b.pont: forces.spring.b has no member 'pont'"},
      {"forces.spring.stiffness.x",
       "forces.spring.stiffness.x: forces.spring.stiffness is a single value"},
      {"parameters.m1",
       "parameters.m1: unknown parameter 'm1' (parameters of double_pendulum: none)"},
      {"initial.q.q7", "initial.q.q7: unknown coordinate 'q7' (coordinates: theta1, theta2)"},
      {"initial.qdd.theta1", "initial.qdd.theta1: unknown part 'qdd' (expected q or qd)"},
      {"initial.q", "initial.q: expected initial.q.<coordinate> or initial.qd.<coordinate>"},
      {"variables.speed",
       "variables.speed: the scenario declares no variable 'speed' (variables: torque)"},
      {"integrator.order",
       "integrator.order: unknown part 'order' (expected name, tolerance, rtol, atol or step)"},
      {"t_end.x", "t_end.x: expected t_end"},
      {"outputs",
       "outputs: unknown part 'outputs' (expected parameters, initial, variables, forces, "
       "integrator, t_end "
       "or output_interval)"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.path);
    CHECK_THAT(refusal(c.path), Contains(c.culprit));
  }
}

TEST_CASE("overrides: a changed value is checked where the file's own would be",
          "[scenario][sweep][bad_input]") {
  CHECK_THROWS_WITH(sim::Simulation(changed({{"forces.spring.stiffness", -3.0}})),
                    Contains("spring.json: /forces/0/stiffness (force element 'spring'): expected "
                             "a finite number >= 0, found -3"));
  CHECK_THROWS_WITH(sim::Simulation(changed({{"initial.q.theta1", "fast"}})),
                    Contains("spring.json: /initial/q/theta1: expected a number, found a string"));
  CHECK_THROWS_WITH(changed({{"t_end", 0.0}}),
                    Contains("spring.json: /t_end: expected a number > 0, found 0"));
}

TEST_CASE("overrides: --set's text is JSON when it reads as JSON, else a string",
          "[scenario][sweep]") {
  CHECK(sim::parse_override("t_end=2.5").value == 2.5);
  CHECK(sim::parse_override("forces.s.b.point=[0, 1, 0]").value == json::array({0, 1, 0}));
  CHECK(sim::parse_override("forces.m.enabled=false").value == false);
  CHECK(sim::parse_override("integrator.name=cvode").value == "cvode");
  CHECK(sim::parse_override("forces.m.value=2 * sin(t)").value == "2 * sin(t)");
  CHECK_THROWS_WITH(sim::parse_override("t_end"), Contains("--set 't_end': expected path=value"));
}

namespace {

// The engine's replies to the given requests, one per line.
std::vector<json> serve(const std::vector<json>& requests) {
  std::string input;
  for (const json& r : requests) input += r.dump() + "\n";
  std::istringstream in(input);
  std::ostringstream out;
  REQUIRE(sim::serve(in, out) == 0);
  std::vector<json> replies;
  std::istringstream lines(out.str());
  for (std::string line; std::getline(lines, line);) {
    // NaN as Python's json writes it, outside strings: null for nlohmann.
    for (std::size_t at = line.find("NaN"); at != std::string::npos;
         at = line.find("NaN", at + 1)) {
      if ((line[at - 1] == '[' || line[at - 1] == ' ') &&
          (line[at + 3] == ',' || line[at + 3] == ']')) {
        line.replace(at, 3, "null");
      }
    }
    replies.push_back(json::parse(line));
  }
  return replies;
}

json load(json keep,
          json targets = json::array({{{"path", "forces.spring.stiffness"}, {"at", "/set/k"}}})) {
  return {{"load",
           {{"scenario", {{"text", kSpring}, {"origin", "spring.json"}, {"directory", "."}}},
            {"origin", "sweep.json"},
            {"targets", std::move(targets)},
            {"keep", std::move(keep)}}}};
}

}  // namespace

TEST_CASE("serve: the engine's rows are the runs' own numbers, failures kept",
          "[scenario][sweep]") {
  const json keep = {
      {"final", json::array({"q"})}, {"extrema", json::array({"rod2.y"})}, {"counters", true}};
  const auto replies = serve({load(keep),
                              {{"run", 0}, {"values", {35.0}}},
                              {{"run", 1}, {"values", {-1.0}}},
                              {{"run", 2}, {"values", {35.0}}}});
  REQUIRE(replies.size() == 4);
  const auto columns = replies[0]["loaded"]["columns"];
  CHECK(columns ==
        json::array({"end(theta1)", "end(theta2)", "minimum(rod2.y)", "maximum(rod2.y)", "steps",
                     "rejected_steps", "rhs_evaluations", "residual_evaluations",
                     "jacobian_evaluations", "newton_iterations"}));
  // The same run as Simulation makes it, every number read back exactly.
  const sim::Scenario s = changed({{"forces.spring.stiffness", 35.0}});
  sim::Simulation simulation(s);
  const sim::RunResult r = simulation.run();
  const json& row = replies[1];
  CHECK(row["run"] == 0);
  CHECK(row["status"] == "ok");
  CHECK(row["values"][0].get<double>() == r.final.q(0));
  CHECK(row["values"][1].get<double>() == r.final.q(1));
  CHECK(row["values"][4].get<double>() == static_cast<double>(r.statistics.steps));
  CHECK(row["cpu"].get<double>() > 0.0);
  // A refused value fails its run alone, naming the scenario's key.
  CHECK(replies[2]["status"] == "failed");
  CHECK_THAT(replies[2]["error"].get<std::string>(), Contains("spring.json: /forces/0/stiffness"));
  CHECK(replies[2]["values"][0].is_null());      // NaN, read by nlohmann as null
  CHECK(replies[3]["values"] == row["values"]);  // the next run is as the first

  // A batch: the same rows, one line each.
  const json runs = {
      {"runs", {{{"run", 0}, {"values", {35.0}}}, {{"run", 1}, {"values", {-1.0}}}}}};
  const auto batch = serve({load(keep), runs});
  REQUIRE(batch.size() == 3);
  CHECK(batch[1]["values"] == row["values"]);
  CHECK(batch[2]["status"] == "failed");
}

TEST_CASE("serve: a bad sweep is refused at load, naming the sweep's key",
          "[scenario][sweep][bad_input]") {
  const auto target = [](const char* path, const char* at) {
    return json::array({{{"path", path}, {"at", at}}});
  };
  struct Case {
    json request;
    std::string culprit;
  };
  const Case cases[] = {
      {load(json::object(), target("forces.sprng.stiffness", "/set/forces.sprng.stiffness")),
       "sweep.json: /set/forces.sprng.stiffness: no force element 'sprng' (elements: spring, "
       "motor)"},
      {load({{"extremes", json::array({"theta1"})}}),
       "sweep.json: /keep/extremes: unknown key 'extremes'"},
      {load({{"extrema", json::array({"q9"})}}), "sweep.json: /keep/extrema/0: in 'minimum(q9)'"},
      {load({{"values", {{"a", "theta1"}}}}),
       "sweep.json: /keep/values/a: in 'theta1' at column 1: 'theta1' varies during the run"},
      {load({{"final", json::array({"qdd"})}}),
       "sweep.json: /keep/final/0: unknown group 'qdd' (expected q or qd)"},
      {load({{"values", {{"end(theta1)", "end(theta2)"}}}}),
       "sweep.json: /keep/values/end(theta1): a second column named 'end(theta1)'"},
      {load({{"at", {{"times", {9.0}}, {"of", {"theta1"}}}}}),
       "sweep.json: /keep/at/of/0: in 'at(theta1, 9)'"},
      {json{{"run", 0}, {"values", json::array()}}, "request: no sweep loaded"},
      {json{{"ask", 0}}, "request: expected \"load\", \"run\" or \"runs\""},
  };
  for (const Case& c : cases) {
    CAPTURE(c.culprit);
    const auto replies = serve({c.request});
    REQUIRE(replies.size() == 1);
    CHECK_THAT(replies[0].value("error", ""), Contains(c.culprit));
  }
}
