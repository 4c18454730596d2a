// Scenario files (apps/sim/scenario.hpp, docs/scenarios.md): every bad input
// names its culprit by JSON path; events stop the integration exactly at their
// time (checked against the work of a constant torque); chained segments
// write each instant once; qdd in the CSV against finite differences of qd;
// memory does not grow with the run's length; model modules load, and the
// wrong ones are refused.
#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "allocation_count.hpp"
#include "codegen/run_command.hpp"
#include "run.hpp"
#include <symdyn/runtime/breakpoints.hpp>
#include <symdyn/runtime/model_module.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn;
using Catch::Matchers::Contains;

sim::Scenario parse(const std::string& text) {
  return sim::parse_scenario(text, "test.json");
}

// What loading and building the scenario throws, "" if nothing.
std::string error_of(const std::string& text) {
  try {
    sim::Simulation simulation(parse(text));
  } catch (const sim::ScenarioError& e) {
    return e.what();
  }
  return "";
}

std::vector<runtime::State> states_of(const sim::Scenario& s, sim::RunOptions o,
                                      sim::RunResult* result = nullptr) {
  std::vector<runtime::State> states;
  o.on_sample = [&](const runtime::State& st, const runtime::Vector&) { states.push_back(st); };
  sim::RunResult r = sim::run_scenario(s, o);
  if (result != nullptr) *result = r;
  return states;
}

// What a double pendulum with the one force element `element` throws.
std::string element_error(const std::string& element) {
  return error_of(R"j({"model": "double_pendulum", "forces": [)j" + element + "]}");
}

// A stream that drops what it is given, without allocating.
class NullBuffer : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return c; }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

}  // namespace

