// models.md 1: the double pendulum released from horizontal at rest, free
// motion for 10 s. No damping: the total energy is the headline.
#include "run.hpp"

#if __has_include("double_pendulum_absolute.hpp")
#include "double_pendulum_absolute.hpp"
#endif
#if __has_include("double_pendulum_relative.hpp")
#include "double_pendulum_relative.hpp"
#endif

namespace symdyn::sim {
namespace {

using runtime::Model;

std::vector<Variant> variants() {
  std::vector<Variant> v;
#if __has_include("double_pendulum_absolute.hpp")
  v.push_back({"absolute", &Model::from<symdyn_generated::double_pendulum_absolute>});
#endif
#if __has_include("double_pendulum_relative.hpp")
  v.push_back({"relative", &Model::from<symdyn_generated::double_pendulum_relative>});
#endif
  return v;
}

// The free end of rod 2 (l2 = 1, G at its middle), as CSV channels.
std::vector<Channel> configure(runtime::MultibodySystem& system) {
  const int rod2 = system.model().body_index("rod2");
  const auto tip = [&system, rod2](const runtime::State& s, int axis) {
    return system.evaluate_kinematics(s).point_position(rod2, runtime::Vec3(0.5, 0.0, 0.0))(axis);
  };
  return {{"tip_x", [tip](const runtime::State& s) { return tip(s, 0); }},
          {"tip_y", [tip](const runtime::State& s) { return tip(s, 1); }}};
}

// Energy is conserved: its drift relative to the largest kinetic energy
// (E(0) = 0 here) is bounded by the integration tolerance.
std::vector<Headline> headline(const RunResult& run, runtime::MultibodySystem&) {
  return {{"energy drift |E - E0| / max T", energy_drift(run).relative(), "", 0.0, energy_drift_bound(run)}};
}

const Registration registration({
    .model = "double_pendulum",
    .description = "two rods released horizontal at rest, free motion (energy conserved)",
    .variants = variants(),
    .t_end = 10.0,
    .integrator = "dopri5",
    .tolerance = 1e-10,
    .output_interval = 0.01,
    .q0 = {},
    .qd0 = {},
    .configure = configure,
    .headline = headline,
});

}  // namespace
}  // namespace symdyn::sim
