#include "model/dynamics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <unordered_map>

#include "model/intermediates.hpp"
#include "symbolic/diff.hpp"
#include "symbolic/traversal.hpp"

namespace symdyn::model {
namespace {

// A twist (angular velocity, velocity of the body point at O) or a wrench
// (moment about O, force): their dot product is a power.
struct Spatial {
  Vec3 angular, linear;
};

Expr dot(const Spatial& a, const Spatial& b) { return model::dot(a.angular, b.angular) + model::dot(a.linear, b.linear); }

Spatial sum(const Spatial& a, const Spatial& b) { return {a.angular + b.angular, a.linear + b.linear}; }

bool is_zero(const Spatial& s) {
  for (int i = 0; i < 3; ++i) {
    if (!s.angular[i].is_zero() || !s.linear[i].is_zero()) return false;
  }
  return true;
}

// The inertia about O of a body or a subtree: mass m, first moment m·c and
// rotational inertia K about O (c from O to the centre of mass).
struct SpatialInertia {
  Expr mass{0};
  Vec3 moment = zero3();
  Mat3 rotational{Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0), Expr(0)};
};

SpatialInertia sum(const SpatialInertia& a, const SpatialInertia& b) {
  SpatialInertia sum{a.mass + b.mass, a.moment + b.moment, {}};
  for (int i = 0; i < 9; ++i) sum.rotational[i] = a.rotational[i] + b.rotational[i];
  return sum;
}

// The momentum a twist s gives: (K·ω + m·c×v, m·v + ω×m·c).
Spatial momentum(const SpatialInertia& I, const Spatial& s) {
  return {I.rotational * s.angular + cross(I.moment, s.linear), I.mass * s.linear + cross(s.angular, I.moment)};
}

// A body of mass m and inertia J (world axes, at G) whose G is at c from O:
// K = J + m·(|c|²·1 - c·cᵀ).
SpatialInertia about(Expr m, const Vec3& c, const Mat3& J) {
  SpatialInertia I{m, m * c, J};
  for (int i = 0; i < 3; ++i) {
    const Expr& c1 = c[(i + 1) % 3];
    const Expr& c2 = c[(i + 2) % 3];
    I.rotational[3 * i + i] += m * (c1 * c1 + c2 * c2);
    for (int j = 0; j < 3; ++j) {
      if (j != i) I.rotational[3 * i + j] -= m * c[i] * c[j];
    }
  }
  return I;
}

// A principal moment that occurs twice (or more) in a diagonal inertia, else 0.
Expr repeated_moment(const Mat3& I) {
  if (!(I[1].is_zero() && I[2].is_zero() && I[5].is_zero())) return Expr(0);
  if (I[0] == I[4] || I[0] == I[8]) return I[0];
  return I[4] == I[8] ? I[4] : Expr(0);
}

// R·I·Rᵀ, an inertia tensor in body axes turned to world axes, as
// λ·1 + R·(I - λ·1)·Rᵀ since R is a rotation: with λ a repeated principal
// moment, none of R's columns remain for a ball and one for a rod.
Mat3 to_world(const Mat3& R, const Mat3& I) {
  const Expr lambda = repeated_moment(I);
  Mat3 shifted = I;
  for (int i = 0; i < 3; ++i) shifted[4 * i] -= lambda;
  const Mat3 RI = R * shifted;
  Mat3 J;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      J[3 * i + j] = RI[3 * i] * R[3 * j] + RI[3 * i + 1] * R[3 * j + 1] + RI[3 * i + 2] * R[3 * j + 2];
      if (i == j) J[3 * i + j] += lambda;
    }
  }
  return J;
}

// A tree's reference point O, as seen from the world origin: where the root's
// motion has taken it before its first rotation. A fixed pivot for an arm, the
// body's own centre for a floating one: a point about which the partial
// twists are short, and near the tree wherever it wanders. (A body alone is
// its own tree, about its centre of mass.)
Vec3 leading_displacement(const Transform& motion) {
  Vec3 O = zero3();
  for (const Transform::Step& s : motion.steps()) {
    if (s.is_rotation) break;
    O = O + s.displacement;
  }
  return O;
}

