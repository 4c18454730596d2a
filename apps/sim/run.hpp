#pragma once
// Running a scenario (scenario.hpp): the model, its force elements, events
// (the integration stops exactly at each and restarts), the chosen
// integrator, rows written as they are produced (CSV), and the checks,
// computed by accumulators as the run goes: memory does not grow with the
// run's length.
//
//   Simulation sim(find_builtin("double_pendulum"), {.t_end = 2.0});  // every name resolved here
//   RunResult r = sim.run();
//   fmt::print("{}", summary(r));

#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "scenario.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::sim {

struct RunOptions {
  std::string variant;                    // empty: the scenario's, else the model's first
  std::optional<double> t_end;            // default: the scenario's
  std::string integrator;                 // empty: the scenario's
  std::optional<double> tolerance;        // relative and absolute; default: the scenario's
  std::optional<double> rtol;             // relative only, over tolerance
  std::optional<double> atol;             // absolute only, over tolerance
  std::optional<double> output_interval;  // default: the scenario's
  // The initial step; rk4 and midpoint: the fixed step, required (a default from the
  // output interval would make the interval change the result).
  std::optional<double> step;
  std::optional<double> global_tolerance;  // default: the scenario's, else none (0)
  // Emitted M and h when the model has them, else assembled from the kinematics.
  bool assembled = false;
  std::ostream* csv = nullptr;  // CSV of every output instant, if given
  // Called with every output instant as it is produced (a failed run has
  // delivered those before the failure), qdd (nq) included.
  std::function<void(const runtime::State& s, const runtime::Vector& qdd)> on_sample;
  bool progress = false;  // progress bar on stderr (only drawn on a terminal)
};

// A number that characterizes a run, and the band [low, high] it should be in.
struct Check {
  std::string name;
  double value = 0.0;
  std::string unit;
  double low = 0.0, high = 0.0;
  bool ok() const { return value >= low && value <= high; }
};

// Energy bookkeeping of a run: drift = max_t |E(t) - E(0)|,
// scale = max(|E(0)|, max_t T(t)), so that a run starting at E = 0 (the double
// pendulum) still has a scale.
struct EnergyDrift {
  double initial = 0.0, final = 0.0;  // J
  double absolute = 0.0;              // J
  double scale = 0.0;                 // J
  double relative() const { return scale > 0.0 ? absolute / scale : absolute; }
};

struct RunResult {
  std::string model, variant, integrator, equations;
  double t_end = 0.0;
  double relative_tolerance = 0.0;
  double absolute_tolerance = 0.0;
  double global_tolerance = 0.0;         // 0: none asked (statistics.global_error_estimate is NaN)
  std::vector<std::string> columns;      // of the CSV
  std::vector<std::string> coordinates;  // the model's q names
  long rows = 0;                         // output instants, t = 0 .. t_end, each once
  int segments = 0;                      // integrations: 1 + the event times
  runtime::State initial, final;
  EnergyDrift energy;
  runtime::Statistics statistics;  // summed over the segments
  std::string jacobians;           // how they were computed (MultibodySystem::jacobian_method)
  double wall_seconds = 0.0;
  std::vector<Check> checks;
  std::vector<double> values;  // of Simulation::keep, in the order asked
  // The system's warnings (MultibodySystem::warnings: a mass matrix that lost
  // half its digits), each once, with its time.
  std::vector<std::string> warnings;
};

class Simulation {
 public:
  // Builds the run: every name of the scenario is resolved and every option
  // checked here (ScenarioError, OptionError naming the culprit), before a
  // row is written.
  Simulation(const Scenario& scenario, const RunOptions& options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Rows the run will write: t_end / interval, plus one per event time.
  double expected_rows() const;
  // The system the run integrates (its model draws an animation's scene).
  runtime::MultibodySystem& system();
  // A number to compute as the run goes, written as a check's value is (a
  // statistic of the outputs' names: "maximum(q2)", "at(chassis.ux, 2)");
  // RunResult::values gives it. Throws ScenarioError at `value`'s key.
  void keep(const Node& value);
  // Throws NumericError (from the integrator, naming the time and the culprit).
  RunResult run();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

RunResult run_scenario(const Scenario& scenario, const RunOptions& options = {});

// A few lines for the terminal: the run, the integrator's counters, the final
// state, the energy and the checks with their bands.
std::string summary(const RunResult& run);

}  // namespace symdyn::sim
