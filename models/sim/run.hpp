#pragma once
// Running a scenario: the model of the chosen variant, its force elements,
// the chosen integrator, outputs at a fixed interval (kept in memory and
// optionally written as CSV), then the scenario's headline numbers.
//
//   const Scenario& s = find_scenario("double_pendulum");
//   RunResult r = run_scenario(s, {.t_end = 2.0});
//   fmt::print("{}", summary(r));

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "scenario.hpp"

namespace symdyn::sim {

struct RunOptions {
  std::string variant;                    // empty: the scenario's first
  std::optional<double> t_end;            // default: the scenario's
  std::string integrator;                 // empty: the scenario's
  std::optional<double> tolerance;        // relative and absolute; default: the scenario's
  std::optional<double> rtol;             // relative only, over tolerance
  std::optional<double> atol;             // absolute only, over tolerance
  std::optional<double> output_interval;  // default: the scenario's
  std::optional<double> step;             // initial (rk4, midpoint: fixed) step; their default: interval / 10
  // Emitted M and h when the model has them, else assembled from the kinematics.
  bool assembled = false;
  std::ostream* csv = nullptr;  // CSV of every output instant, if given
  // Called with every output sample as it is produced (a failed run has
  // delivered those before the failure).
  std::function<void(const Sample&)> on_sample;
  bool progress = false;        // progress bar on stderr (only drawn on a terminal)
};

struct RunResult {
  std::string model, variant, integrator, equations;
  double t_end = 0.0, tolerance = 0.0;  // tolerance: the relative one
  double absolute_tolerance = 0.0;
  std::vector<std::string> columns;  // of the CSV
  std::vector<Sample> samples;       // every output instant, t = 0 .. t_end
  runtime::Statistics statistics;
  double wall_seconds = 0.0;
  std::vector<Headline> headlines;

  const Sample& initial() const { return samples.front(); }
  const Sample& final() const { return samples.back(); }
};

// Throws OptionError (unknown variant or integrator, bad option), ModelError,
// NumericError (from the integrator, naming the time and the culprit).
RunResult run_scenario(const Scenario& scenario, const RunOptions& options = {});

// Energy bookkeeping of a run, over its samples:
//   drift = max_t |E(t) - E(0)|, scale = max(|E(0)|, max_t T(t)),
// so that a run starting at E = 0 (the double pendulum) still has a scale.
struct EnergyDrift {
  double absolute = 0.0;  // J
  double scale = 0.0;     // J
  double relative() const { return scale > 0.0 ? absolute / scale : absolute; }
};
EnergyDrift energy_drift(const RunResult& run);

// The energy drift a conservative run may show at its relative tolerance: errors
// of order tolerance per step add up over thousands of steps, hence 1e4 times
// the tolerance, and never less than 1e-6.
double energy_drift_bound(const RunResult& run);

// A few lines for the terminal: the run, the integrator's counters, the final
// state, the energy and the headline numbers with their bands.
std::string summary(const RunResult& run);

}  // namespace symdyn::sim
