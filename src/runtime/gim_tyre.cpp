#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

#include <symdyn/runtime/element_properties.hpp>
#include <symdyn/runtime/gim_tyre.hpp>

namespace symdyn::runtime {

// Derivation of the brush formulas of the header. Per unit of xi, adhesion
// stresses are the bristle stiffness times deflections, linear in xi for the
// slips (deflection grows from 0 at the leading edge) and parabolic for
// camber (the carcass' lateral offset under camber vanishes at both edges);
// their constants make the small-slip forces C_long s_long, C_lat s_lat and
// C_camber gamma. Integrating them over [0, xi_s], and the friction limit
// over [xi_s, 1], gives Fx and Fy; weighting the lateral stress by the
// lever arm a (1 - 2 xi) about the contact centre gives Mz.
BrushOutput gim_brush(const BrushInput& in) {
  BrushOutput out;
  const double Fz = in.normal_force;
  if (!(Fz > 0.0)) return out;
  const double X = in.stiffness_long * in.slip_long;
  const double Y = in.stiffness_lat * in.slip_lat;
  const double G = in.stiffness_camber * in.camber;
  const double L = 3.0 * in.friction * Fz;
  const double muFz = in.friction * Fz;

  double u = 1.0;  // 1 - xi_s
  if (X * X + (Y + 3.0 * G) * (Y + 3.0 * G) >= L * L) {
    out.sliding = true;
  } else {
    // (L^2 - 9 G^2) u^2 - 6 Y G u - (X^2 + Y^2) = 0: the root where the
    // quadratic turns positive (adhesion holds for u in [u_s, 1]).
    const double A = L * L - 9.0 * G * G;
    const double B = -6.0 * Y * G;
    const double C0 = -(X * X + Y * Y);
    if (std::abs(A) <= 1e-14 * L * L) {
      u = B != 0.0 ? -C0 / B : 0.0;
    } else {
      const double sq = std::sqrt(std::max(0.0, B * B - 4.0 * A * C0));
      // The root with 2 A u + B = +sq, in the form that avoids cancellation.
      u = B <= 0.0 ? (-B + sq) / (2.0 * A) : (2.0 * C0) / (-B - sq);
    }
    u = std::clamp(u, 0.0, 1.0);
  }
  const double xs = 1.0 - u;
  out.adhesion = xs;
  const double xs2 = xs * xs, xs3 = xs2 * xs;
  const double S = 1.0 - 3.0 * xs2 + 2.0 * xs3;
  double tx = X, ty = Y + 3.0 * G * u;
  const double tn = std::hypot(tx, ty);
  if (tn > 0.0) {
    tx /= tn;
    ty /= tn;
  } else {
    tx = ty = 0.0;
  }
  out.Fx = -(X * xs2 + muFz * tx * S);
  out.Fy = -(Y * xs2 + G * (3.0 * xs2 - 2.0 * xs3) + muFz * ty * S);
  out.Mz = -in.half_length * (Y * (xs2 - 4.0 / 3.0 * xs3) + 3.0 * (G - muFz * ty) * xs2 * u * u);
  return out;
}

GimTyre::GimTyre(std::string name, int body, const GimTyreProperties& p, const Plane& ground)
    : name_(std::move(name)), body_(body), p_(p), ground_(ground) {
  const std::string me = this->name();
  check_property(me, "r1", p_.r1, Sign::positive);
  check_property(me, "r2", p_.r2, Sign::positive);
  if (!(p_.r2 <= p_.r1)) {
    throw PropertyError(
        me, "r2",
        fmt::format("expected the section radius <= r1 = {:.6g}, found {:.6g}", p_.r1, p_.r2));
  }
  check_property(me, "Kz", p_.Kz, Sign::positive);
  check_property(me, "Cz", p_.Cz, Sign::non_negative);
  check_property(me, "Fznom", p_.Fznom, Sign::positive);
  check_property(me, "Clongnom", p_.Clongnom, Sign::non_negative);
  check_property(me, "nlong", p_.nlong);
  check_property(me, "Clatnom", p_.Clatnom, Sign::non_negative);
  check_property(me, "nlat", p_.nlat);
  check_property(me, "Ccambernom", p_.Ccambernom);
  check_property(me, "ncamber", p_.ncamber);
  check_property(me, "mu_static", p_.mu_static, Sign::non_negative);
  check_property(me, "mu_dynamic", p_.mu_dynamic, Sign::non_negative);
  check_direction(me, "axis", p_.axis);
  check_property(me, "centre", p_.centre);
  check_plane(me, ground_);
  ground_.normal.normalize();
  p_.axis.normalize();
}

GimTyre::Result GimTyre::evaluate(const Kinematics& k) const {
  Result r;
  const Vec3& n = ground_.normal;
  const Vec3 C = k.point_position(body_, p_.centre);
  const Vec3 e = k.to_global(body_, p_.axis);
  const Vec3 d = (n - n.dot(e) * e).normalized();
  r.contact_point = C - (p_.r1 - p_.r2) * d - p_.r2 * n;
  r.penetration = -(r.contact_point - ground_.point).dot(n);
  r.x = e.cross(n).normalized();
  r.y = n.cross(r.x);
  r.camber = std::asin(std::clamp(e.dot(n), -1.0, 1.0));
  if (r.penetration <= 0.0) return r;

  const Vec3 vP = k.velocity_at(body_, r.contact_point);
  const Vec3 vC = k.velocity_at(body_, C);
  const double V = std::max(std::abs(vC.dot(r.x)), 1e-3);
  r.slip_long = vP.dot(r.x) / V;
  r.slip_lat = vP.dot(r.y) / V;
  const double elastic = p_.Kz * r.penetration;
  r.Fz = std::max(0.0, elastic - std::sqrt(elastic / p_.Fznom) * p_.Cz * vP.dot(n));
  if (r.Fz <= 0.0) return r;
  const double slip = std::min(1.0, std::hypot(r.slip_long, r.slip_lat));
  r.friction = p_.mu_static - (p_.mu_static - p_.mu_dynamic) * slip;
  const double load = r.Fz / p_.Fznom;
  BrushInput in;
  in.normal_force = r.Fz;
  in.slip_long = r.slip_long;
  in.slip_lat = r.slip_lat;
  in.camber = r.camber;
  in.friction = r.friction;
  in.stiffness_long = p_.Clongnom * std::pow(load, p_.nlong);
  in.stiffness_lat = p_.Clatnom * std::pow(load, p_.nlat);
  in.stiffness_camber = p_.Ccambernom * std::pow(load, p_.ncamber);
  in.half_length = std::sqrt(2.0 * p_.r1 * r.penetration);
  r.brush = gim_brush(in);
  r.force = r.brush.Fx * r.x + r.brush.Fy * r.y + r.Fz * n;
  r.moment = r.brush.Mz * n;
  return r;
}

void GimTyre::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const Result r = evaluate(k);
  if (r.Fz <= 0.0) return;
  loads.add_force_at(body_, k, r.contact_point, r.force);
  loads.add_moment(body_, r.moment);
}

}  // namespace symdyn::runtime
