#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

#include <symdyn/runtime/element_parameters.hpp>
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
template <class T>
BasicBrushOutput<T> gim_brush(const BasicBrushInput<T>& in) {
  using std::abs, std::sqrt;
  BasicBrushOutput<T> out;
  const T Fz = in.normal_force;
  if (!(Fz > 0.0)) return out;
  const T X = in.stiffness_long * in.slip_long;
  const T Y = in.stiffness_lat * in.slip_lat;
  const T G = in.stiffness_camber * in.camber;
  const T L = 3.0 * in.friction * Fz;
  const T muFz = in.friction * Fz;

  T u = T(1.0);  // 1 - xi_s
  if (X * X + (Y + 3.0 * G) * (Y + 3.0 * G) >= L * L) {
    out.sliding = true;
  } else {
    // (L^2 - 9 G^2) u^2 - 6 Y G u - (X^2 + Y^2) = 0: the root where the
    // quadratic turns positive (adhesion holds for u in [u_s, 1]).
    const T A = L * L - 9.0 * G * G;
    const T B = -6.0 * Y * G;
    const T C0 = -(X * X + Y * Y);
    if (abs(A) <= 1e-14 * L * L) {
      u = B != 0.0 ? T(-C0 / B) : T(0.0);
    } else {
      const T discriminant = B * B - 4.0 * A * C0;
      const T sq = discriminant > 0.0 ? T(sqrt(discriminant)) : T(0.0);
      // The root with 2 A u + B = +sq, in the form that avoids cancellation.
      u = B <= 0.0 ? T((-B + sq) / (2.0 * A)) : T((2.0 * C0) / (-B - sq));
    }
    u = std::clamp(u, T(0.0), T(1.0));
  }
  const T xs = 1.0 - u;
  out.adhesion = xs;
  const T xs2 = xs * xs, xs3 = xs2 * xs;
  const T S = 1.0 - 3.0 * xs2 + 2.0 * xs3;
  T tx = X, ty = Y + 3.0 * G * u;
  const T tn2 = tx * tx + ty * ty;
  if (tn2 > 0.0) {
    const T tn = sqrt(tn2);
    tx = tx / tn;
    ty = ty / tn;
  } else {
    tx = ty = T(0.0);
  }
  out.Fx = -(X * xs2 + muFz * tx * S);
  out.Fy = -(Y * xs2 + G * (3.0 * xs2 - 2.0 * xs3) + muFz * ty * S);
  out.Mz = -in.half_length * (Y * (xs2 - 4.0 / 3.0 * xs3) + 3.0 * (G - muFz * ty) * xs2 * u * u);
  return out;
}

BrushOutput gim_brush(const BrushInput& in) {
  return gim_brush<double>(in);
}

GimTyre::GimTyre(std::string name, int body, const GimTyreProperties& p, const Plane& ground)
    : name_(std::move(name)), body_(body), p_(p), ground_(ground) {
  const std::string me = this->name();
  check_parameter(me, "gim_tyre", "r1", p_.r1);
  check_parameter(me, "gim_tyre", "r2", p_.r2);
  if (!(p_.r2 <= p_.r1)) {
    throw PropertyError(
        me, "r2",
        fmt::format("expected the section radius <= r1 = {:.6g}, found {:.6g}", p_.r1, p_.r2));
  }
  check_parameter(me, "gim_tyre", "Kz", p_.Kz);
  check_parameter(me, "gim_tyre", "Cz", p_.Cz);
  check_parameter(me, "gim_tyre", "Fznom", p_.Fznom);
  check_parameter(me, "gim_tyre", "Clongnom", p_.Clongnom);
  check_parameter(me, "gim_tyre", "nlong", p_.nlong);
  check_parameter(me, "gim_tyre", "Clatnom", p_.Clatnom);
  check_parameter(me, "gim_tyre", "nlat", p_.nlat);
  check_parameter(me, "gim_tyre", "Ccambernom", p_.Ccambernom);
  check_parameter(me, "gim_tyre", "ncamber", p_.ncamber);
  check_parameter(me, "gim_tyre", "mu_static", p_.mu_static);
  check_parameter(me, "gim_tyre", "mu_dynamic", p_.mu_dynamic);
  check_parameter(me, "gim_tyre", "axis", p_.axis);
  check_parameter(me, "gim_tyre", "centre", p_.centre);
  check_plane(me, ground_);
  ground_.normal.normalize();
  p_.axis.normalize();
}

