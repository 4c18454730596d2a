#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "fixtures/double_pendulum.hpp"
#include "fixtures/rigid_body.hpp"
#include "fixtures/spring_mass.hpp"
#include "test_util.hpp"
#include "trike.hpp"
#include <symdyn/runtime/bushing.hpp>
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

using namespace symdyn::runtime;
using namespace symdyn::runtime::test;
using Catch::Matchers::Contains;
namespace fx = symdyn_fixtures;

namespace {

State random_body_state() {
  Vector q = random_vector(6, -1.0, 1.0);
  q(4) = uniform(-1.2, 1.2);
  return make_state(uniform(0, 2), q, random_vector(6, -2.0, 2.0));
}

Mat3 body_rotation(const Vector& q) {
  return fx::rigid_body::rot(2, q(3)) * fx::rigid_body::rot(1, q(4)) * fx::rigid_body::rot(0, q(5));
}

// Generalized forces of the elements alone (gravity excluded).
Vector generalized(MultibodySystem& sys, const State& s) {
  Vector Q;
  sys.applied_forces(s, Q);
  return Q;
}

// Velocity of the body point p (body coordinates) of the rigid body fixture
// with rates qd, from the closed form x + R p.
Vec3 point_velocity(const Vector& q, const Vector& qd, const Vec3& p) {
  const Vec3 w = fx::rigid_body::axes(q.data()) * qd.tail(3);
  return Vec3(qd.head(3)) + w.cross(body_rotation(q) * p);
}

}  // namespace

TEST_CASE("A force at a point is reduced to G exactly", "[runtime][forces]") {
  // Loads: F at G and the moment (P - G) x F.
  Model m = Model::from<fx::rigid_body>();
  MultibodySystem sys(m);
  const Vec3 p(0.3, -0.2, 0.5), F(1.0, 2.0, -3.0), T(0.1, 0.0, 0.2);
  sys.add<PointLoad>("load", BodyPoint{0, p}, F, T);
  for (int trial = 0; trial < 200; ++trial) {
    const State s = random_body_state();
    const Vector Q = generalized(sys, s);
    const Mat3 R = body_rotation(s.q);
    CHECK((sys.loads().F.col(0) - F).norm() < 1e-15);
    CHECK((sys.loads().M.col(0) - ((R * p).cross(F) + T)).norm() < 1e-14);
    // Virtual power: Q_j = F . v_P(qd = e_j) + T . w(qd = e_j).
    for (int j = 0; j < 6; ++j) {
      const Vector e = Vector::Unit(6, j);
      const Vec3 wj = fx::rigid_body::axes(s.q.data()) * e.tail(3);
      CHECK(Q(j) == Approx(F.dot(point_velocity(s.q, e, p)) + T.dot(wj)).margin(1e-13));
    }
  }
}

TEST_CASE("Point loads and user forces as functions of time and state", "[runtime][forces]") {
  MultibodySystem sys(Model::from<fx::spring_mass>());
  sys.add<PointLoad>("pulse", BodyPoint{0, Vec3::Zero()},
                     [](const State& s, const Kinematics&, Vec3& f, Vec3&) {
                       f = Vec3(3.0, 0.0, 0.0) * std::sin(s.t) * s.q(0);
                     });
  sys.add<UserForce>("drag", [](const State& s, const Kinematics& k, Loads& l) {
    l.add_force(0, -0.5 * k.v(0));
    l.add_generalized(0, s.t);
  });
  const State s = make_state(0.7, Vector::Constant(1, 2.0), Vector::Constant(1, 1.5));
  // u = (1, 2, 2)/3: the pulse projects with u_x, the drag gives -0.5 qd.
  CHECK(generalized(sys, s)(0) == Approx(3.0 * std::sin(0.7) * 2.0 / 3.0 - 0.5 * 1.5 + 0.7));
}

