// The reactions of closed loops (MultibodySystem::loop_reactions and the tree's
// joint_reactions with the closures' forces): a loaded four-bar held static
// against its free-body diagrams solved by hand, the implicit slider-crank's
// against the explicit variant's, and every body's Newton-Euler balance with
// the closure forces at random states, where the free hinges transmit no
// moment about their axes.

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "four_bar.hpp"
#include "four_bar_parametric.hpp"
#include "random_state.hpp"
#include "slider_crank_dependent.hpp"
#include "slider_crank_implicit.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/loop_closure.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

namespace {

using namespace symdyn::runtime;
namespace gen = symdyn_generated;
using symdyn::testing::one_coordinate_state;

// The four-bar's geometry and masses (models/four_bar.cpp, variant closed).
constexpr double r1 = 0.1, r2 = 0.35, r3 = 0.3, d = 0.4;
constexpr double m1 = 0.2, m2 = 0.5, m3 = 0.4;
const Vec3 gravity(0, -9.81, 0);
constexpr int crank = 0, coupler = 1, rocker = 2;

double cross2(const Vec3& r, const Vec3& f) {
  return r.x() * f.y() - r.y() * f.x();
}

// Each loop reaction by axis: the force of a closure (global axes).
Vec3 closure_force(const Model& model, const Vector& reaction) {
  Vec3 f = Vec3::Zero();
  for (int k = 0; k < model.ncon(); ++k) f(model.constraint_axis(k)) = reaction(k);
  return f;
}

// The joint reaction of body i in global axes: the force, the moment about its joint point.
Vec3 force(const Kinematics& k, const Matrix& reaction, int i) {
  return k.R(i) * reaction.col(i).head<3>();
}
Vec3 moment(const Kinematics& k, const Matrix& reaction, int i) {
  return k.R(i) * reaction.col(i).tail<3>();
}

// The four-bar's positions at the extended state x, and its joints' points:
// O and D on the ground, A the crank's end, C the closure.
struct FourBarPoints {
  Kinematics k;
  Vec3 O, A, C, D;
};
FourBarPoints four_bar_points(const Model& model, const State& x) {
  FourBarPoints p{model.make_kinematics(), Vec3::Zero(), {}, {}, Vec3(d, 0, 0)};
  model.positions(x.t, x.q.data(), p.k);
  p.A = p.k.x(crank) + p.k.R(crank) * Vec3(r1 / 2, 0, 0);
  p.C = p.k.x(rocker) + p.k.R(rocker) * Vec3(r3 / 2, 0, 0);
  return p;
}

// The four-bar's phi and psi at q0 by the two-circle intersection (C on the
// left of A -> D, the model's assembly): the loops' guesses, so that states
// far apart stay on that branch.
Vector four_bar_guess(double q0) {
  const double ax = r1 * std::cos(q0), ay = r1 * std::sin(q0);
  const double ux = d - ax, uy = -ay, e = std::hypot(ux, uy);
  const double a = (r2 * r2 - r3 * r3 + e * e) / (2 * e), h = std::sqrt(r2 * r2 - a * a);
  const double cx = ax + (a * ux - h * uy) / e, cy = ay + (a * uy + h * ux) / e;
  return Eigen::Vector2d(std::atan2(cy - ay, cx - ax) - q0, std::atan2(cy, cx - d));
}

}  // namespace

