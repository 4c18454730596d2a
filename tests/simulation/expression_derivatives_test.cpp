// The exact derivatives of scenario expressions (Expression::evaluate with a
// gradient) and of the generalized forces they give (coordinate_force):
// every function of the expression language, each branch of those that
// switch, and every kind of quantity a force law reads, against Richardson
// differences; the trike scenario's Jacobians against Richardson differences
// of its residual, no element differenced.
#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "differences.hpp"
#include "expression.hpp"
#include "run.hpp"
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn;
using runtime::Matrix;
using runtime::State;
using runtime::Vector;

using symdyn::testing::richardson;

// Symbols x, y, z: 0, 1, 2.
struct Point : sim::Environment {
  double v[3] = {0.0, 0.0, 0.0};
  double value(int symbol) const override { return v[symbol]; }
};

sim::Expression parse_xyz(const std::string& text) {
  sim::Resolver r;
  r.symbol = [](std::string_view name) -> int {
    if (name == "x") return 0;
    if (name == "y") return 1;
    if (name == "z") return 2;
    throw sim::ExpressionError(fmt::format("unknown name '{}'", name));
  };
  return sim::Expression::parse(text, r);
}

// The gradient of e at p, by symbol (x, y, z), 0 for a symbol it does not read.
std::vector<double> exact_gradient(const sim::Expression& e, const Point& p) {
  std::vector<double> by_slot(e.symbols().size()), out(3, 0.0);
  e.evaluate(p, by_slot.data());
  for (std::size_t i = 0; i < by_slot.size(); ++i)
    out[static_cast<std::size_t>(e.symbols()[i])] = by_slot[i];
  return out;
}

void check_gradient(const std::string& text, const Point& p, double h = 1e-4) {
  CAPTURE(text, p.v[0], p.v[1], p.v[2]);
  const sim::Expression e = parse_xyz(text);
  std::vector<double> g(e.symbols().size());
  CHECK(e.evaluate(p, g.data()) == e.evaluate(p));
  const auto exact = exact_gradient(e, p);
  for (int c = 0; c < 3; ++c) {
    const double d = richardson(
        [&](double x) {
          Point q = p;
          q.v[c] = x;
          return e.evaluate(q);
        },
        p.v[c], h);
    CAPTURE(c);
    CHECK(exact[static_cast<std::size_t>(c)] ==
          Approx(d).margin(1e-8).epsilon(1e-7 * std::max(1.0, std::abs(d))));
  }
}

}  // namespace

TEST_CASE("an expression's gradient equals Richardson differences, every function",
          "[scenario][derivatives]") {
  // Each at random points of its domain: x in (-0.9, 0.9), y in (0.5, 2), z in (-2, 2).
  const char* texts[] = {"-x + y - z",
                         "x * y / z",
                         "y ^ z",
                         "(x + 2) ^ 3",
                         "2 ^ x",
                         "y ^ 0.5",
                         "sin(x * y)",
                         "cos(z) * x",
                         "tan(x)",
                         "asin(x)",
                         "acos(x)",
                         "atan(z * y)",
                         "atan2(z, x)",
                         "sqrt(y + x)",
                         "exp(x - z)",
                         "log(y)",
                         "abs(z)",
                         "sign(z) * y",
                         "step(z) * x",
                         "min(x, z)",
                         "max(x, z)",
                         "clamp(z, -1, 1)",
                         "clamp(3 * z, x, y)",
                         "pi * x ^ 2",
                         "min(x, 2) + max(3, y * z)"};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int round = 0; round < 20; ++round) {
    Point p;
    p.v[0] = 0.9 * u(rng);
    p.v[1] = 1.25 + 0.75 * u(rng);
    p.v[2] = 2.0 * u(rng);
    for (const char* text : texts) check_gradient(text, p);
  }
}

