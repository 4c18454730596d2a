#include <Eigen/LU>
#include <array>
#include <utility>

#include <symdyn/runtime/bushing.hpp>
#include <symdyn/runtime/element_parameters.hpp>

namespace symdyn::runtime {

Bushing::Bushing(std::string name, BodyFrame a, BodyFrame b, const BushingProperties& p,
                 std::string_view order)
    : name_(std::move(name)), a_(a), b_(b), p_(p), order_(CardanOrder::parse(order)) {
  const std::string me = this->name();
  check_property(me, "a/origin", a_.origin);
  check_axes(me, "a/axes", a_.axes);
  check_property(me, "b/origin", b_.origin);
  check_axes(me, "b/axes", b_.axes);
  check_parameter(me, "bushing", "stiffness", p_.stiffness);
  check_parameter(me, "bushing", "damping", p_.damping);
  check_parameter(me, "bushing", "rotational_stiffness", p_.rotational_stiffness);
  check_parameter(me, "bushing", "rotational_damping", p_.rotational_damping);
  check_parameter(me, "bushing", "preload_force", p_.preload_force);
  check_parameter(me, "bushing", "preload_torque", p_.preload_torque);
}

template <class T>
Bushing::BasicDeflection<T> Bushing::deflection(const BodyMotion<T>& a,
                                                const BodyMotion<T>& b) const {
  const Mat3T<T> RA = a.R * a_.axes.cast<T>();
  const Mat3T<T> RB = b.R * b_.axes.cast<T>();
  const Vec3T<T> OA = a.point(a_.origin), OB = b.point(b_.origin);
  BasicDeflection<T> def;
  def.d = RA.transpose() * (OB - OA);
  def.dd = RA.transpose() * (b.velocity_at(OB) - a.velocity_at(OA) - a.w.cross(OB - OA));
  def.theta = cardan_angles(order_, Mat3T<T>(RA.transpose() * RB));
  const Mat3T<T> E = cardan_rate_matrix(order_, def.theta);
  def.thetad = E.inverse() * (RA.transpose() * (b.w - a.w));
  return def;
}

Bushing::Deflection Bushing::deflection(const Kinematics& k) const {
  return deflection(body_motion(k, a_.body), body_motion(k, b_.body));
}

// R_A f on b and its opposite on a at the mid-point of O_A and O_B, and the moments
// ±R_A E^-T tau, reduced to the centres of gravity.
template <class T>
std::array<Wrench<T>, 2> Bushing::wrenches(const BodyMotion<T>& a, const BodyMotion<T>& b) const {
  const BasicDeflection<T> def = deflection(a, b);
  const Mat3T<T> RA = a.R * a_.axes.cast<T>();
  const Vec3T<T> f = p_.preload_force.cast<T>() - p_.stiffness.cast<T>().cwiseProduct(def.d) -
                     p_.damping.cast<T>().cwiseProduct(def.dd);
  const Vec3T<T> tau = p_.preload_torque.cast<T>() -
                       p_.rotational_stiffness.cast<T>().cwiseProduct(def.theta) -
                       p_.rotational_damping.cast<T>().cwiseProduct(def.thetad);
  const Mat3T<T> E = cardan_rate_matrix(order_, def.theta);
  const Vec3T<T> F = RA * f;
  const Vec3T<T> moment = RA * (E.transpose().inverse() * tau);
  const Vec3T<T> mid = T(0.5) * (a.point(a_.origin) + b.point(b_.origin));
  Wrench<T> on_b{F, Vec3T<T>((mid - b.x).cross(F) + moment)};
  Wrench<T> on_a{Vec3T<T>(-F), Vec3T<T>((mid - a.x).cross(Vec3T<T>(-F)) - moment)};
  return {on_b, on_a};
}

void Bushing::apply(const State& /*s*/, const Kinematics& k, Loads& loads) const {
  const auto [on_b, on_a] = wrenches(body_motion(k, a_.body), body_motion(k, b_.body));
  loads.add_force(b_.body, on_b.force);
  loads.add_moment(b_.body, on_b.moment);
  loads.add_force(a_.body, on_a.force);
  loads.add_moment(a_.body, on_a.moment);
}

void Bushing::add_load_derivatives(const State& /*s*/, const Kinematics& k,
                                   const KinematicsDerivatives& dk, Matrix& dQ_dq,
                                   Matrix& dQ_dqd) const {
  // Slot 0: b, 1: a, as the wrenches.
  const auto b = seeded_motion<2>(k, b_.body, 0), a = seeded_motion<2>(k, a_.body, 1);
  add_wrench_derivatives<2>(k, dk, {b_.body, a_.body}, wrenches(a, b), dQ_dq, dQ_dqd);
}

double Bushing::potential_energy(const State& /*s*/, const Kinematics& k) const {
  const Deflection def = deflection(k);
  return 0.5 * (def.d.cwiseProduct(p_.stiffness).dot(def.d) +
                def.theta.cwiseProduct(p_.rotational_stiffness).dot(def.theta));
}

}  // namespace symdyn::runtime
