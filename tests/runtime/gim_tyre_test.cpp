#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "fixtures/rigid_body.hpp"
#include "test_util.hpp"
#include <symdyn/runtime/gim_tyre.hpp>
#include <symdyn/runtime/multibody_system.hpp>

using namespace symdyn::runtime;
using namespace symdyn::runtime::test;
namespace fx = symdyn_fixtures;

namespace {

BrushInput base() {
  BrushInput in;
  in.normal_force = 1000.0;
  in.friction = 1.0;
  in.stiffness_long = 30000.0;
  in.stiffness_lat = 20000.0;
  in.stiffness_camber = 1000.0;
  in.half_length = 0.05;
  return in;
}

// The brush integrated bristle by bristle (midpoint rule over xi): adhesion
// stress while within the friction limit and no bristle ahead has slid, the
// friction limit in the direction of the stress at the first sliding bristle
// afterwards. Independent of the closed forms of gim_brush.
BrushOutput integrate_brush(const BrushInput& in, int n = 200000) {
  const double X = in.stiffness_long * in.slip_long, Y = in.stiffness_lat * in.slip_lat;
  const double G = in.stiffness_camber * in.camber, mu = in.friction, Fz = in.normal_force;
  BrushOutput out;
  bool sliding = false;
  double tx = 0, ty = 0;
  for (int i = 0; i < n; ++i) {
    const double xi = (i + 0.5) / n, dxi = 1.0 / n;
    double sx = 2 * X * xi, sy = 2 * Y * xi + 6 * G * xi * (1 - xi);
    const double limit = 6 * mu * Fz * xi * (1 - xi);
    if (!sliding && std::hypot(sx, sy) > limit) {
      sliding = true;
      out.adhesion = xi;
      const double nrm = std::hypot(sx, sy);
      tx = sx / nrm;
      ty = sy / nrm;
    }
    if (sliding) {
      sx = limit * tx;
      sy = limit * ty;
    }
    out.Fx -= sx * dxi;
    out.Fy -= sy * dxi;
    out.Mz -= in.half_length * (1 - 2 * xi) * sy * dxi;
  }
  return out;
}

}  // namespace

TEST_CASE("Gim brush: hand-computed cases", "[runtime][gim]") {
  SECTION("longitudinal slip, half the contact adhering") {
    BrushInput in = base();
    in.slip_long = 0.05;  // X = 1500 = half of 3 mu Fz: xi_s = 0.5
    const BrushOutput out = gim_brush(in);
    CHECK(out.adhesion == Approx(0.5));
    CHECK_FALSE(out.sliding);
    CHECK(out.Fx == Approx(-(1500 * 0.25 + 1000 * (1 - 0.75 + 0.25))));  // -875
    CHECK(out.Fy == 0.0);
    CHECK(out.Mz == 0.0);
  }
  SECTION("lateral slip: force and aligning moment") {
    BrushInput in = base();
    in.slip_lat = 0.075;  // Y = 1500: xi_s = 0.5
    const BrushOutput out = gim_brush(in);
    CHECK(out.Fy == Approx(-875.0));
    // Mz = -a (Y (1/4 - 1/6) - 3 mu Fz (1/4)(1/4)) = 62.5 a
    CHECK(out.Mz == Approx(62.5 * 0.05));
  }
  SECTION("small slips: linear stiffnesses and a trail of a/3") {
    BrushInput in = base();
    in.slip_long = 1e-7;
    in.slip_lat = -2e-7;
    const BrushOutput out = gim_brush(in);
    CHECK(out.Fx == Approx(-30000 * 1e-7).epsilon(1e-5));
    CHECK(out.Fy == Approx(20000 * 2e-7).epsilon(1e-5));
    CHECK(out.Mz == Approx(-out.Fy * 0.05 / 3.0).epsilon(1e-5));
  }
  SECTION("camber alone, in full adhesion") {
    BrushInput in = base();
    in.camber = 0.01;
    const BrushOutput out = gim_brush(in);
    CHECK(out.adhesion == 1.0);
    CHECK(out.Fy == Approx(-10.0));
    CHECK(out.Mz == Approx(0.0).margin(1e-15));
  }
  SECTION("full sliding") {
    BrushInput in = base();
    in.slip_long = 0.2;
    in.slip_lat = 0.15;  // X = 6000, Y = 3000: beyond 3 mu Fz
    const BrushOutput out = gim_brush(in);
    CHECK(out.sliding);
    CHECK(out.adhesion == 0.0);
    CHECK(out.Fx == Approx(-1000 * 6000 / std::hypot(6000, 3000)));
    CHECK(out.Fy == Approx(-1000 * 3000 / std::hypot(6000, 3000)));
    CHECK(out.Mz == 0.0);
  }
  SECTION("no load, no force") {
    BrushInput in = base();
    in.normal_force = 0.0;
    in.slip_long = 0.1;
    const BrushOutput out = gim_brush(in);
    CHECK(out.Fx == 0.0);
  }
}

TEST_CASE("Gim brush agrees with the brush integrated bristle by bristle", "[runtime][gim]") {
  for (int trial = 0; trial < 60; ++trial) {
    BrushInput in = base();
    in.slip_long = uniform(-0.15, 0.15);
    in.slip_lat = uniform(-0.15, 0.15);
    in.camber = uniform(-0.3, 0.3);
    in.friction = uniform(0.5, 1.2);
    const BrushOutput a = gim_brush(in);
    const BrushOutput b = integrate_brush(in);
    const double scale = in.friction * in.normal_force;
    CHECK(std::abs(a.Fx - b.Fx) < 2e-4 * scale);
    CHECK(std::abs(a.Fy - b.Fy) < 2e-4 * scale);
    CHECK(std::abs(a.Mz - b.Mz) < 2e-4 * scale * in.half_length);
    CHECK(std::abs(a.adhesion - b.adhesion) < 1e-4);
  }
}

