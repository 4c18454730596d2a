#pragma once
// Composition of relative motions, as EasyDyn composed CAGeM's code: the
// emitted relative_accelerations (and relative_partial_velocities) give each
// body's motion relative to its reference in the reference's axes; composing
// them, references first, gives the absolute kinematics (docs/design.md):
//   r = R_B·x_rel, x = x_B + r, R = R_B·R_rel, w = w_B + R_B·w_rel,
//   v = v_B + w_B×r + R_B·v_rel,
//   a = a_B + dw_B×r + w_B×(w_B×r) + 2·w_B×(R_B·v_rel) + R_B·a_rel,
//   dw = dw_B + w_B×(R_B·w_rel) + R_B·dw_rel,
//   dv_j = dv_B,j + dw_B,j×r + R_B·dv_rel,j,   dw_j = dw_B,j + R_B·dw_rel,j.
// The emitted `accelerations` composes the same way in generated code; this is
// the other way round (smaller code, composition in Eigen at run time).

#include <vector>

#include <symdyn/runtime/kinematics.hpp>

namespace symdyn::runtime {

class RelativeMotion {
 public:
  // reference_body[i]: the body i moves relative to, or -1 (the ground).
  // Throws ModelError naming a body whose reference is unknown or which is
  // relative to itself through a cycle.
  RelativeMotion(std::vector<int> reference_body, int nq);

  int nbody() const { return static_cast<int>(reference_.size()); }
  int nq() const { return nq_; }

  // The relative motions, in a buffer of Kinematics' shapes: the emitted
  // relative entry points write its raw arrays (no dependent parameters).
  Kinematics& relative() { return relative_; }

  // Writes the absolute R, x, v, w, a, dw of every body into k, and its
  // partial velocities when `partials` (then relative ones must be evaluated).
  void compose(Kinematics& k, bool partials) const;

 private:
  std::vector<int> reference_;
  std::vector<int> order_;  // every reference before the bodies relative to it
  int nq_;
  Kinematics relative_;
};

}  // namespace symdyn::runtime
