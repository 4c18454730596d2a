#pragma once
// The preallocated kinematics buffer of a model: every array the emitted entry
// points write, sized once, read through typed Eigen views. Nothing here
// allocates after construction, so the hot path (residual, accelerations) is
// allocation-free.
//
// Conventions (docs/emitted_interface.md): body i has its frame at its centre
// of gravity G_i; R_i maps body axes to global axes; every vector is in the
// global frame. Body index -1 means the ground (fixed, identity frame) in the
// point helpers, so that force elements can attach to the ground.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace symdyn::runtime {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// Index of the ground in the point helpers and force elements.
inline constexpr int ground = -1;

// How much of the kinematics an evaluation needs, each level including the
// one before: nothing beyond the state; positions R, x with the partial
// velocities (to project forces on bodies); velocities v, w as well.
enum class KinematicsLevel { none, positions, velocities };

class Kinematics {
 public:
  Kinematics() = default;
  Kinematics(int nq, int nbody, int ndep);

  int nq() const { return nq_; }
  int nbody() const { return nbody_; }

  // Rotation body -> global of body i (3 x 3).
  Eigen::Map<const RowMat3> R(int i) const { return Eigen::Map<const RowMat3>(&R_[9 * i]); }
  // Position of G_i, its velocity and acceleration; angular velocity and
  // angular acceleration of body i (3 each, global frame).
  Eigen::Map<const Vec3> x(int i) const { return vec(x_, i); }
  Eigen::Map<const Vec3> v(int i) const { return vec(v_, i); }
  Eigen::Map<const Vec3> w(int i) const { return vec(w_, i); }
  Eigen::Map<const Vec3> a(int i) const { return vec(a_, i); }
  Eigen::Map<const Vec3> dw(int i) const { return vec(dw_, i); }
  // Partial velocities dv_i/dqd_j and dw_i/dqd_j (3 each).
  Eigen::Map<const Vec3> dv_dqd(int i, int j) const { return vec(dv_, i * nq_ + j); }
  Eigen::Map<const Vec3> dw_dqd(int i, int j) const { return vec(dwq_, i * nq_ + j); }
  // All partial velocities of body i: row j is dv_i/dqd_j (nq x 3).
  using PartialsMap = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>;
  PartialsMap dv_dqd(int i) const { return PartialsMap(&dv_[3 * i * nq_], nq_, 3); }
  PartialsMap dw_dqd(int i) const { return PartialsMap(&dwq_[3 * i * nq_], nq_, 3); }
  // Dependent parameters and their time derivatives (ndep each), when evaluated.
  const std::vector<double>& p() const { return p_; }
  const std::vector<double>& pd() const { return pd_; }
  const std::vector<double>& pdd() const { return pdd_; }

  // Global position of the point with body coordinates p_body (from G) of a
  // body; for the ground, p_body is already global.
  Vec3 point_position(int body, const Vec3& p_body) const;
  // Global velocity of that material point: v + w x (R p).
  Vec3 point_velocity(int body, const Vec3& p_body) const;
  // Velocity of the material point of a body that is at the global position X.
  Vec3 velocity_at(int body, const Vec3& X) const;
  // A body-axes vector in global axes (R p); identity for the ground.
  Vec3 to_global(int body, const Vec3& p_body) const;
  // Rotation of a body, identity for the ground.
  Mat3 rotation(int body) const;

  // Raw arrays for the emitted entry points (shapes as in the contract).
  double* R_data() { return R_.data(); }         // (nbody x 3 x 3)
  double* x_data() { return x_.data(); }         // (nbody x 3)
  double* v_data() { return v_.data(); }         // (nbody x 3)
  double* w_data() { return w_.data(); }         // (nbody x 3)
  double* a_data() { return a_.data(); }         // (nbody x 3)
  double* dw_data() { return dw_.data(); }       // (nbody x 3)
  double* dv_dqd_data() { return dv_.data(); }   // (nbody x nq x 3)
  double* dw_dqd_data() { return dwq_.data(); }  // (nbody x nq x 3)
  double* p_data() { return p_.data(); }         // (max(ndep, 1))
  double* pd_data() { return pd_.data(); }       // (max(ndep, 1))
  double* pdd_data() { return pdd_.data(); }     // (max(ndep, 1))

  // Sets v, w (and a, dw) to zero; used before evaluating positions only.
  void clear_rates();

  // Whether R, x, v, w, the partial velocities and (with accelerations) a and
  // dw hold finite values only: one pass over each array, the fast check
  // before a search for the culprit.
  bool all_finite(bool accelerations) const;
  // Whether R, x and (from velocities up) v, w hold finite values only.
  bool finite_up_to(KinematicsLevel level) const;

 private:
  static Eigen::Map<const Vec3> vec(const std::vector<double>& a, int i) {
    return Eigen::Map<const Vec3>(&a[3 * i]);
  }

  int nq_ = 0;
  int nbody_ = 0;
  std::vector<double> R_, x_, v_, w_, a_, dw_, dv_, dwq_, p_, pd_, pdd_;
};

// The per-model scratch space of the runtime is its kinematics buffer.
using Workspace = Kinematics;

}  // namespace symdyn::runtime
