#pragma once
// The independent reference of the paper tables: kinematics and accelerations
// of a model computed without the generated code and without symbolic
// differentiation.
//
//   positions      T0G of every body as the numeric product of the 4x4
//                  matrices of its elementary motions (Rodrigues for each
//                  rotation), composed with its reference body's;
//   velocities,    central differences (fourth order, Richardson) of those
//   accelerations  positions along the path q(tau) = q + qd tau + qdd tau^2/2,
//                  t + tau; skew(w) = dR/dt R^T, skew(dw) = d2R/dt2 R^T + dR/dt dR/dt^T;
//   partial        dv_i/dqd_j = dx_i/dq_j and skew(dw_i/dqd_j) = dR_i/dq_j R_i^T
//   velocities     (velocities are affine in qd), central differences in q_j;
//   qdd            M qdd = -h with M and h assembled from the above (virtual
//                  power, gravity the only load).
//
// Only the model's definition (its motions as products of elementary
// transformations, dependent parameters as expressions, masses, inertia and
// gravity) is evaluated, numerically. Errors against it are of the order of
// the finite differences: about 1e-10 relative for unit-sized states.

#include <Eigen/Dense>
#include <vector>

#include <symdyn/model/model.hpp>

namespace symdyn::paper {

struct StateSample {
  double t = 0.0;
  Eigen::VectorXd q, qd, qdd;  // (nq) each
};

// Kinematics of all bodies, in the layout of docs/emitted_interface.md.
struct BodyKinematics {
  std::vector<double> R, x, v, w, a, dw;  // (nbody x 3 x 3), then (nbody x 3) each
  std::vector<double> dv, dwq;            // (nbody x nq x 3) each
};

class Reference {
 public:
  explicit Reference(const model::Model& model);

  int nq() const { return nq_; }
  int nbody() const { return nbody_; }

  // Positions, velocities, accelerations and partial velocities at s.
  BodyKinematics kinematics(const StateSample& s) const;
  // The accelerations of the free system under gravity at (t, q, qd).
  Eigen::VectorXd accelerations(const StateSample& s) const;

 private:
  // T0G (4 x 4) of every body at (t, q).
  std::vector<Eigen::Matrix4d> transforms(double t, const Eigen::VectorXd& q) const;

  const model::Model& model_;
  int nq_, nbody_;
  std::vector<double> mass_;              // (nbody)
  std::vector<Eigen::Matrix3d> inertia_;  // (nbody) at G, body axes
  Eigen::Vector3d gravity_;
};

}  // namespace symdyn::paper
