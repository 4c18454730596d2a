#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "fixtures/double_pendulum.hpp"
#include "fixtures/rigid_body.hpp"
#include "fixtures/spring_mass.hpp"
#include "test_util.hpp"
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

using namespace symdyn::runtime;
using namespace symdyn::runtime::test;
namespace fx = symdyn_fixtures;

TEST_CASE("Kinetic energy of a body whose inertia axes are not aligned", "[runtime][energy]") {
  MultibodySystem rb(Model::from<fx::rigid_body>());
  const Eigen::DiagonalMatrix<double, 3> I(0.1, 0.2, 0.25);
  int misaligned = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Vector q = random_vector(6, -1.5, 1.5);
    q(4) = uniform(-1.2, 1.2);
    const State s = make_state(0, q, random_vector(6, -3, 3));
    // Hand computation in body axes: w_b = R^T w with w from the Cardan rates.
    const Mat3 R =
        fx::rigid_body::rot(2, q(3)) * fx::rigid_body::rot(1, q(4)) * fx::rigid_body::rot(0, q(5));
    const Vec3 w = fx::rigid_body::axes(q.data()) * s.qd.tail(3);
    const Vec3 wb = R.transpose() * w;
    const Vec3 v = s.qd.head(3);
    const double T = 0.5 * 2.0 * v.squaredNorm() + 0.5 * wb.dot(I * wb);
    const Energies e = rb.energies(s);
    CHECK(e.kinetic == Approx(T).epsilon(1e-13));
    CHECK(e.gravitational == Approx(2.0 * 9.81 * q(2)).epsilon(1e-13).margin(1e-13));
    // EasyDyn's unrotated formula differs for such bodies: the test can fail.
    const double easydyn = 0.5 * 2.0 * v.squaredNorm() + 0.5 * w.dot(I * w);
    if (std::abs(easydyn - T) > 1e-3 * T) ++misaligned;
    // Momentum about the origin: p = m v, L = x x m v + R I R^T w.
    const Momentum p = rb.momentum(s);
    CHECK((p.linear - 2.0 * v).norm() < 1e-14);
    const Vec3 L = Vec3(q.head(3)).cross(2.0 * v) + R * (I * wb);
    CHECK((p.angular - L).norm() < 1e-13);
  }
  CHECK(misaligned > 150);
}

TEST_CASE("Double pendulum energy: closed form and conservation", "[runtime][energy]") {
  MultibodySystem dp(Model::from<fx::double_pendulum_absolute>());
  Vector qdd, yd;
  for (int trial = 0; trial < 200; ++trial) {
    const State s = make_state(0, random_vector(2, -4, 4), random_vector(2, -4, 4));
    const Lagrange L = double_pendulum_lagrange(s.q, s.qd);
    const Energies e = dp.energies(s);
    CHECK(e.kinetic == Approx(0.5 * s.qd.dot(L.M * s.qd)).epsilon(1e-13));
    const double y1 = 0.5 * std::sin(s.q(0));
    const double y2 = std::sin(s.q(0)) + 0.5 * std::sin(s.q(0) + s.q(1));
    CHECK(e.gravitational == Approx(9.81 * (y1 + y2)).margin(1e-13));
    // dE/dt = 0 along the free motion (central difference, O(h^2)).
    dp.accelerations(s, qdd, yd);
    const double h = 1e-4;
    auto energy_at = [&](double sign) {
      State p = s;
      p.q = s.q + sign * h * s.qd + 0.5 * h * h * qdd;
      p.qd = s.qd + sign * h * qdd;
      return dp.energies(p).total();
    };
    CHECK(std::abs(energy_at(1) - energy_at(-1)) / (2 * h) < 1e-5 * (1 + s.qd.squaredNorm()));
  }
}

TEST_CASE("Elastic energy of springs is part of the total", "[runtime][energy]") {
  MultibodySystem sm(Model::from<fx::spring_mass>());
  const double k = 4.0 * std::numbers::pi * std::numbers::pi;
  sm.add<PointSpringDamper>("spring", BodyPoint{ground, Vec3::Zero()}, BodyPoint{0, Vec3::Zero()},
                            k, 2.0);
  sm.add<CoordinateSpringDamper>("stop", 0, 5.0, 0.0, 0.5);
  const State s = make_state(0, Vector::Constant(1, 1.4), Vector::Constant(1, 0.8));
  const Energies e = sm.energies(s);
  CHECK(e.kinetic == Approx(0.5 * 0.8 * 0.8));
  CHECK(e.gravitational == Approx(k * 1.4));  // -m x.g with g = -k u, x = q u
  CHECK(e.elastic == Approx(0.5 * k * 0.6 * 0.6 + 0.5 * 5.0 * 0.9 * 0.9));
  CHECK(e.total() == Approx(e.kinetic + e.gravitational + e.elastic));
}
