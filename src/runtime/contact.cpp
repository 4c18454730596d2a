#include <algorithm>
#include <cmath>
#include <utility>

#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/element_properties.hpp>

namespace symdyn::runtime {

void check_plane(const std::string& element, const Plane& plane) {
  check_property(element, "plane_point", plane.point);
  check_direction(element, "plane_normal", plane.normal);
}

PlaneContact::PlaneContact(std::string name, int body, const Vec3& point, double radius,
                           const Plane& plane, const ContactProperties& p)
    : name_(std::move(name)), body_(body), point_(point), radius_(radius), plane_(plane), p_(p) {
  const std::string me = this->name();
  check_property(me, "point", point_);
  check_property(me, "radius", radius_, Sign::non_negative);
  check_plane(me, plane_);
  // N = Kn delta^pk + Cd delta^pd deltad: without Kn > 0 a body sinks through the plane.
  check_property(me, "stiffness", p_.stiffness, Sign::positive);
  check_property(me, "stiffness_exponent", p_.stiffness_exponent, Sign::positive);
  check_property(me, "damping", p_.damping, Sign::non_negative);
  check_property(me, "damping_exponent", p_.damping_exponent, Sign::non_negative);
  check_property(me, "friction", p_.friction, Sign::non_negative);
  check_property(me, "slip_speed", p_.slip_speed, Sign::positive);
  plane_.normal.normalize();
}

PlaneContact::Result PlaneContact::evaluate(const Kinematics& k) const {
  Result r;
  const Vec3& n = plane_.normal;
  const Vec3 X = k.point_position(body_, point_);
  r.penetration = radius_ - (X - plane_.point).dot(n);
  r.contact_point = X - radius_ * n;
  if (r.penetration <= 0.0) return r;
  const Vec3 vC = k.velocity_at(body_, r.contact_point);
  r.penetration_rate = -vC.dot(n);
  const double N = p_.stiffness * std::pow(r.penetration, p_.stiffness_exponent) +
                   p_.damping * std::pow(r.penetration, p_.damping_exponent) * r.penetration_rate;
  r.normal_force = std::max(0.0, N);
  const Vec3 vt = vC - vC.dot(n) * n;
  const double speed = vt.norm();
  const double reg = p_.regularization == FrictionRegularization::linear
                         ? std::max(speed, p_.slip_speed)
                         : std::sqrt(speed * speed + p_.slip_speed * p_.slip_speed);
  r.force = r.normal_force * n - p_.friction * r.normal_force / reg * vt;
  return r;
}

void PlaneContact::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const Result r = evaluate(k);
  if (r.normal_force > 0.0) loads.add_force_at(body_, k, r.contact_point, r.force);
}

SimpleTyre::SimpleTyre(std::string name, int body, const SimpleTyreProperties& p,
                       const Plane& ground)
    : name_(std::move(name)), body_(body), p_(p), ground_(ground) {
  const std::string me = this->name();
  check_property(me, "radius", p_.radius, Sign::positive);
  check_property(me, "stiffness", p_.stiffness, Sign::positive);
  check_property(me, "damping", p_.damping, Sign::non_negative);
  check_property(me, "friction", p_.friction, Sign::non_negative);
  check_property(me, "epsilon", p_.epsilon, Sign::positive);
  check_direction(me, "axis", p_.axis);
  check_property(me, "centre", p_.centre);
  check_plane(me, ground_);
  ground_.normal.normalize();
  p_.axis.normalize();
}

SimpleTyre::Result SimpleTyre::evaluate(const Kinematics& k) const {
  Result r;
  const Vec3& n = ground_.normal;
  const Vec3 C = k.point_position(body_, p_.centre);
  const Vec3 e = k.to_global(body_, p_.axis);
  // d = unit(n - (n.e) e): the direction, in the wheel plane, closest to n.
  const Vec3 d = (n - n.dot(e) * e).normalized();
  r.contact_point = C - p_.radius * d;
  r.penetration = -(r.contact_point - ground_.point).dot(n);
  r.contact_velocity = k.velocity_at(body_, r.contact_point);
  if (r.penetration <= 0.0) return r;
  const Vec3& vP = r.contact_velocity;
  r.normal_force = std::max(0.0, p_.stiffness * r.penetration - p_.damping * vP.dot(n));
  const Vec3 vt = vP - vP.dot(n) * n;
  r.force = r.normal_force * n - p_.friction * r.normal_force * vt /
                                     std::sqrt(vt.squaredNorm() + p_.epsilon * p_.epsilon);
  return r;
}

void SimpleTyre::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const Result r = evaluate(k);
  if (r.normal_force > 0.0) loads.add_force_at(body_, k, r.contact_point, r.force);
}

}  // namespace symdyn::runtime