TEST_CASE("A point load's law with its derivatives makes its part of the Jacobians exact",
          "[runtime][forces]") {
  // On the trike's front wheel: F = (3 q_yaw + 2 v_x qd_steer, 5 sin(t) qd_travel, 0) and
  // T = (0, 0, 2 q_steer), their derivatives by hand (v_x of the wheel's G).
  constexpr int yaw = 3, travel = 6, steer = 10, wheel = 4;
  const PointLoad::Law law = [](const State& s, const Kinematics& k, Vec3& f, Vec3& t) {
    f = Vec3(3.0 * s.q(yaw) + 2.0 * k.v(wheel)(0) * s.qd(steer), 5.0 * std::sin(s.t) * s.qd(travel),
             0.0);
    t = Vec3(0.0, 0.0, 2.0 * s.q(steer));
  };
  const PointLoad::LawDerivatives derivatives = [law](const State& s, const Kinematics& k,
                                                      const KinematicsDerivatives& dk, Vec3& f,
                                                      Vec3& t, Matrix& dW_dq, Matrix& dW_dqd) {
    law(s, k, f, t);
    for (int c = 0; c < k.nq(); ++c) {
      dW_dq(0, c) += 2.0 * dk.dv_dq(wheel, c)(0) * s.qd(steer);
      dW_dqd(0, c) += 2.0 * k.dv_dqd(wheel, c)(0) * s.qd(steer);
    }
    dW_dq(0, yaw) += 3.0;
    dW_dqd(0, steer) += 2.0 * k.v(wheel)(0);
    dW_dqd(1, travel) += 5.0 * std::sin(s.t);
    dW_dq(5, steer) += 2.0;
  };
  MultibodySystem exact(Model::from<symdyn_generated::trike>());
  MultibodySystem differenced(Model::from<symdyn_generated::trike>());
  const BodyPoint at{wheel, Vec3(0.1, -0.05, 0.2)};
  exact.add<PointLoad>("push", at, law, derivatives);
  differenced.add<PointLoad>("push", at, law);
  CHECK(exact.jacobian_method() == "exact (emitted derivatives)");
  CHECK(differenced.jacobian_method() ==
        "exact (emitted derivatives), but by central differences for load 'push'");
  for (int trial = 0; trial < 5; ++trial) {
    State s = exact.initial_state();
    s.t = uniform(0.0, 2.0);
    s.q += random_vector(13, -0.3, 0.3);
    s.qd = random_vector(13, -2.0, 2.0);
    Vector qdd, yd;
    exact.accelerations(s, qdd, yd);
    Matrix M, C, K, Md, Cd, Kd;
    exact.jacobians(s, qdd, M, C, K);
    differenced.jacobians(s, qdd, Md, Cd, Kd);
    const double scale = std::max({1.0, Kd.cwiseAbs().maxCoeff(), Cd.cwiseAbs().maxCoeff()});
    CHECK((K - Kd).cwiseAbs().maxCoeff() < 1e-7 * scale);
    CHECK((C - Cd).cwiseAbs().maxCoeff() < 1e-7 * scale);
  }
}

TEST_CASE("Generalized spring-dampers, nonlinear laws and tracking", "[runtime][forces]") {
  MultibodySystem sys(Model::from<fx::double_pendulum_absolute>());
  sys.add<CoordinateSpringDamper>("k0", 0, 100.0, 5.0, 0.25);
  sys.add<CoordinateForce>("cubic", 1, [](double, double q, double qd, const State&) {
    return -40.0 * q * q * q - 2.0 * qd * std::abs(qd);
  });
  // The trike's steering: Q = -500 (q - delta_ref(t)) - 50 qd.
  auto delta_ref = [](double t) { return t < 1.0 ? 0.0 : t < 1.2 ? 0.1 * (t - 1.0) / 0.2 : 0.1; };
  sys.add<CoordinateTracking>("steer", 1, 500.0, 50.0, delta_ref);
  Vector q(2), qd(2);
  q << 0.5, -0.3;
  qd << 0.2, -1.1;
  const Vector Q = generalized(sys, make_state(1.1, q, qd));
  CHECK(Q(0) == Approx(-100.0 * 0.25 - 5.0 * 0.2));
  CHECK(Q(1) == Approx(-40.0 * -0.027 - 2.0 * -1.1 * 1.1 - 500.0 * (-0.3 - 0.05) - 50.0 * -1.1));
}