TEST_CASE("a loaded four-bar held static: its reactions solved by hand", "[models][loops]") {
  // A load L at a point of the coupler 0.1 m ahead of its G, gravity, and the
  // crank held by the torque tau: unknowns z = (O, A, C, D, tau), O the
  // ground's force on the crank, A the crank's on the coupler, C the
  // coupler's on the rocker, D the ground's on the rocker.
  const Vec3 load(3.0, -5.0, 0.0);
  for (double q0 : {0.3, 1.2, 2.5, 4.0}) {
    INFO("q0 = " << q0);
    MultibodySystem system(Model::from<gen::four_bar>());
    const Model& model = system.model();
    system.add<PointLoad>("load", BodyPoint{coupler, Vec3(0.1, 0, 0)}, load);
    const State s = one_coordinate_state(0.0, q0, 0.0);
    system.set_loop_guess(four_bar_guess(q0));
    const State x = system.extended_state(s);
    const FourBarPoints p = four_bar_points(model, x);
    const Vec3 G1 = p.k.x(crank), G2 = p.k.x(coupler), G3 = p.k.x(rocker);
    const Vec3 at = G2 + p.k.R(coupler) * Vec3(0.1, 0, 0);
    // Rows: crank x, y, moment about O; coupler x, y, about A; rocker x, y, about D.
    Eigen::Matrix<double, 9, 9> E = Eigen::Matrix<double, 9, 9>::Zero();
    Eigen::Matrix<double, 9, 1> rhs;
    const auto force_columns = [&](int row, int column, double sign) {
      E(row, column) = sign;
      E(row + 1, column + 1) = sign;
    };
    const auto moment_columns = [&](int row, int column, const Vec3& r, double sign) {
      E(row, column) = -sign * r.y();  // r × f = r.x f.y - r.y f.x
      E(row, column + 1) = sign * r.x();
    };
    force_columns(0, 0, 1);  // crank: O - A + m1 g = 0
    force_columns(0, 2, -1);
    moment_columns(2, 2, p.A - p.O, -1);  // tau + (A - O) × (-A) + (G1 - O) × m1 g = 0
    E(2, 8) = 1;
    force_columns(3, 2, 1);  // coupler: A - C + m2 g + L = 0
    force_columns(3, 4, -1);
    moment_columns(5, 4, p.C - p.A, -1);  // (C - A) × (-C) + (G2 - A) × m2 g + (at - A) × L = 0
    force_columns(6, 4, 1);               // rocker: C + D + m3 g = 0
    force_columns(6, 6, 1);
    moment_columns(8, 4, p.C - p.D, 1);  // (C - D) × C + (G3 - D) × m3 g = 0
    rhs << -m1 * gravity.head<2>(), -cross2(G1 - p.O, m1 * gravity),
        -(m2 * gravity + load).head<2>(), -cross2(G2 - p.A, m2 * gravity) - cross2(at - p.A, load),
        -m3 * gravity.head<2>(), -cross2(G3 - p.D, m3 * gravity);
    const Eigen::Matrix<double, 9, 1> z = E.fullPivLu().solve(rhs);
    const double tau = z(8);
    const Vec3 O(z(0), z(1), 0), A(z(2), z(3), 0), C(z(4), z(5), 0), D(z(6), z(7), 0);

    // Held by tau, the four-bar stays at rest.
    system.add<CoordinateForce>("hold", 0,
                                [tau](double, double, double, const State&) { return tau; });
    Vector qdd, yd;
    system.accelerations(s, qdd, yd);
    CHECK(std::abs(qdd(0)) < 1e-9);

    Vector reaction;
    system.loop_reactions(s, reaction);
    REQUIRE(reaction.size() == 2);
    CHECK(model.loop_reaction_name(0) == "C.Fx");
    CHECK(model.loop_reaction_name(1) == "C.Fy");
    CHECK((closure_force(model, reaction) - C).norm() < 1e-9 * (1 + C.norm()));

    Matrix joints;
    system.joint_reactions(s, joints);
    const double scale = 1 + O.norm() + A.norm() + D.norm();
    CHECK((force(p.k, joints, crank) - O).norm() < 1e-9 * scale);
    CHECK((force(p.k, joints, coupler) - A).norm() < 1e-9 * scale);
    CHECK((force(p.k, joints, rocker) - D).norm() < 1e-9 * scale);
    // The crank's joint transmits the torque that holds it; the free hinges none.
    CHECK(std::abs(moment(p.k, joints, crank).z() - tau) < 1e-9 * (1 + std::abs(tau)));
    CHECK(std::abs(moment(p.k, joints, coupler).z()) < 1e-9 * scale);
    CHECK(std::abs(moment(p.k, joints, rocker).z()) < 1e-9 * scale);
  }
}

