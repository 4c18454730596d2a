// The inverse dynamics (recursive Newton-Euler) and forward dynamics (the
// articulated-body algorithm) of model/dynamics.hpp, over the bodies the
// equations of motion derived (dynamics_terms.hpp), named in the same
// IntermediateNames so that they share the kinematics, h and each other.

#include <fmt/format.h>

#include <algorithm>

#include <symdyn/model/detail/dynamics_terms.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::model::detail {
namespace {

Mat3 transpose(const Mat3& A) {
  return {A[0], A[3], A[6], A[1], A[4], A[7], A[2], A[5], A[8]};
}

Mat3 skew(const Vec3& d) {
  return {Expr(0), -d[2], d[1], d[2], Expr(0), -d[0], -d[1], d[0], Expr(0)};
}

// A general symmetric spatial inertia, an articulated body's: the momentum of
// a twist (ω, v) is (A·ω + B·v, Bᵀ·ω + C·v), A and C symmetric. A rigid body
// about its G has A = K, B = 0, C = m·1.
struct ArticulatedInertia {
  Mat3 A, B, C;
};

ArticulatedInertia articulated(const SpatialInertia& I) {
  const Expr m = I.mass;
  return {I.rotational,
          skew(I.moment),
          {m, Expr(0), Expr(0), Expr(0), m, Expr(0), Expr(0), Expr(0), m}};
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
  const Expr half = Expr(1) / Expr(2), sum = B[at(i, i)] + B[at(j, j)],
             h = half * (B[at(i, i)] - B[at(j, j)]);
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
    if (R[4 * k].is_one() && R[3 * k + i].is_zero() && R[3 * k + j].is_zero() &&
        R[3 * i + k].is_zero() && R[3 * j + k].is_zero() && R[3 * i + i] == R[3 * j + j] &&
        R[3 * i + j] == -R[3 * j + i]) {
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
      out.A[3 * i + j] = out.A[3 * j + i] =
          A[3 * i + j] - P[3 * i + j] - P[3 * j + i] - SCS[3 * i + j];
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
  return !(s.displacement[0].is_number() && s.displacement[1].is_number() &&
           s.displacement[2].is_number());
}

// Whether a step moves in time (a joint's): it depends on a symbol that is not
// a run-time parameter (a step of those alone, Tdisp(r1/2, 0, 0), is constant).
bool moves(const Step& s) {
  std::vector<Expr> values;
  if (s.is_rotation) {
    values.push_back(s.angle);
  } else {
    values.assign(s.displacement.begin(), s.displacement.end());
  }
  const std::vector<Expr> symbols = symbolic::free_symbols(values);
  return std::any_of(symbols.begin(), symbols.end(),
                     [](Expr x) { return x.symbol_kind() != symbolic::SymbolKind::Parameter; });
}

Mat3 rotation(const Step& s) {
  return Transform::rotation_matrix(s.axis, s.angle);
}

Spatial twist_up(const Spatial& s, const Step& step) {
  if (step.is_rotation) return {rotation(step) * s.angular, rotation(step) * s.linear};
  return {s.angular, s.linear + cross(step.displacement, s.angular)};
}

Spatial twist_down(const Spatial& s, const Step& step) {
  if (step.is_rotation)
    return {transpose_times(rotation(step), s.angular), transpose_times(rotation(step), s.linear)};
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

// The recursive algorithms over the bodies of EquationsOfMotion
// (dynamics.cpp), their names in the same IntermediateNames.
class Recursion {
 public:
  Recursion(const Model& model, const std::vector<BodyTerms>& bodies, IntermediateNames& names)
      : model_(model),
        bodies_(bodies),
        names_(names),
        nq_(model.coordinates().size()),
        refs_(model.reference_indices()),
        order_(model.topological_order()),
        movers_(nq_) {
    for (int i : order_) {
      for (const LocalTwist& l : bodies_[i].local)
        movers_[l.j].push_back({static_cast<std::size_t>(i), l.coefficient, l.direction});
    }
  }

  // tau_j = h_j + Σ_a Σ_d c_dj·l_d·(I·α)^C_a, α the acceleration qdd adds
  // (parents first), I·α gathered up (children first) into gathered_.
  std::vector<Expr> inverse_dynamics(const std::vector<Expr>& bias) {
    std::vector<Spatial> alpha(bodies_.size());
    std::vector<Spatial>& gathered = gathered_;
    gathered.assign(bodies_.size(), {});
    for (int i : order_) {
      const BodyTerms& b = bodies_[i];
      Spatial a = refs_[i] < 0 ? Spatial{} : to_body(alpha[refs_[i]], b.R, b.r);
      for (const LocalTwist& l : b.local)
        a = a + (l.coefficient * model_.coordinates()[l.j].qdd) * b.directions[l.direction];
      name(a, model_.bodies()[i].name() + ".qa");
      alpha[i] = a;
      gathered[i] = momentum(b.own_inertia, a);
    }
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) {
      name(gathered[*i], model_.bodies()[*i].name() + ".qf");
      if (refs_[*i] >= 0) {
        gathered[refs_[*i]] =
            gathered[refs_[*i]] + to_reference(gathered[*i], bodies_[*i].R, bodies_[*i].x);
      }
    }
    std::vector<Expr> tau;
    for (std::size_t k = 0; k < nq_; ++k) {
      std::vector<Expr> terms{bias[k]};
      for (const Mover& m : movers_[k])
        terms.push_back(m.coefficient * dot(direction(m), gathered[m.body]));
      tau.push_back(symbolic::add(terms));
    }
    return tau;
  }

  // After inverse_dynamics: each body's joint reaction W = f^C + (I·α)^C - A^C
  // (force, then moment about its joint point), in its axes; the applied
  // wrenches A (global axes, at G) turned to the body's axes by `k`'s R.
  std::vector<Expr> joint_reactions(const Kinematics& k) {
    using model::operator+;  // not the steps' below
    const std::vector<Expr> F = applied_force_symbols(model_), M = applied_moment_symbols(model_);
    std::vector<Spatial> applied(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const Mat3& R = k.bodies[i].R;
      applied[i] = {transpose_times(R, {M[3 * i], M[3 * i + 1], M[3 * i + 2]}),
                    transpose_times(R, {F[3 * i], F[3 * i + 1], F[3 * i + 2]})};
    }
    std::vector<Expr> out(6 * bodies_.size());
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) {
      const BodyTerms& b = bodies_[*i];
      const std::string& n = model_.bodies()[*i].name();
      name(applied[*i], n + ".A");
      if (refs_[*i] >= 0)
        applied[refs_[*i]] = applied[refs_[*i]] + to_reference(applied[*i], b.R, b.x);
      Spatial w = b.wrench + gathered_[*i] + Expr(-1) * applied[*i];
      name(w, n + ".W");
      const Vec3 moment = w.angular + cross(joint_to_G(*i), w.linear);
      std::copy(w.linear.begin(), w.linear.end(), out.begin() + 6 * *i);
      std::copy(moment.begin(), moment.end(), out.begin() + 6 * *i + 3);
    }
    return out;
  }
  // Why the articulated-body algorithm does not apply, or nothing: each
  // coordinate must drive the local motion of exactly one body.
  std::string articulated_body_obstacle() const {
    for (std::size_t j = 0; j < nq_; ++j) {
      std::vector<std::size_t> bodies;
      for (const Mover& m : movers_[j]) {
        if (std::find(bodies.begin(), bodies.end(), m.body) == bodies.end())
          bodies.push_back(m.body);
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

  void articulated_body_algorithm(Dynamics& d) {
    dynamics_ = &d;
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
    dynamics_->forward.assign(nq_, Expr(0));
    dynamics_->pivots.assign(2 * nq_, Expr(0));
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) {
      if (!articulate(*i, a[*i], inertia, bias)) {
        dynamics_->forward.clear();
        dynamics_->pivots.clear();
        return;
      }
    }
    std::vector<Spatial> alpha(bodies_.size());
    for (int i : order_) accelerate(i, a[i], alpha);
  }

 private:
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

  // Children first: I^A and p^A complete, the body's coordinates eliminated
  // (D factored, Y, z), I^a and p^a added to the reference's. False (why_not
  // said) where a pivot is exactly zero: M is singular everywhere.
  bool articulate(int i, Articulated& out, std::vector<ArticulatedInertia>& inertia,
                  std::vector<Spatial>& bias) {
    const BodyTerms& b = bodies_[i];
    const std::string& n = model_.bodies()[i].name();
    ArticulatedInertia& IA = inertia[i];
    names_.name_all(IA.A, n + ".IAa");
    names_.name_all(IA.B, n + ".IAb");
    names_.name_all(IA.C, n + ".IAc");
    name(bias[i], n + ".pA");
    for (const LocalTwist& l : b.local) {
      if (std::find(out.coordinates.begin(), out.coordinates.end(), l.j) == out.coordinates.end())
        out.coordinates.push_back(l.j);
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
    const std::vector<Step> up =
        merged(reversed(out.joint) + reversed(articulated_[refs_[i]].constant));
    const ArticulatedInertia carried = carry(Ia, up, n + ".X");
    ArticulatedInertia& IB = inertia[refs_[i]];
    for (int e = 0; e < 9; ++e)
      IB.A[e] += carried.A[e], IB.B[e] += carried.B[e], IB.C[e] += carried.C[e];
    bias[refs_[i]] = bias[refs_[i]] + carry(pa, up, wrench_up, n + ".pc");
    return true;
  }

  // A twist or wrench through steps, named after each.
  Spatial carry(Spatial s, const std::vector<Step>& steps,
                Spatial (*through)(const Spatial&, const Step&), const std::string& prefix) {
    for (std::size_t k = 0; k < steps.size(); ++k) {
      s = through(s, steps[k]);
      name(s, fmt::format("{}{}_", prefix, k));
    }
    return s;
  }

  ArticulatedInertia carry(ArticulatedInertia I, const std::vector<Step>& steps,
                           const std::string& prefix) {
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
  bool factor(const std::string& n, const std::vector<Spatial>& U, const Spatial& pA,
              Articulated& out) {
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
        dynamics_->why_not =
            fmt::format("the pivot of coordinate '{}' in body '{}' is zero whatever the state",
                        model_.coordinates()[out.coordinates[m]].q.name(), n);
        return false;
      }
      out.inverse_pivot.push_back(Expr(1) / d);
      dynamics_->pivots[2 * out.coordinates[m]] = d;
      dynamics_->pivots[2 * out.coordinates[m] + 1] = diagonal;
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
    if (refs_[i] >= 0)
      carried = carry(alpha[refs_[i]], merged(articulated_[refs_[i]].constant + a.joint),
                      twist_down, n + ".ac");
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
      dynamics_->forward[a.coordinates[m]] = qdd[m];
    }
    name(total, n + ".aa");
    alpha[i] = total;
  }

  // G from the joint point (after the last step that moves), in the body's
  // axes: the displacements of the constant steps after it, turned as in
  // dynamics.cpp's in_body_axes.
  Vec3 joint_to_G(int i) const {
    using model::operator+;
    const std::vector<Step>& steps = model_.bodies()[i].motion().steps();
    Mat3 R = identity3();
    Vec3 r = zero3();
    for (auto s = steps.rbegin(); s != steps.rend() && !moves(*s); ++s) {
      if (s->is_rotation) {
        R = rotation(*s) * R;
      } else {
        r = r + transpose_times(R, s->displacement);
      }
    }
    return r;
  }

  // A local twist of some body, as one coordinate drives it.
  struct Mover {
    std::size_t body;
    Expr coefficient;
    std::size_t direction;
  };

  void name(Spatial& s, const std::string& prefix) {
    names_.name_all(s.angular, prefix + "w");
    names_.name_all(s.linear, prefix + "v");
  }

  const Spatial& direction(const Mover& m) const { return bodies_[m.body].directions[m.direction]; }

  const Model& model_;
  const std::vector<BodyTerms>& bodies_;
  IntermediateNames& names_;
  const std::size_t nq_;
  const std::vector<int> refs_;
  const std::vector<int> order_;
  std::vector<std::vector<Mover>> movers_;  // (nq) the local twists of each coordinate
  std::vector<Articulated> articulated_;    // (nbody)
  std::vector<Spatial> gathered_;           // (nbody) (I·α)^C, from inverse_dynamics
  Dynamics* dynamics_ = nullptr;            // what forward_dynamics() fills
};

}  // namespace

void inverse_dynamics(const Model& model, const std::vector<BodyTerms>& bodies,
                      const Kinematics* reactions, IntermediateNames& names, Dynamics& d) {
  Recursion recursion(model, bodies, names);
  d.inverse = recursion.inverse_dynamics(d.bias);
  if (reactions) d.reactions = recursion.joint_reactions(*reactions);
}

void forward_dynamics(const Model& model, const std::vector<BodyTerms>& bodies,
                      IntermediateNames& names, Dynamics& d) {
  Recursion recursion(model, bodies, names);
  d.why_not = recursion.articulated_body_obstacle();
  if (d.why_not.empty()) recursion.articulated_body_algorithm(d);
}

}  // namespace symdyn::model::detail
