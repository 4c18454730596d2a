#pragma once
// Generalized forces acting directly on one coordinate q_j (a force for a
// translation, a torque for a rotation). Positive Q pushes q_j up.

#include <functional>
#include <string>

#include <symdyn/runtime/force_element.hpp>

namespace symdyn::runtime {

// Linear spring-damper on a coordinate: Q = -k (q - free_value) - c qd.
class CoordinateSpringDamper : public ForceElement {
 public:
  CoordinateSpringDamper(std::string name, int coordinate, double stiffness, double damping,
                         double free_value = 0.0);
  std::string name() const override { return "coordinate spring '" + name_ + "'"; }
  KinematicsLevel reads() const override { return KinematicsLevel::none; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // dQ/dq_j = -k, dQ/dqd_j = -c
  LoadDerivatives load_derivatives() const override { return LoadDerivatives::exact; }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;
  // 1/2 k (q - free_value)^2
  double potential_energy(const State& s, const Kinematics& k) const override;

 private:
  std::string name_;
  int j_;
  double k_, c_, q0_;
};

// Nonlinear generalized force Q = law(t, q_j, qd_j, state) on a coordinate
// (the state gives access to the other coordinates and extra states).
class CoordinateForce : public ForceElement {
 public:
  using Law = std::function<double(double t, double q, double qd, const State& s)>;
  // The law's derivatives at the same arguments: ∂Q/∂q and ∂Q/∂qd set in dQ_dq and
  // dQ_dqd (nq each, zeroed by the caller; a law of q_j and qd_j alone sets entry j).
  using LawDerivatives = std::function<void(double t, double q, double qd, const State& s,
                                            Vector& dQ_dq, Vector& dQ_dqd)>;
  // Differenced; exact where the law's derivatives are given.
  CoordinateForce(std::string name, int coordinate, Law law, LawDerivatives derivatives = nullptr);
  std::string name() const override { return "coordinate force '" + name_ + "'"; }
  KinematicsLevel reads() const override { return KinematicsLevel::none; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // Row j of dQ/dq and dQ/dqd: the law's derivatives.
  LoadDerivatives load_derivatives() const override {
    return derivatives_ ? LoadDerivatives::exact : LoadDerivatives::differenced;
  }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;

 private:
  std::string name_;
  int j_;
  Law law_;
  LawDerivatives derivatives_;
  mutable Vector dQ_dq_, dQ_dqd_;  // the law's (nq)
};

// PD tracking of a reference r(t) (with optional rate rd(t), zero if absent):
// Q = -kp (q - r(t)) - kd (qd - rd(t)). The trike's steering with kd on qd
// alone is rd = null.
class CoordinateTracking : public ForceElement {
 public:
  using Reference = std::function<double(double t)>;
  CoordinateTracking(std::string name, int coordinate, double kp, double kd, Reference r,
                     Reference rd = nullptr);
  std::string name() const override { return "coordinate tracking '" + name_ + "'"; }
  KinematicsLevel reads() const override { return KinematicsLevel::none; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // dQ/dq_j = -kp, dQ/dqd_j = -kd
  LoadDerivatives load_derivatives() const override { return LoadDerivatives::exact; }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;

 private:
  std::string name_;
  int j_;
  double kp_, kd_;
  Reference r_, rd_;
};

}  // namespace symdyn::runtime
