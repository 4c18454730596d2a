// models.md 2: the 3-D robot (turret, arm, gripper) with a spring-damper on
// the arm extension q2, thrown from q = (0, 0.3, 0.6, 0, 0) with the turret and
// the wrist spinning, for 10 s.
//
// Headlines: the damper only dissipates (the total energy, elastic included,
// never rises between outputs), and nothing exerts a moment about the vertical
// turret axis (gravity is vertical, the spring internal, the turret joint
// free), so the angular momentum about global z is conserved.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "run.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>

#if __has_include("robot3d_absolute.hpp")
#include "robot3d_absolute.hpp"
#endif
#if __has_include("robot3d_relative.hpp")
#include "robot3d_relative.hpp"
#endif

namespace symdyn::sim {
namespace {

using runtime::Model;

std::vector<Variant> variants() {
  std::vector<Variant> v;
#if __has_include("robot3d_absolute.hpp")
  v.push_back({"absolute", &Model::from<symdyn_generated::robot3d_absolute>});
#endif
#if __has_include("robot3d_relative.hpp")
  v.push_back({"relative", &Model::from<symdyn_generated::robot3d_relative>});
#endif
  return v;
}

constexpr int extension = 2;  // q2, the arm's prismatic coordinate

std::vector<Channel> configure(runtime::MultibodySystem& system) {
  if (system.model().nq() != 5) {
    throw runtime::ModelError(fmt::format("robot3d scenario: the model has {} coordinates, models.md 5",
                                          system.model().nq()));
  }
  system.add<runtime::CoordinateSpringDamper>("arm extension", extension, 1000.0, 20.0, 0.6);
  return {{"spring_force", [](const runtime::State& s) {
             return -1000.0 * (s.q(extension) - 0.6) - 20.0 * s.qd(extension);
           }},
          {"angular_momentum_z", [&system](const runtime::State& s) { return system.momentum(s).angular(2); }}};
}

std::vector<Headline> headline(const RunResult& run, runtime::MultibodySystem& system) {
  const double scale = std::max(energy_drift(run).scale, 1.0);
  double rise = 0.0;
  for (std::size_t k = 1; k < run.samples.size(); ++k) {
    rise = std::max(rise, run.samples[k].energies.total() - run.samples[k - 1].energies.total());
  }
  const double L0 = system.momentum(run.initial().state).angular(2);
  double drift = 0.0;
  for (const auto& s : run.samples) drift = std::max(drift, std::abs(system.momentum(s.state).angular(2) - L0));
  return {{"largest energy rise between outputs / max T", rise / scale, "", 0.0, energy_drift_bound(run)},
          {"angular momentum drift about z / |L0|", drift / std::abs(L0), "", 0.0, 1e-6}};
}

const Registration registration({
    .model = "robot3d",
    .description = "turret, arm and gripper with a spring-damper on the arm extension",
    .variants = variants(),
    .t_end = 10.0,
    .integrator = "dopri5",
    .tolerance = 1e-9,
    .output_interval = 0.01,
    .q0 = {0.0, 0.3, 0.6, 0.0, 0.0},
    .qd0 = {1.0, 0.0, 0.0, 2.0, 0.0},
    .configure = configure,
    .headline = headline,
});

}  // namespace
}  // namespace symdyn::sim
