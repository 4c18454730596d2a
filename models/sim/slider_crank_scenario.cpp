// models.md 3: the slider-crank spun at 50 rad/s from q0 = 0, free motion for
// 1 s (about 7 revolutions).
//
// Headlines, from energy conservation E = 1/2 M(q0) qd0^2 + V(q0): at q0 = 0
// and pi the slider is at a dead centre (M = 5e-3 kg m^2, V = 0), so the crank
// passes there at exactly 50 rad/s, about its fastest (gravity adds a little
// just before); at q0 = pi/2 the whole linkage moves with the crank (M =
// 1.133e-2 kg m^2) and its weight is raised by 0.736 J, so it slows to
// sqrt(2 (6.25 - 0.736) / 1.133e-2) = 31.2 rad/s, near its slowest (30.5 a
// little later, where the rod's rotation adds to M).
#include <algorithm>
#include <numbers>

#include "run.hpp"

#if __has_include("slider_crank_inline.hpp")
#include "slider_crank_inline.hpp"
#endif
#if __has_include("slider_crank_dependent.hpp")
#include "slider_crank_dependent.hpp"
#endif

namespace symdyn::sim {
namespace {

using runtime::Model;

std::vector<Variant> variants() {
  std::vector<Variant> v;
#if __has_include("slider_crank_inline.hpp")
  v.push_back({"inline", &Model::from<symdyn_generated::slider_crank_inline>});
#endif
#if __has_include("slider_crank_dependent.hpp")
  v.push_back({"dependent", &Model::from<symdyn_generated::slider_crank_dependent>});
#endif
  return v;
}

// The slider's position and velocity along x.
std::vector<Channel> configure(runtime::MultibodySystem& system) {
  const int slider = system.model().body_index("slider");
  return {{"slider_x", [&system, slider](const runtime::State& s) { return system.evaluate_kinematics(s).x(slider)(0); }},
          {"slider_v", [&system, slider](const runtime::State& s) { return system.evaluate_kinematics(s).v(slider)(0); }}};
}

std::vector<Headline> headline(const RunResult& run, runtime::MultibodySystem&) {
  double lo = run.initial().state.qd(0), hi = lo;
  for (const auto& s : run.samples) {
    lo = std::min(lo, s.state.qd(0));
    hi = std::max(hi, s.state.qd(0));
  }
  const double turns = (run.final().state.q(0) - run.initial().state.q(0)) / (2.0 * std::numbers::pi);
  return {{"slowest crank speed", lo, "rad/s", 30.0, 32.5},
          {"fastest crank speed", hi, "rad/s", 50.0, 51.0},
          {"crank revolutions", turns, "", 5.0, 8.0},
          {"energy drift |E - E0| / max T", energy_drift(run).relative(), "", 0.0, energy_drift_bound(run)}};
}

const Registration registration({
    .model = "slider_crank",
    .description = "crank spun at 50 rad/s from q0 = 0, free motion",
    .variants = variants(),
    .t_end = 1.0,
    .integrator = "dopri5",
    .tolerance = 1e-10,
    .output_interval = 1e-3,
    .q0 = {0.0},
    .qd0 = {50.0},
    .configure = configure,
    .headline = headline,
});

}  // namespace
}  // namespace symdyn::sim
