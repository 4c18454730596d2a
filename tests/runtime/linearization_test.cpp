#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <sstream>

#include "fixtures/double_pendulum.hpp"
#include "fixtures/spring_mass.hpp"
#include "test_util.hpp"
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

using namespace symdyn::runtime;
using namespace symdyn::runtime::test;
namespace fx = symdyn_fixtures;

namespace {
State hanging() {
  Vector q(2);
  q << -std::numbers::pi / 2, 0.0;
  return make_state(0, q, Vector::Zero(2));
}
}  // namespace

TEST_CASE("Double pendulum: small oscillations about the hanging equilibrium",
          "[runtime][linearization]") {
  MultibodySystem dp(Model::from<fx::double_pendulum_absolute>());
  const Linearization lin = linearize(dp, hanging());
  // Closed form: M at q1 = 0 and K the Hessian of V = g (m1 y1 + m2 y2).
  const double g = 9.81, I = 1.0 / 12.0;
  Matrix M(2, 2), K(2, 2);
  M << 2 * I + 0.25 + 1 + 0.25 + 1, I + 0.25 + 0.5, I + 0.25 + 0.5, I + 0.25;
  K << g * (0.5 + 1 + 0.5), g * 0.5, g * 0.5, g * 0.5;
  CHECK((lin.M - M).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((lin.K - K).cwiseAbs().maxCoeff() < 1e-6);
  CHECK(lin.C.cwiseAbs().maxCoeff() < 1e-6);
  // omega^2: roots of det(K - w2 M) = 0.
  const double a = M.determinant(),
               b = -(K(0, 0) * M(1, 1) + K(1, 1) * M(0, 0) - 2 * K(0, 1) * M(0, 1));
  const double c = K.determinant();
  const double w2lo = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const double w2hi = (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const std::vector<Mode> ms = modes(lin);
  REQUIRE(ms.size() == 2);  // conjugate pairs listed once
  CHECK(ms[0].natural_frequency_hz ==
        Approx(std::sqrt(w2lo) / (2 * std::numbers::pi)).epsilon(1e-7));
  CHECK(ms[1].natural_frequency_hz ==
        Approx(std::sqrt(w2hi) / (2 * std::numbers::pi)).epsilon(1e-7));
  for (const Mode& m : ms) {
    CHECK(std::abs(m.damping_ratio) < 1e-6);
    CHECK(m.pole.imag() > 0);
    CHECK(m.damped_frequency_hz == Approx(m.natural_frequency_hz).epsilon(1e-7));
    // (K - w^2 M) psi = 0, psi normalized with largest entry 1.
    const double w2 = std::norm(m.pole);
    const Eigen::VectorXcd r = (K - w2 * M).cast<std::complex<double>>() * m.shape;
    CHECK(r.norm() < 1e-5);
    CHECK(m.shape.cwiseAbs().maxCoeff() == Approx(1.0));
    const double mm =
        std::abs((m.shape.transpose() * M.cast<std::complex<double>>() * m.shape)(0, 0));
    CHECK(m.modal_mass == Approx(mm).epsilon(1e-6));
  }
  // The low mode swings both rods the same way, the high one in opposition.
  CHECK(ms[0].shape(0).real() * ms[0].shape(1).real() > 0);
  CHECK(ms[1].shape(0).real() * ms[1].shape(1).real() < 0);

  SECTION("a locked coordinate is removed") {
    LinearizationOptions o;
    o.locked = {1};
    const Linearization l1 = linearize(dp, hanging(), o);
    CHECK(l1.coordinates == std::vector<std::string>{"q0"});
    const std::vector<Mode> m1 = modes(l1);
    REQUIRE(m1.size() == 1);
    CHECK(std::norm(m1[0].pole) == Approx(K(0, 0) / M(0, 0)).epsilon(1e-7));
  }
}

TEST_CASE("Damped oscillator: damping ratio and input matrix", "[runtime][linearization]") {
  const double k = 4.0 * std::numbers::pi * std::numbers::pi, c = 1.5;
  MultibodySystem sm(Model::from<fx::spring_mass>());
  sm.add<CoordinateSpringDamper>("spring", 0, k, c, 2.0);
  double u = 0.0;
  // A force u along the direction of motion (projected through the partials).
  sm.add<PointLoad>(
      "actuator", BodyPoint{0, Vec3::Zero()},
      [&](const State&, const Kinematics&, Vec3& f, Vec3&) { f = u * Vec3(1.0, 2.0, 2.0) / 3.0; });
  LinearizationOptions o;
  o.inputs.push_back(Input{"u", [&] { return u; }, [&](double v) { u = v; }});
  const Linearization lin =
      linearize(sm, make_state(0, Vector::Constant(1, 1.0), Vector::Zero(1)), o);
  CHECK(lin.B(0, 0) == Approx(1.0).epsilon(1e-8));
  CHECK(lin.Bx(1, 0) == Approx(1.0).epsilon(1e-8));  // m = 1
  CHECK(lin.A(1, 0) == Approx(-k).epsilon(1e-7));
  const std::vector<Mode> ms = modes(lin);
  REQUIRE(ms.size() == 1);
  CHECK(ms[0].natural_frequency_hz == Approx(1.0).epsilon(1e-7));
  CHECK(ms[0].damping_ratio == Approx(c / (2 * std::sqrt(k))).epsilon(1e-7));
  CHECK(ms[0].damped_frequency_hz ==
        Approx(std::sqrt(k - c * c / 4) / (2 * std::numbers::pi)).epsilon(1e-7));

  SECTION("CSV export of matrices and modes") {
    std::ostringstream mat, mod;
    write_matrices_csv(mat, lin);
    write_modes_csv(mod, lin, ms);
    std::istringstream lines(mat.str());
    std::string line;
    std::getline(lines, line);
    CHECK(line == "matrix,row,s");
    std::getline(lines, line);
    CHECK(line == "M,0,1");
    std::getline(lines, line);
    CHECK(line.rfind("C,0,1.5", 0) == 0);
    std::getline(lines, line);
    CHECK(line.rfind("K,0,39.47", 0) == 0);
    std::getline(lines, line);
    CHECK(line == "matrix,row,u");
    std::istringstream mlines(mod.str());
    std::getline(mlines, line);
    CHECK(line ==
          "mode,pole_re,pole_im,natural_frequency_hz,damped_frequency_hz,damping_ratio,"
          "modal_mass,s_re,s_im");
    std::getline(mlines, line);
    CHECK(line.rfind("0,-0.75", 0) == 0);
  }
}