TEST_CASE("where a function switches, the gradient is that of the branch its value takes",
          "[scenario][derivatives]") {
  const auto at = [](double x, double y, double z) {
    Point p;
    p.v[0] = x;
    p.v[1] = y;
    p.v[2] = z;
    return p;
  };
  // clamp(z, x, y) = max(x, min(z, y)): below, inside, above its band; on its lower
  // bound max returns x, on its upper one min returns z.
  CHECK(exact_gradient(parse_xyz("clamp(z, x, y)"), at(-1, 1, -2)) == std::vector<double>{1, 0, 0});
  CHECK(exact_gradient(parse_xyz("clamp(z, x, y)"), at(-1, 1, 0.5)) ==
        std::vector<double>{0, 0, 1});
  CHECK(exact_gradient(parse_xyz("clamp(z, x, y)"), at(-1, 1, 2)) == std::vector<double>{0, 1, 0});
  CHECK(exact_gradient(parse_xyz("clamp(z, x, y)"), at(-1, 1, 1)) == std::vector<double>{0, 0, 1});
  CHECK(exact_gradient(parse_xyz("clamp(z, x, y)"), at(-1, 1, -1)) == std::vector<double>{1, 0, 0});
  // min and max: the argument returned; abs from 0 on the right-hand one.
  CHECK(exact_gradient(parse_xyz("min(x, y)"), at(1, 2, 0)) == std::vector<double>{1, 0, 0});
  CHECK(exact_gradient(parse_xyz("min(x, y)"), at(3, 2, 0)) == std::vector<double>{0, 1, 0});
  CHECK(exact_gradient(parse_xyz("max(x, y)"), at(1, 2, 0)) == std::vector<double>{0, 1, 0});
  CHECK(exact_gradient(parse_xyz("max(x, y)"), at(3, 2, 0)) == std::vector<double>{1, 0, 0});
  CHECK(exact_gradient(parse_xyz("abs(x)"), at(-2, 0, 0)) == std::vector<double>{-1, 0, 0});
  CHECK(exact_gradient(parse_xyz("abs(x)"), at(0, 0, 0)) == std::vector<double>{1, 0, 0});
  CHECK(exact_gradient(parse_xyz("step(x) + sign(y)"), at(0, 1, 0)) ==
        std::vector<double>{0, 0, 0});
  // A constant exponent's log of a negative base is never read; a base that is a constant,
  // its own.
  CHECK(exact_gradient(parse_xyz("x ^ 2"), at(-3, 0, 0)) == std::vector<double>{-6, 0, 0});
  check_gradient("(-2) ^ 3 * x", at(0.3, 1, 1));
  // A partial derivative that is infinite multiplies only the non-zero entries of its
  // argument's gradient: x·|(x, y)| at the origin, whose derivatives are 0.
  CHECK(exact_gradient(parse_xyz("x * sqrt(x ^ 2 + y ^ 2) + z"), at(0, 0, 1)) ==
        std::vector<double>{0, 0, 1});
  // Constants alone: a gradient of nothing, a value.
  const sim::Expression c = sim::Expression::constant(4.0);
  CHECK(c.symbols().empty());
  CHECK(c.evaluate(Point{}, nullptr) == 4.0);
}