template <class T>
GimTyre::BasicResult<T> GimTyre::evaluate(const BodyMotion<T>& wheel) const {
  using std::abs, std::asin, std::pow, std::sqrt;
  BasicResult<T> r;
  const Vec3T<T> n = ground_.normal.cast<T>();
  const Vec3T<T> C = wheel.point(p_.centre);
  const Vec3T<T> e = wheel.to_global(p_.axis);
  const Vec3T<T> d = (n - n.dot(e) * e).normalized();
  r.contact_point = C - (p_.r1 - p_.r2) * d - p_.r2 * n;
  r.penetration = -(r.contact_point - ground_.point.cast<T>()).dot(n);
  r.x = e.cross(n).normalized();
  r.y = n.cross(r.x);
  r.camber = asin(std::clamp(T(e.dot(n)), T(-1.0), T(1.0)));
  if (r.penetration <= 0.0) return r;

  const Vec3T<T> vP = wheel.velocity_at(r.contact_point);
  const Vec3T<T> vC = wheel.velocity_at(C);
  const T forward = abs(vC.dot(r.x));
  const T V = forward > 1e-3 ? forward : T(1e-3);
  r.slip_long = vP.dot(r.x) / V;
  r.slip_lat = vP.dot(r.y) / V;
  const T elastic = p_.Kz * r.penetration;
  const T Fz = elastic - sqrt(elastic / p_.Fznom) * p_.Cz * vP.dot(n);
  if (Fz <= 0.0) return r;
  r.Fz = Fz;
  // min(1, |slip|), its derivative taken 0 at zero slip (the tip of mu's cone).
  const T slip2 = r.slip_long * r.slip_long + r.slip_lat * r.slip_lat;
  const T slip = slip2 >= 1.0 ? T(1.0) : slip2 > 0.0 ? T(sqrt(slip2)) : T(0.0);
  r.friction = p_.mu_static - (p_.mu_static - p_.mu_dynamic) * slip;
  const T load = r.Fz / p_.Fznom;
  BasicBrushInput<T> in;
  in.normal_force = r.Fz;
  in.slip_long = r.slip_long;
  in.slip_lat = r.slip_lat;
  in.camber = r.camber;
  in.friction = r.friction;
  in.stiffness_long = p_.Clongnom * pow(load, p_.nlong);
  in.stiffness_lat = p_.Clatnom * pow(load, p_.nlat);
  in.stiffness_camber = p_.Ccambernom * pow(load, p_.ncamber);
  in.half_length = sqrt(2.0 * p_.r1 * r.penetration);
  r.brush = gim_brush(in);
  r.force = r.brush.Fx * r.x + r.brush.Fy * r.y + r.Fz * n;
  r.moment = r.brush.Mz * n;
  return r;
}

GimTyre::Result GimTyre::evaluate(const Kinematics& k) const {
  return evaluate(body_motion(k, body_));
}

void GimTyre::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const Result r = evaluate(k);
  if (r.Fz <= 0.0) return;
  loads.add_force_at(body_, k, r.contact_point, r.force);
  loads.add_moment(body_, r.moment);
}

void GimTyre::add_load_derivatives(const State& /*s*/, const Kinematics& k,
                                   const KinematicsDerivatives& dk, Matrix& dQ_dq,
                                   Matrix& dQ_dqd) const {
  const auto wheel = seeded_motion<1>(k, body_, 0);
  const auto r = evaluate(wheel);
  if (!(r.Fz > 0.0)) return;
  const Wrench<MotionDual<1>> w{r.force, (r.contact_point - wheel.x).cross(r.force) + r.moment};
  add_wrench_derivatives<1>(k, dk, {body_}, {w}, dQ_dq, dQ_dqd);
}

}  // namespace symdyn::runtime
