// models.md 4: the trike dropped from 0.5 m at 5 m/s, settling on its
// suspensions during the first second, then steered to 0.1 rad, for 5 s.
// Bodies in models.md's order: S1 chassis, S2 rear axle, S3 and S4 rear
// wheels, S5 front wheel.
//
// Headlines: the drive holds the forward speed near its 5 m/s set point, the
// chassis rides on its tyres (neither falls through the ground nor flies), and
// the steering turns the trike to the left (the yaw grows) at the steady yaw rate
// of a rolling vehicle, v·tan(delta)/wheelbase, within the tyres' slip.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "run.hpp"
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/point_forces.hpp>

#if __has_include("trike.hpp")
#include "trike.hpp"
#endif

namespace symdyn::sim {
namespace {

using runtime::Model;
using runtime::State;

std::vector<Variant> variants() {
  std::vector<Variant> v;
#if __has_include("trike.hpp")
  v.push_back({"default", &Model::from<symdyn_generated::trike>});
#endif
  return v;
}

constexpr int chassis = 0, left_wheel = 2, right_wheel = 3, front_wheel = 4;
constexpr int yaw = 3, rear_suspension = 6, axle_roll = 7, left_spin = 8, right_spin = 9, steering = 10,
              front_suspension = 11;

// Steering set point: 0 before 1 s, a ramp to 0.1 rad over 0.2 s, then 0.1.
double steering_reference(double t) {
  if (t < 1.0) return 0.0;
  if (t < 1.2) return 0.1 * (t - 1.0) / 0.2;
  return 0.1;
}

// The chassis' forward speed: the velocity of G1 along the chassis x axis.
double forward_speed(const runtime::Kinematics& k) { return k.v(chassis).dot(k.R(chassis).col(0)); }

std::vector<Channel> configure(runtime::MultibodySystem& system) {
  if (system.model().nq() != 13 || system.model().nbody() != 5) {
    throw runtime::ModelError(fmt::format("trike scenario: the model has {} coordinates and {} bodies, models.md 13 and 5",
                                          system.model().nq(), system.model().nbody()));
  }
  using runtime::CoordinateSpringDamper;
  system.add<CoordinateSpringDamper>("rear suspension", rear_suspension, 20000.0, 1500.0, -0.06);
  system.add<CoordinateSpringDamper>("rear axle roll", axle_roll, 5000.0, 200.0, 0.0);
  system.add<CoordinateSpringDamper>("front suspension", front_suspension, 15000.0, 1000.0, 0.05);
  system.add<runtime::CoordinateTracking>("steering", steering, 500.0, 50.0, steering_reference);
  system.add<runtime::UserForce>("drive", [](const State&, const runtime::Kinematics& k, runtime::Loads& loads) {
    const double torque = std::clamp(50.0 * (5.0 - forward_speed(k)), -100.0, 100.0);
    loads.add_generalized(left_spin, torque);
    loads.add_generalized(right_spin, torque);
  });
  std::vector<std::shared_ptr<runtime::SimpleTyre>> tyres;
  for (const auto& [name, body] : {std::pair{"rear left", left_wheel}, {"rear right", right_wheel}, {"front", front_wheel}}) {
    tyres.push_back(system.add<runtime::SimpleTyre>(name, body, runtime::SimpleTyreProperties{}));
  }
  std::vector<Channel> channels{
      {"forward_speed", [&system](const State& s) { return forward_speed(system.evaluate_kinematics(s)); }},
      {"steering_reference", [](const State& s) { return steering_reference(s.t); }}};
  for (std::size_t i = 0; i < tyres.size(); ++i) {
    const char* name[] = {"normal_force_rear_left", "normal_force_rear_right", "normal_force_front"};
    channels.push_back({name[i], [&system, tyre = tyres[i]](const State& s) {
                          return tyre->evaluate(system.evaluate_kinematics(s)).normal_force;
                        }});
  }
  return channels;
}

// Yaw rate of a rolling vehicle steered by delta with wheelbase l: v·tan(delta)/l.
// The wheelbase runs from the front wheel's hub (x = 1.2 in the chassis) to the
// rear axle at the suspension's static travel.
double kinematic_yaw_rate(double speed, double delta, double rear_travel) {
  const double wheelbase = 1.2 - (-0.9 - rear_travel * std::cos(std::numbers::pi / 4));
  return speed * std::tan(delta) / wheelbase;
}

std::vector<Headline> headline(const RunResult& run, runtime::MultibodySystem& system) {
  double low = run.initial().state.q(2), high = low;
  for (const auto& s : run.samples) {
    low = std::min(low, s.state.q(2));
    high = std::max(high, s.state.q(2));
  }
  const State& end = run.final().state;
  // The yaw rate one second before the end, to see that the turn is steady.
  const auto before = std::find_if(run.samples.begin(), run.samples.end(),
                                   [&](const Sample& s) { return s.state.t >= end.t - 1.0; });
  const double speed = forward_speed(system.evaluate_kinematics(end));
  const double yaw_rate = end.qd(yaw);
  return {{"final forward speed", speed, "m/s", 4.5, 5.5},
          {"yaw turned", end.q(yaw) - run.initial().state.q(yaw), "rad", 0.2, 3.0},
          {"final yaw rate / v·tan(delta)/wheelbase", yaw_rate / kinematic_yaw_rate(speed, end.q(steering), end.q(rear_suspension)),
           "", 0.9, 1.1},
          {"yaw rate change over the last second", std::abs(yaw_rate - before->state.qd(yaw)) / yaw_rate, "", 0.0, 0.02},
          {"lowest chassis height", low, "m", 0.3, 0.5},
          {"highest chassis height", high, "m", 0.5, 0.7}};
}

const Registration registration({
    .model = "trike",
    .description = "drops onto its tyres at 5 m/s, settles, then steers 0.1 rad (drive on the rear wheels)",
    .variants = variants(),
    .t_end = 5.0,
    .integrator = "cvode",
    .tolerance = 1e-6,
    .output_interval = 0.01,
    .q0 = {0, 0, 0.5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    .qd0 = {5, 0, 0, 0, 0, 0, 0, 0, 5 / 0.3, 5 / 0.3, 0, 0, 5 / 0.3},
    .configure = configure,
    .headline = headline,
});

}  // namespace
}  // namespace symdyn::sim