TEST_CASE("scenario files: each bad input names its culprit by JSON path",
          "[scenario][bad_input]") {
  struct Case {
    std::string text, culprit;
  };
  const std::string dp = R"j("model": "double_pendulum")j";
  const Case cases[] = {
      {"{" + dp + ",}", "test.json: not JSON: parse error at line 1, column 29"},
      {"[1]", "test.json: /: expected an object, found an array"},
      {"{}", "test.json: /: missing key 'model'"},
      {"{" + dp + R"j(, "t_ned": 1})j",
       "test.json: /t_ned: unknown key 't_ned' (expected: $schema, description, model,"},
      {"{" + dp + R"j(, "t_end": -1})j", "test.json: /t_end: expected a number > 0, found -1"},
      {"{" + dp + R"j(, "t_end": "10"})j", "test.json: /t_end: expected a number, found a string"},
      {R"j({"model": "pendulum"})j",
       "test.json: /model: no built-in model 'pendulum' (built in: double_pendulum,"},
      {R"j({"model": {"name": "double_pendulum", "varient": "absolute"}})j",
       "test.json: /model/varient: unknown key 'varient' (expected: name, variant, module)"},
      {"{" + dp + R"j(, "integrator": {"name": "dopri5", "rtol": 0}})j",
       "test.json: /integrator/rtol: expected a number > 0, found 0"},
      {"{" + dp + R"j(, "parameters": {"m1": 2}})j",
       "test.json: /parameters/m1: unknown parameter 'm1' (the model has no run-time parameters)"},
      {"{" + dp + R"j(, "initial": {"q": {"q7": 1}}})j",
       "test.json: /initial/q/q7: unknown coordinate 'q7' (coordinates: theta1, theta2)"},
      {"{" + dp + R"j(, "forces": [{"type": "spring", "name": "s"}]})j",
       "test.json: /forces/0/type (force element 's'): unknown force element type 'spring' (types: "
       "coordinate_spring_damper, "
       "coordinate_force, coordinate_tracking, point_spring_damper, point_load, bushing, "
       "plane_contact, simple_tyre, "
       "gim_tyre)"},
      {"{" + dp +
           R"j(, "forces": [{"type": "coordinate_spring_damper", "name": "s", "coordinate": "theta1", "stifness": 1}]})j",
       "test.json: /forces/0/stifness (force element 's'): unknown key 'stifness' for a "
       "coordinate_spring_damper (expected: type, name, "
       "enabled, coordinate, stiffness, damping, free_value)"},
      {"{" + dp +
           R"j(, "forces": [{"type": "plane_contact", "name": "c", "body": "rod3", "stiffness": 1}]})j",
       "test.json: /forces/0/body (force element 'c'): unknown body 'rod3' (bodies: rod1, rod2, or "
       "ground)"},
      {"{" + dp +
           R"j(, "forces": [{"type": "coordinate_force", "name": "rod1", "coordinates": "theta1", "value": 1}]})j",
       "test.json: /forces/0/name (force element 'rod1'): 'rod1' is a body's name: name the "
       "element otherwise"},
      {"{" + dp +
           R"j(, "forces": [{"type": "coordinate_force", "name": "m", "coordinates": "theta1", "value": "2 * (theta1"}]})j",
       "test.json: /forces/0/value (force element 'm'): in '2 * (theta1' at column 12: expected "
       "')' at "
       "the end"},
      {"{" + dp +
           R"j(, "forces": [{"type": "coordinate_force", "name": "m", "coordinates": "theta1", "value": "theta1_ddot"}]})j",
       "test.json: /forces/0/value (force element 'm'): in 'theta1_ddot' at column 1: "
       "'theta1_ddot': "
       "accelerations are not known here"},
      {"{" + dp + R"j(, "outputs": [{"name": "tip", "value": "rod2.xx"}]})j",
       "test.json: /outputs/0/value: in 'rod2.xx' at column 1: unknown quantity 'xx' of body "
       "'rod2' (valid: x, y, z,"},
      {"{" + dp + R"j(, "outputs": ["qddd"]})j",
       "test.json: /outputs/0: unknown output 'qddd' (expected q, qd, qdd, energies, or an "
       "object)"},
      {"{" + dp + R"j(, "events": [{"time": 3, "disable": "motor"}], "t_end": 2})j",
       "test.json: /events/0/time: expected a time inside (0, t_end = 2), found 3"},
      {"{" + dp + R"j(, "t_end": 2, "events": [{"time": 1, "disable": "motor"}]})j",
       "test.json: /events/0/disable: unknown force element 'motor' (elements: none)"},
      {"{" + dp + R"j(, "t_end": 2, "events": [{"time": 1, "set": {"tau": 0}}]})j",
       "test.json: /events/0/set/tau: unknown variable 'tau' (variables: none)"},
      {"{" + dp + R"j(, "checks": [{"name": "c", "value": "theta1", "band": [0, 1]}]})j",
       "test.json: /checks/0/value (check 'c'): in 'theta1' at column 1: 'theta1' varies during "
       "the run: a "
       "check reads it through"},
      {"{" + dp + R"j(, "checks": [{"name": "c", "value": "mean(theta1)", "band": [0, 1]}]})j",
       "test.json: /checks/0/value (check 'c'): in 'mean(theta1)' at column 1: unknown function "
       "'mean' "
       "(statistics: start, end,"},
      {"{" + dp + R"j(, "checks": [{"name": "c", "value": "end(theta1)", "band": [0]}]})j",
       "test.json: /checks/0/band (check 'c'): expected [low, high], found 1 entries"},
      {R"j({"model": {"name": "double_pendulum", "module": "nowhere/double_pendulum.so"}})j",
       "model module 'nowhere/double_pendulum.so' not found"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    CHECK_THAT(error_of(c.text), Contains(c.culprit));
  }
}

TEST_CASE(
    "scenario files: what a JSON reader hides is refused, naming the key, the element and the file",
    "[scenario][bad_input]") {
  struct Case {
    std::string text, culprit;
  };
  const std::string dp = R"j("model": "double_pendulum")j";
  const std::string contact =
      R"j({"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": 1e5)j";
  const Case cases[] = {
      // A key given twice: nlohmann's DOM keeps the last one silently.
      {"{" + dp + R"j(, "t_end": 1, "t_end": 5})j",
       "test.json: /t_end: key 't_end' is given twice in this object"},
      {"{" + dp +
           R"j(, "forces": [{"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": 1e5,
          "damping": 10, "stiffness": 2e5}]})j",
       "test.json: /forces/0/stiffness (force element 'foot'): key 'stiffness' is given twice in "
       "this object"},
      {"{" + dp + R"j(, "initial": {"q": {"theta1": 0.1, "theta1": 0.2}}})j",
       "test.json: /initial/q/theta1: key 'theta1' is given twice"},
      // Numbers a double cannot hold, and NaN or Infinity as Python's json writes them.
      {"{" + dp + ", \"forces\": [" + contact + R"j(, "damping": 1e400}]})j",
       "test.json: /forces/0/damping (force element 'foot'): 1e400 is beyond the range of a "
       "double"},
      {"{" + dp + ", \"forces\": [" + contact + R"j(, "friction": NaN}]})j",
       "test.json: /forces/0/friction (force element 'foot'): NaN is not a number in JSON, and "
       "numbers here must be "
       "finite"},
      {"{" + dp + R"j(, "initial": {"qd": {"theta2": -Infinity}}})j",
       "test.json: /initial/qd/theta2: -Infinity is not a number in JSON"},
      {"{" + dp + R"j(, "t_end": 1e-400})j",
       "test.json: /t_end: 1e-400 is too small for a double (it would read as 0)"},
      {"{" + dp + R"j(, "checks": [{"name": "e", "value": "end(theta1)", "band": [0, -1e999]}]})j",
       "test.json: /checks/0/band/1 (check 'e'): -1e999 is beyond the range of a double"},
      // Other parse errors say where in the document they are.
      {"{" + dp + R"j(, "forces": [{"type": "plane_contact" "name": "foot"}]})j",
       "expected '}' (in /forces/0)"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    CHECK_THAT(error_of(c.text), Contains(c.culprit));
  }
}

