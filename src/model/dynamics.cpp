#include <symdyn/model/dynamics.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <unordered_map>

#include <symdyn/model/intermediates.hpp>
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::model {
namespace {

// The Vec3 and Mat3 operators, which those of Spatial below would hide.
using model::operator+;
using model::operator*;

// A twist (angular velocity, velocity of G) or a wrench (moment about G,
// force): their dot product is a power.
struct Spatial {
  Vec3 angular = zero3(), linear = zero3();
};

Expr dot(const Spatial& a, const Spatial& b) { return model::dot(a.angular, b.angular) + model::dot(a.linear, b.linear); }

Spatial operator+(const Spatial& a, const Spatial& b) { return {a.angular + b.angular, a.linear + b.linear}; }

Spatial operator*(Expr c, const Spatial& s) { return {c * s.angular, c * s.linear}; }

Mat3 zero_matrix() { return {Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0)}; }

// The inertia of a body or a subtree about a point: mass m, first moment h
// (m times the centre of mass from the point) and rotational inertia K.
struct SpatialInertia {
  Expr mass{0};
  Vec3 moment = zero3();
  Mat3 rotational = zero_matrix();
};

SpatialInertia operator+(const SpatialInertia& a, const SpatialInertia& b) {
  SpatialInertia sum{a.mass + b.mass, a.moment + b.moment, {}};
  for (int i = 0; i < 9; ++i) sum.rotational[i] = a.rotational[i] + b.rotational[i];
  return sum;
}

// The momentum a twist s gives: (K·ω + h×v, m·v + ω×h).
Spatial momentum(const SpatialInertia& I, const Spatial& s) {
  return {I.rotational * s.angular + cross(I.moment, s.linear), I.mass * s.linear + cross(s.angular, I.moment)};
}

// R·K·Rᵀ for a symmetric K: the upper triangle, mirrored.
Mat3 rotate_symmetric(const Mat3& R, const Mat3& K) {
  const Mat3 RK = R * K;
  Mat3 out;
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      out[3 * i + j] = out[3 * j + i] = sum3(RK[3 * i] * R[3 * j], RK[3 * i + 1] * R[3 * j + 1], RK[3 * i + 2] * R[3 * j + 2]);
    }
  }
  return out;
}

// A child's inertia (its axes, about its G) in its reference's axes about the
// reference's G, the child's G being at d: turned by R, then moved,
//   h' = h + m·d,   K' = K + m·(|d|²·1 - d·dᵀ) + 2·(d·h)·1 - d·hᵀ - h·dᵀ.
SpatialInertia to_reference(const SpatialInertia& I, const Mat3& R, const Vec3& d) {
  const Vec3 h = R * I.moment;
  SpatialInertia out{I.mass, h + I.mass * d, rotate_symmetric(R, I.rotational)};
  const Expr& m = I.mass;
  for (int i = 0; i < 3; ++i) {
    const int u = (i + 1) % 3, w = (i + 2) % 3;
    out.rotational[4 * i] += m * (d[u] * d[u] + d[w] * d[w]) + Expr(2) * (d[u] * h[u] + d[w] * h[w]);
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
Spatial to_reference(const Spatial& wrench, const Mat3& R, const Vec3& d) {
  const Vec3 f = R * wrench.linear;
  return {R * wrench.angular + cross(d, f), f};
}

Mat3 transpose(const Mat3& A) { return {A[0], A[3], A[6], A[1], A[4], A[7], A[2], A[5], A[8]}; }

Mat3 skew(const Vec3& d) { return {Expr(0), -d[2], d[1], d[2], Expr(0), -d[0], -d[1], d[0], Expr(0)}; }

// A general symmetric spatial inertia, an articulated body's: the momentum of
// a twist (ω, v) is (A·ω + B·v, Bᵀ·ω + C·v), A and C symmetric. A rigid body
// about its G has A = K, B = 0, C = m·1.
struct ArticulatedInertia {
  Mat3 A, B, C;
};

ArticulatedInertia articulated(const SpatialInertia& I) {
  const Expr m = I.mass;
  return {I.rotational, skew(I.moment), {m, Expr(0), Expr(0), Expr(0), m, Expr(0), Expr(0), Expr(0), m}};
}

Spatial momentum(const ArticulatedInertia& I, const Spatial& s) {
  return {I.A * s.angular + I.B * s.linear, transpose_times(I.B, s.angular) + I.C * s.linear};
}

// An articulated inertia Xᵀ·I·X in other axes (R: from I's to the new) or
// about another point, I's origin at d from it (S = skew(d), P = B·S):
//   A' = A - P - Pᵀ - S·C·S,   B' = B + S·C,   C' = C.
// R·B·Rᵀ for a rotation R about axis k by an angle whose cosine and sine
// are c and s, in the plane (i, j): the symmetric part of B's block there
// turns by twice the angle and its antisymmetric part α stays,
//   B'_ii = (B_ii + B_jj)/2 + h·cos 2θ - σ·sin 2θ,   B'_jj = B_ii + B_jj - B'_ii,
//   B'_ij = h·sin 2θ + σ·cos 2θ ± α,   h = (B_ii - B_jj)/2, σ, α = (B_ij ± B_ji)/2,
// fewer products than R·B·Rᵀ multiplied out.
Mat3 turned_in_plane(const Mat3& B, int k, Expr c, Expr s, Expr c2, Expr s2) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const auto at = [](int r, int col) { return 3 * r + col; };
  Mat3 out = B;
  const Expr half = Expr(1) / Expr(2), sum = B[at(i, i)] + B[at(j, j)], h = half * (B[at(i, i)] - B[at(j, j)]);
  const Expr sigma = half * (B[at(i, j)] + B[at(j, i)]), alpha = half * (B[at(i, j)] - B[at(j, i)]);
  out[at(i, i)] = half * sum + h * c2 - sigma * s2;
  out[at(j, j)] = sum - out[at(i, i)];
  const Expr off = h * s2 + sigma * c2;
  out[at(i, j)] = off + alpha;
  out[at(j, i)] = off - alpha;
  out[at(i, k)] = c * B[at(i, k)] - s * B[at(j, k)];
  out[at(j, k)] = s * B[at(i, k)] + c * B[at(j, k)];
  out[at(k, i)] = c * B[at(k, i)] - s * B[at(k, j)];
  out[at(k, j)] = s * B[at(k, i)] + c * B[at(k, j)];
  return out;
}

// The axis k of a rotation about a coordinate axis, R = [c -s; s c] in the
// plane after it, or -1.
int plane_rotation_axis(const Mat3& R) {
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    if (R[4 * k].is_one() && R[3 * k + i].is_zero() && R[3 * k + j].is_zero() && R[3 * i + k].is_zero() &&
        R[3 * j + k].is_zero() && R[3 * i + i] == R[3 * j + j] && R[3 * i + j] == -R[3 * j + i]) {
      return k;
    }
  }
  return -1;
}

