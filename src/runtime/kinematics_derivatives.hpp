#pragma once
// The derivatives with respect to q of the kinematics force elements read,
// from the emitted kinematics_derivatives (docs/emitted_interface.md), and of
// body points, for the exact derivatives of force elements
// (ForceElement::add_load_derivatives). Preallocated; nothing allocates after
// construction.
//
// For a point P of body i at r = P - x_i (global axes), with J_j = ∂P/∂q_j:
//   J_j          = dv_ij + dw_ij × r                         (its partial velocity)
//   ∂J_j/∂q_k    = ∂dv_ij/∂q_k + ∂dw_ij/∂q_k × r + dw_ij × (dw_ik × r)
//   ∂Ṗ/∂q_k      = ∂v_i/∂q_k + ∂w_i/∂q_k × r + w_i × (dw_ik × r)
// since ∂r/∂q_k = dw_ik × r (∂R/∂q_k = skew(dw_ik)·R), and ∂Ṗ/∂qd_k = J_k.
// Points of the ground have none of them (zero).

#include <vector>

#include <symdyn/runtime/kinematics.hpp>

namespace symdyn::runtime {

class KinematicsDerivatives {
 public:
  KinematicsDerivatives() = default;
  KinematicsDerivatives(int nq, int nbody);

  // ∂v_i/∂q_k, ∂w_i/∂q_k (3 each).
  Eigen::Map<const Vec3> dv_dq(int i, int k) const { return vec(dv_dq_, i * nq_ + k); }
  Eigen::Map<const Vec3> dw_dq(int i, int k) const { return vec(dw_dq_, i * nq_ + k); }
  // ∂(dv_i/dqd_j)/∂q_k, ∂(dw_i/dqd_j)/∂q_k (3 each).
  Eigen::Map<const Vec3> ddv_dq(int i, int j, int k) const {
    return vec(ddv_dq_, (i * nq_ + j) * nq_ + k);
  }
  Eigen::Map<const Vec3> ddw_dq(int i, int j, int k) const {
    return vec(ddw_dq_, (i * nq_ + j) * nq_ + k);
  }

  // Of the point of `body` at r = P - x (global axes), with the kinematics k
  // of the same state: J_j, ∂J_j/∂q_k and ∂Ṗ/∂q_k above.
  Vec3 point_partial(const Kinematics& k, int body, const Vec3& r, int j) const;
  Vec3 point_partial_derivative(const Kinematics& k, int body, const Vec3& r, int j, int kk) const;
  Vec3 point_velocity_derivative(const Kinematics& k, int body, const Vec3& r, int kk) const;

  // Raw arrays for the emitted entry point (shapes as in the contract).
  double* dv_dq_data() { return dv_dq_.data(); }    // (nbody x nq x 3)
  double* dw_dq_data() { return dw_dq_.data(); }    // (nbody x nq x 3)
  double* ddv_dq_data() { return ddv_dq_.data(); }  // (nbody x nq x nq x 3)
  double* ddw_dq_data() { return ddw_dq_.data(); }  // (nbody x nq x nq x 3)

  // Whether every array holds finite values only.
  bool all_finite() const;

 private:
  static Eigen::Map<const Vec3> vec(const std::vector<double>& a, int i) {
    return Eigen::Map<const Vec3>(&a[3 * i]);
  }

  int nq_ = 0;
  std::vector<double> dv_dq_, dw_dq_, ddv_dq_, ddw_dq_;
};

}  // namespace symdyn::runtime