TEST_CASE(
    "scenario files: a law's constants of the wrong sign are refused, naming the element and the "
    "key",
    "[scenario][bad_input]") {
  struct Case {
    std::string element, culprit;
  };
  const Case cases[] = {
      // A contact without stiffness lets the body sink through the plane with zero force.
      {R"j({"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": -1e5})j",
       "test.json: /forces/0/stiffness (force element 'foot'): expected a finite number > 0, found "
       "-100000"},
      {R"j({"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": 0})j",
       "/forces/0/stiffness (force element 'foot'): expected a finite number > 0, found 0"},
      {R"j({"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": 1e5, "damping": -3})j",
       "/forces/0/damping (force element 'foot'): expected a finite number >= 0, found -3"},
      {R"j({"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": 1e5, "friction": -0.5})j",
       "/forces/0/friction (force element 'foot'): expected a finite number >= 0, found -0.5"},
      {R"j({"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": 1e5, "stiffness_exponent": 0})j",
       "/forces/0/stiffness_exponent (force element 'foot'): expected a finite number > 0, found "
       "0"},
      {R"j({"type": "plane_contact", "name": "foot", "body": "rod2", "stiffness": 1e5, "radius": -0.1})j",
       "/forces/0/radius (force element 'foot'): expected a finite number >= 0, found -0.1"},
      {R"j({"type": "coordinate_spring_damper", "name": "k", "coordinate": "theta1", "stiffness": 10, "damping": -1})j",
       "/forces/0/damping (force element 'k'): expected a finite number >= 0, found -1"},
      {R"j({"type": "coordinate_spring_damper", "name": "k", "coordinate": "theta1", "stiffness": -10})j",
       "/forces/0/stiffness (force element 'k'): expected a finite number >= 0, found -10"},
      {R"j({"type": "coordinate_tracking", "name": "servo", "coordinate": "theta1", "kp": 100, "kd": -2})j",
       "/forces/0/kd (force element 'servo'): expected a finite number >= 0, found -2"},
      {R"j({"type": "point_spring_damper", "name": "s", "a": {"body": "ground"}, "b": {"body": "rod2"},
           "stiffness": 100, "free_length": -0.5})j",
       "/forces/0/free_length (force element 's'): expected a finite number >= 0, found -0.5"},
      {R"j({"type": "bushing", "name": "mount", "a": {"body": "ground"}, "b": {"body": "rod1"},
           "rotational_stiffness": [10, -10, 10]})j",
       "/forces/0/rotational_stiffness (force element 'mount'): expected 3 finite numbers >= 0, "
       "found (10, -10, 10)"},
      // Axes that are not a rotation make the bushing's angles meaningless.
      {R"j({"type": "bushing", "name": "mount", "a": {"body": "ground", "axes": [[1, 0, 0], [0, 2, 0], [0, 0, 1]]},
           "b": {"body": "rod1"}})j",
       "/forces/0/a/axes (force element 'mount'): expected orthonormal axes"},
      {R"j({"type": "bushing", "name": "mount", "a": {"body": "ground"},
           "b": {"body": "rod1", "axes": [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}})j",
       "/forces/0/b/axes (force element 'mount'): expected right-handed axes"},
      {R"j({"type": "simple_tyre", "name": "wheel", "body": "rod2", "axis": [0, 0, 0]})j",
       "/forces/0/axis (force element 'wheel'): expected a non-zero direction, found (0, 0, 0)"},
      {R"j({"type": "simple_tyre", "name": "wheel", "body": "rod2", "stiffness": 0})j",
       "/forces/0/stiffness (force element 'wheel'): expected a finite number > 0, found 0"},
      {R"j({"type": "gim_tyre", "name": "wheel", "body": "rod2", "r1": 0.3, "r2": 0.4})j",
       "/forces/0/r2 (force element 'wheel'): expected the section radius <= r1 = 0.3, found 0.4"},
      {R"j({"type": "gim_tyre", "name": "wheel", "body": "rod2", "mu_dynamic": -0.8})j",
       "/forces/0/mu_dynamic (force element 'wheel'): expected a finite number >= 0, found -0.8"},
      {R"j({"type": "gim_tyre", "name": "wheel", "body": "rod2", "Kz": -2e5})j",
       "/forces/0/Kz (force element 'wheel'): expected a finite number > 0, found -200000"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.element);
    CHECK_THAT(element_error(c.element), Contains(c.culprit));
  }
}

