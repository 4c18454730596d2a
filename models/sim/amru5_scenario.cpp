// models.md 5: the six-legged walker on foot contacts, its leg coordinates
// driven by PD actuators along a tripod gait (legs {0, 3, 4} in phase, {1, 2,
// 5} half a period later), for 10 s. Feet are the bodies whose name contains
// "foot", in leg order.
//
// Headlines: the main body stays up on its legs (height, roll and pitch
// bounded) and advances in both halves of the run. Channels: the body's height
// and each foot's normal force (0 while the foot is in the air).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "run.hpp"
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>

#if __has_include("amru5_inline.hpp")
#include "amru5_inline.hpp"
#endif
#if __has_include("amru5_dependent.hpp")
#include "amru5_dependent.hpp"
#endif

namespace symdyn::sim {
namespace {

using runtime::Model;
using runtime::State;

std::vector<Variant> variants() {
  std::vector<Variant> v;
#if __has_include("amru5_inline.hpp")
  v.push_back({"inline", &Model::from<symdyn_generated::amru5_inline>});
#endif
#if __has_include("amru5_dependent.hpp")
  v.push_back({"dependent", &Model::from<symdyn_generated::amru5_dependent>});
#endif
  return v;
}

constexpr int legs = 6;
constexpr double omega = 2.0 * std::numbers::pi * 0.5;  // gait frequency, rad/s

// Leg k: yaw, vertical and horizontal slider coordinates; hips with hy > 0
// (k even) are left legs.
int yaw_of(int k) { return 6 + 3 * k; }
int v_of(int k) { return 7 + 3 * k; }
int h_of(int k) { return 8 + 3 * k; }
double side(int k) { return k % 2 == 0 ? 1.0 : -1.0; }
double phase(int k) { return (k == 0 || k == 3 || k == 4) ? 0.0 : std::numbers::pi; }

std::vector<int> feet(const Model& m) {
  std::vector<int> out;
  for (int i = 0; i < m.nbody(); ++i) {
    if (m.body_names()[static_cast<std::size_t>(i)].find("foot") != std::string::npos) out.push_back(i);
  }
  if (out.size() != legs) {
    throw runtime::ModelError(fmt::format("amru5 scenario: {} bodies named '*foot*', expected {}", out.size(), legs));
  }
  return out;
}

std::vector<Channel> configure(runtime::MultibodySystem& system) {
  if (system.model().nq() != 6 + 3 * legs) {
    throw runtime::ModelError(
        fmt::format("amru5 scenario: the model has {} coordinates, models.md 24", system.model().nq()));
  }
  runtime::ContactProperties ground;
  ground.stiffness = 1e5;
  ground.damping = 1e3;
  ground.friction = 0.8;
  ground.slip_speed = 0.01;
  ground.regularization = runtime::FrictionRegularization::smooth;
  const std::vector<int> foot = feet(system.model());
  std::vector<Channel> channels{{"body_height", [](const State& s) { return s.q(2); }}};
  for (int k = 0; k < legs; ++k) {
    auto contact = system.add<runtime::PlaneContact>(fmt::format("foot {}", k), foot[static_cast<std::size_t>(k)],
                                                     runtime::Vec3::Zero(), 0.0, runtime::Plane{}, ground);
    channels.push_back({fmt::format("foot_{}_normal_force", k), [&system, contact](const State& s) {
                          return contact->evaluate(system.evaluate_kinematics(s)).normal_force;
                        }});
    const double s = side(k), phi = phase(k);
    system.add<runtime::CoordinateTracking>(fmt::format("leg {} yaw", k), yaw_of(k), 500.0, 20.0,
                                            [s, phi](double t) { return s * 0.2 * std::sin(omega * t + phi); });
    system.add<runtime::CoordinateTracking>(fmt::format("leg {} lift", k), v_of(k), 20000.0, 500.0,
                                            [phi](double t) { return 0.04 * std::max(0.0, std::cos(omega * t + phi)); });
    system.add<runtime::CoordinateSpringDamper>(fmt::format("leg {} reach", k), h_of(k), 20000.0, 500.0, 0.35);
  }
  return channels;
}

// The gait moves each stance foot towards +x relative to the main body (the
// yaw of a left leg turns its foot forwards while the foot is down, v_ref = 0,
// and backwards while it is lifted), so the body advances towards -x.
std::vector<Headline> headline(const RunResult& run, runtime::MultibodySystem&) {
  double low = run.initial().state.q(2), high = low, tilt = 0.0;
  for (const auto& s : run.samples) {
    low = std::min(low, s.state.q(2));
    high = std::max(high, s.state.q(2));
    tilt = std::max({tilt, std::abs(s.state.q(4)), std::abs(s.state.q(5))});
  }
  const State& start = run.initial().state;
  const State& end = run.final().state;
  // Half-way through, so that a body that stopped walking shows.
  const State& middle = run.samples[run.samples.size() / 2].state;
  return {{"lowest body height", low, "m", 0.3, 0.62},
          {"highest body height", high, "m", 0.62, 0.8},
          {"largest roll or pitch", tilt, "rad", 0.0, 0.3},
          {"advance along -x, first half", start.q(0) - middle.q(0), "m", 0.01, 1.0},
          {"advance along -x, second half", middle.q(0) - end.q(0), "m", 0.01, 1.0}};
}

std::vector<double> initial_q() {
  std::vector<double> q(6 + 3 * legs, 0.0);
  q[2] = 0.62;
  for (int k = 0; k < legs; ++k) q[static_cast<std::size_t>(h_of(k))] = 0.35;
  return q;
}

const Registration registration({
    .model = "amru5",
    .description = "six legs on foot contacts, PD actuators along a tripod gait",
    .variants = variants(),
    .t_end = 10.0,
    .integrator = "cvode",
    .tolerance = 1e-6,
    .output_interval = 0.01,
    .q0 = initial_q(),
    .qd0 = {},
    .configure = configure,
    .headline = headline,
});

}  // namespace
}  // namespace symdyn::sim