ArticulatedInertia turned(const ArticulatedInertia& I, const Mat3& R) {
  if (const int k = plane_rotation_axis(R); k >= 0) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const Expr c = R[4 * i], s = R[3 * j + i], c2 = c * c - s * s, s2 = Expr(2) * c * s;
    return {turned_in_plane(I.A, k, c, s, c2, s2), turned_in_plane(I.B, k, c, s, c2, s2),
            turned_in_plane(I.C, k, c, s, c2, s2)};
  }
  return {rotate_symmetric(R, I.A), R * I.B * transpose(R), rotate_symmetric(R, I.C)};
}

ArticulatedInertia moved(const ArticulatedInertia& I, const Vec3& d) {
  const Mat3 &A = I.A, &B = I.B, &C = I.C;
  const Mat3 S = skew(d);
  const Mat3 SC = S * C, P = B * S, SCS = SC * S;
  ArticulatedInertia out{A, B, C};
  for (int i = 0; i < 9; ++i) out.B[i] = B[i] + SC[i];
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      out.A[3 * i + j] = out.A[3 * j + i] = A[3 * i + j] - P[3 * i + j] - P[3 * j + i] - SCS[3 * i + j];
    }
  }
  return out;
}

// I - y·yᵀ·s for a spatial y (s a scalar): the rank-one update of the articulated-body algorithm.
ArticulatedInertia minus_outer(const ArticulatedInertia& I, const Spatial& y, Expr s) {
  ArticulatedInertia out = I;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (j >= i) {
        out.A[3 * i + j] = out.A[3 * j + i] = I.A[3 * i + j] - y.angular[i] * y.angular[j] * s;
        out.C[3 * i + j] = out.C[3 * j + i] = I.C[3 * i + j] - y.linear[i] * y.linear[j] * s;
      }
      out.B[3 * i + j] = I.B[3 * i + j] - y.angular[i] * y.linear[j] * s;
    }
  }
  return out;
}

// A reference's twist or acceleration seen by the body: (Rᵀ·ω, Rᵀ·v + (Rᵀ·ω)×r).
Spatial to_body(const Spatial& s, const Mat3& R, const Vec3& r) {
  const Vec3 w = transpose_times(R, s.angular);
  return {w, transpose_times(R, s.linear) + cross(w, r)};
}

// The steps of a motion as frame changes, x_outer = R·x_inner or x_inner + t:
// a twist, a wrench or an articulated inertia carried outward through one
// (up) or a twist inward (down, the inverse).
using Step = Transform::Step;

bool varies(const Step& s) {
  if (s.is_rotation) return !s.angle.is_number();
  return !(s.displacement[0].is_number() && s.displacement[1].is_number() && s.displacement[2].is_number());
}

Mat3 rotation(const Step& s) { return Transform::rotation_matrix(s.axis, s.angle); }

Spatial twist_up(const Spatial& s, const Step& step) {
  if (step.is_rotation) return {rotation(step) * s.angular, rotation(step) * s.linear};
  return {s.angular, s.linear + cross(step.displacement, s.angular)};
}

Spatial twist_down(const Spatial& s, const Step& step) {
  if (step.is_rotation) return {transpose_times(rotation(step), s.angular), transpose_times(rotation(step), s.linear)};
  return {s.angular, s.linear - cross(step.displacement, s.angular)};
}

Spatial wrench_up(const Spatial& f, const Step& step) {
  if (step.is_rotation) return {rotation(step) * f.angular, rotation(step) * f.linear};
  return {f.angular + cross(step.displacement, f.linear), f.linear};
}

