#include <Eigen/LU>
#include <utility>

#include <symdyn/runtime/bushing.hpp>
#include <symdyn/runtime/element_properties.hpp>

namespace symdyn::runtime {

Bushing::Bushing(std::string name, BodyFrame a, BodyFrame b, const BushingProperties& p,
                 std::string_view order)
    : name_(std::move(name)), a_(a), b_(b), p_(p), order_(CardanOrder::parse(order)) {
  const std::string me = this->name();
  check_property(me, "a/origin", a_.origin);
  check_axes(me, "a/axes", a_.axes);
  check_property(me, "b/origin", b_.origin);
  check_axes(me, "b/axes", b_.axes);
  check_property(me, "stiffness", p_.stiffness, Sign::non_negative);
  check_property(me, "damping", p_.damping, Sign::non_negative);
  check_property(me, "rotational_stiffness", p_.rotational_stiffness, Sign::non_negative);
  check_property(me, "rotational_damping", p_.rotational_damping, Sign::non_negative);
  check_property(me, "preload_force", p_.preload_force);
  check_property(me, "preload_torque", p_.preload_torque);
}

Bushing::Deflection Bushing::deflection(const Kinematics& k) const {
  const Mat3 RA = k.rotation(a_.body) * a_.axes;
  const Mat3 RB = k.rotation(b_.body) * b_.axes;
  const Vec3 OA = k.point_position(a_.body, a_.origin);
  const Vec3 OB = k.point_position(b_.body, b_.origin);
  const Vec3 wA = a_.body == ground ? Vec3::Zero() : Vec3(k.w(a_.body));
  const Vec3 wB = b_.body == ground ? Vec3::Zero() : Vec3(k.w(b_.body));
  Deflection def;
  def.d = RA.transpose() * (OB - OA);
  def.dd = RA.transpose() * (k.point_velocity(b_.body, b_.origin) -
                             k.point_velocity(a_.body, a_.origin) - wA.cross(OB - OA));
  def.theta = cardan_angles(order_, RA.transpose() * RB);
  const Mat3 E = cardan_rate_matrix(order_, def.theta);
  def.thetad = E.partialPivLu().solve(RA.transpose() * (wB - wA));
  return def;
}

void Bushing::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const Deflection def = deflection(k);
  const Mat3 RA = k.rotation(a_.body) * a_.axes;
  const Vec3 f =
      p_.preload_force - p_.stiffness.cwiseProduct(def.d) - p_.damping.cwiseProduct(def.dd);
  const Vec3 tau = p_.preload_torque - p_.rotational_stiffness.cwiseProduct(def.theta) -
                   p_.rotational_damping.cwiseProduct(def.thetad);
  const Mat3 E = cardan_rate_matrix(order_, def.theta);
  const Vec3 F = RA * f;
  const Vec3 Mom = RA * E.transpose().partialPivLu().solve(tau);
  const Vec3 mid =
      0.5 * (k.point_position(a_.body, a_.origin) + k.point_position(b_.body, b_.origin));
  loads.add_force_at(b_.body, k, mid, F);
  loads.add_force_at(a_.body, k, mid, -F);
  loads.add_moment(b_.body, Mom);
  loads.add_moment(a_.body, -Mom);
}

double Bushing::potential_energy(const State& /*s*/, const Kinematics& k) const {
  const Deflection def = deflection(k);
  return 0.5 * (def.d.cwiseProduct(p_.stiffness).dot(def.d) +
                def.theta.cwiseProduct(p_.rotational_stiffness).dot(def.theta));
}

}  // namespace symdyn::runtime