TEST_CASE(
    "scenario files: an element's constants as the runtime's table has them: a required one "
    "missing, one out of its range, an unknown key with the close ones named",
    "[scenario][bad_input]") {
  struct Case {
    std::string element, culprit;
  };
  const Case cases[] = {
      {R"j({"type": "point_spring_damper", "name": "s", "a": {"body": "ground"}, "b": {"body": "rod2"},
           "stiffness": 100})j",
       "test.json: /forces/0 (force element 's'): missing key 'free_length' (a number >= 0, m: the "
       "length L where the spring is relaxed)"},
      {R"j({"type": "plane_contact", "name": "foot", "body": "rod2"})j",
       "/forces/0 (force element 'foot'): missing key 'stiffness' (a number > 0, N/m^pk: Kn in N = "
       "Kn delta^pk + Cd delta^pd deltad)"},
      {R"j({"type": "gim_tyre", "name": "wheel", "body": "rod2", "Fznom": 0})j",
       "/forces/0/Fznom (force element 'wheel'): expected a finite number > 0, found 0"},
      {R"j({"type": "simple_tyre", "name": "wheel", "body": "rod2", "epsilon": -0.05})j",
       "/forces/0/epsilon (force element 'wheel'): expected a finite number > 0, found -0.05"},
      {R"j({"type": "bushing", "name": "mount", "a": {"body": "ground"}, "b": {"body": "rod1"},
           "stiffness": 1e4})j",
       "/forces/0/stiffness (force element 'mount'): expected an array of 3 numbers, found a "
       "number"},
      {R"j({"type": "simple_tyre", "name": "wheel", "body": "rod2", "radious": 0.3})j",
       "/forces/0/radious (force element 'wheel'): unknown key 'radious' for a simple_tyre "
       "(expected: type, name, enabled, body, radius, stiffness, damping, friction, epsilon, "
       "axis, centre, ground); did you mean radius?"},
      {R"j({"type": "gim_tyre", "name": "wheel", "body": "rod2", "kz": 2e5})j",
       "unknown key 'kz' for a gim_tyre (expected: type, name, enabled, body, r1, r2, Kz, Cz, "
       "Fznom, Clongnom, nlong, Clatnom, nlat, Ccambernom, ncamber, mu_static, mu_dynamic, axis, "
       "centre, ground); did you mean Kz or Cz?"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.element);
    CHECK_THAT(element_error(c.element), Contains(c.culprit));
  }
  // A key far from every known one names none.
  CHECK_THAT(
      error_of(R"j({"model": "double_pendulum", "forces": [{"type": "coordinate_spring_damper",
                 "name": "k", "coordinate": "q0", "stiffness": 1, "elasticity": 2}]})j"),
      Contains("damping, free_value)") && !Contains("did you mean"));
}

TEST_CASE("scenario files: a check band that no value could pass is refused before the run",
          "[scenario][bad_input]") {
  const std::string dp =
      R"j({"model": "double_pendulum", "checks": [{"name": "energy", "value": "drift(total_energy)", )j";
  CHECK_THAT(error_of(dp + R"j("band": [1e-3, 0]}]})j"),
             Contains("test.json: /checks/0/band (check 'energy'): the band [0.001, 0] is "
                      "reversed: its low end is above "
                      "its high end, so no value passes; write [0, 0.001]"));
  CHECK_THAT(error_of(dp + R"j("band": ["10 * rtol", "rtol"]}]})j"),
             Contains("/checks/0/band (check 'energy'): the band [1e-07, 1e-08] is reversed"));
  CHECK_THAT(error_of(dp + R"j("band": [0, "1e308 * 10"]}]})j"),
             Contains("/checks/0/band (check 'energy'): the band [0, inf] is not finite"));
  // A band that reads a statistic is only known at the end: not refused here.
  CHECK(error_of(dp + R"j("band": [0, "0.01 * start(total_energy)"]}]})j").empty());
}

