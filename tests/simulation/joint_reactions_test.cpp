// Joint reactions (docs/emitted_interface.md, docs/runtime.md) against
// independent values: a pendulum's pivot force in closed form (generated in
// process, the interpreter over the emitted program), every body's Newton-Euler
// balance at random states with applied loads, the base reaction as the rate
// of the total momentum less gravity (momentum differenced in time), and the
// slider-crank's pin forces from a free-body diagram solved here by hand.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "chain_2_relative.hpp"
#include "double_pendulum_absolute.hpp"
#include "double_pendulum_relative.hpp"
#include "simulation/random_state.hpp"
#include "slider_crank_dependent.hpp"
#include "trike.hpp"
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/model.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;
namespace gen = symdyn_generated;

Vec3 force(const Matrix& reaction, int i) {
  return reaction.col(i).head<3>();
}
Vec3 moment(const Matrix& reaction, int i) {
  return reaction.col(i).tail<3>();
}

// Constant loads at every body's G, global axes, drawn once.
class RandomLoads : public ForceElement {
 public:
  RandomLoads(int nbody, std::mt19937& rng) : F_(3, nbody), M_(3, nbody) {
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (double& f : F_.reshaped()) f = u(rng);
    for (double& m : M_.reshaped()) m = u(rng);
  }
  std::string name() const override { return "random loads"; }
  KinematicsLevel reads() const override { return KinematicsLevel::positions; }
  void apply(const State&, const Kinematics&, Loads& loads) const override {
    for (int i = 0; i < F_.cols(); ++i) {
      loads.add_force(i, F_.col(i));
      loads.add_moment(i, M_.col(i));
    }
  }
  const Matrix& F() const { return F_; }
  const Matrix& M() const { return M_; }

 private:
  Matrix F_, M_;
};

// Each body's G from its joint point in its axes, read off the models' motions by hand.
Vec3 joint_to_G(const std::string& model, const std::string& body) {
  if (model == "double_pendulum") return {0.5, 0.0, 0.0};
  if (model == "chain_2") return {0.25, 0.0, 0.0};
  if (body == "crank") return {0.05, 0.0, 0.0};
  if (body == "rod") return {-0.15, 0.0, 0.0};
  return Vec3::Zero();  // the slider: its joint is its displacement
}

// Every body: F_i - Σ_c F_c + m·g + F_applied = m·a and, about G,
// n_i + (J_i - G)×F_i - Σ_c (n_c + (J_c - G)×F_c) + M_applied = J·dω + ω×J·ω,
// from the accelerations entry point at the system's qdd, in global axes.
template <class G>
void check_newton_euler() {
  INFO(G::model << " " << G::variant);
  MultibodySystem system(Model::from<G>());
  std::mt19937 rng(7);
  const auto loads = system.add<RandomLoads>(G::nbody, rng);
  const Model& model = system.model();
  for (int trial = 0; trial < 10; ++trial) {
    const State s = symdyn::testing::random_state(system, rng);
    Vector qdd, yd;
    system.accelerations(s, qdd, yd);
    Matrix reaction;
    system.joint_reactions(s, qdd, reaction);
    Kinematics k = model.make_kinematics();
    model.accelerations(s.t, s.q.data(), s.qd.data(), qdd.data(), k);
    std::vector<Vec3> f(G::nbody), n(G::nbody), J(G::nbody);  // global; n about J
    for (int i = 0; i < G::nbody; ++i) {
      f[i] = k.R(i) * force(reaction, i);
      n[i] = k.R(i) * moment(reaction, i);
      J[i] = k.x(i) - k.R(i) * joint_to_G(G::model, model.body_names()[i]);
    }
    for (int i = 0; i < G::nbody; ++i) {
      INFO("body " << model.body_names()[i]);
      Vec3 F = f[i] + model.mass(i) * model.gravity() + loads->F().col(i);
      Vec3 M = n[i] + (J[i] - k.x(i)).cross(f[i]) + loads->M().col(i);
      for (int c = 0; c < G::nbody; ++c) {
        if (model.reference_body(c) != i) continue;
        F -= f[c];
        M -= n[c] + (J[c] - k.x(i)).cross(f[c]);
      }
      const Mat3 Jg = model.global_inertia(i, k);
      const Vec3 w = k.w(i);
      const Vec3 inertial_force = model.mass(i) * k.a(i);
      const Vec3 inertial_moment = Jg * k.dw(i) + w.cross(Jg * w);
      CHECK((F - inertial_force).norm() < 1e-10 * (1 + inertial_force.norm()));
      CHECK((M - inertial_moment).norm() < 1e-10 * (1 + inertial_moment.norm()));
    }
  }
}

