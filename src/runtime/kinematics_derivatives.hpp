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

#include <Eigen/Core>
#include <array>
#include <unsupported/Eigen/AutoDiff>
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

// Force elements whose law is too long to differentiate by hand (bushings,
// contacts, tyres) write it once for a scalar T and are differentiated by
// forward-mode automatic differentiation (exact to rounding) with respect to
// the motions of the bodies they act on, then by the chain rule through the
// kinematics' derivatives (add_wrench_derivatives).
//
// The motion of a body: position x of G, rotation R, velocities v and w. Its
// perturbation (12 numbers): δx, δθ (R → (I + skew(δθ))·R), δv, δw; with
// respect to q_k they are dv_k, dw_k, ∂v/∂q_k, ∂w/∂q_k; to qd_k, 0, 0, dv_k, dw_k.
template <int Bodies>
using MotionDual = Eigen::AutoDiffScalar<Eigen::Matrix<double, 12 * Bodies, 1>>;
template <class T>
using Vec3T = Eigen::Matrix<T, 3, 1>;
template <class T>
using Mat3T = Eigen::Matrix<T, 3, 3>;

template <class T>
struct BodyMotion {
  Vec3T<T> x, v, w;
  Mat3T<T> R;
  // Of a point given in body coordinates from G / a global point X.
  Vec3T<T> to_global(const Vec3& p) const { return R * p.cast<T>(); }
  Vec3T<T> point(const Vec3& p) const { return x + to_global(p); }
  Vec3T<T> velocity_at(const Vec3T<T>& X) const { return v + w.cross(X - x); }
};

// The motion of `body` (the ground: at rest, identity) from the kinematics,
// with no derivatives or seeded as the slot-th of Bodies bodies (the ground:
// constant).
BodyMotion<double> body_motion(const Kinematics& k, int body);
template <int Bodies>
BodyMotion<MotionDual<Bodies>> seeded_motion(const Kinematics& k, int body, int slot);

// A force at G and a moment (global axes) on a body.
template <class T>
struct Wrench {
  Vec3T<T> force = Vec3T<T>::Zero(), moment = Vec3T<T>::Zero();
};

// Adds to dQ_dq and dQ_dqd (nq x nq) the derivatives of Q_j = Σ_a F_a·dv_aj + M_a·dw_aj
// of the wrenches (F_a, M_a) on bodies[a] (none on the ground), each a function of the
// motions of the bodies, bodies[a]'s seeded as slot a (seeded_motion):
//   ∂Q_j/∂q_k  = Σ_a ∂W_a/∂q_k·(dv_aj, dw_aj) + F_a·∂dv_aj/∂q_k + M_a·∂dw_aj/∂q_k,
//   ∂Q_j/∂qd_k = Σ_a ∂W_a/∂qd_k·(dv_aj, dw_aj).
template <int Bodies>
void add_wrench_derivatives(const Kinematics& k, const KinematicsDerivatives& dk,
                            const std::array<int, Bodies>& bodies,
                            const std::array<Wrench<MotionDual<Bodies>>, Bodies>& wrenches,
                            Eigen::MatrixXd& dQ_dq, Eigen::MatrixXd& dQ_dqd);

}  // namespace symdyn::runtime
