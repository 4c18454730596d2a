#pragma once
// Changes to a scenario named by a path, each putting a JSON value in place of
// the scenario's: what a sweep changes from run to run (docs/sweeps.md), and
// symdyn-sim's --set. Paths, parts joined by dots:
//
//   parameters.<name>                     a run-time parameter of the model
//   initial.q.<coordinate>                initial.qd.<coordinate>
//   variables.<name>                      a variable the scenario declares
//   forces.<element>.<member>[.<part>]*   a member of the force element of that name;
//                                         further parts index its objects and arrays
//                                         (forces.spring.a.point.1: y of the spring's point a)
//   integrator.name|tolerance|rtol|atol|step
//   t_end, output_interval
//
// integrator.tolerance replaces the scenario's rtol and atol, as the file's
// own "tolerance" would if it were alone.
//
// A path is checked against the scenario and its model when the change is
// made; an OverrideError names the path, what is wrong and the valid names:
//   forces.rear_lft.stiffness: no force element 'rear_lft' (elements: rear_suspension, ...)
// The value is checked where the scenario's own would be (by Simulation), so
// a refusal names the scenario's key: /forces/5/stiffness (force element 'rear_left').

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "scenario.hpp"
#include <symdyn/runtime/model.hpp>

namespace symdyn::sim {

// A path that names nothing of the scenario: what() is "<path>: <detail>".
class OverrideError : public ScenarioError {
 public:
  OverrideError(std::string path, std::string detail);
  const std::string& path() const { return path_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string path_, detail_;
};

struct Override {
  std::string path;
  nlohmann::json value;
};

// "path=value": the value read as JSON when it is one (2.5e5, true, [0, 1, 0],
// "text"), else as the text itself (cvode, or an expression). ScenarioError
// without '='.
Override parse_override(std::string_view assignment);

// Throws OverrideError when the path names nothing of the scenario or model.
void check_override(const Scenario& scenario, const runtime::Model& model, std::string_view path);

// The scenario with the changes made in order; `model` is the scenario's
// (make_model), against which parameter and coordinate names are checked.
// Throws OverrideError.
Scenario with_overrides(const Scenario& scenario, const runtime::Model& model,
                        const std::vector<Override>& overrides);

}  // namespace symdyn::sim