// The roots' reactions (the base's) are the rate of the total momentum less
// gravity, P and L about the origin differenced along the motion (h = 1e-5):
// a single root whose joint point is the origin (rod1, crank, link0) takes
// its moment there too; absolute models sum every body's.
template <class G>
void check_base_reaction() {
  INFO(G::model << " " << G::variant);
  MultibodySystem system(Model::from<G>());
  const Model& model = system.model();
  std::mt19937 rng(9);
  for (int trial = 0; trial < 5; ++trial) {
    const State s = symdyn::testing::random_state(system, rng);
    Vector qdd, yd;
    system.accelerations(s, qdd, yd);
    Matrix reaction;
    system.joint_reactions(s, qdd, reaction);
    const double h = 1e-5;
    const auto shifted = [&](double dt) {
      State x = s;
      x.t += dt;
      x.q += dt * s.qd + 0.5 * dt * dt * qdd;
      x.qd += dt * qdd;
      return system.momentum(x);
    };
    const Momentum plus = shifted(h), minus = shifted(-h);
    const Vec3 dP = (plus.linear - minus.linear) / (2 * h);
    const Vec3 dL = (plus.angular - minus.angular) / (2 * h);
    Kinematics k = model.make_kinematics();
    model.positions(s.t, s.q.data(), k);
    Vec3 F = Vec3::Zero(), M = Vec3::Zero(), weight = Vec3::Zero(), weight_moment = Vec3::Zero();
    for (int i = 0; i < model.nbody(); ++i) {
      weight += model.mass(i) * model.gravity();
      weight_moment += k.x(i).cross(model.mass(i) * model.gravity());
      if (model.reference_body(i) >= 0) continue;
      const Vec3 fi = k.R(i) * force(reaction, i);
      const Vec3 Ji = k.x(i) - k.R(i) * joint_to_G(G::model, model.body_names()[i]);
      F += fi;
      M += k.R(i) * moment(reaction, i) + Ji.cross(fi);
    }
    CHECK((F + weight - dP).norm() < 1e-6 * (1 + dP.norm()));
    CHECK((M + weight_moment - dL).norm() < 1e-6 * (1 + dL.norm()));
  }
}

}  // namespace