TEST_CASE("the implicit slider-crank's pin reactions equal the explicit variant's",
          "[models][loops]") {
  // Explicit, every body's joint to the ground carries all the constraint
  // forces on it; implicit, the crank pin's force F (on the rod from the
  // crank, at P) is the closure's: the explicit rod's is the implicit rod's
  // plus F, the crank's minus F, the slider's the same; the moments about
  // the joint points (the crank's O, the rod's slider pin J) likewise.
  MultibodySystem explicit_(Model::from<gen::slider_crank_dependent>());
  MultibodySystem implicit(Model::from<gen::slider_crank_implicit>());
  const Model& model = implicit.model();
  REQUIRE(model.loop_reaction_name(0) == "crank_pin.Fx");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-40.0, 40.0), acc(-500.0, 500.0);
  const double l1 = 0.1;
  for (int trial = 0; trial < 20; ++trial) {
    const State s = one_coordinate_state(0.1 * trial, angle(rng), rate(rng));
    const Vector qdd = Vector::Constant(1, acc(rng));
    INFO("q0 = " << s.q(0) << ", qd0 = " << s.qd(0) << ", qdd0 = " << qdd(0));
    // On the explicit variant's branch (the slider right of the crank).
    Kinematics p = explicit_.model().make_kinematics();
    explicit_.model().dependent_parameters(s.t, s.q.data(), s.qd.data(), qdd.data(), p);
    implicit.set_loop_guess(Eigen::Vector2d(p.p()[0], p.p()[1]));
    Matrix e, i;
    Vector pin;
    explicit_.joint_reactions(s, qdd, e);
    implicit.joint_reactions(s, qdd, i);
    implicit.loop_reactions(s, qdd, pin);
    const Vec3 F = closure_force(model, pin);
    Kinematics k = explicit_.model().make_kinematics();
    explicit_.model().positions(s.t, s.q.data(), k);
    const Vec3 P(l1 * std::cos(s.q(0)), l1 * std::sin(s.q(0)), 0), J = k.x(2);
    const double scale = 1 + e.cwiseAbs().maxCoeff();
    CHECK((force(k, e, 0) - (force(k, i, 0) - F)).norm() < 1e-9 * scale);
    CHECK((force(k, e, 1) - (force(k, i, 1) + F)).norm() < 1e-9 * scale);
    CHECK((force(k, e, 2) - force(k, i, 2)).norm() < 1e-9 * scale);
    CHECK((moment(k, e, 0) - (moment(k, i, 0) + P.cross(-F))).norm() < 1e-9 * scale);
    CHECK((moment(k, e, 1) - (moment(k, i, 1) + (P - J).cross(F))).norm() < 1e-9 * scale);
    CHECK((moment(k, e, 2) - moment(k, i, 2)).norm() < 1e-9 * scale);
  }
}

TEST_CASE("the four-bar's bodies balance with the closure forces at random states",
          "[models][loops]") {
  // With the accelerations of the dynamics (a load on the rocker, no torque on
  // the crank): for each body, the forces it receives (its joint's, those its
  // child receives reversed, the closure's, gravity, the load) equal m·a and
  // their moments about G the rate of its angular momentum; every hinge is
  // free, so none transmits a moment about its axis.
  MultibodySystem system(Model::from<gen::four_bar>());
  const Model& model = system.model();
  const Vec3 load(-2.0, 4.0, 0.0), load_point(0.05, 0, 0);
  system.add<PointLoad>("load", BodyPoint{rocker, load_point}, load);
  LoopClosure loops(model);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-20.0, 20.0);
  for (int trial = 0; trial < 20; ++trial) {
    const State s = one_coordinate_state(0.05 * trial, angle(rng), rate(rng));
    INFO("q0 = " << s.q(0) << ", qd0 = " << s.qd(0));
    system.set_loop_guess(four_bar_guess(s.q(0)));
    loops.set_guess(four_bar_guess(s.q(0)));
    Vector qdd, yd, reaction;
    system.accelerations(s, qdd, yd);
    Matrix joints;
    system.joint_reactions(s, qdd, joints);
    system.loop_reactions(s, qdd, reaction);
    const Vec3 F_C = closure_force(model, reaction);  // on the rocker from the coupler

    State x;
    loops.close(model, s.t, s.q, s.qd, x.q, x.qd);
    const Vector xdd = loops.T() * qdd + loops.c();
    Kinematics k = model.make_kinematics();
    model.accelerations(s.t, x.q.data(), x.qd.data(), xdd.data(), k);
    const FourBarPoints p = four_bar_points(model, State{s.t, x.q, x.qd, {}});
    const Vec3 at = k.x(rocker) + k.R(rocker) * load_point;

    struct Balance {
      Vec3 force, moment;  // about G
    };
    std::vector<Balance> received(3);
    const auto add = [&](int i, const Vec3& f, const Vec3& point) {
      received[i].force += f;
      received[i].moment += (point - k.x(i)).cross(f);
    };
    for (Balance& b : received) b = {Vec3::Zero(), Vec3::Zero()};
    add(crank, force(k, joints, crank), p.O);
    received[crank].moment += moment(k, joints, crank);
    add(crank, -force(k, joints, coupler), p.A);
    received[crank].moment -= moment(k, joints, coupler);
    add(coupler, force(k, joints, coupler), p.A);
    received[coupler].moment += moment(k, joints, coupler);
    add(coupler, -F_C, p.C);
    add(rocker, force(k, joints, rocker), p.D);
    received[rocker].moment += moment(k, joints, rocker);
    add(rocker, F_C, p.C);
    add(rocker, load, at);
    const double masses[3] = {m1, m2, m3};
    for (int i = 0; i < 3; ++i) {
      INFO("body " << model.body_names()[i]);
      add(i, masses[i] * gravity, k.x(i));
      const Mat3 J = model.global_inertia(i, k);
      const Vec3 ma = masses[i] * k.a(i);
      const Vec3 rate = J * k.dw(i) + k.w(i).cross(J * k.w(i));
      const double scale = 1 + ma.norm() + F_C.norm();
      CHECK((received[i].force - ma).norm() < 1e-9 * scale);
      CHECK((received[i].moment - rate).norm() < 1e-9 * scale);
      CHECK(std::abs(moment(k, joints, i).z()) < 1e-9 * scale);
    }
  }
}