TEST_CASE("Gim brush is continuous at the boundary of full sliding", "[runtime][gim]") {
  for (int trial = 0; trial < 100; ++trial) {
    BrushInput in = base();
    const double angle = uniform(-3.14, 3.14);
    in.camber = uniform(-0.2, 0.2);
    // Find the slip magnitude r on the boundary X^2 + (Y + 3G)^2 = (3 mu Fz)^2
    // along the direction (cos, sin) by bisection, then step across it.
    auto outside = [&](double r) {
      const double X = 30000 * r * std::cos(angle), Y = 20000 * r * std::sin(angle);
      const double G = 1000 * in.camber;
      return X * X + (Y + 3 * G) * (Y + 3 * G) >= 9e6;
    };
    double lo = 0, hi = 1;
    if (outside(lo)) continue;  // camber alone already slides
    // 45 halvings leave a gap of 3e-14 across the boundary (rounding-proof).
    for (int it = 0; it < 45; ++it) (outside(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    BrushInput a = in, b = in;
    a.slip_long = lo * std::cos(angle);
    a.slip_lat = lo * std::sin(angle);
    b.slip_long = hi * std::cos(angle);
    b.slip_lat = hi * std::sin(angle);
    const BrushOutput fa = gim_brush(a), fb = gim_brush(b);
    CHECK_FALSE(fa.sliding);
    CHECK(fb.sliding);
    CHECK(std::abs(fa.Fx - fb.Fx) < 1e-4);
    CHECK(std::abs(fa.Fy - fb.Fy) < 1e-4);
    CHECK(std::abs(fa.Mz - fb.Mz) < 1e-4);
    CHECK(std::hypot(fb.Fx, fb.Fy) == Approx(1000.0));
  }
}

TEST_CASE("Gim tyre: geometry, slips and load on a rolling wheel", "[runtime][gim]") {
  MultibodySystem sys(Model::from<fx::rigid_body>());
  GimTyreProperties p;
  p.r1 = 0.3;
  p.r2 = 0.1;
  p.Kz = 2e5;
  p.Cz = 800;
  p.Fznom = 3000;
  p.Clongnom = 5e4;
  p.nlong = 0.8;
  p.Clatnom = 4e4;
  p.nlat = 0.9;
  p.Ccambernom = 2e3;
  p.ncamber = 1.1;
  p.mu_static = 1.0;
  p.mu_dynamic = 0.8;
  auto tyre = sys.add<GimTyre>("rear", 0, p);
  // Upright wheel, axle y, centre 0.29 above ground: penetration 0.01; moving
  // at (10, 0.5, 0), spinning at 30 rad/s about y: vP = (10 - 9, 0.5, 0).
  Vector q(6), qd(6);
  q << 0, 0, 0.29, 0, 0, 0;
  qd << 10, 0.5, 0, 0, 30, 0;
  Vector Q;
  sys.applied_forces(make_state(0, q, qd), Q);
  const GimTyre::Result r = tyre->evaluate(sys.kinematics());
  CHECK(r.penetration == Approx(0.01));
  CHECK((r.contact_point - Vec3(0, 0, -0.01)).norm() < 1e-15);
  CHECK(r.slip_long == Approx(0.1));
  CHECK(r.slip_lat == Approx(0.05));
  CHECK(r.camber == 0.0);
  CHECK(r.Fz == Approx(2000.0));
  CHECK(r.friction == Approx(1.0 - 0.2 * std::hypot(0.1, 0.05)));
  BrushInput in;
  in.normal_force = 2000;
  in.slip_long = 0.1;
  in.slip_lat = 0.05;
  in.friction = r.friction;
  in.stiffness_long = 5e4 * std::pow(2.0 / 3.0, 0.8);
  in.stiffness_lat = 4e4 * std::pow(2.0 / 3.0, 0.9);
  in.stiffness_camber = 2e3 * std::pow(2.0 / 3.0, 1.1);
  in.half_length = std::sqrt(2 * 0.3 * 0.01);
  const BrushOutput b = gim_brush(in);
  const Vec3 F(b.Fx, b.Fy, 2000.0);
  CHECK((sys.loads().F.col(0) - F).norm() < 1e-9);
  CHECK((sys.loads().M.col(0) - (Vec3(0, 0, -0.3).cross(F) + Vec3(0, 0, b.Mz))).norm() < 1e-9);

  // Roll by 0.1 about x: camber 0.1; sinking at 0.2 m/s adds damping
  // sqrt(Kz pen / Fznom) Cz 0.2.
  q << 0, 0, 0.25, 0, 0, 0.1;
  qd << 0, 0, -0.2, 0, 0, 0;
  sys.applied_forces(make_state(0, q, qd), Q);
  const GimTyre::Result c = tyre->evaluate(sys.kinematics());
  CHECK(c.camber == Approx(0.1));
  const Vec3 d = Vec3(0, -std::sin(0.1), std::cos(0.1));  // unit(z - (z.e) e)
  const Vec3 P = Vec3(0, 0, 0.25) - 0.2 * d - Vec3(0, 0, 0.1);
  CHECK((c.contact_point - P).norm() < 1e-14);
  const double pen = -P.z();
  CHECK(c.Fz == Approx(2e5 * pen + std::sqrt(2e5 * pen / 3000) * 800 * 0.2));
  // Lifted: nothing.
  q(2) = 0.5;
  sys.applied_forces(make_state(0, q, qd), Q);
  CHECK(sys.loads().F.col(0).norm() == 0.0);
}
