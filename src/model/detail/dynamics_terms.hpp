#pragma once
// Private to the equations of motion (dynamics.cpp: M and h;
// recursive_dynamics.cpp: inverse and forward dynamics): the spatial algebra
// they share and what they know of each body, in its axes about its G.

#include <optional>
#include <string>
#include <vector>

#include <symdyn/model/detail/intermediates.hpp>
#include <symdyn/model/dynamics.hpp>

namespace symdyn::model::detail {

// The Vec3 and Mat3 operators, which those of Spatial below would hide.
using model::operator+;
using model::operator*;

// A twist (angular velocity, velocity of G) or a wrench (moment about G,
// force): their dot product is a power.
struct Spatial {
  Vec3 angular = zero3(), linear = zero3();
};

inline Expr dot(const Spatial& a, const Spatial& b) {
  return model::dot(a.angular, b.angular) + model::dot(a.linear, b.linear);
}

inline Spatial operator+(const Spatial& a, const Spatial& b) {
  return {a.angular + b.angular, a.linear + b.linear};
}

inline Spatial operator*(Expr c, const Spatial& s) {
  return {c * s.angular, c * s.linear};
}

inline Mat3 zero_matrix() {
  return {Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0)};
}

// The inertia of a body or a subtree about a point: mass m, first moment h
// (m times the centre of mass from the point) and rotational inertia K.
struct SpatialInertia {
  Expr mass{0};
  Vec3 moment = zero3();
  Mat3 rotational = zero_matrix();
};

inline SpatialInertia operator+(const SpatialInertia& a, const SpatialInertia& b) {
  SpatialInertia sum{a.mass + b.mass, a.moment + b.moment, {}};
  for (int i = 0; i < 9; ++i) sum.rotational[i] = a.rotational[i] + b.rotational[i];
  return sum;
}

// The momentum a twist s gives: (K·ω + h×v, m·v + ω×h).
inline Spatial momentum(const SpatialInertia& I, const Spatial& s) {
  return {I.rotational * s.angular + cross(I.moment, s.linear),
          I.mass * s.linear + cross(s.angular, I.moment)};
}

// R·K·Rᵀ for a symmetric K: the upper triangle, mirrored.
inline Mat3 rotate_symmetric(const Mat3& R, const Mat3& K) {
  const Mat3 RK = R * K;
  Mat3 out;
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      out[3 * i + j] = out[3 * j + i] =
          sum3(RK[3 * i] * R[3 * j], RK[3 * i + 1] * R[3 * j + 1], RK[3 * i + 2] * R[3 * j + 2]);
    }
  }
  return out;
}

// A child's inertia (its axes, about its G) in its reference's axes about the
// reference's G, the child's G being at d: turned by R, then moved,
//   h' = h + m·d,   K' = K + m·(|d|²·1 - d·dᵀ) + 2·(d·h)·1 - d·hᵀ - h·dᵀ.
inline SpatialInertia to_reference(const SpatialInertia& I, const Mat3& R, const Vec3& d) {
  const Vec3 h = R * I.moment;
  SpatialInertia out{I.mass, h + I.mass * d, rotate_symmetric(R, I.rotational)};
  const Expr& m = I.mass;
  for (int i = 0; i < 3; ++i) {
    const int u = (i + 1) % 3, w = (i + 2) % 3;
    out.rotational[4 * i] +=
        m * (d[u] * d[u] + d[w] * d[w]) + Expr(2) * (d[u] * h[u] + d[w] * h[w]);
    for (int j = i + 1; j < 3; ++j) {
      const Expr shift = -(m * d[i] * d[j]) - d[i] * h[j] - h[i] * d[j];
      out.rotational[3 * i + j] += shift;
      out.rotational[3 * j + i] += shift;
    }
  }
  return out;
}

// A child's wrench (its axes, about its G) in its reference's axes about the
// reference's G: (R·n + d×R·f, R·f).
inline Spatial to_reference(const Spatial& wrench, const Mat3& R, const Vec3& d) {
  const Vec3 f = R * wrench.linear;
  return {R * wrench.angular + cross(d, f), f};
}

// The local twist l_j = coefficient·direction of coordinate j.
struct LocalTwist {
  std::size_t j;
  Expr coefficient;
  std::size_t direction;
};

// What the sums need of each body, in its axes about its G.
struct BodyTerms {
  Mat3 R;                               // its axes to its reference's
  Vec3 x;                               // its G from its reference's, reference axes
  Spatial twist, acceleration;          // (ω, v) and (dω/dt, a) at qdd = 0, less gravity
  std::vector<Spatial> directions;      // of the local twists
  std::vector<LocalTwist> local;        // l_j = coefficient·direction, for every nonzero l_j
  std::vector<Spatial> momenta;         // F = I^C·direction, for each direction
  Vec3 r;                               // its G from its reference's, its axes
  SpatialInertia inertia, own_inertia;  // of the body, then of its subtree; of the body
  Spatial wrench, own_wrench;  // of the body, then of its subtree (at qdd = 0); of the body
  std::vector<std::optional<Spatial>> gathered, from_children;  // (nq) G_k and G'_k, where nonzero
};

// d.inverse, tau = M·qdd + h (nq), by recursive Newton-Euler from h = d.bias;
// given the absolute kinematics (the bodies' orientations), also d.reactions.
void inverse_dynamics(const Model& model, const std::vector<BodyTerms>& bodies,
                      const Kinematics* reactions, IntermediateNames& names, Dynamics& d);

// d.forward and d.pivots by the articulated-body algorithm, or d.why_not.
void forward_dynamics(const Model& model, const std::vector<BodyTerms>& bodies,
                      IntermediateNames& names, Dynamics& d);

}  // namespace symdyn::model::detail