namespace {

// The trike with force elements `forces` (JSON), its variable speed = 5.
sim::Scenario trike_with(const std::string& forces) {
  return sim::parse_scenario(
      R"j({"model": "trike", "variables": {"speed": 5}, "t_end": 1, "forces": [)j" + forces + "]}",
      "test.json");
}

// A state of the trike near its initial one, moving.
State random_trike_state(runtime::MultibodySystem& system, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  State s = system.initial_state();
  s.t = 0.5 * (1.0 + u(rng));
  for (int j = 0; j < s.q.size(); ++j) {
    s.q(j) += 0.3 * u(rng);
    s.qd(j) = 2.0 * u(rng);
  }
  return s;
}

// The kinematics of the system's model at s, with their derivatives.
struct KinematicsAt {
  runtime::Kinematics k;
  runtime::KinematicsDerivatives dk;
  KinematicsAt(const runtime::Model& m, const State& s)
      : k(m.nq(), m.nbody(), m.ndep()), dk(m.nq(), m.nbody()) {
    m.velocities(s.t, s.q.data(), s.qd.data(), k);
    m.partial_velocities(s.t, s.q.data(), k);
    m.kinematics_derivatives(s.t, s.q.data(), s.qd.data(), dk);
  }
};

// The generalized forces of the system's one force element at s: its loads projected,
// Q_j = Σ_i F_i·dv_ij + M_i·dw_ij + Q_j.
Vector element_Q(runtime::MultibodySystem& system, const State& s) {
  const runtime::Model& m = system.model();
  const KinematicsAt at(m, s);
  runtime::Loads loads(m.nq(), m.nbody());
  system.force_elements().front()->apply(s, at.k, loads);
  Vector Q = loads.Q;
  for (int j = 0; j < m.nq(); ++j) {
    for (int i = 0; i < m.nbody(); ++i) {
      Q(j) += loads.F.col(i).dot(at.k.dv_dqd(i, j)) + loads.M.col(i).dot(at.k.dw_dqd(i, j));
    }
  }
  return Q;
}

// The trike with one force element (JSON): its exact ∂Q/∂q and ∂Q/∂qd against Richardson
// differences of its Q at random states; `check` sees the exact ones.
template <class Check>
void check_element_derivatives(const std::string& element, std::mt19937& rng, Check check) {
  CAPTURE(element);
  sim::Simulation sim(trike_with(element));
  runtime::MultibodySystem& system = sim.system();
  CHECK(system.jacobian_method() == "exact (emitted derivatives)");
  const runtime::ForceElement& e = *system.force_elements().front();
  REQUIRE(e.load_derivatives() != runtime::LoadDerivatives::differenced);
  const int n = system.model().nq();
  for (int round = 0; round < 4; ++round) {
    const State s = random_trike_state(system, rng);
    const KinematicsAt at(system.model(), s);
    Matrix dQ_dq = Matrix::Zero(n, n), dQ_dqd = Matrix::Zero(n, n);
    e.add_load_derivatives(s, at.k, at.dk, dQ_dq, dQ_dqd);
    Matrix Kd(n, n), Cd(n, n);
    for (int j = 0; j < n; ++j) {
      const auto along = [&](Vector State::*member) {
        return [&, member](double x) {
          State p = s;
          (p.*member)(j) = x;
          return element_Q(system, p);
        };
      };
      Kd.col(j) = richardson(along(&State::q), s.q(j), 1e-4);
      Cd.col(j) = richardson(along(&State::qd), s.qd(j), 1e-4);
    }
    const double scale = std::max({1.0, Kd.cwiseAbs().maxCoeff(), Cd.cwiseAbs().maxCoeff()});
    CHECK((dQ_dq - Kd).cwiseAbs().maxCoeff() < 1e-7 * scale);
    CHECK((dQ_dqd - Cd).cwiseAbs().maxCoeff() < 1e-7 * scale);
    check(dQ_dq, dQ_dqd);
  }
}

// Each kind of quantity a force law reads: coordinates and rates by name, time,
// variables, and every kind of body quantity (G, its velocity, the angular velocity,
// the velocity in body axes, the rotation), through every function.
const char* const laws[] = {
    "clamp(50 * (speed - chassis.ux), -100, 100)",
    "3 * yaw * steer_dot + sin(t) * x - 2 * roll ^ 2",
    "chassis.x * chassis.y - exp(chassis.z) + front_wheel.z",
    "chassis.vx * chassis.vy + 2 * left_rear_wheel.vz",
    "chassis.wx - chassis.wy * front_wheel.wz + abs(left_rear_wheel.wy)",
    "chassis.ux + chassis.uy ^ 2 + front_wheel.uz * rear_axle.ux",
    "chassis.R00 + chassis.R01 * chassis.R12 - front_wheel.R20 + rear_axle.R21 * chassis.R22",
    "atan2(chassis.vy, chassis.vx) + sqrt(1 + chassis.wz ^ 2) / (2 + cos(steer))",
    "max(-5, min(chassis.uy, 5)) * tan(0.2 * pitch) + log(2 + sign(yaw)) * step(t - 0.5)",
    "asin(0.5 * sin(roll)) - acos(0.5 * cos(front_travel)) + atan(chassis.R10)",
};

}  // namespace

TEST_CASE("a coordinate force's exact derivatives equal Richardson differences of its Q",
          "[scenario][derivatives]") {
  std::mt19937 rng(3);
  for (const char* law : laws) {
    check_element_derivatives(fmt::format(R"j({{"type": "coordinate_force", "name": "f",
                          "coordinates": ["left_spin", "steer"], "value": "{}"}})j",
                                          law),
                              rng, [](const Matrix& dQ_dq, const Matrix& dQ_dqd) {
                                // Its two coordinates alone receive it, equally.
                                CHECK(dQ_dq.row(8) == dQ_dq.row(10));
                                CHECK(dQ_dqd.row(8) == dQ_dqd.row(10));
                                CHECK(dQ_dq.row(0).isZero());
                              });
  }
}

