#include "run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/progress_bar.hpp>

namespace symdyn::sim {

namespace {

using runtime::EquationsSource;
using runtime::MultibodySystem;
using runtime::State;

// The scenario's initial state, or the model's when the scenario has none.
State initial_state(const Scenario& scenario, const MultibodySystem& system) {
  State s = system.initial_state();
  const auto set = [&](const std::vector<double>& values, runtime::Vector& into, const char* what) {
    if (values.empty()) return;
    if (static_cast<Eigen::Index>(values.size()) != into.size()) {
      throw runtime::ModelError(fmt::format("scenario '{}': {} has {} entries, the model has {} coordinates",
                                            scenario.model, what, values.size(), into.size()));
    }
    for (std::size_t j = 0; j < values.size(); ++j) into(static_cast<Eigen::Index>(j)) = values[j];
  };
  set(scenario.q0, s.q, "q0");
  set(scenario.qd0, s.qd, "qd0");
  return s;
}

runtime::IntegratorOptions integrator_options(const Scenario& scenario, const RunOptions& options,
                                              const std::string& integrator) {
  runtime::IntegratorOptions o;
  const double tolerance = options.tolerance.value_or(scenario.tolerance);
  o.relative_tolerance = options.rtol.value_or(tolerance);
  o.absolute_tolerance = options.atol.value_or(tolerance);
  o.output_interval = options.output_interval.value_or(scenario.output_interval);
  if (options.step) {
    o.initial_step = *options.step;
  } else if (integrator == "rk4" || integrator == "midpoint") {
    o.initial_step = o.output_interval / 10.0;
  }
  return o;
}

}  // namespace

RunResult run_scenario(const Scenario& scenario, const RunOptions& options) {
  const Variant& variant =
      options.variant.empty() ? scenario.variants.front() : scenario.variant(options.variant);
  runtime::Model model = variant.make();
  const bool emitted = !options.assembled && model.has_equations_of_motion();
  MultibodySystem system(std::move(model), emitted ? EquationsSource::emitted : EquationsSource::assembled);
  const std::vector<Channel> channels = scenario.configure ? scenario.configure(system) : std::vector<Channel>{};

  RunResult r;
  r.model = scenario.model;
  r.variant = variant.name;
  r.integrator = options.integrator.empty() ? scenario.integrator : options.integrator;
  r.equations = emitted ? "emitted" : "assembled";
  r.t_end = options.t_end.value_or(scenario.t_end);
  r.tolerance = options.rtol.value_or(options.tolerance.value_or(scenario.tolerance));
  r.absolute_tolerance = options.atol.value_or(options.tolerance.value_or(scenario.tolerance));

  std::unique_ptr<runtime::CsvRecorder> csv;
  std::ostringstream unused;
  csv = std::make_unique<runtime::CsvRecorder>(options.csv != nullptr ? *options.csv : unused, system);
  for (const auto& c : channels) csv->add_channel(c.name, c.value);
  r.columns = csv->columns();

  runtime::IntegratorOptions o = integrator_options(scenario, options, r.integrator);
  o.on_output = [&](const State& s, const runtime::Vector&, const runtime::Vector&) {
    r.samples.push_back({s, system.energies(s)});
    if (options.on_sample) options.on_sample(r.samples.back());
    if (options.csv != nullptr) csv->write(s);
  };
  runtime::ProgressBar bar;
  if (options.progress) o.on_progress = bar.callback();
  auto integrator = runtime::make_integrator(r.integrator, o);

  const auto start = std::chrono::steady_clock::now();
  integrator->integrate(system, initial_state(scenario, system), r.t_end);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bar.finish();
  r.statistics = integrator->statistics();
  if (scenario.headline) r.headlines = scenario.headline(r, system);
  return r;
}

EnergyDrift energy_drift(const RunResult& run) {
  EnergyDrift d;
  const double e0 = run.initial().energies.total();
  d.scale = std::abs(e0);
  for (const auto& s : run.samples) {
    d.absolute = std::max(d.absolute, std::abs(s.energies.total() - e0));
    d.scale = std::max(d.scale, s.energies.kinetic);
  }
  return d;
}

double energy_drift_bound(const RunResult& run) { return std::max(1e-6, 1e4 * run.tolerance); }

std::string summary(const RunResult& run) {
  const auto& st = run.statistics;
  const std::string tolerance =
      run.tolerance == run.absolute_tolerance
          ? fmt::format("tolerance {:g}", run.tolerance)
          : fmt::format("rtol {:g}, atol {:g}", run.tolerance, run.absolute_tolerance);
  std::string out = fmt::format("{} ({}, {} equations), {} at {}, t = 0 .. {:g} s\n", run.model, run.variant,
                                run.equations, run.integrator, tolerance, run.t_end);
  out += fmt::format("  steps {} (rejected {}), evaluations: {} accelerations, {} residuals, {} Jacobians; {:.3f} s\n",
                     st.steps, st.rejected_steps, st.rhs_evaluations, st.residual_evaluations,
                     st.jacobian_evaluations, run.wall_seconds);
  const State& s = run.final().state;
  const auto n = s.q.size();
  std::string q, qd;
  for (Eigen::Index j = 0; j < n; ++j) {
    const auto& name = run.columns[static_cast<std::size_t>(1 + j)];
    q += fmt::format("{}{} = {:.6f}", j ? ", " : "", name, s.q(j));
    qd += fmt::format("{}{}_dot = {:.6f}", j ? ", " : "", name, s.qd(j));
  }
  out += fmt::format("  final state at t = {:g}: {}\n                        {}\n", s.t, q, qd);
  const EnergyDrift d = energy_drift(run);
  out += fmt::format("  energy: initial {:.9g} J, final {:.9g} J, max |E - E0| = {:.3g} J ({:.3g} of {:.4g} J)\n",
                     run.initial().energies.total(), run.final().energies.total(), d.absolute, d.relative(),
                     d.scale);
  for (const auto& h : run.headlines) {
    out += fmt::format("  {}: {:.6g} {} (expected {:g} .. {:g}) {}\n", h.name, h.value, h.unit, h.low, h.high,
                       h.ok() ? "ok" : "OUT OF RANGE");
  }
  return out;
}

}  // namespace symdyn::sim
