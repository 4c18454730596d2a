#pragma once
// Forces between and at points of bodies (points in body coordinates from G;
// `ground` for a fixed global point), and user forces.

#include <functional>
#include <string>

#include <symdyn/runtime/force_element.hpp>

namespace symdyn::runtime {

// A body point: the body index (or `ground`) and its coordinates in body axes
// from G (global coordinates for the ground).
struct BodyPoint {
  int body = ground;
  Vec3 point = Vec3::Zero();
};

// Linear spring and damper between two body points, along their line:
// with L = |P_b - P_a|, u = (P_b - P_a)/L and Ld = u . (v_Pb - v_Pa),
// the tension T = k (L - free_length) + c Ld pulls P_b towards P_a (-T u on b,
// +T u on a), each reduced to G. Throws NumericError when the points coincide.
class PointSpringDamper : public ForceElement {
 public:
  PointSpringDamper(std::string name, BodyPoint a, BodyPoint b, double stiffness,
                    double free_length, double damping = 0.0);
  std::string name() const override { return "spring '" + name_ + "'"; }
  // Without damping only the positions.
  KinematicsLevel reads() const override {
    return c_ != 0.0 ? KinematicsLevel::velocities : KinematicsLevel::positions;
  }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  LoadDerivatives load_derivatives() const override {
    return LoadDerivatives::exact_with_kinematics_derivatives;
  }
  // Q_j = -T·∂L/∂q_j: ∂Q_j/∂q_k = -∂T/∂q_k·∂L/∂q_j - T·∂²L/∂q_j∂q_k, ∂Q_j/∂qd_k =
  // -c·∂L/∂q_k·∂L/∂q_j.
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;
  // 1/2 k (L - free_length)^2
  double potential_energy(const State& s, const Kinematics& k) const override;
  // Length and its rate at the last kinematics given.
  double length(const Kinematics& k) const;

 private:
  std::string name_;
  BodyPoint a_, b_;
  double k_, L0_, c_;
};

// A force and a torque (global axes) at a point of a body, constant or a
// function of time, state and kinematics.
class PointLoad : public ForceElement {
 public:
  using Law = std::function<void(const State& s, const Kinematics& k, Vec3& force, Vec3& torque)>;
  // The same law with its derivatives: force and torque, and in dW_dq, dW_dqd
  // (6 x nq, sized by the caller: the force's rows, then the torque's) their
  // derivatives with respect to q and qd, dk the kinematics' derivatives.
  using LawDerivatives =
      std::function<void(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                         Vec3& force, Vec3& torque, Matrix& dW_dq, Matrix& dW_dqd)>;
  // Constant force and torque.
  PointLoad(std::string name, BodyPoint at, const Vec3& force, const Vec3& torque = Vec3::Zero());
  // Force and torque computed by law at each evaluation, differenced; exact
  // where the law's derivatives are given.
  PointLoad(std::string name, BodyPoint at, Law law, LawDerivatives derivatives = nullptr);
  std::string name() const override { return "load '" + name_ + "'"; }
  // A constant load only needs its point; a law may read anything.
  KinematicsLevel reads() const override {
    return law_ ? KinematicsLevel::velocities : KinematicsLevel::positions;
  }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // Q_j = F·J_j + T·dw_j, ∂Q_j/∂q_k = F·∂J_j/∂q_k + T·∂dw_j/∂q_k (+ ∂F/∂q_k·J_j + ∂T/∂q_k·dw_j
  // for a law, and ∂Q_j/∂qd_k = ∂F/∂qd_k·J_j + ∂T/∂qd_k·dw_j); a law without its derivatives is
  // differenced.
  LoadDerivatives load_derivatives() const override {
    return law_ && !derivatives_ ? LoadDerivatives::differenced
                                 : LoadDerivatives::exact_with_kinematics_derivatives;
  }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;

 private:
  std::string name_;
  BodyPoint at_;
  Vec3 force_, torque_;
  Law law_;
  LawDerivatives derivatives_;
  mutable Matrix dW_dq_, dW_dqd_;  // the law's (6 x nq)
};

// Anything else: a callback that adds loads given (t, state, kinematics),
// reading the kinematics up to `reads` (none: generalized forces only).
class UserForce : public ForceElement {
 public:
  using Callback = std::function<void(const State& s, const Kinematics& k, Loads& loads)>;
  // The callback's Jacobian: in dQ_dq and dQ_dqd (nq x nq, zeroed by the caller) the
  // derivatives with respect to q and qd of the generalized forces its loads give,
  // Q_j = Σ_i F_i·dv_ij + M_i·dw_ij + Q_j (a force at a point: F·J_j with J_j its
  // partial velocity, KinematicsDerivatives::point_partial), at the kinematics k and
  // their derivatives dk of the state (dk: where reads is not none).
  using Jacobian =
      std::function<void(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                         Matrix& dQ_dq, Matrix& dQ_dqd)>;
  // Differenced; exact where the Jacobian is given.
  UserForce(std::string name, Callback callback,
            KinematicsLevel reads = KinematicsLevel::velocities, Jacobian jacobian = nullptr);
  std::string name() const override { return "user force '" + name_ + "'"; }
  KinematicsLevel reads() const override { return reads_; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  LoadDerivatives load_derivatives() const override {
    if (!jacobian_) return LoadDerivatives::differenced;
    return reads_ == KinematicsLevel::none ? LoadDerivatives::exact
                                           : LoadDerivatives::exact_with_kinematics_derivatives;
  }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;

 private:
  std::string name_;
  Callback callback_;
  KinematicsLevel reads_;
  Jacobian jacobian_;
  mutable Matrix dQ_dq_, dQ_dqd_;  // the callback's (nq x nq)
};

}  // namespace symdyn::runtime