class EquationsOfMotion {
 public:
  EquationsOfMotion(const Model& model, const Kinematics& k)
      : model_(model),
        k_(k),
        refs_(model.reference_indices()),
        at_zero_qdd_(zero_qdd(model)),
        bodies_(k.bodies.size()),
        is_reference_(model.referenced()) {}

  Dynamics run() {
    define_at_zero_qdd();
    const std::vector<int> order = model_.topological_order();
    for (int i : order) add_body(i);
    for (auto it = order.rbegin(); it != order.rend(); ++it) gather_subtree(*it);
    for (std::size_t a = 0; a < bodies_.size(); ++a) add_momenta(a);
    find_movers(order);
    const std::size_t nq = model_.coordinates().size();
    d_.mass_matrix.assign(nq * nq, Expr(0));
    d_.bias.assign(nq, Expr(0));
    for (std::size_t k = 0; k < nq; ++k) {
      std::vector<Expr> terms;
      for (const Mover& m : movers_[k]) terms.push_back(m.coefficient * dot(direction(m), bodies_[m.body].wrench));
      d_.bias[k] = symbolic::add(terms);
      for (std::size_t j = 0; j <= k; ++j) {
        d_.mass_matrix[j * nq + k] = d_.mass_matrix[k * nq + j] = mass_matrix_entry(j, k);
      }
    }
    std::vector<symbolic::Definition> composites = names_.take_definitions();
    d_.definitions.insert(d_.definitions.end(), composites.begin(), composites.end());
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

  // What the sums need of each body, about its tree's O.
  struct Body {
    Vec3 offset = zero3();                 // c: O to the body's centre of mass
    std::vector<Spatial> directions;       // of the local twists
    std::vector<LocalTwist> local;         // l_j = coefficient·direction, for every nonzero l_j
    std::vector<Spatial> partial;          // (nq) S_j = S_B,j + l_j: the partial twists
    std::vector<Spatial> momenta;          // F = I^C·direction, for each direction
    SpatialInertia inertia;                // of the body, then of its subtree
    Spatial wrench;                        // of the body, then of its subtree (at qdd = 0)
  };

  static symbolic::Substitution zero_qdd(const Model& model) {
    std::unordered_map<Expr, Expr> zero;
    for (const Coordinate& c : model.coordinates()) zero.emplace(c.qdd, Expr(0));
    return symbolic::Substitution(std::move(zero));
  }

  // qdd -> 0; each pdd_k -> pdd⁰_k and each intermediate that depends on an
  // acceleration -> its own value at qdd = 0, defined in order on the ones
  // before. A value that is a number or a symbol replaces the symbol as it is,
  // so that zeros cancel the terms they multiply.
  void define_at_zero_qdd() {
    auto define = [&](Expr symbol, Expr value, symbolic::SymbolKind kind) {
      const Expr at_rest_value = at_zero_qdd_(value);
      if (at_rest_value == value) return;
      if (at_rest_value.is_number() || at_rest_value.is_symbol()) return at_zero_qdd_.add(symbol, at_rest_value);
      const Expr at_rest = symbolic::symbol(fmt::format("{}__0", symbol.name()), kind);
      d_.definitions.push_back({at_rest, at_rest_value});
      at_zero_qdd_.add(symbol, at_rest);
    };
    for (const DependentKinematics& p : k_.dependents) {
      define(p.symbols.acceleration, p.acceleration, symbolic::SymbolKind::DependentAcceleration);
    }
    for (const symbolic::Definition& i : k_.intermediates) define(i.symbol, i.value, symbolic::SymbolKind::Intermediate);
  }

  Vec3 at_zero_qdd(const Vec3& v) { return {at_zero_qdd_(v[0]), at_zero_qdd_(v[1]), at_zero_qdd_(v[2])}; }

  void name(Spatial& s, const std::string& prefix) {
    names_.name_all(s.angular, prefix + "w");
    names_.name_all(s.linear, prefix + "v");
  }

  // The body's offset from O, local partial twists, inertia and wrench.
  void add_body(int i) {
    const BodyKinematics& b = k_.bodies[i];
    const model::Body& body = model_.bodies()[i];
    const std::string& n = body.name();
    Body& out = bodies_[i];
    const int ref = refs_[i];
    const Mat3 R_B = ref >= 0 ? k_.bodies[ref].R : identity3();
    if (ref >= 0) {
      out.offset = bodies_[ref].offset + R_B * b.relative.x;
    } else if (is_reference_[i]) {
      out.offset = b.relative.x - leading_displacement(body.motion());
    }
    names_.name_all(out.offset, n + ".c");
    add_local_twists(b, R_B, body.motion(), out);
    for (std::size_t d = 0; d < out.directions.size(); ++d) name(out.directions[d], fmt::format("{}.l{}_", n, d));
    out.partial.assign(b.dv_dqd.size(), Spatial{zero3(), zero3()});
    if (ref >= 0) out.partial = bodies_[ref].partial;
    std::vector<bool> moved(out.partial.size(), false);
    for (const LocalTwist& l : out.local) {
      const Spatial& direction = out.directions[l.direction];
      out.partial[l.j] = sum(out.partial[l.j], {l.coefficient * direction.angular, l.coefficient * direction.linear});
      moved[l.j] = true;
    }
    for (std::size_t j = 0; j < moved.size(); ++j) {
      if (ref >= 0 && moved[j]) name(out.partial[j], fmt::format("{}.S{}_", n, j));
    }
    Mat3 J = to_world(b.R, body.inertia());
    names_.name_all(J, n + ".J");
    out.inertia = about(body.mass(), out.offset, J);
    const Vec3 w = b.w;
    const Vec3 force = body.mass() * (at_zero_qdd(b.a) - model_.gravity());
    out.wrench = {cross(out.offset, force) + J * at_zero_qdd(b.dw) + cross(w, J * w), force};
  }

  // The local twists l_j = (R_B·dw_rel,j, R_B·dv_rel,j - (R_B·dw_rel,j)×c), as
  // coefficients times directions, a body's momentum being computed once per
  // direction. Of three ways to span them, the one with the fewest directions
  // (the first on a tie): one per coordinate; one per rate the local velocity
  // holds (a dependent parameter's pd_p has coefficients dp/dq_j: the slider
  // driven by p alone); one per screw of the local motion (link6's
  // Troty(beta - alpha), in any variant).
  void add_local_twists(const BodyKinematics& b, const Mat3& R_B, const Transform& motion, Body& out) const {
    const std::size_t nq = b.dv_dqd.size();
    Span by_coordinate;
    for (std::size_t j = 0; j < nq; ++j) {
      std::vector<Expr> unit(nq, Expr(0));
      unit[j] = Expr(1);
      by_coordinate.add(b.relative.dv_dqd[j], b.relative.dw_dqd[j], std::move(unit));
    }
    std::vector<Span> spans{by_coordinate};
    if (by_coordinate.directions.size() > 1) {  // else nothing has fewer
      spans.push_back(by_rates(b.relative));
      spans.push_back(by_screws(motion, b.relative.x));
    }
    const Span& fewest = *std::min_element(spans.begin(), spans.end(), [](const Span& x, const Span& y) {
      return x.directions.size() < y.directions.size();
    });
    for (std::size_t d = 0; d < fewest.directions.size(); ++d) {
      const auto& [dv_rel, dw_rel] = fewest.directions[d];
      Spatial l{R_B * dw_rel, {}};
      l.linear = R_B * dv_rel - cross(l.angular, out.offset);
      for (std::size_t j = 0; j < nq; ++j) {
        if (!fewest.coefficients[d][j].is_zero()) out.local.push_back({j, fewest.coefficients[d][j], d});
      }
      out.directions.push_back(l);
    }
  }

  // Relative twists (reference axes, at the body's centre of mass) and, for
  // each, its coefficient in the local twist of every coordinate.
  struct Span {
    std::vector<std::pair<Vec3, Vec3>> directions;  // (dv, dw)
    std::vector<std::vector<Expr>> coefficients;    // (directions x nq)

    // Keeps a direction unless it or all its coefficients are zero.
    void add(const Vec3& dv, const Vec3& dw, std::vector<Expr> coefficient) {
      const auto zero = [](Expr e) { return e.is_zero(); };
      if (std::all_of(dv.begin(), dv.end(), zero) && std::all_of(dw.begin(), dw.end(), zero)) return;
      if (std::all_of(coefficient.begin(), coefficient.end(), zero)) return;
      directions.emplace_back(dv, dw);
      coefficients.push_back(std::move(coefficient));
    }
  };

  // One direction per rate r the local velocity holds, ∂(v, w)/∂r, with
  // coefficients dr/dqd_j: 1 for qd_j, dp/dq_j for a dependent rate pd_p.
  Span by_rates(const Motion& local) const {
    std::vector<Expr> velocity(local.v.begin(), local.v.end());
    velocity.insert(velocity.end(), local.w.begin(), local.w.end());
    const std::size_t nq = model_.coordinates().size();
    Span span;
    for (Expr rate : symbolic::free_symbols(velocity)) {
      const symbolic::SymbolKind kind = rate.symbol_kind();
      if (kind != symbolic::SymbolKind::Rate && kind != symbolic::SymbolKind::DependentRate) continue;
      std::vector<Expr> coefficient(nq, Expr(0));
      for (std::size_t j = 0; j < nq; ++j) {
        if (rate == model_.coordinates()[j].qd) coefficient[j] = Expr(1);
      }
      for (const DependentKinematics& p : k_.dependents) {
        if (rate == p.symbols.rate) coefficient = p.jacobian_symbols;
      }
      symbolic::Differentiator by_rate(rate);
      auto partial = [&](const Vec3& v) { return Vec3{by_rate(v[0]), by_rate(v[1]), by_rate(v[2])}; };
      span.add(partial(local.v), partial(local.w), std::move(coefficient));
    }
    return span;
  }

  // One direction per screw s of the local motion, with coefficients dσ_s/dq_j.
  Span by_screws(const Transform& motion, const Vec3& x_rel) const {
    Span span;
    for (const Screw& screw : screws(motion, x_rel)) span.add(screw.dv, screw.dw, coordinate_derivatives(screw.scalar));
    return span;
  }

  // A screw of a local motion: the relative twist (reference axes, at the
  // body's centre of mass) per unit rate of one varying scalar σ of a step,
  // a rotation's angle or a component of a displacement.
  struct Screw {
    Vec3 dv, dw;
    Expr scalar;
  };

  static std::vector<Screw> screws(const Transform& motion, const Vec3& x_rel) {
    std::vector<Screw> out;
    Mat3 R = identity3();
    Vec3 origin = zero3();
    for (const Transform::Step& s : motion.steps()) {
      if (s.is_rotation) {
        const Vec3 axis = R * s.axis;
        if (!s.angle.is_number()) out.push_back({cross(axis, x_rel - origin), axis, s.angle});
        R = R * Transform::rotation_matrix(s.axis, s.angle);
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        if (s.displacement[k].is_number()) continue;
        Vec3 e = zero3();
        e[k] = Expr(1);
        out.push_back({R * e, zero3(), s.displacement[k]});
      }
      origin = origin + R * s.displacement;
    }
    return out;
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
    return total;
  }

  // Called children first: names the subtree's inertia and wrench, and adds
  // them to the reference's.
  void gather_subtree(int i) {
    Body& b = bodies_[i];
    const std::string& n = model_.bodies()[i].name();
    b.inertia.mass = names_(b.inertia.mass, n + ".mass");
    names_.name_all(b.inertia.moment, n + ".mc");
    names_.name_all(b.inertia.rotational, n + ".K");
    name(b.wrench, n + ".f");
    if (refs_[i] < 0) return;
    Body& B = bodies_[refs_[i]];
    B.inertia = sum(B.inertia, b.inertia);
    B.wrench = sum(B.wrench, b.wrench);
  }

  // The momenta F = I^C·l of the body's local twist directions, about O.
  void add_momenta(std::size_t a) {
    Body& body = bodies_[a];
    for (std::size_t d = 0; d < body.directions.size(); ++d) {
      body.momenta.push_back(momentum(body.inertia, body.directions[d]));
      name(body.momenta.back(), fmt::format("{}.F{}_", model_.bodies()[a].name(), d));
    }
  }

  // For every coordinate, the local twists it drives and the bodies it moves
  // (those below them).
  void find_movers(const std::vector<int>& order) {
    const std::size_t nq = model_.coordinates().size();
    movers_.assign(nq, {});
    moved_.assign(nq, {});
    std::vector<std::vector<bool>> moves(bodies_.size(), std::vector<bool>(nq, false));
    for (int i : order) {
      if (refs_[i] >= 0) moves[i] = moves[refs_[i]];
      for (const LocalTwist& l : bodies_[i].local) {
        movers_[l.j].push_back({static_cast<std::size_t>(i), l.coefficient, l.direction});
        moves[i][l.j] = true;
      }
    }
    for (int i : order) {
      for (std::size_t k = 0; k < nq; ++k) {
        if (moves[i][k]) moved_[k].push_back(static_cast<std::size_t>(i));
      }
    }
  }

  // M_jk = Σ_i S_ij·I_i·S_ik. When every body q_k moves has the same partial
  // twist S_j (q_j moves them all alike: a coordinate above them in the tree),
  // M_jk = S_j·Φ_k with Φ_k = Σ_i I_i·S_ik, the momentum q_k's rate gives the
  // system: one dot product, whatever the number of bodies q_k drives (a
  // dependent parameter makes them many). Otherwise, summing over the bodies
  // a that q_k (then q_j) drives, their momenta F = I^C_a·l_a and the partial
  // twists of a (then of a's reference B):
  //   M_jk = Σ_a F_ak·S_aj + Σ_a F_aj·S_Bk.
  Expr mass_matrix_entry(std::size_t j, std::size_t k) {
    for (auto [x, y] : {std::pair(j, k), std::pair(k, j)}) {
      if (const Spatial* S = common_partial(x, y)) return is_zero(*S) ? Expr(0) : dot(*S, system_momentum(y));
    }
    std::vector<Expr> terms;
    for (const Mover& m : movers_[k]) {
      const Spatial& S = bodies_[m.body].partial[j];
      if (!is_zero(S)) terms.push_back(m.coefficient * dot(momentum_of(m), S));
    }
    for (const Mover& m : movers_[j]) {
      const int B = refs_[m.body];
      if (B >= 0 && !is_zero(bodies_[B].partial[k])) {
        terms.push_back(m.coefficient * dot(momentum_of(m), bodies_[B].partial[k]));
      }
    }
    return symbolic::add(terms);
  }

  // The partial twist for q_x of every body q_y moves, if they all share it.
  const Spatial* common_partial(std::size_t x, std::size_t y) const {
    const Spatial* common = nullptr;
    for (std::size_t i : moved_[y]) {
      const Spatial& S = bodies_[i].partial[x];
      if (common == nullptr) {
        common = &S;
      } else if (S.angular != common->angular || S.linear != common->linear) {
        return nullptr;
      }
    }
    return common;
  }

  // Φ_k = Σ_i I_i·S_ik = Σ_a c_ak·F_a over the local twists q_k drives.
  const Spatial& system_momentum(std::size_t k) {
    auto [it, added] = system_momenta_.try_emplace(k, Spatial{zero3(), zero3()});
    if (!added) return it->second;
    for (const Mover& m : movers_[k]) {
      const Spatial& F = momentum_of(m);
      it->second = sum(it->second, {m.coefficient * F.angular, m.coefficient * F.linear});
    }
    name(it->second, fmt::format("Phi{}_", k));
    return it->second;
  }

  const Spatial& direction(const Mover& m) const { return bodies_[m.body].directions[m.direction]; }
  const Spatial& momentum_of(const Mover& m) const { return bodies_[m.body].momenta[m.direction]; }

  const Model& model_;
  const Kinematics& k_;
  const std::vector<int> refs_;
  symbolic::Substitution at_zero_qdd_;
  IntermediateNames names_;
  std::vector<Body> bodies_;
  std::vector<bool> is_reference_;
  std::vector<std::vector<Mover>> movers_;         // (nq) the local twists of each coordinate
  std::vector<std::vector<std::size_t>> moved_;    // (nq) the bodies each coordinate moves
  std::unordered_map<std::size_t, Spatial> system_momenta_;  // Φ_k, once asked for
  Dynamics d_;
};

}  // namespace

Dynamics derive_dynamics(const Model& model, const Kinematics& k) {
  const std::size_t nq = model.coordinates().size();
  if (!k.bodies.empty() && k.bodies.front().dv_dqd.size() != nq) {
    throw ModelError(fmt::format("model '{}': the equations of motion need symbolic partial velocities", model.name()));
  }
  return EquationsOfMotion(model, k).run();
}

}  // namespace symdyn::model