TEST_CASE("scenario files: what would silently do nothing, do twice or read NaN is refused",
          "[scenario][bad_input]") {
  struct Case {
    std::string text, culprit;
  };
  const std::string dp = R"j("model": "double_pendulum")j";
  const Case cases[] = {
      // Elements that push nothing.
      {"{" + dp +
           R"j(, "forces": [{"type": "point_load", "name": "push", "at": {"body": "ground"}, "force": [1, 0, 0]}]})j",
       "/forces/0/at/body (force element 'push'): a load on the ground moves nothing: name a body"},
      {"{" + dp +
           R"j(, "forces": [{"type": "plane_contact", "name": "floor", "body": "ground", "stiffness": 1e5}]})j",
       "/forces/0/body (force element 'floor'): a contact on the ground moves nothing: name a "
       "body"},
      {"{" + dp + R"j(, "forces": [{"type": "simple_tyre", "name": "wheel", "body": "ground"}]})j",
       "/forces/0/body (force element 'wheel'): a tyre on the ground moves nothing"},
      {"{" + dp +
           R"j(, "forces": [{"type": "point_spring_damper", "name": "s", "a": {"body": "rod1"},
          "b": {"body": "rod1", "point": [0.5, 0, 0]}, "stiffness": 10, "free_length": 0}]})j",
       "/forces/0/b/body (force element 's'): a spring with both ends on body 'rod1' moves nothing "
       "(its forces cancel)"},
      {"{" + dp +
           R"j(, "forces": [{"type": "bushing", "name": "mount", "a": {"body": "ground"}, "b": {"body": "ground"}}]})j",
       "/forces/0/b/body (force element 'mount'): a bushing between two points of the ground moves "
       "nothing"},
      // A coordinate listed twice would get the force twice.
      {"{" + dp +
           R"j(, "forces": [{"type": "coordinate_force", "name": "m", "coordinates": ["theta1", "theta2", "theta1"], "value": 1}]})j",
       "/forces/0/coordinates/2 (force element 'm'): coordinate 'theta1' is listed twice: its "
       "force "
       "would be applied twice"},
      // Two CSV columns of one name.
      {"{" + dp + R"j(, "outputs": ["q", {"name": "theta1", "value": "2 * theta1"}]})j",
       "test.json: /outputs/1/value: the CSV already has a column 'theta1': name this output "
       "otherwise"},
      {"{" + dp + R"j(, "outputs": [{"name": "t", "value": "theta1"}]})j",
       "/outputs/0/value: the CSV already has a column 't'"},
      {"{" + dp +
           R"j(, "outputs": [{"name": "a", "value": "theta1"}, {"name": "a", "value": "theta2"}]})j",
       "/outputs/1/value: the CSV already has a column 'a'"},
      {"{" + dp +
           R"j(, "outputs": [{"body": "rod2", "quantity": "position"}, {"body": "rod2", "quantity": "position"}]})j",
       "/outputs/1/quantity: the CSV already has a column 'rod2.x'"},
      // Names that would shadow one another in expressions.
      {"{" + dp + R"j(, "variables": {"rod1": 2}})j",
       "test.json: /variables/rod1: 'rod1' is a body's name: name the variable otherwise"},
      {"{" + dp +
           R"j(, "variables": {"k": 2}, "forces": [{"type": "coordinate_force", "name": "k", "coordinates": "theta1", "value": 1}]})j",
       "/forces/0/name (force element 'k'): 'k' is a variable's name: name the element otherwise"},
      // at() outside the run is never set: its check would read NaN.
      {"{" + dp +
           R"j(, "t_end": 2, "checks": [{"name": "late", "value": "at(theta1, 5)", "band": [-1, 1]}]})j",
       "/checks/0/value (check 'late'): in 'at(theta1, 5)' at column 1: at(): the time 5 is "
       "outside "
       "the run [0, t_end = 2]"},
      {"{" + dp +
           R"j(, "checks": [{"name": "early", "value": "at(theta1, -1)", "band": [-1, 1]}]})j",
       "at(): the time -1 is outside the run"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    CHECK_THAT(error_of(c.text), Contains(c.culprit));
  }
}