TEST_CASE("Point-to-point spring-damper", "[runtime][forces]") {
  SECTION("along the spring-mass direction: Q = -k (q - L0) - c qd") {
    MultibodySystem sys(Model::from<fx::spring_mass>());
    sys.add<PointSpringDamper>("s", BodyPoint{ground, Vec3::Zero()}, BodyPoint{0, Vec3::Zero()},
                               7.0, 2.0, 0.3);
    for (double q : {0.5, 1.0, 3.0}) {
      CHECK(generalized(sys, make_state(0, Vector::Constant(1, q), Vector::Constant(1, -0.4)))(0) ==
            Approx(-7.0 * (q - 2.0) - 0.3 * -0.4));
    }
  }
  SECTION("between two rods: loads by hand and Q = -dV/dq") {
    MultibodySystem sys(Model::from<fx::double_pendulum_absolute>());
    const Vec3 pa(0.2, 0.05, 0.0), pb(-0.3, 0.1, 0.0);
    const double k = 30.0, L0 = 0.4;
    auto spring = sys.add<PointSpringDamper>("link", BodyPoint{0, pa}, BodyPoint{1, pb}, k, L0);
    auto points = [&](const Vector& q) {
      const Mat3 R1 = Eigen::AngleAxisd(q(0), Vec3::UnitZ()).toRotationMatrix();
      const Mat3 R2 = Eigen::AngleAxisd(q(0) + q(1), Vec3::UnitZ()).toRotationMatrix();
      const Vec3 x1 = R1 * Vec3(0.5, 0, 0), x2 = R1 * Vec3(1.0, 0, 0) + R2 * Vec3(0.5, 0, 0);
      return std::pair<Vec3, Vec3>{x1 + R1 * pa, x2 + R2 * pb};
    };
    auto energy = [&](const Vector& q) {
      const auto [A, B] = points(q);
      return 0.5 * k * ((B - A).norm() - L0) * ((B - A).norm() - L0);
    };
    for (int trial = 0; trial < 100; ++trial) {
      const State s = make_state(0, random_vector(2, -3, 3), Vector::Zero(2));
      const Vector Q = generalized(sys, s);
      const auto [A, B] = points(s.q);
      const double L = (B - A).norm();
      const Vec3 F = -k * (L - L0) * (B - A) / L;  // on rod 2
      const Kinematics& kin = sys.kinematics();
      CHECK((sys.loads().F.col(1) - F).norm() < 1e-12);
      CHECK((sys.loads().F.col(0) + F).norm() < 1e-12);
      CHECK((sys.loads().M.col(1) - (B - kin.x(1)).cross(F)).norm() < 1e-12);
      CHECK(spring->potential_energy(s, kin) == Approx(energy(s.q)));
      for (int j = 0; j < 2; ++j) {
        const double h = 1e-6;
        const Vector e = Vector::Unit(2, j) * h;
        const double dV = (energy(s.q + e) - energy(s.q - e)) / (2 * h);
        CHECK(Q(j) == Approx(-dV).margin(1e-6));
      }
    }
  }
  SECTION("coincident points are a NumericError") {
    MultibodySystem sys(Model::from<fx::spring_mass>());
    sys.add<PointSpringDamper>("s", BodyPoint{ground, Vec3::Zero()}, BodyPoint{0, Vec3::Zero()},
                               7.0, 2.0);
    CHECK_THROWS_WITH(generalized(sys, make_state(0.25, Vector::Zero(1), Vector::Zero(1))),
                      "t = 0.25: spring 's': its two points coincide (direction undefined)");
  }
}

