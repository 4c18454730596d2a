#include <utility>

#include <symdyn/runtime/element_parameters.hpp>
#include <symdyn/runtime/generalized_forces.hpp>

namespace symdyn::runtime {

CoordinateSpringDamper::CoordinateSpringDamper(std::string name, int coordinate, double stiffness,
                                               double damping, double free_value)
    : name_(std::move(name)), j_(coordinate), k_(stiffness), c_(damping), q0_(free_value) {
  check_parameter(this->name(), "coordinate_spring_damper", "stiffness", k_);
  check_parameter(this->name(), "coordinate_spring_damper", "damping", c_);
  check_parameter(this->name(), "coordinate_spring_damper", "free_value", q0_);
}

void CoordinateSpringDamper::apply(const State& s, const Kinematics& /*k*/, Loads& loads) const {
  loads.add_generalized(j_, -k_ * (s.q(j_) - q0_) - c_ * s.qd(j_));
}

void CoordinateSpringDamper::add_load_derivatives(const State& /*s*/, const Kinematics& /*k*/,
                                                  const KinematicsDerivatives& /*dk*/,
                                                  Matrix& dQ_dq, Matrix& dQ_dqd) const {
  dQ_dq(j_, j_) -= k_;
  dQ_dqd(j_, j_) -= c_;
}

double CoordinateSpringDamper::potential_energy(const State& s, const Kinematics& /*k*/) const {
  const double e = s.q(j_) - q0_;
  return 0.5 * k_ * e * e;
}

CoordinateForce::CoordinateForce(std::string name, int coordinate, Law law,
                                 LawDerivatives derivatives)
    : name_(std::move(name)),
      j_(coordinate),
      law_(std::move(law)),
      derivatives_(std::move(derivatives)) {}

void CoordinateForce::apply(const State& s, const Kinematics& /*k*/, Loads& loads) const {
  loads.add_generalized(j_, law_(s.t, s.q(j_), s.qd(j_), s));
}

void CoordinateForce::add_load_derivatives(const State& s, const Kinematics& /*k*/,
                                           const KinematicsDerivatives& /*dk*/, Matrix& dQ_dq,
                                           Matrix& dQ_dqd) const {
  const auto nq = s.q.size();
  dQ_dq_.setZero(nq);
  dQ_dqd_.setZero(nq);
  derivatives_(s.t, s.q(j_), s.qd(j_), s, dQ_dq_, dQ_dqd_);
  check_law_derivatives(name(), s, dQ_dq_, dQ_dqd_, nq, 1);
  dQ_dq.row(j_) += dQ_dq_.transpose();
  dQ_dqd.row(j_) += dQ_dqd_.transpose();
}

CoordinateTracking::CoordinateTracking(std::string name, int coordinate, double kp, double kd,
                                       Reference r, Reference rd)
    : name_(std::move(name)),
      j_(coordinate),
      kp_(kp),
      kd_(kd),
      r_(std::move(r)),
      rd_(std::move(rd)) {
  check_parameter(this->name(), "coordinate_tracking", "kp", kp_);
  check_parameter(this->name(), "coordinate_tracking", "kd", kd_);
}

void CoordinateTracking::apply(const State& s, const Kinematics& /*k*/, Loads& loads) const {
  const double rd = rd_ ? rd_(s.t) : 0.0;
  loads.add_generalized(j_, -kp_ * (s.q(j_) - r_(s.t)) - kd_ * (s.qd(j_) - rd));
}

void CoordinateTracking::add_load_derivatives(const State& /*s*/, const Kinematics& /*k*/,
                                              const KinematicsDerivatives& /*dk*/, Matrix& dQ_dq,
                                              Matrix& dQ_dqd) const {
  dQ_dq(j_, j_) -= kp_;
  dQ_dqd(j_, j_) -= kd_;
}

}  // namespace symdyn::runtime