TEST_CASE("events: a torque switched off stops the integration exactly there", "[scenario]") {
  // A constant torque tau on theta1 from rest until t = 1, then free motion. Its
  // work is tau (theta1(1) - theta1(0)), so E(1) = E(0) + tau Δtheta1; after it, E is constant.
  const double tau = 3.0;
  for (const char* how : {R"j("disable": "motor")j", R"j("set": {"tau": 0})j"}) {
    CAPTURE(how);
    const std::string text = fmt::format(R"j({{
      "model": "double_pendulum", "t_end": 2, "output_interval": 0.01,
      "integrator": {{"name": "dopri5", "tolerance": 1e-11}},
      "variables": {{"tau": {}}},
      "forces": [{{"type": "coordinate_force", "name": "motor", "coordinates": "theta1", "value": "tau"}}],
      "events": [{{"time": 1, {}}}],
      "outputs": ["q", "qd", "qdd", "energies", {{"name": "torque", "value": "motor.Q"}}]
    }})j",
                                         tau, how);
    sim::RunResult r;
    const auto states = states_of(parse(text), {}, &r);
    CHECK(r.segments == 2);
    REQUIRE(states.size() == 201);  // the instant t = 1 once, though both segments deliver it
    for (std::size_t k = 1; k < states.size(); ++k) CHECK(states[k].t > states[k - 1].t);
    CHECK(states[100].t == 1.0);
    // The CSV of the same run: energies, qdd, the torque.
    std::ostringstream csv;
    sim::RunOptions with_csv;
    with_csv.csv = &csv;
    sim::run_scenario(parse(text), with_csv);
    std::istringstream lines(csv.str());
    std::string line;
    std::getline(lines, line);
    CHECK(line ==
          "t,theta1,theta2,theta1_dot,theta2_dot,theta1_ddot,theta2_ddot,kinetic_energy,"
          "gravitational_energy,elastic_energy,"
          "total_energy,torque");
    std::vector<std::vector<double>> rows;
    while (std::getline(lines, line)) {
      std::vector<double> v;
      std::istringstream fields(line);
      for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
      rows.push_back(v);
    }
    REQUIRE(rows.size() == 201);
    const double E0 = rows[0][10], dq = rows[100][1] - rows[0][1];
    CHECK(rows[100][10] == Approx(E0 + tau * dq).margin(1e-7));
    for (std::size_t k = 100; k < rows.size(); ++k)
      CHECK(rows[k][10] == Approx(rows[100][10]).margin(1e-7));
    CHECK(rows[100][11] == tau);  // the row at the event: before the change
    CHECK(rows[101][11] == 0.0);
    // qdd against the five-point difference of qd (error of order h^4 qd^(5), h = 0.01 s).
    for (std::size_t k = 120; k < 190; k += 17) {
      for (std::size_t j = 3; j < 5; ++j) {
        const double fd =
            (rows[k - 2][j] - 8.0 * rows[k - 1][j] + 8.0 * rows[k + 1][j] - rows[k + 2][j]) /
            (12.0 * 0.01);
        CHECK(rows[k][j + 2] == Approx(fd).epsilon(1e-3).margin(1e-3));
      }
    }
  }
}

// The integrator's own output path (dense output) is not the scenario's: the
// allocations of a bare integration with the same outputs are subtracted.
TEST_CASE("a run's memory does not grow with its length", "[scenario]") {
  if (!symdyn_test::allocation_count()) {
    WARN("allocations cannot be counted here (sanitizer build)");
    return;
  }
  NullBuffer sink;
  std::ostream out(&sink);
  const sim::Scenario& scenario = sim::find_builtin("double_pendulum");
  const auto count = [] { return *symdyn_test::allocation_count(); };
  const auto integrator_alone = [&](double t_end) {
    runtime::MultibodySystem system(sim::make_model(scenario));
    runtime::IntegratorOptions o;
    o.relative_tolerance = o.absolute_tolerance = scenario.rtol;
    o.output_interval = scenario.output_interval;
    o.on_output = [](const runtime::State&, const runtime::Vector&, const runtime::Vector&) {};
    auto integrator = runtime::make_integrator(scenario.integrator, o);
    const std::size_t before = count();
    integrator->integrate(system, system.initial_state(), t_end);
    return count() - before;
  };
  const auto scenario_run = [&](double t_end) {
    sim::RunOptions o;
    o.t_end = t_end;
    o.csv = &out;
    sim::Simulation simulation(scenario, o);
    const std::size_t before = count();
    const sim::RunResult r = simulation.run();
    return count() - before;
  };
  // 101 and 1001 rows, with the checks' statistics and the CSV's channels.
  const std::size_t short_run = scenario_run(1.0) - integrator_alone(1.0);
  const std::size_t long_run = scenario_run(10.0) - integrator_alone(10.0);
  CAPTURE(short_run, long_run);
  CHECK(long_run <= short_run + 4);
}