TEST_CASE("the parametric four-bar's closure point follows its lengths", "[models][loops]") {
  // Other lengths move C (an emitted function of the run-time parameters):
  // with the closure's force there, the free hinges still transmit no moment.
  MultibodySystem system(Model::from<gen::four_bar_parametric>());
  const double l2 = 0.38, l3 = 0.33;
  system.set_parameter("r2", l2);
  system.set_parameter("r3", l3);
  for (double q0 : {0.1, 0.2, 0.3}) {
    const State s = one_coordinate_state(0.0, q0, 3.0);
    Matrix joints;
    system.joint_reactions(s, joints);
    const double scale = 1 + joints.cwiseAbs().maxCoeff();
    for (int i = 0; i < 3; ++i) CHECK(std::abs(joints(5, i)) < 1e-9 * scale);
    // C is the rocker's end: r3 from D along the rocker.
    const State x = system.extended_state(s);
    Matrix points(3, 2);
    system.model().closure_points(s.t, x.q.data(), points.data());
    const double psi = x.q(2);
    CHECK((points.col(0) - Vec3(d + l3 * std::cos(psi), l3 * std::sin(psi), 0)).norm() < 1e-12);
  }
}

TEST_CASE("a loop given by its equations reports its multipliers, and no joint reactions",
          "[models][loops]") {
  // The four-bar described as if its loop were a constraint(): the same
  // equations (point_a - point_b), so its multipliers are the closure's force
  // on the coupler, the opposite of close_loop's reaction (on the rocker).
  ModelDescription d = Model::describe<gen::four_bar>();
  d.loop_bodies = {-1, -1};
  d.constraint_axis = {-1, -1};
  MultibodySystem as_equations{Model(d)}, closed(Model::from<gen::four_bar>());
  CHECK(as_equations.model().loop_reaction_name(0) == "C.lambda0");
  CHECK(as_equations.model().loop_reaction_name(1) == "C.lambda1");
  const State s = one_coordinate_state(0.0, 0.3, 2.0);
  Vector lambda, reaction;
  as_equations.loop_reactions(s, lambda);
  closed.loop_reactions(s, reaction);
  CHECK((lambda + reaction).norm() < 1e-12 * (1 + reaction.norm()));
  Matrix joints;
  CHECK_THROWS_WITH(as_equations.joint_reactions(s, joints),
                    Catch::Contains("loop 'C' is given by its equations (constraint), whose "
                                    "forces act on no known body"));
}

TEST_CASE("loop reactions: bad input is named", "[models][loops]") {
  MultibodySystem tree(Model::from<gen::slider_crank_dependent>());
  Vector reaction;
  CHECK_THROWS_WITH(tree.loop_reactions(one_coordinate_state(0, 0.1, 0), reaction),
                    Catch::Contains("has no closed loops"));
  MultibodySystem loops(Model::from<gen::four_bar>());
  CHECK_THROWS_WITH(
      loops.loop_reactions(one_coordinate_state(0, 0.1, 0), Vector::Zero(3), reaction),
      Catch::Contains("3 accelerations given; expected 1"));
}
