#include <symdyn/runtime/point_forces.hpp>

#include <fmt/format.h>

#include <utility>

#include <symdyn/runtime/element_properties.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime {

PointSpringDamper::PointSpringDamper(std::string name, BodyPoint a, BodyPoint b,
                                     double stiffness, double free_length, double damping)
    : name_(std::move(name)), a_(a), b_(b), k_(stiffness), L0_(free_length), c_(damping) {
  check_property(this->name(), "point_a", a_.point);
  check_property(this->name(), "point_b", b_.point);
  check_property(this->name(), "stiffness", k_, Sign::non_negative);
  check_property(this->name(), "free_length", L0_, Sign::non_negative);
  check_property(this->name(), "damping", c_, Sign::non_negative);
}

double PointSpringDamper::length(const Kinematics& k) const {
  return (k.point_position(b_.body, b_.point) - k.point_position(a_.body, a_.point)).norm();
}

void PointSpringDamper::apply(const State& s, const Kinematics& k, Loads& loads) const {
  const Vec3 Pa = k.point_position(a_.body, a_.point);
  const Vec3 Pb = k.point_position(b_.body, b_.point);
  const Vec3 d = Pb - Pa;
  const double L = d.norm();
  if (!(L > 0.0)) {
    throw NumericError(fmt::format("t = {}: {}: its two points coincide (direction undefined)",
                                   s.t, name()));
  }
  const Vec3 u = d / L;
  // Ld = u . (v_Pb - v_Pa)
  const double Ld = c_ == 0.0 ? 0.0
                              : u.dot(k.point_velocity(b_.body, b_.point) - k.point_velocity(a_.body, a_.point));
  const double tension = k_ * (L - L0_) + c_ * Ld;
  loads.add_force_at(b_.body, k, Pb, -tension * u);
  loads.add_force_at(a_.body, k, Pa, tension * u);
}

double PointSpringDamper::potential_energy(const State& /*s*/, const Kinematics& k) const {
  const double e = length(k) - L0_;
  return 0.5 * k_ * e * e;
}

PointLoad::PointLoad(std::string name, BodyPoint at, const Vec3& force, const Vec3& torque)
    : name_(std::move(name)), at_(at), force_(force), torque_(torque) {
  check_property(this->name(), "point", at_.point);
  check_property(this->name(), "force", force_);
  check_property(this->name(), "torque", torque_);
}

PointLoad::PointLoad(std::string name, BodyPoint at, Law law)
    : name_(std::move(name)), at_(at), force_(Vec3::Zero()), torque_(Vec3::Zero()),
      law_(std::move(law)) {
  check_property(this->name(), "point", at_.point);
}

void PointLoad::apply(const State& s, const Kinematics& k, Loads& loads) const {
  Vec3 f = force_;
  Vec3 m = torque_;
  if (law_) law_(s, k, f, m);
  loads.add_force_at(at_.body, k, k.point_position(at_.body, at_.point), f);
  loads.add_moment(at_.body, m);
}

UserForce::UserForce(std::string name, Callback callback, KinematicsLevel reads)
    : name_(std::move(name)), callback_(std::move(callback)), reads_(reads) {}

void UserForce::apply(const State& s, const Kinematics& k, Loads& loads) const {
  callback_(s, k, loads);
}

}  // namespace symdyn::runtime