TEST_CASE("joint reactions: a pendulum's pivot force is m(g cos θ + c θ̇²) along the rod",
          "[reactions]") {
  // A rod hinged at the origin about z, its G at c below the pivot at θ = 0.
  namespace sm = symdyn::model;
  const double m = 2.0, c = 0.4, Izz = 0.05, g = 9.81;
  sm::Model pendulum("pendulum");
  const sm::Expr q = pendulum.coordinate("theta");
  pendulum.body("rod").mass(m).inertia(0.01, Izz, Izz).motion(sm::Trotz(q) * sm::Tdisp(0, -c, 0));
  pendulum.gravity(0, -g, 0);
  symdyn::codegen::Options options;
  options.entry_points = {"joint_reactions"};
  const auto code = symdyn::codegen::generate(pendulum, "default", "pendulum", options);
  REQUIRE(code.functions.size() == 1);
  const symdyn::codegen::EmittedFunction& f = code.functions[0];
  REQUIRE(f.program);
  for (const double theta : {0.0, 0.7, -2.0, 3.0}) {
    for (const double rate : {0.0, 1.5, -4.0}) {
      const double acceleration = -m * g * c * std::sin(theta) / (Izz + m * c * c);
      // t, q, qd, qdd, F_applied, M_applied (no parameters).
      const std::vector<double> in{0.0, theta, rate, acceleration, 0, 0, 0, 0, 0, 0};
      const std::vector<double> r = f.program->evaluate<double>(in);
      REQUIRE(r.size() == 6);
      INFO("theta " << theta << " rate " << rate);
      // Body axes: y from G to the pivot, x along the motion of G.
      CHECK(r[1] == Approx(m * (g * std::cos(theta) + c * rate * rate)).margin(1e-12));
      CHECK(r[0] == Approx(m * g * std::sin(theta) * Izz / (Izz + m * c * c)).margin(1e-12));
      // A free hinge about z, at the pivot: no moment at all.
      for (int e : {2, 3, 4, 5}) CHECK(std::abs(r[e]) < 1e-12);
    }
  }
}

TEST_CASE("joint reactions: every body's Newton-Euler balance at random states", "[reactions]") {
  check_newton_euler<gen::double_pendulum_relative>();
  check_newton_euler<gen::double_pendulum_absolute>();
  check_newton_euler<gen::chain_2_relative>();
  check_newton_euler<gen::slider_crank_dependent>();
}

TEST_CASE("joint reactions: the base reaction is the total momentum's rate less gravity",
          "[reactions]") {
  check_base_reaction<gen::double_pendulum_relative>();
  check_base_reaction<gen::double_pendulum_absolute>();
  check_base_reaction<gen::chain_2_relative>();
  check_base_reaction<gen::slider_crank_dependent>();
}

TEST_CASE("joint reactions: the slider-crank's pins against a free-body diagram", "[reactions]") {
  // Every body moves from the ground: each reaction is the sum of the pins'
  // forces on it. By hand: F_A, the crank's on the rod at A; F_B, the rod's on
  // the slider at B (= the slider's G); N, the guide's on the slider (y):
  //   rod:    m_r·a_r = F_A - F_B + m_r·g,  I_r·α_r = (A - G_r)×F_A - (B - G_r)×F_B
  //   slider: m_s·a_s = F_B + N·ŷ + m_s·g
  MultibodySystem system(Model::from<gen::slider_crank_dependent>());
  const Model& model = system.model();
  const int crank = model.body_index("crank"), rod = model.body_index("rod"),
            slider = model.body_index("slider");
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    const State s = symdyn::testing::random_state(system, rng);
    Vector qdd, yd;
    system.accelerations(s, qdd, yd);
    Kinematics k = model.make_kinematics();
    model.accelerations(s.t, s.q.data(), s.qd.data(), qdd.data(), k);
    const Vec3 A = k.x(crank) + k.R(crank) * Vec3(0.05, 0, 0), B = k.x(slider);
    const Vec3 rA = A - k.x(rod), rB = B - k.x(rod);
    const Vec3 g = model.gravity();
    const double mr = model.mass(rod), ms = model.mass(slider),
                 Ir = model.inertia(rod)(2, 2);  // about z, which stays global z
    // Unknowns u = (F_Ax, F_Ay, F_Bx, F_By, N).
    Eigen::Matrix<double, 5, 5> E = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> rhs;
    E(0, 0) = 1, E(0, 2) = -1, rhs(0) = mr * (k.a(rod).x() - g.x());
    E(1, 1) = 1, E(1, 3) = -1, rhs(1) = mr * (k.a(rod).y() - g.y());
    E(2, 0) = -rA.y(), E(2, 1) = rA.x(), E(2, 2) = rB.y(), E(2, 3) = -rB.x();
    rhs(2) = Ir * k.dw(rod).z();
    E(3, 2) = 1, rhs(3) = ms * (k.a(slider).x() - g.x());
    E(4, 3) = 1, E(4, 4) = 1, rhs(4) = ms * (k.a(slider).y() - g.y());
    const Eigen::Matrix<double, 5, 1> u = E.fullPivLu().solve(rhs);
    const Vec3 FA(u(0), u(1), 0), FB(u(2), u(3), 0), N(0, u(4), 0);
    Matrix reaction;
    system.joint_reactions(s, qdd, reaction);
    const auto global_force = [&](int i) -> Vec3 { return k.R(i) * force(reaction, i); };
    const auto global_moment = [&](int i) -> Vec3 { return k.R(i) * moment(reaction, i); };
    const double scale = 1 + FA.norm() + FB.norm();
    INFO("F_A " << FA.transpose() << " F_B " << FB.transpose() << " N " << u(4));
    // The rod: both pins, about its joint point B.
    CHECK((global_force(rod) - (FA - FB)).norm() < 1e-9 * scale);
    CHECK((global_moment(rod) - (A - B).cross(FA)).norm() < 1e-9 * scale);
    // The slider: the rod's pin and the guide, at B.
    CHECK((global_force(slider) - (FB + N)).norm() < 1e-9 * scale);
    CHECK(global_moment(slider).norm() < 1e-9 * scale);
    // The crank about O: the rod's pin only (O's pin has no moment, nothing drives it).
    CHECK((global_moment(crank) - A.cross(-FA)).norm() < 1e-9 * scale);
  }
}