TEST_CASE("a point load's exact derivatives equal Richardson differences of its Q",
          "[scenario][derivatives]") {
  // Its force and torque laws read the state: their derivatives and the point's motion.
  std::mt19937 rng(5);
  for (const char* law : laws) {
    check_element_derivatives(fmt::format(R"j({{"type": "point_load", "name": "f",
                          "at": {{"body": "front_wheel", "point": [0.1, -0.05, 0.2]}},
                          "force": ["{}", "2 * chassis.vz - steer", 30],
                          "torque": [0, "{}", "yaw_dot"]}})j",
                                          law, law),
                              rng, [](const Matrix&, const Matrix&) {});
  }
}

TEST_CASE("a coordinate force of the state alone needs no kinematics' derivatives",
          "[scenario][derivatives]") {
  sim::Simulation sim(trike_with(
      R"j({"type": "coordinate_force", "name": "f", "coordinates": "steer",
           "value": "-200 * steer - 10 * steer_dot * abs(steer_dot) + speed * t"})j"));
  const runtime::ForceElement& element = *sim.system().force_elements().front();
  CHECK(element.load_derivatives() == runtime::LoadDerivatives::exact);
  CHECK(element.reads() == runtime::KinematicsLevel::none);
}

TEST_CASE("a law whose derivative is not finite is refused, naming its element and its law",
          "[scenario][derivatives]") {
  sim::Simulation sim(trike_with(
      R"j({"type": "coordinate_force", "name": "f", "coordinates": "steer",
           "value": "-sqrt(abs(steer))"})j"));
  runtime::MultibodySystem& system = sim.system();
  State s = system.initial_state();
  s.q(10) = 0.0;  // steer: sqrt's derivative at 0
  Vector qdd, yd;
  system.accelerations(s, qdd, yd);
  Matrix M, C, K;
  CHECK_THROWS_WITH(system.jacobians(s, qdd, M, C, K),
                    Catch::Matchers::Contains("coordinate force 'f'") &&
                        Catch::Matchers::Contains("'-sqrt(abs(steer))' is not finite"));
  // Beside 0, its derivative.
  s.q(10) = 0.01;
  const KinematicsAt at(system.model(), s);
  Matrix dQ_dq = Matrix::Zero(13, 13), dQ_dqd = Matrix::Zero(13, 13);
  system.force_elements().front()->add_load_derivatives(s, at.k, at.dk, dQ_dq, dQ_dqd);
  CHECK(dQ_dq(10, 10) == Approx(-0.5 / std::sqrt(0.01)));
}

TEST_CASE("the trike scenario's Jacobians are exact, its drive included",
          "[scenario][derivatives]") {
  sim::Simulation sim(sim::find_builtin("trike"));
  runtime::MultibodySystem& system = sim.system();
  CHECK(system.jacobian_method() == "exact (emitted derivatives)");
  for (int round = 0; round < 3; ++round) {
    State s = system.initial_state();
    s.t = 1.1;                      // steering
    s.q(2) -= 0.01 + 0.01 * round;  // the wheels into the ground: the tyres push
    s.q(10) = 0.05;
    s.qd(0) = 4.0 + round;  // the drive between its bounds (chassis.ux near speed = 5)
    s.qd(10) = 0.3;
    for (int spin : {8, 9, 12}) s.qd(spin) = s.qd(0) / 0.3;  // rolling (radius 0.3)
    Vector qdd, yd;
    system.accelerations(s, qdd, yd);
    Matrix M, C, K;
    system.jacobians(s, qdd, M, C, K);
    // Steps small enough to stay on each side of the tyres' and the drive's switches.
    Matrix Kd, Cd;
    symdyn::testing::residual_jacobians_by_differences(system, s, qdd, Cd, Kd,
                                                       [](double) { return 1e-5; });
    const double scale = std::max({1.0, Kd.cwiseAbs().maxCoeff(), Cd.cwiseAbs().maxCoeff()});
    CAPTURE(round, scale);
    CHECK((K - Kd).cwiseAbs().maxCoeff() < 1e-7 * scale);
    CHECK((C - Cd).cwiseAbs().maxCoeff() < 1e-7 * scale);
  }
}

TEST_CASE("the trike's run summary names no element differenced", "[scenario][derivatives]") {
  sim::RunOptions o;
  o.t_end = 1.0;  // the scenario's checks read t_end - 1
  o.integrator = "newmark";
  const sim::RunResult r = sim::run_scenario(sim::find_builtin("trike"), o);
  CHECK(r.jacobians == "exact (emitted derivatives)");
  CHECK(sim::summary(r).find("central differences") == std::string::npos);
}
