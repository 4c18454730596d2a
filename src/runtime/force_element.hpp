#pragma once
// Force elements: small types that add forces and moments at the centres of
// gravity of bodies (global axes) and generalized forces on coordinates.
//
// Points are given in body coordinates (from G, in body axes); body index
// `ground` (-1) attaches to the fixed ground, whose "body coordinates" are
// global. A force F at a point P of a body is reduced to G exactly: the force
// F at G plus the moment (P - G) x F. Reactions on the ground are dropped.

#include <Eigen/Core>
#include <string>

#include <symdyn/runtime/dynamic_system.hpp>
#include <symdyn/runtime/kinematics.hpp>
#include <symdyn/runtime/kinematics_derivatives.hpp>

namespace symdyn::runtime {

// Forces F (3 x nbody), moments M (3 x nbody) at G in global axes, and
// generalized forces Q (nq) on the coordinates. Preallocated; clear() zeroes.
class Loads {
 public:
  Loads() = default;
  Loads(int nq, int nbody) : F(3, nbody), M(3, nbody), Q(nq) { clear(); }

  void clear() {
    F.setZero();
    M.setZero();
    Q.setZero();
    on_bodies_ = false;
  }
  // Force at G of a body (ignored for the ground).
  void add_force(int body, const Vec3& f) {
    if (body == ground) return;
    F.col(body) += f;
    on_bodies_ = true;
  }
  void add_moment(int body, const Vec3& m) {
    if (body == ground) return;
    M.col(body) += m;
    on_bodies_ = true;
  }
  // Force f at the global point X of a body with centre of gravity at G:
  // f at G plus the moment (X - G) x f.
  void add_force_at(int body, const Kinematics& k, const Vec3& X, const Vec3& f) {
    if (body == ground) return;
    F.col(body) += f;
    M.col(body) += (X - k.x(body)).cross(f);
    on_bodies_ = true;
  }
  void add_generalized(int coordinate, double q) { Q(coordinate) += q; }

  // Whether a force or moment was added on a body since clear().
  bool on_bodies() const { return on_bodies_; }

  // Read them; add through the functions above.
  Eigen::Matrix<double, 3, Eigen::Dynamic> F;  // (3 x nbody)
  Eigen::Matrix<double, 3, Eigen::Dynamic> M;  // (3 x nbody)
  Vector Q;                                    // (nq)

 private:
  bool on_bodies_ = false;
};

// How a force element's generalized forces are differentiated (ForceElement::load_derivatives).
enum class LoadDerivatives { differenced, exact, exact_with_kinematics_derivatives };

// What a force element sees: the state (t, q, qd, y) and the kinematics of
// that state up to the level it declares by reads(). The runtime evaluates
// no more than the attached elements read: an element of level `none` sees
// stale kinematics and may only add generalized forces (a force on a body
// needs the partial velocities to be projected: ModelError); `positions`
// gives R, x and the partial velocities; `velocities` also v and w.
class ForceElement {
 public:
  virtual ~ForceElement() = default;
  // A short description naming the element ("spring 'strut'").
  virtual std::string name() const = 0;
  // The kinematics apply() and potential_energy() read.
  virtual KinematicsLevel reads() const { return KinematicsLevel::velocities; }
  // Adds this element's loads. Must not allocate (it runs in the hot path).
  virtual void apply(const State& s, const Kinematics& k, Loads& loads) const = 0;
  // How this element's generalized forces Q (its loads projected: Q_j =
  // Σ_i F_i·dv_ij + M_i·dw_ij + Q_j) are differentiated for exact Jacobians
  // (MultibodySystem::jacobians): by central differences of its Q alone (the
  // default, named by MultibodySystem::jacobian_method), or exactly by
  // add_load_derivatives, from the state and kinematics alone or also from
  // the derivatives of the kinematics (where the model has them; else
  // differenced).
  virtual LoadDerivatives load_derivatives() const { return LoadDerivatives::differenced; }
  // Adds dQ/dq and dQ/dqd (nq x nq each) of this element at the state, exactly;
  // dk holds the kinematics' derivatives where load_derivatives() asks for them.
  // Called only where the element is not differenced; must not allocate.
  virtual void add_load_derivatives(const State& /*s*/, const Kinematics& /*k*/,
                                    const KinematicsDerivatives& /*dk*/, Matrix& /*dQ_dq*/,
                                    Matrix& /*dQ_dqd*/) const {}
  // Elastic energy stored in the element (0 for non-conservative elements).
  virtual double potential_energy(const State& /*s*/, const Kinematics& /*k*/) const { return 0.0; }
};

// The derivatives a user's law gave (dQ_dq, dQ_dqd, at the state s) checked for the element
// named `element`: still rows x cols (ModelError) and finite (NumericError).
void check_law_derivatives(const std::string& element, const State& s,
                           const Eigen::Ref<const Matrix>& dQ_dq,
                           const Eigen::Ref<const Matrix>& dQ_dqd, Eigen::Index rows,
                           Eigen::Index cols);

}  // namespace symdyn::runtime