// A torque on a coordinate (a motor) is not a body load: it is what the joint
// transmits about its axis.
class ElbowTorque : public ForceElement {
 public:
  std::string name() const override { return "elbow torque"; }
  KinematicsLevel reads() const override { return KinematicsLevel::none; }
  void apply(const State&, const Kinematics&, Loads& loads) const override {
    loads.add_generalized(1, kTorque);
  }
  static constexpr double kTorque = 3.0;
};

TEST_CASE("joint reactions: a hinge's moment about its axis is the torque driving it",
          "[reactions]") {
  // double_pendulum relative: rod2 hinged on rod1 about z by theta2; free, it
  // transmits no moment about z at the elbow, driven, exactly the torque.
  MultibodySystem system(Model::from<gen::double_pendulum_relative>());
  const int rod2 = system.model().body_index("rod2");
  std::mt19937 rng(5);
  for (const bool driven : {false, true}) {
    if (driven) system.add<ElbowTorque>();
    for (int trial = 0; trial < 5; ++trial) {
      const State s = symdyn::testing::random_state(system, rng);
      Matrix reaction;
      system.joint_reactions(s, reaction);
      CHECK(reaction(5, rod2) == Approx(driven ? ElbowTorque::kTorque : 0.0).margin(1e-12));
    }
  }
}

TEST_CASE("joint reactions: named components, and a model emitted without them", "[reactions]") {
  MultibodySystem system(Model::from<gen::double_pendulum_relative>());
  CHECK(system.model().has_joint_reactions());
  Matrix reaction;
  Vector wrong(3);
  CHECK_THROWS_WITH(system.joint_reactions(system.initial_state(), wrong, reaction),
                    Catch::Contains("qdd has 3 entries"));
  system.joint_reactions(system.initial_state(), reaction);
  CHECK(reaction.rows() == 6);
  CHECK(reaction.cols() == 2);
  CHECK(std::string(Model::kReactionComponents[5]) == "Mz");
  MultibodySystem trike(Model::from<gen::trike>());
  CHECK_FALSE(trike.model().has_joint_reactions());
  CHECK_THROWS_WITH(trike.joint_reactions(trike.initial_state(), reaction),
                    Catch::Contains("without joint_reactions") && Catch::Contains("REACTIONS"));
}
