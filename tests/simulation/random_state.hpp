#pragma once
// States of a generated model for the simulation tests (random ones, and those of
// a one-coordinate mechanism), and a matrix norm.

#include <catch2/catch.hpp>
#include <random>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::testing {

// A random state near the initial one, t in [0, 1], where the model is
// defined: small perturbations, since the dependent parameters of closed-loop
// models (amru5's acos) are defined only near the assembled configuration;
// states where the kinematics are not finite are drawn again.
inline runtime::State random_state(runtime::MultibodySystem& system, std::mt19937& rng) {
  constexpr double q_spread = 0.2, qd_spread = 2.0;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    runtime::State s = system.initial_state();  // the independent coordinates of closed loops
    s.t = 0.5 * (1.0 + u(rng));
    for (int j = 0; j < system.num_coordinates(); ++j) {
      s.q(j) += q_spread * u(rng);
      s.qd(j) += qd_spread * u(rng);
    }
    try {
      system.evaluate_kinematics(s);
      return s;
    } catch (const runtime::NumericError&) {
    }
  }
  FAIL("model " << system.model().name()
                << ": no state with finite kinematics near the initial one");
  return {};
}

// The state of a mechanism of one independent coordinate (a closed loop's crank).
inline runtime::State one_coordinate_state(double t, double q, double qd) {
  runtime::State s;
  s.t = t;
  s.q = runtime::Vector::Constant(1, q);
  s.qd = runtime::Vector::Constant(1, qd);
  return s;
}

inline double max_abs(const runtime::Matrix& a) {
  return a.size() ? a.cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace symdyn::testing
