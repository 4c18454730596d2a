#pragma once
// The two problems the integrators' accuracy is measured on, shared by
// integrator_accuracy_test.cpp and bench/integrator_accuracy.cpp:
//
//   slider_crank     the free slider-crank (dependent variant) spun at 50 rad/s from
//                    crank = 0, 100 s: about 620 turns, so the crank reaches ~3 900 rad;
//   double_pendulum  the double pendulum (absolute variant) released at rest from
//                    q = (-pi/2 + 0.5, 0.5) (0.5 rad from hanging, both joints), 100 s.
//                    A swing of this size is regular (quasi-periodic): errors grow
//                    linearly in time, so a final error measures the integrator. From
//                    the horizontal release of the scenario the motion is chaotic and
//                    any error of 1e-13 grows past 1e-5 within 100 s.

#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "double_pendulum_absolute.hpp"
#include "slider_crank_dependent.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn_test::accuracy {

using symdyn::runtime::IntegratorOptions;
using symdyn::runtime::Model;
using symdyn::runtime::MultibodySystem;
using symdyn::runtime::State;
using symdyn::runtime::Statistics;

struct Problem {
  std::string name;
  std::unique_ptr<MultibodySystem> system;
  State initial;
  double t_end = 100.0;
};

inline std::vector<Problem> problems() {
  using symdyn::runtime::EquationsSource;
  std::vector<Problem> out;
  {
    Problem p{
        "slider_crank",
        std::make_unique<MultibodySystem>(Model::from<symdyn_generated::slider_crank_dependent>(),
                                          EquationsSource::emitted),
        {}};
    p.initial = p.system->initial_state();
    p.initial.q.setZero();
    p.initial.qd.setConstant(50.0);
    out.push_back(std::move(p));
  }
  {
    Problem p{
        "double_pendulum",
        std::make_unique<MultibodySystem>(Model::from<symdyn_generated::double_pendulum_absolute>(),
                                          EquationsSource::emitted),
        {}};
    p.initial = p.system->initial_state();
    p.initial.q << -std::numbers::pi / 2 + 0.5, 0.5;
    p.initial.qd.setZero();
    out.push_back(std::move(p));
  }
  return out;
}

// The final state of `integrator` at rtol = atol = tol, outputs only at t_end
// (global: IntegratorOptions::global_tolerance).
inline State solve(Problem& p, const std::string& integrator, double tol,
                   Statistics* stats = nullptr, double step = 0.0, double global = 0.0) {
  IntegratorOptions o;
  o.relative_tolerance = tol;
  o.absolute_tolerance = tol;
  o.global_tolerance = global;
  o.output_times = {p.t_end};
  o.initial_step = step;
  auto integ = symdyn::runtime::make_integrator(integrator, o);
  const State end = integ->integrate(*p.system, p.initial, p.t_end);
  if (stats != nullptr) *stats = integ->statistics();
  return end;
}

// The largest difference over q and qd.
inline double max_error(const State& a, const State& b) {
  return std::max((a.q - b.q).cwiseAbs().maxCoeff(), (a.qd - b.qd).cwiseAbs().maxCoeff());
}

}  // namespace symdyn_test::accuracy