TEST_CASE("Cardan angles round-trip in every axis order", "[runtime][forces]") {
  for (const char* order : {"xyz", "xzy", "yxz", "yzx", "zxy", "zyx"}) {
    const CardanOrder o = CardanOrder::parse(order);
    for (int trial = 0; trial < 200; ++trial) {
      const Vec3 a(uniform(-3, 3), uniform(-1.5, 1.5), uniform(-3, 3));
      const Mat3 R = cardan_rotation(o, a);
      CHECK((cardan_angles(o, R) - a).norm() < 1e-9);
      // E maps angle rates to the angular velocity: skew(w) = dR/dt R^T.
      const Vec3 rates(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const double h = 1e-6;
      const Mat3 dR =
          (cardan_rotation(o, a + h * rates) - cardan_rotation(o, a - h * rates)) / (2 * h);
      const Mat3 W = dR * R.transpose();
      const Vec3 w(W(2, 1), W(0, 2), W(1, 0));
      CHECK((cardan_rate_matrix(o, a) * rates - w).norm() < 1e-8);
    }
  }
  CHECK_THROWS_WITH(CardanOrder::parse("xxz"), "Cardan order 'xxz': the three axes must differ");
  CHECK_THROWS_WITH(CardanOrder::parse("xyw"), "Cardan order 'xyw': axes must be x, y or z");
}

TEST_CASE("Bushing between the ground and a body", "[runtime][forces]") {
  BushingProperties p;
  p.stiffness = Vec3(100, 200, 300);
  p.damping = Vec3(1, 2, 3);
  p.rotational_stiffness = Vec3(10, 20, 30);
  p.rotational_damping = Vec3(0.1, 0.2, 0.3);
  p.preload_force = Vec3(5, 0, 0);
  p.preload_torque = Vec3(0, 0, 0.5);
  SECTION("translation without rotation, applied at the mid-point") {
    MultibodySystem sys(Model::from<fx::rigid_body>());
    // Frame B at the body point (0.1, 0, 0); frame A on the ground at (0, 0, 1).
    sys.add<Bushing>("mount", BodyFrame{ground, Vec3(0, 0, 1)}, BodyFrame{0, Vec3(0.1, 0, 0)}, p);
    Vector q(6), qd(6);
    q << 0.02, -0.01, 1.03, 0, 0, 0;
    qd << 0.5, 0.0, -0.2, 0, 0, 0;
    generalized(sys, make_state(0, q, qd));
    const Vec3 d(0.12, -0.01, 0.03), dd(0.5, 0.0, -0.2);
    const Vec3 F = p.preload_force - p.stiffness.cwiseProduct(d) - p.damping.cwiseProduct(dd);
    const Vec3 mid = 0.5 * (Vec3(0, 0, 1) + Vec3(0.12, -0.01, 1.03));
    CHECK((sys.loads().F.col(0) - F).norm() < 1e-12);
    CHECK((sys.loads().M.col(0) - ((mid - Vec3(0.02, -0.01, 1.03)).cross(F) + p.preload_torque))
              .norm() < 1e-12);
  }
  SECTION("rotation about one axis: moment -k theta - c thetad about it") {
    MultibodySystem sys(Model::from<fx::rigid_body>());
    sys.add<Bushing>("mount", BodyFrame{ground, Vec3(0, 0, 1)}, BodyFrame{0, Vec3::Zero()}, p);
    Vector q(6), qd(6);
    q << 0, 0, 1, 0.3, 0, 0;  // yaw 0.3 about z
    qd << 0, 0, 0, 0.7, 0, 0;
    generalized(sys, make_state(0, q, qd));
    CHECK((sys.loads().F.col(0) - p.preload_force).norm() < 1e-12);
    CHECK((sys.loads().M.col(0) - Vec3(0, 0, 0.5 - 30 * 0.3 - 0.3 * 0.7)).norm() < 1e-12);
  }
  SECTION("large rotations: the moment derives from the angular potential") {
    BushingProperties r;
    r.rotational_stiffness = Vec3(10, 20, 30);
    MultibodySystem sys(Model::from<fx::rigid_body>());
    auto b = sys.add<Bushing>("mount", BodyFrame{ground, Vec3::Zero()}, BodyFrame{0, Vec3::Zero()},
                              r, "zxy");
    for (int trial = 0; trial < 100; ++trial) {
      Vector q = Vector::Zero(6);
      q.tail(3) = random_vector(3, -0.8, 0.8);
      const State s = make_state(0, q, Vector::Zero(6));
      const Vector Q = generalized(sys, s);
      for (int j = 3; j < 6; ++j) {
        const double h = 1e-6;
        State sp = s, sm = s;
        sp.q(j) += h;
        sm.q(j) -= h;
        const double Vp = b->potential_energy(sp, sys.evaluate_kinematics(sp));
        const double Vm = b->potential_energy(sm, sys.evaluate_kinematics(sm));
        CHECK(Q(j) == Approx(-(Vp - Vm) / (2 * h)).margin(1e-6));
      }
    }
  }
}

TEST_CASE("Penalty contact of a sphere with a plane", "[runtime][forces]") {
  ContactProperties c;
  c.stiffness = 1e5;
  c.stiffness_exponent = 1.5;
  c.damping = 2e3;
  c.damping_exponent = 1.0;
  c.friction = 0.6;
  c.slip_speed = 0.01;
  MultibodySystem sys(Model::from<fx::rigid_body>());
  // Sphere of radius 0.1 at body point (0, 0, -0.2); ground z = 0.
  sys.add<PlaneContact>("foot", 0, Vec3(0, 0, -0.2), 0.1, Plane{}, c);
  Vector q(6), qd(6);
  q << 0, 0, 0.28, 0, 0, 0;         // sphere centre at z = 0.08: penetration 0.02
  qd << 0.3, 0.4, -0.1, 0, 0, 1.0;  // roll rate 1 about x
  generalized(sys, make_state(0, q, qd));
  // Contact point C = (0, 0, -0.02); material velocity v + w x (C - x).
  const Vec3 C(0, 0, -0.02), x(0, 0, 0.28);
  const Vec3 vC = Vec3(0.3, 0.4, -0.1) + Vec3(1, 0, 0).cross(C - x);
  const double delta = 0.02, deltad = -vC.z();
  const double N = 1e5 * std::pow(delta, 1.5) + 2e3 * delta * deltad;
  const Vec3 vt(vC.x(), vC.y(), 0);
  const Vec3 F = Vec3(0, 0, N) - 0.6 * N * vt / vt.norm();
  CHECK((sys.loads().F.col(0) - F).norm() < 1e-10);
  CHECK((sys.loads().M.col(0) - (C - x).cross(F)).norm() < 1e-10);
  // Below the slip speed the friction is linear in vt.
  qd << 0.004, 0.003, 0, 0, 0, 0;
  generalized(sys, make_state(0, q, qd));
  CHECK(sys.loads().F(0, 0) == Approx(-0.6 * 1e5 * std::pow(delta, 1.5) * 0.004 / 0.01));
  // Separated or pulling: no force.
  q(2) = 0.31;
  generalized(sys, make_state(0, q, qd));
  CHECK(sys.loads().F.col(0).norm() == 0.0);
  q(2) = 0.29;
  qd << 0, 0, 10.0, 0, 0, 0;  // leaving fast: the damping term would pull
  generalized(sys, make_state(0, q, qd));
  CHECK(sys.loads().F.col(0).norm() == 0.0);
}

TEST_CASE("Simple tyre of docs/models.md on a cambered, steered, spinning wheel",
          "[runtime][forces]") {
  MultibodySystem sys(Model::from<fx::rigid_body>());
  SimpleTyreProperties t;  // the trike's: R 0.3, k 2e5, c 500, mu 0.9, eps 0.05
  auto tyre = sys.add<SimpleTyre>("front", 0, t);
  for (int trial = 0; trial < 100; ++trial) {
    Vector q(6), qd(6);
    q << uniform(-1, 1), uniform(-1, 1), uniform(0.27, 0.3), uniform(-3, 3), uniform(-0.5, 0.5),
        uniform(-0.3, 0.3);
    qd << uniform(-5, 5), uniform(-1, 1), uniform(-0.5, 0.5), uniform(-1, 1), uniform(-20, 20),
        uniform(-1, 1);
    generalized(sys, make_state(0, q, qd));
    // By hand: e = R y; d = unit(z - (z.e) e); P = C - R d.
    const Mat3 R = body_rotation(q);
    const Vec3 e = R.col(1), z = Vec3::UnitZ(), C = q.head(3);
    const Vec3 d = (z - z.dot(e) * e).normalized();
    const Vec3 P = C - 0.3 * d;
    const double delta = -P.z();
    const Vec3 w = fx::rigid_body::axes(q.data()) * qd.tail(3);
    const Vec3 vP = Vec3(qd.head(3)) + w.cross(P - C);
    Vec3 F = Vec3::Zero();
    if (delta > 0) {
      const double N = std::max(0.0, 2e5 * delta - 500 * vP.z());
      const Vec3 vt(vP.x(), vP.y(), 0.0);
      F = N * z - 0.9 * N * vt / std::sqrt(vt.squaredNorm() + 0.05 * 0.05);
    }
    CHECK((sys.loads().F.col(0) - F).norm() < 1e-9 * (1 + F.norm()));
    CHECK((sys.loads().M.col(0) - (P - C).cross(F)).norm() < 1e-9 * (1 + F.norm()));
    CHECK((tyre->evaluate(sys.kinematics()).contact_point - P).norm() < 1e-14);
  }
}