ArticulatedInertia inertia_up(const ArticulatedInertia& I, const Step& step) {
  return step.is_rotation ? turned(I, rotation(step)) : moved(I, step.displacement);
}

// The steps to take one after the other, without those that change nothing,
// adjacent displacements added into one (a child's last constant step and its
// reference's first: one move instead of two).
std::vector<Step> merged(const std::vector<Step>& steps) {
  std::vector<Step> out;
  for (const Step& s : steps) {
    if (s.is_rotation ? s.angle.is_zero() : is_zero(s.displacement)) continue;
    if (!s.is_rotation && !out.empty() && !out.back().is_rotation) {
      out.back().displacement = out.back().displacement + s.displacement;
      if (is_zero(out.back().displacement)) out.pop_back();
      continue;
    }
    out.push_back(s);
  }
  return out;
}

std::vector<Step> reversed(std::vector<Step> steps) {
  std::reverse(steps.begin(), steps.end());
  return steps;
}

std::vector<Step> operator+(std::vector<Step> a, const std::vector<Step>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// A motion T = S_1·...·S_n seen from its last frame (the body's): r, the
// body's G from the reference's in the body's axes, and the screws, the unit
// twists at G of every varying angle or displacement component σ, with σ.
// Built from the last step back, R being the rotation of the steps after the
// current one, so that nothing is turned there and back: a hinge's axis and
// a slider's direction come out as constant as they are.
struct Screw {
  Spatial twist;
  Expr scalar;
};

struct MotionInBodyAxes {
  Vec3 r = zero3();
  std::vector<Screw> screws;
};

MotionInBodyAxes in_body_axes(const Transform& motion) {
  MotionInBodyAxes out;
  Mat3 R = identity3();
  const std::vector<Transform::Step>& steps = motion.steps();
  for (auto s = steps.rbegin(); s != steps.rend(); ++s) {
    if (s->is_rotation) {
      if (!s->angle.is_number()) {
        const Vec3 axis = transpose_times(R, s->axis);
        out.screws.push_back({{axis, cross(axis, out.r)}, s->angle});
      }
      R = Transform::rotation_matrix(s->axis, s->angle) * R;
      continue;
    }
    for (int k = 2; k >= 0; --k) {
      if (s->displacement[k].is_number()) continue;
      Vec3 e = zero3();
      e[k] = Expr(1);
      out.screws.push_back({{zero3(), transpose_times(R, e)}, s->displacement[k]});
    }
    out.r = out.r + transpose_times(R, s->displacement);
  }
  std::reverse(out.screws.begin(), out.screws.end());
  return out;
}

class EquationsOfMotion {
 public:
  EquationsOfMotion(const Model& model, const Kinematics& k, const SimplifyFunction& simplify)
      : model_(model),
        k_(k),
        simplify_(simplify),
        nq_(model.coordinates().size()),
        refs_(model.reference_indices()),
        order_(model.topological_order()),
        d_dt_(rates(model)),
        at_zero_qdd_(zero_qdd(model)),
        bodies_(k.bodies.size()) {}

  Dynamics run() {
    define_at_zero_qdd();
    for (int i : order_) add_body(i);
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) gather_subtree(*i);
    for (std::size_t a = 0; a < bodies_.size(); ++a) add_momenta(a);
    find_movers();
    for (Body& b : bodies_) b.gathered.resize(nq_), b.from_children.resize(nq_);
    for (std::size_t k = 0; k < nq_; ++k) gather_momenta(k);
    d_.mass_matrix.assign(nq_ * nq_, Expr(0));
    d_.bias.assign(nq_, Expr(0));
    for (std::size_t k = 0; k < nq_; ++k) {
      std::vector<Expr> terms;
      for (const Mover& m : movers_[k]) terms.push_back(m.coefficient * dot(direction(m), bodies_[m.body].wrench));
      d_.bias[k] = symbolic::add(terms);
      for (std::size_t j = 0; j <= k; ++j) d_.mass_matrix[j * nq_ + k] = d_.mass_matrix[k * nq_ + j] = mass_matrix_entry(j, k);
    }
    d_.inverse = inverse_dynamics();
    d_.why_not = articulated_body_obstacle();
    if (d_.why_not.empty()) articulated_body_algorithm();
    std::vector<symbolic::Definition> gathered = names_.take_definitions();
    d_.definitions.insert(d_.definitions.end(), gathered.begin(), gathered.end());
    return std::move(d_);
  }

 private:
  struct LocalTwist {
    std::size_t j;
    Expr coefficient;
    std::size_t direction;
  };

  // A local twist of some body, as one coordinate drives it.
  struct Mover {
    std::size_t body;
    Expr coefficient;
    std::size_t direction;
  };

  // What the sums need of each body, in its axes about its G.
  struct Body {
    Mat3 R;                                 // its axes to its reference's
    Vec3 x;                                 // its G from its reference's, reference axes
    Spatial twist, acceleration;            // (ω, v) and (dω/dt, a) at qdd = 0, less gravity
    std::vector<Spatial> directions;        // of the local twists
    std::vector<LocalTwist> local;          // l_j = coefficient·direction, for every nonzero l_j
    std::vector<Spatial> momenta;           // F = I^C·direction, for each direction
    Vec3 r;                                 // its G from its reference's, its axes
    SpatialInertia inertia, own_inertia;    // of the body, then of its subtree; of the body
    Spatial wrench, own_wrench;             // of the body, then of its subtree (at qdd = 0); of the body
    std::vector<std::optional<Spatial>> gathered, from_children;  // (nq) G_k and G'_k, where nonzero
  };

  static symbolic::RateMap rates(const Model& model) {
    symbolic::RateMap rates;
    for (const Coordinate& c : model.coordinates()) rates.emplace(c.q, c.qd), rates.emplace(c.qd, c.qdd);
    for (const Dependent& d : model.dependents()) rates.emplace(d.symbol, d.rate), rates.emplace(d.rate, d.acceleration);
    return rates;
  }

  static symbolic::Substitution zero_qdd(const Model& model) {
    std::unordered_map<Expr, Expr> zero;
    for (const Coordinate& c : model.coordinates()) zero.emplace(c.qdd, Expr(0));
    return symbolic::Substitution(std::move(zero));
  }

  // qdd -> 0 and each pdd_k -> pdd⁰_k, its value at qdd = 0, defined in order
  // on the ones before. A value that is a number or a symbol replaces the
  // symbol as it is, so that zeros cancel the terms they multiply.
  void define_at_zero_qdd() {
    for (const DependentKinematics& p : k_.dependents) {
      const Expr symbol = p.symbols.acceleration;
      const Expr at_rest_value = at_zero_qdd_(p.acceleration);
      if (at_rest_value.is_number() || at_rest_value.is_symbol()) {
        at_zero_qdd_.add(symbol, at_rest_value);
        continue;
      }
      const Expr at_rest = symbolic::symbol(fmt::format("{}__0", symbol.name()), symbolic::SymbolKind::DependentAcceleration);
      d_.definitions.push_back({at_rest, at_rest_value});
      at_zero_qdd_.add(symbol, at_rest);
    }
  }

  Expr simplified(Expr e) const { return simplify_ ? simplify_(e) : e; }
  Vec3 d_dt(const Vec3& v) { return {d_dt_(v[0]), d_dt_(v[1]), d_dt_(v[2])}; }
  Vec3 at_zero_qdd(const Vec3& v) { return {at_zero_qdd_(v[0]), at_zero_qdd_(v[1]), at_zero_qdd_(v[2])}; }

  void name(Spatial& s, const std::string& prefix) {
    names_.name_all(s.angular, prefix + "w");
    names_.name_all(s.linear, prefix + "v");
  }

  // The body's pose relative to its reference, local twist directions, twist,
  // acceleration at qdd = 0, inertia and wrench, all in its axes (top-down).
  void add_body(int i) {
    const model::Body& body = model_.bodies()[i];
    const std::string& n = body.name();
    Body& out = bodies_[i];
    const MotionInBodyAxes local = in_body_axes(body.motion());
    out.R = k_.bodies[i].relative.R;
    out.x = k_.bodies[i].relative.x;
    names_.name_all(out.x, n + ".xr");  // not ".x": the kinematics' name of the absolute one
    add_local_twists(local.screws, out);
    for (std::size_t d = 0; d < out.directions.size(); ++d) name(out.directions[d], fmt::format("{}.l{}_", n, d));

    // The local twist l = Σ σ'·screw and its rate Σ σ''·screw + σ'·screw',
    // at qdd = 0 (the scalars simplified: an inline dependent parameter's
    // second derivative is long).
    Spatial l, dl;
    for (const Screw& s : local.screws) {
      const Expr rate = simplified(d_dt_(s.scalar));
      l = l + rate * s.twist;
      dl = dl + simplified(at_zero_qdd_(d_dt_(rate))) * s.twist + rate * Spatial{d_dt(s.twist.angular), d_dt(s.twist.linear)};
    }
    const Vec3 dw_l = at_zero_qdd(dl.angular);
    const Vec3 a_l = at_zero_qdd(cross(l.angular, l.linear) + dl.linear);

    // The reference's twist and acceleration (the ground's: 0 and -g), turned
    // to the body's axes.
    Spatial twist_B, acceleration_B{zero3(), zero3() - model_.gravity()};
    if (refs_[i] >= 0) twist_B = bodies_[refs_[i]].twist, acceleration_B = bodies_[refs_[i]].acceleration;
    Vec3 w_B = transpose_times(out.R, twist_B.angular);
    Vec3 dw_B = transpose_times(out.R, acceleration_B.angular);
    names_.name_all(w_B, n + ".wB");
    names_.name_all(dw_B, n + ".dwB");
    Vec3 r = local.r;
    names_.name_all(r, n + ".r");
    out.twist = {w_B + l.angular, transpose_times(out.R, twist_B.linear) + cross(w_B, r) + l.linear};
    out.acceleration = {dw_B + cross(w_B, l.angular) + dw_l,
                        transpose_times(out.R, acceleration_B.linear) + cross(dw_B, r) + cross(w_B, cross(w_B, r)) +
                            Expr(2) * cross(w_B, l.linear) + a_l};
    name(out.twist, n + ".t");
    name(out.acceleration, n + ".a");

    const Mat3& J = body.inertia();
    const Vec3& w = out.twist.angular;
    out.inertia = out.own_inertia = {body.mass(), zero3(), J};
    out.wrench = out.own_wrench = {J * out.acceleration.angular + cross(w, J * w), body.mass() * out.acceleration.linear};
    out.r = r;
  }

  // The local twists as coefficients times directions, a body's momentum being
  // computed once per direction. Of three ways to span them, the one with the
  // fewest directions (the first on a tie): one per coordinate; one per rate
  // the motion holds (a dependent parameter's pd_p has coefficients dp/dq_j:
  // the slider driven by p alone); one per screw (link6's Troty(beta - alpha),
  // in any variant).
  void add_local_twists(const std::vector<Screw>& screws, Body& out) const {
    std::vector<std::vector<Expr>> dscalar_dq;  // (screws x nq)
    for (const Screw& s : screws) dscalar_dq.push_back(coordinate_derivatives(s.scalar));
    Span by_coordinate;
    for (std::size_t j = 0; j < nq_; ++j) {
      std::vector<Expr> weights;
      for (const auto& d : dscalar_dq) weights.push_back(d[j]);
      std::vector<Expr> unit(nq_, Expr(0));
      unit[j] = Expr(1);
      by_coordinate.add(combination(screws, weights), std::move(unit));
    }
    std::vector<Span> spans{by_coordinate};
    if (by_coordinate.directions.size() > 1) {  // else nothing has fewer
      spans.push_back(by_rates(screws));
      Span by_screws;
      for (std::size_t s = 0; s < screws.size(); ++s) by_screws.add(screws[s].twist, dscalar_dq[s]);
      spans.push_back(by_screws);
    }
    const Span& fewest = *std::min_element(spans.begin(), spans.end(), [](const Span& x, const Span& y) {
      return x.directions.size() < y.directions.size();
    });
    for (std::size_t d = 0; d < fewest.directions.size(); ++d) {
      for (std::size_t j = 0; j < nq_; ++j) {
        if (!fewest.coefficients[d][j].is_zero()) out.local.push_back({j, fewest.coefficients[d][j], d});
      }
      out.directions.push_back(fewest.directions[d]);
    }
  }

  static Spatial combination(const std::vector<Screw>& screws, const std::vector<Expr>& weights) {
    Spatial sum;
    for (std::size_t s = 0; s < screws.size(); ++s) sum = sum + weights[s] * screws[s].twist;
    return sum;
  }

  // Local twist directions and, for each, its coefficient in the local twist
  // of every coordinate.
  struct Span {
    std::vector<Spatial> directions;
    std::vector<std::vector<Expr>> coefficients;  // (directions x nq)

    // Keeps a direction unless it or all its coefficients are zero.
    void add(const Spatial& direction, std::vector<Expr> coefficient) {
      if (is_zero(direction.angular) && is_zero(direction.linear)) return;
      if (std::all_of(coefficient.begin(), coefficient.end(), [](Expr e) { return e.is_zero(); })) return;
      directions.push_back(direction);
      coefficients.push_back(std::move(coefficient));
    }
  };

  // One direction per coordinate or dependent parameter r the screws' scalars
  // hold, Σ_s ∂σ_s/∂r·screw_s, with coefficients dr/dq_j (1 for q_j, the
  // Jacobian for p).
  Span by_rates(const std::vector<Screw>& screws) const {
    std::vector<Expr> scalars;
    for (const Screw& s : screws) scalars.push_back(s.scalar);
    Span span;
    for (Expr r : symbolic::free_symbols(scalars)) {
      std::vector<Expr> coefficient(nq_, Expr(0));
      for (std::size_t j = 0; j < nq_; ++j) {
        if (r == model_.coordinates()[j].q) coefficient[j] = Expr(1);
      }
      for (const DependentKinematics& p : k_.dependents) {
        if (r == p.symbols.symbol) coefficient = p.jacobian_symbols;
      }
      std::vector<Expr> weights;
      symbolic::Differentiator by_r(r);
      for (Expr s : scalars) weights.push_back(simplified(by_r(s)));
      span.add(combination(screws, weights), std::move(coefficient));
    }
    return span;
  }

  // dσ/dq_j for every j, through the dependent parameters σ holds.
  std::vector<Expr> coordinate_derivatives(Expr scalar) const {
    std::vector<Expr> total;
    for (const Coordinate& c : model_.coordinates()) total.push_back(symbolic::diff(scalar, c.q));
    for (const DependentKinematics& p : k_.dependents) {
      const Expr by_p = symbolic::diff(scalar, p.symbols.symbol);
      if (by_p.is_zero()) continue;
      for (std::size_t j = 0; j < total.size(); ++j) total[j] += by_p * p.jacobian_symbols[j];
    }
    for (Expr& t : total) t = simplified(t);
    return total;
  }

  // Called children first: names the subtree's inertia and wrench, and adds
  // them to the reference's.
  void gather_subtree(int i) {
    Body& b = bodies_[i];
    const std::string& n = model_.bodies()[i].name();
    b.inertia.mass = names_(b.inertia.mass, n + ".mass");
    names_.name_all(b.inertia.moment, n + ".h");
    names_.name_all(b.inertia.rotational, n + ".K");
    name(b.wrench, n + ".f");
    if (refs_[i] < 0) return;
    Body& B = bodies_[refs_[i]];
    B.inertia = B.inertia + to_reference(b.inertia, b.R, b.x);
    B.wrench = B.wrench + to_reference(b.wrench, b.R, b.x);
  }

  // The momenta F = I^C·l of the body's local twist directions.
  void add_momenta(std::size_t a) {
    Body& body = bodies_[a];
    for (std::size_t d = 0; d < body.directions.size(); ++d) {
      body.momenta.push_back(momentum(body.inertia, body.directions[d]));
      name(body.momenta.back(), fmt::format("{}.F{}_", model_.bodies()[a].name(), d));
    }
  }

  // For every coordinate, the local twists it drives.
  void find_movers() {
    movers_.assign(nq_, {});
    for (int i : order_) {
      for (const LocalTwist& l : bodies_[i].local) movers_[l.j].push_back({static_cast<std::size_t>(i), l.coefficient, l.direction});
    }
  }

  // G_k(a), the momentum q_k's rate gives a's subtree, and G'_k(a), its
  // children's part, for every body (children first).
  void gather_momenta(std::size_t k) {
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) {
      const std::string& n = model_.bodies()[*i].name();
      Body& b = bodies_[*i];
      if (auto& part = b.from_children[k]; part) name(*part, fmt::format("{}.Gc{}_", n, k));
      std::optional<Spatial> total = b.from_children[k];
      for (const LocalTwist& l : b.local) {
        if (l.j == k) total = total.value_or(Spatial{}) + l.coefficient * b.momenta[l.direction];
      }
      if (!total) continue;
      name(*total, fmt::format("{}.G{}_", n, k));
      b.gathered[k] = total;
      if (refs_[*i] < 0) continue;
      auto& parent = bodies_[refs_[*i]].from_children[k];
      parent = parent.value_or(Spatial{}) + to_reference(*total, b.R, b.x);
    }
  }

  // M_jk = Σ_a Σ_d c_dj·l_d·G_k(a) + Σ_a Σ_d c_dk·l_d·G'_j(a).
  Expr mass_matrix_entry(std::size_t j, std::size_t k) const {
    std::vector<Expr> terms;
    for (const Mover& m : movers_[j]) {
      if (const auto& G = bodies_[m.body].gathered[k]) terms.push_back(m.coefficient * dot(direction(m), *G));
    }
    for (const Mover& m : movers_[k]) {
      if (const auto& G = bodies_[m.body].from_children[j]) terms.push_back(m.coefficient * dot(direction(m), *G));
    }
    return symbolic::add(terms);
  }

  const Spatial& direction(const Mover& m) const { return bodies_[m.body].directions[m.direction]; }

  // tau_j = h_j + Σ_a Σ_d c_dj·l_d·(I·α)^C_a, α the acceleration qdd adds
  // (parents first), I·α gathered up (children first).
  std::vector<Expr> inverse_dynamics() {
    std::vector<Spatial> alpha(bodies_.size()), gathered(bodies_.size());
    for (int i : order_) {
      const Body& b = bodies_[i];
      Spatial a = refs_[i] < 0 ? Spatial{} : to_body(alpha[refs_[i]], b.R, b.r);
      for (const LocalTwist& l : b.local) a = a + (l.coefficient * model_.coordinates()[l.j].qdd) * b.directions[l.direction];
      name(a, model_.bodies()[i].name() + ".qa");
      alpha[i] = a;
      gathered[i] = momentum(b.own_inertia, a);
    }
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) {
      name(gathered[*i], model_.bodies()[*i].name() + ".qf");
      if (refs_[*i] >= 0) {
        gathered[refs_[*i]] = gathered[refs_[*i]] + to_reference(gathered[*i], bodies_[*i].R, bodies_[*i].x);
      }
    }
    std::vector<Expr> tau;
    for (std::size_t k = 0; k < nq_; ++k) {
      std::vector<Expr> terms{d_.bias[k]};
      for (const Mover& m : movers_[k]) terms.push_back(m.coefficient * dot(direction(m), gathered[m.body]));
      tau.push_back(symbolic::add(terms));
    }
    return tau;
  }

  // Why the articulated-body algorithm does not apply, or nothing: each
  // coordinate must drive the local motion of exactly one body.
  std::string articulated_body_obstacle() const {
    for (std::size_t j = 0; j < nq_; ++j) {
      std::vector<std::size_t> bodies;
      for (const Mover& m : movers_[j]) {
        if (std::find(bodies.begin(), bodies.end(), m.body) == bodies.end()) bodies.push_back(m.body);
      }
      const std::string& q = model_.coordinates()[j].q.name();
      if (bodies.empty()) return fmt::format("coordinate '{}' drives no body's motion", q);
      if (bodies.size() > 1) {
        return fmt::format("coordinate '{}' drives the motions of bodies '{}' and '{}'", q,
                           model_.bodies()[bodies[0]].name(), model_.bodies()[bodies[1]].name());
      }
    }
    return {};
  }

  // What the articulated-body algorithm keeps of a body between its passes.
  struct Articulated {
    // The body's motion split after its last varying step (its joint): the
    // frame F there is where its articulated quantities are taken, the steps
    // after it being constant (G from F).
    std::vector<Step> joint, constant;
    std::vector<std::size_t> coordinates;  // the k it drives, in order
    std::vector<Spatial> S, Y;             // (k) local twist of each, Y = U·L⁻ᵀ
    std::vector<Expr> z, inverse_pivot;    // (k) z = L⁻¹·u, 1/d
    std::vector<std::vector<Expr>> L;      // (k x k) unit lower triangle of D = L·diag(d)·Lᵀ
  };

  void articulated_body_algorithm() {
    std::vector<Articulated>& a = articulated_;
    a.assign(bodies_.size(), {});
    std::vector<ArticulatedInertia> inertia(bodies_.size());
    std::vector<Spatial> bias(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const std::vector<Step>& steps = model_.bodies()[i].motion().steps();
      auto last = std::find_if(steps.rbegin(), steps.rend(), varies);
      a[i].joint.assign(steps.begin(), last.base());
      a[i].constant.assign(last.base(), steps.end());
      const std::string& n = model_.bodies()[i].name();
      const std::vector<Step> to_joint = merged(reversed(a[i].constant));
      inertia[i] = carry(articulated(bodies_[i].own_inertia), to_joint, n + ".Io");
      bias[i] = carry(bodies_[i].own_wrench, to_joint, wrench_up, n + ".po");
    }
    d_.forward.assign(nq_, Expr(0));
    d_.pivots.assign(2 * nq_, Expr(0));
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) {
      if (!articulate(*i, a[*i], inertia, bias)) {
        d_.forward.clear();
        d_.pivots.clear();
        return;
      }
    }
    std::vector<Spatial> alpha(bodies_.size());
    for (int i : order_) accelerate(i, a[i], alpha);
  }

  // Children first: I^A and p^A complete, the body's coordinates eliminated
  // (D factored, Y, z), I^a and p^a added to the reference's. False (why_not
  // said) where a pivot is exactly zero: M is singular everywhere.
  bool articulate(int i, Articulated& out, std::vector<ArticulatedInertia>& inertia, std::vector<Spatial>& bias) {
    const Body& b = bodies_[i];
    const std::string& n = model_.bodies()[i].name();
    ArticulatedInertia& IA = inertia[i];
    names_.name_all(IA.A, n + ".IAa");
    names_.name_all(IA.B, n + ".IAb");
    names_.name_all(IA.C, n + ".IAc");
    name(bias[i], n + ".pA");
    for (const LocalTwist& l : b.local) {
      if (std::find(out.coordinates.begin(), out.coordinates.end(), l.j) == out.coordinates.end()) out.coordinates.push_back(l.j);
    }
    std::sort(out.coordinates.begin(), out.coordinates.end());
    const std::size_t k = out.coordinates.size();
    std::vector<Spatial> U;
    const std::vector<Step> to_joint = merged(reversed(out.constant));
    for (std::size_t m = 0; m < k; ++m) {
      Spatial s;
      for (const LocalTwist& l : b.local) {
        if (l.j == out.coordinates[m]) s = s + l.coefficient * b.directions[l.direction];
      }
      s = carry(s, to_joint, twist_up, fmt::format("{}.Sg{}_", n, m));
      name(s, fmt::format("{}.S{}_", n, m));
      out.S.push_back(s);
      U.push_back(momentum(IA, s));
      name(U.back(), fmt::format("{}.U{}_", n, m));
    }
    if (!factor(n, U, bias[i], out)) return false;
    ArticulatedInertia Ia = IA;
    Spatial pa = bias[i];
    for (std::size_t m = 0; m < k; ++m) {
      Ia = minus_outer(Ia, out.Y[m], out.inverse_pivot[m]);
      pa = pa + (out.z[m] * out.inverse_pivot[m]) * out.Y[m];
    }
    if (refs_[i] < 0) return true;
    names_.name_all(Ia.A, n + ".Iaa");
    names_.name_all(Ia.B, n + ".Iab");
    names_.name_all(Ia.C, n + ".Iac");
    name(pa, n + ".pa");
    // Out through the body's joint steps, then in to the reference's F.
    const std::vector<Step> up = merged(reversed(out.joint) + reversed(articulated_[refs_[i]].constant));
    const ArticulatedInertia carried = carry(Ia, up, n + ".X");
    ArticulatedInertia& IB = inertia[refs_[i]];
    for (int e = 0; e < 9; ++e) IB.A[e] += carried.A[e], IB.B[e] += carried.B[e], IB.C[e] += carried.C[e];
    bias[refs_[i]] = bias[refs_[i]] + carry(pa, up, wrench_up, n + ".pc");
    return true;
  }

  // A twist or wrench through steps, named after each.
  Spatial carry(Spatial s, const std::vector<Step>& steps, Spatial (*through)(const Spatial&, const Step&),
                const std::string& prefix) {
    for (std::size_t k = 0; k < steps.size(); ++k) {
      s = through(s, steps[k]);
      name(s, fmt::format("{}{}_", prefix, k));
    }
    return s;
  }

  ArticulatedInertia carry(ArticulatedInertia I, const std::vector<Step>& steps, const std::string& prefix) {
    for (std::size_t k = 0; k < steps.size(); ++k) {
      I = inertia_up(I, steps[k]);
      names_.name_all(I.A, fmt::format("{}{}a", prefix, k));
      names_.name_all(I.B, fmt::format("{}{}b", prefix, k));
      names_.name_all(I.C, fmt::format("{}{}c", prefix, k));
    }
    return I;
  }

  // D = Sᵀ·U = L·diag(d)·Lᵀ unrolled (no square root), Y = U·L⁻ᵀ and
  // z = L⁻¹·(tau - Sᵀ·p^A), with E_nm = L_nm·d_m:
  //   E_nm = D_nm - Σ_{p<m} L_np·E_mp,   d_m = D_mm - Σ_{p<m} L_mp·E_mp.
  bool factor(const std::string& n, const std::vector<Spatial>& U, const Spatial& pA, Articulated& out) {
    const std::size_t k = U.size();
    const std::vector<Expr> tau = generalized_force_symbols(model_);
    out.L.assign(k, std::vector<Expr>(k, Expr(0)));
    std::vector<std::vector<Expr>> E(k, std::vector<Expr>(k, Expr(0)));
    for (std::size_t m = 0; m < k; ++m) {
      const Expr diagonal = names_(dot(out.S[m], U[m]), fmt::format("{}.D{}_{}", n, m, m));
      std::vector<Expr> pivot{diagonal};
      for (std::size_t p = 0; p < m; ++p) pivot.push_back(-(out.L[m][p] * E[m][p]));
      const Expr d = names_(symbolic::add(pivot), fmt::format("{}.d{}", n, m));
      if (d.is_zero()) {
        d_.why_not = fmt::format("the pivot of coordinate '{}' in body '{}' is zero whatever the state",
                                 model_.coordinates()[out.coordinates[m]].q.name(), n);
        return false;
      }
      out.inverse_pivot.push_back(Expr(1) / d);
      d_.pivots[2 * out.coordinates[m]] = d;
      d_.pivots[2 * out.coordinates[m] + 1] = diagonal;
      for (std::size_t r = m + 1; r < k; ++r) {
        std::vector<Expr> terms{dot(out.S[r], U[m])};
        for (std::size_t p = 0; p < m; ++p) terms.push_back(-(out.L[r][p] * E[m][p]));
        E[r][m] = names_(symbolic::add(terms), fmt::format("{}.E{}_{}", n, r, m));
        out.L[r][m] = E[r][m] * out.inverse_pivot[m];
      }
      Spatial y = U[m];
      Expr z = tau[out.coordinates[m]] - dot(out.S[m], pA);
      for (std::size_t p = 0; p < m; ++p) {
        y = y + (-out.L[m][p]) * out.Y[p];
        z = z - out.L[m][p] * out.z[p];
      }
      name(y, fmt::format("{}.Y{}_", n, m));
      out.Y.push_back(y);
      out.z.push_back(names_(z, fmt::format("{}.z{}", n, m)));
    }
    return true;
  }

  // Parents first: α' = X·α_B, qdd = L⁻ᵀ·diag(d)⁻¹·(z - Yᵀ·α'), α = α' + S·qdd.
  void accelerate(int i, const Articulated& a, std::vector<Spatial>& alpha) {
    const std::string& n = model_.bodies()[i].name();
    // In from the reference's F: its constant steps, then the body's joint steps.
    Spatial carried;
    if (refs_[i] >= 0) carried = carry(alpha[refs_[i]], merged(articulated_[refs_[i]].constant + a.joint), twist_down, n + ".ac");
    const std::size_t k = a.coordinates.size();
    std::vector<Expr> qdd(k);
    for (std::size_t m = k; m-- > 0;) {
      std::vector<Expr> terms{(a.z[m] - dot(a.Y[m], carried)) * a.inverse_pivot[m]};
      for (std::size_t r = m + 1; r < k; ++r) terms.push_back(-(a.L[r][m] * qdd[r]));
      qdd[m] = names_(symbolic::add(terms), fmt::format("{}.qdd{}", n, m));
    }
    Spatial total = carried;
    for (std::size_t m = 0; m < k; ++m) {
      total = total + qdd[m] * a.S[m];
      d_.forward[a.coordinates[m]] = qdd[m];
    }
    name(total, n + ".aa");
    alpha[i] = total;
  }

  const Model& model_;
  const Kinematics& k_;
  const SimplifyFunction& simplify_;
  const std::size_t nq_;
  const std::vector<int> refs_;
  const std::vector<int> order_;
  symbolic::TimeDerivative d_dt_;
  symbolic::Substitution at_zero_qdd_;
  IntermediateNames names_;
  std::vector<Body> bodies_;
  std::vector<std::vector<Mover>> movers_;  // (nq) the local twists of each coordinate
  std::vector<Articulated> articulated_;    // (nbody)
  Dynamics d_;
};

}  // namespace

std::vector<Expr> generalized_force_symbols(const Model& model) {
  std::vector<Expr> tau;
  for (const Coordinate& c : model.coordinates()) tau.push_back(symbolic::symbol("tau." + c.q.name(), symbolic::SymbolKind::Free));
  return tau;
}

Dynamics derive_dynamics(const Model& model, const Kinematics& k, const SimplifyFunction& simplify) {
  return EquationsOfMotion(model, k, simplify).run();
}

}  // namespace symdyn::model
