#include <algorithm>
#include <cmath>
#include <utility>

#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/element_parameters.hpp>

namespace symdyn::runtime {

void check_plane(const std::string& element, const Plane& plane) {
  check_property(element, "plane_point", plane.point);
  check_direction(element, "plane_normal", plane.normal);
}

PlaneContact::PlaneContact(std::string name, int body, const Vec3& point, double radius,
                           const Plane& plane, const ContactProperties& p)
    : name_(std::move(name)), body_(body), point_(point), radius_(radius), plane_(plane), p_(p) {
  const std::string me = this->name();
  check_parameter(me, "plane_contact", "point", point_);
  check_parameter(me, "plane_contact", "radius", radius_);
  check_plane(me, plane_);
  // N = Kn delta^pk + Cd delta^pd deltad: without Kn > 0 a body sinks through the plane.
  check_parameter(me, "plane_contact", "stiffness", p_.stiffness);
  check_parameter(me, "plane_contact", "stiffness_exponent", p_.stiffness_exponent);
  check_parameter(me, "plane_contact", "damping", p_.damping);
  check_parameter(me, "plane_contact", "damping_exponent", p_.damping_exponent);
  check_parameter(me, "plane_contact", "friction", p_.friction);
  check_parameter(me, "plane_contact", "slip_speed", p_.slip_speed);
  plane_.normal.normalize();
}

template <class T>
PlaneContact::BasicResult<T> PlaneContact::evaluate(const BodyMotion<T>& body) const {
  using std::pow, std::sqrt;
  BasicResult<T> r;
  const Vec3T<T> n = plane_.normal.cast<T>();
  const Vec3T<T> X = body.point(point_);
  r.penetration = radius_ - (X - plane_.point.cast<T>()).dot(n);
  r.contact_point = X - radius_ * n;
  if (r.penetration <= 0.0) return r;
  const Vec3T<T> vC = body.velocity_at(r.contact_point);
  r.penetration_rate = -vC.dot(n);
  const T N = p_.stiffness * pow(r.penetration, p_.stiffness_exponent) +
              p_.damping * pow(r.penetration, p_.damping_exponent) * r.penetration_rate;
  if (N <= 0.0) return r;
  r.normal_force = N;
  const Vec3T<T> vt = vC - vC.dot(n) * n;
  // reg(|vt|); |vt| is taken only where it is used (its derivative is singular at 0).
  const T speed2 = vt.squaredNorm(), vs2 = T(p_.slip_speed * p_.slip_speed);
  const T reg = p_.regularization == FrictionRegularization::smooth ? sqrt(speed2 + vs2)
                : speed2 > vs2                                      ? sqrt(speed2)
                                                                    : T(p_.slip_speed);
  r.force = r.normal_force * n - T(p_.friction * r.normal_force / reg) * vt;
  return r;
}

PlaneContact::Result PlaneContact::evaluate(const Kinematics& k) const {
  return evaluate(body_motion(k, body_));
}

void PlaneContact::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const Result r = evaluate(k);
  if (r.normal_force > 0.0) loads.add_force_at(body_, k, r.contact_point, r.force);
}

void PlaneContact::add_load_derivatives(const State& /*s*/, const Kinematics& k,
                                        const KinematicsDerivatives& dk, Matrix& dQ_dq,
                                        Matrix& dQ_dqd) const {
  const auto body = seeded_motion<1>(k, body_, 0);
  const auto r = evaluate(body);
  if (!(r.normal_force > 0.0)) return;
  const Wrench<MotionDual<1>> w{r.force, (r.contact_point - body.x).cross(r.force)};
  add_wrench_derivatives<1>(k, dk, {body_}, {w}, dQ_dq, dQ_dqd);
}

SimpleTyre::SimpleTyre(std::string name, int body, const SimpleTyreProperties& p,
                       const Plane& ground)
    : name_(std::move(name)), body_(body), p_(p), ground_(ground) {
  const std::string me = this->name();
  check_parameter(me, "simple_tyre", "radius", p_.radius);
  check_parameter(me, "simple_tyre", "stiffness", p_.stiffness);
  check_parameter(me, "simple_tyre", "damping", p_.damping);
  check_parameter(me, "simple_tyre", "friction", p_.friction);
  check_parameter(me, "simple_tyre", "epsilon", p_.epsilon);
  check_parameter(me, "simple_tyre", "axis", p_.axis);
  check_parameter(me, "simple_tyre", "centre", p_.centre);
  check_plane(me, ground_);
  ground_.normal.normalize();
  p_.axis.normalize();
}

template <class T>
SimpleTyre::BasicResult<T> SimpleTyre::evaluate(const BodyMotion<T>& wheel) const {
  using std::sqrt;
  BasicResult<T> r;
  const Vec3T<T> n = ground_.normal.cast<T>();
  const Vec3T<T> C = wheel.point(p_.centre);
  const Vec3T<T> e = wheel.to_global(p_.axis);
  // d = unit(n - (n.e) e): the direction, in the wheel plane, closest to n.
  const Vec3T<T> d = (n - n.dot(e) * e).normalized();
  r.contact_point = C - p_.radius * d;
  r.penetration = -(r.contact_point - ground_.point.cast<T>()).dot(n);
  r.contact_velocity = wheel.velocity_at(r.contact_point);
  if (r.penetration <= 0.0) return r;
  const Vec3T<T>& vP = r.contact_velocity;
  const T N = p_.stiffness * r.penetration - p_.damping * vP.dot(n);
  if (N <= 0.0) return r;
  r.normal_force = N;
  const Vec3T<T> vt = vP - vP.dot(n) * n;
  r.force = r.normal_force * n -
            T(p_.friction * r.normal_force / sqrt(vt.squaredNorm() + p_.epsilon * p_.epsilon)) * vt;
  return r;
}

SimpleTyre::Result SimpleTyre::evaluate(const Kinematics& k) const {
  return evaluate(body_motion(k, body_));
}

void SimpleTyre::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const Result r = evaluate(k);
  if (r.normal_force > 0.0) loads.add_force_at(body_, k, r.contact_point, r.force);
}

void SimpleTyre::add_load_derivatives(const State& /*s*/, const Kinematics& k,
                                      const KinematicsDerivatives& dk, Matrix& dQ_dq,
                                      Matrix& dQ_dqd) const {
  const auto wheel = seeded_motion<1>(k, body_, 0);
  const auto r = evaluate(wheel);
  if (!(r.normal_force > 0.0)) return;
  const Wrench<MotionDual<1>> w{r.force, (r.contact_point - wheel.x).cross(r.force)};
  add_wrench_derivatives<1>(k, dk, {body_}, {w}, dQ_dq, dQ_dqd);
}

}  // namespace symdyn::runtime