TEST_CASE("model modules: a module runs as the built-in model, the wrong ones are refused",
          "[scenario][module]") {
  const std::string text =
      fmt::format(R"j({{"model": {{"name": "double_pendulum", "module": "{}"}}, "t_end": 1,
                                          "integrator": {{"name": "dopri5", "tolerance": 1e-10}}}})j",
                  MODULE_DOUBLE_PENDULUM);
  sim::RunResult from_module, built_in;
  states_of(parse(text), {}, &from_module);
  sim::RunOptions one_second;
  one_second.t_end = 1.0;
  states_of(sim::find_builtin("double_pendulum"), one_second, &built_in);
  CHECK(from_module.model == "double_pendulum");
  CHECK(from_module.final.q == built_in.final.q);
  CHECK(from_module.final.qd == built_in.final.qd);

  const auto module_error = [](const std::string& path) {
    return error_of(
        fmt::format(R"j({{"model": {{"name": "double_pendulum", "module": "{}"}}}})j", path));
  };
  CHECK_THAT(module_error(MODULE_CHAIN_2),
             Contains(fmt::format(
                 "model module '{}' holds model 'chain_2', the scenario names 'double_pendulum'",
                 MODULE_CHAIN_2)));
  CHECK_THAT(module_error(MODULE_OTHER_ABI),
             Contains(fmt::format(
                 "model module '{}' was built for module interface {}, this symdyn-sim reads {}",
                 MODULE_OTHER_ABI, runtime::model_module_abi + 1, runtime::model_module_abi)));
  // A model with closed loops: a p's rate is not the state's.
  CHECK_THAT(error_of(fmt::format(R"j({{"model": {{"name": "four_bar", "module": "{}"}},
                                        "initial": {{"qd": {{"phi": 1}}}}}})j",
                                  MODULE_FOUR_BAR)),
             Contains("/initial/qd/phi: 'phi' is an implicit dependent parameter of the closed "
                      "loops (C): its rate follows from the independent coordinates' (crank)"));
  const auto dir = testing::scratch_directory("module");
  std::ofstream(dir / "text.so") << "not a library\n";
  CHECK_THAT(
      module_error((dir / "text.so").string()),
      Contains(fmt::format("model module '{}' cannot be loaded", (dir / "text.so").string())));
  std::filesystem::remove_all(dir);
}

TEST_CASE("scenario files: a model with closed loops runs in its independent coordinates",
          "[scenario][module][loops]") {
  // The four-bar's coupler angle phi read by name (against the two-circle
  // intersection at the final crank angle), its loop's reactions as columns, and the
  // rocker's free hinge transmitting no moment once the closure's force is in.
  const std::string text = fmt::format(R"j({{
    "model": {{"name": "four_bar", "module": "{}"}},
    "initial": {{"q": {{"crank": 0.3, "phi": 0.8}}, "qd": {{"crank": 4}}}},
    "t_end": 0.5,
    "integrator": {{"name": "dopri5", "tolerance": 1e-10}},
    "outputs": ["q", "qd", {{"loop": "C"}}],
    "checks": [
      {{"name": "end phi", "value": "end(phi)", "band": [-10, 10]}},
      {{"name": "rocker hinge", "value": "maximum(abs(reaction.rocker.Mz))", "band": [0, 1e-9]}}
    ]}})j",
                                       MODULE_FOUR_BAR);
  sim::RunResult r;
  states_of(parse(text), {}, &r);
  REQUIRE(r.final.q.size() == 1);
  for (const char* column :
       {"crank", "phi", "psi", "phi_dot", "psi_dot", "reaction.C.Fx", "reaction.C.Fy"}) {
    INFO(column);
    CHECK(std::find(r.columns.begin(), r.columns.end(), column) != r.columns.end());
  }
  const double r1 = 0.1, r2 = 0.35, r3 = 0.3, d = 0.4, q0 = r.final.q(0);
  const double ax = r1 * std::cos(q0), ay = r1 * std::sin(q0);
  const double ux = d - ax, uy = -ay, e = std::hypot(ux, uy);
  const double a = (r2 * r2 - r3 * r3 + e * e) / (2 * e), h = std::sqrt(r2 * r2 - a * a);
  const double cx = ax + (a * ux - h * uy) / e, cy = ay + (a * uy + h * ux) / e;
  const double phi = std::atan2(cy - ay, cx - ax) - q0;
  REQUIRE(r.checks.size() == 2);
  CHECK(std::abs(std::remainder(r.checks[0].value - phi, 2 * std::numbers::pi)) < 1e-9);
  CHECK(r.checks[1].ok());
}

TEST_CASE("symdyn-sim runs a scenario file, a module relative to it", "[scenario][module][sim]") {
  const auto dir = testing::scratch_directory("scenario_file");
  std::filesystem::copy_file(MODULE_DOUBLE_PENDULUM, dir / "pendulum.so");
  std::ofstream(dir / "swing.json") << R"j({
    "model": {"name": "double_pendulum", "module": "pendulum.so"},
    "initial": {"q": {"theta1": -0.5}},
    "t_end": 2,
    "checks": [{"name": "start theta1", "value": "start(theta1)", "unit": "rad", "band": [-0.6, -0.4]}]
  })j";
  const auto r = testing::run_command({SYMDYN_SIM, "swing.json", "--out", "swing.csv"}, 120, dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("(201 rows of 9 columns"));
  CHECK_THAT(r.out, Contains("start theta1: -0.5 rad (expected -0.6 .. -0.4) ok"));
  CHECK(std::filesystem::exists(dir / "swing.csv"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("docs/scenarios.md: the complete example runs and passes its checks",
          "[scenario][module]") {
  // The page quotes this file (tests/docs/code_blocks.py checks it, byte for byte).
  std::string text = testing::read_text(SYMDYN_DOCS "/../tests/docs/fixtures/swing.json");
  const std::string module = "build/swing_module.so";
  REQUIRE(text.find(module) != std::string::npos);
  text.replace(text.find(module), module.size(), MODULE_DOUBLE_PENDULUM);
  const sim::RunResult r = sim::run_scenario(parse(text));
  CHECK(r.segments == 3);
  CHECK(r.rows == 501);
  CHECK(r.columns == std::vector<std::string>{
                         "t", "theta1", "theta2", "theta1_dot", "theta2_dot", "theta1_ddot",
                         "theta2_ddot", "kinetic_energy", "gravitational_energy", "elastic_energy",
                         "total_energy", "rod2.x", "rod2.y", "rod2.z", "spring.length", "tip_x"});
  REQUIRE(r.checks.size() == 2);
  for (const auto& c : r.checks) {
    INFO(c.name << " = " << c.value);
    CHECK(c.ok());
  }
}

TEST_CASE(
    "integrate_with_breakpoints: each instant once, the callback at each breakpoint, bad lists "
    "refused",
    "[scenario]") {
  runtime::MultibodySystem system(sim::make_model(sim::find_builtin("slider_crank")));
  runtime::IntegratorOptions o;
  o.output_interval = 0.1;
  std::vector<double> times;
  o.on_output = [&](const runtime::State& s, const runtime::Vector&, const runtime::Vector&) {
    times.push_back(s.t);
  };
  auto integrator = runtime::make_integrator("dopri5", o);
  std::vector<double> seen;
  // The crank stopped dead at 0.25 s: the state the next segment starts from is changed too.
  const auto stop = [&](std::size_t, runtime::State& s) {
    seen.push_back(s.t);
    s.qd.setZero();
  };
  runtime::State start = system.initial_state();
  start.qd(0) = 5.0;
  const auto run =
      runtime::integrate_with_breakpoints(*integrator, system, start, {0.25, 0.5}, 1.0, stop);
  CHECK(run.segments == 3);
  CHECK(seen == std::vector<double>{0.25, 0.5});
  // 0 .. 0.2, 0.25 (the first segment's end), 0.35, 0.45, 0.5, 0.6 .. 1.0: every instant once.
  REQUIRE(times.size() == 12);
  CHECK(times[3] == 0.25);
  CHECK(times[6] == 0.5);
  for (std::size_t k = 1; k < times.size(); ++k) CHECK(times[k] > times[k - 1]);
  CHECK(run.final.t == 1.0);
  CHECK(run.statistics.steps > 0);
  // The callback's output is restored: a plain run after it sees every instant.
  times.clear();
  integrator->integrate(system, start, 0.2);
  CHECK(times.size() == 3);
  CHECK_THROWS_WITH(
      runtime::integrate_with_breakpoints(*integrator, system, start, {0.5, 0.25}, 1.0, stop),
      "breakpoint 1 at t = 0.25: breakpoints must increase strictly inside (0, 1)");
  CHECK_THROWS_WITH(
      runtime::integrate_with_breakpoints(*integrator, system, start, {1.0}, 1.0, stop),
      "breakpoint 0 at t = 1: breakpoints must increase strictly inside (0, 1)");
}

TEST_CASE(
    "scenario files: the integrator's global_tolerance is read, and a bad one named by JSON path",
    "[scenario]") {
  const sim::Scenario s = parse(
      R"j({"model": "double_pendulum", "t_end": 0.5, "integrator": {"name": "rk4", "step": 0.01, "global_tolerance": 1e-6}})j");
  REQUIRE(s.global_tolerance);
  CHECK(*s.global_tolerance == 1e-6);
  const sim::RunResult r = sim::run_scenario(s);
  CHECK(r.global_tolerance == 1e-6);
  CHECK(r.statistics.global_tolerance_met);
  CHECK(r.statistics.global_error_estimate <= 1e-6);
  CHECK_THROWS_WITH(
      parse(
          R"j({"model": "double_pendulum", "integrator": {"name": "rk4", "step": 0.01, "global_tolerance": 0}})j"),
      "test.json: /integrator/global_tolerance: expected a number > 0, found 0");
}
