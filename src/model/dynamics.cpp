#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <unordered_map>

#include <symdyn/model/detail/dynamics_terms.hpp>
#include <symdyn/model/detail/intermediates.hpp>
#include <symdyn/model/dynamics.hpp>
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::model {
namespace {

using namespace detail;

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
  EquationsOfMotion(const Model& model, const Kinematics& k, const SimplifyFunction& simplify,
                    bool reactions)
      : model_(model),
        k_(k),
        simplify_(simplify),
        reactions_(reactions),
        nq_(model.coordinates().size()),
        refs_(model.reference_indices()),
        order_(model.topological_order()),
        d_dt_(model.rates()),
        at_zero_qdd_(zero_qdd(model)),
        bodies_(k.bodies.size()) {}

  Dynamics run() {
    define_at_zero_qdd();
    for (int i : order_) add_body(i);
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) gather_subtree(*i);
    for (std::size_t a = 0; a < bodies_.size(); ++a) add_momenta(a);
    find_movers();
    for (BodyTerms& b : bodies_) b.gathered.resize(nq_), b.from_children.resize(nq_);
    for (std::size_t k = 0; k < nq_; ++k) gather_momenta(k);
    dynamics_.mass_matrix.assign(nq_ * nq_, Expr(0));
    dynamics_.bias.assign(nq_, Expr(0));
    for (std::size_t k = 0; k < nq_; ++k) {
      std::vector<Expr> terms;
      for (const Mover& m : movers_[k])
        terms.push_back(m.coefficient * dot(direction(m), bodies_[m.body].wrench));
      dynamics_.bias[k] = symbolic::add(terms);
      for (std::size_t j = 0; j <= k; ++j)
        dynamics_.mass_matrix[j * nq_ + k] = dynamics_.mass_matrix[k * nq_ + j] =
            mass_matrix_entry(j, k);
    }
    detail::inverse_dynamics(model_, bodies_, reactions_ ? &k_ : nullptr, names_, dynamics_);
    detail::forward_dynamics(model_, bodies_, names_, dynamics_);
    std::vector<symbolic::Definition> gathered = names_.take_definitions();
    dynamics_.definitions.insert(dynamics_.definitions.end(), gathered.begin(), gathered.end());
    return std::move(dynamics_);
  }

 private:
  // A local twist of some body, as one coordinate drives it.
  struct Mover {
    std::size_t body;
    Expr coefficient;
    std::size_t direction;
  };

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
      const Expr at_rest = symbolic::symbol(fmt::format("{}__0", symbol.name()),
                                            symbolic::SymbolKind::DependentAcceleration);
      dynamics_.definitions.push_back({at_rest, at_rest_value});
      at_zero_qdd_.add(symbol, at_rest);
    }
  }

  Expr simplified(Expr e) const { return simplify_ ? simplify_(e) : e; }
  Vec3 d_dt(const Vec3& v) { return {d_dt_(v[0]), d_dt_(v[1]), d_dt_(v[2])}; }
  Vec3 at_zero_qdd(const Vec3& v) {
    return {at_zero_qdd_(v[0]), at_zero_qdd_(v[1]), at_zero_qdd_(v[2])};
  }

  void name(Spatial& s, const std::string& prefix) {
    names_.name_all(s.angular, prefix + "w");
    names_.name_all(s.linear, prefix + "v");
  }

  // The body's pose relative to its reference, local twist directions, twist,
  // acceleration at qdd = 0, inertia and wrench, all in its axes (top-down).
  void add_body(int i) {
    const model::Body& body = model_.bodies()[i];
    const std::string& n = body.name();
    BodyTerms& out = bodies_[i];
    const MotionInBodyAxes local = in_body_axes(body.motion());
    out.R = k_.bodies[i].relative.R;
    out.x = k_.bodies[i].relative.x;
    names_.name_all(out.x, n + ".xr");  // not ".x": the kinematics' name of the absolute one
    add_local_twists(local.screws, out);
    for (std::size_t d = 0; d < out.directions.size(); ++d)
      name(out.directions[d], fmt::format("{}.l{}_", n, d));

    // The local twist l = Σ σ'·screw and its rate Σ σ''·screw + σ'·screw',
    // at qdd = 0 (the scalars simplified: an inline dependent parameter's
    // second derivative is long).
    Spatial l, dl;
    for (const Screw& s : local.screws) {
      const Expr rate = simplified(d_dt_(s.scalar));
      l = l + rate * s.twist;
      dl = dl + simplified(at_zero_qdd_(d_dt_(rate))) * s.twist +
           rate * Spatial{d_dt(s.twist.angular), d_dt(s.twist.linear)};
    }
    const Vec3 dw_l = at_zero_qdd(dl.angular);
    const Vec3 a_l = at_zero_qdd(cross(l.angular, l.linear) + dl.linear);

    // The reference's twist and acceleration (the ground's: 0 and -g), turned
    // to the body's axes.
    Spatial twist_B, acceleration_B{zero3(), zero3() - model_.gravity()};
    if (refs_[i] >= 0)
      twist_B = bodies_[refs_[i]].twist, acceleration_B = bodies_[refs_[i]].acceleration;
    Vec3 w_B = transpose_times(out.R, twist_B.angular);
    Vec3 dw_B = transpose_times(out.R, acceleration_B.angular);
    names_.name_all(w_B, n + ".wB");
    names_.name_all(dw_B, n + ".dwB");
    Vec3 r = local.r;
    names_.name_all(r, n + ".r");
    out.twist = {w_B + l.angular,
                 transpose_times(out.R, twist_B.linear) + cross(w_B, r) + l.linear};
    out.acceleration = {dw_B + cross(w_B, l.angular) + dw_l,
                        transpose_times(out.R, acceleration_B.linear) + cross(dw_B, r) +
                            cross(w_B, cross(w_B, r)) + Expr(2) * cross(w_B, l.linear) + a_l};
    name(out.twist, n + ".t");
    name(out.acceleration, n + ".a");

    const Mat3& J = body.inertia();
    const Vec3& w = out.twist.angular;
    out.inertia = out.own_inertia = {body.mass(), zero3(), J};
    out.wrench = out.own_wrench = {J * out.acceleration.angular + cross(w, J * w),
                                   body.mass() * out.acceleration.linear};
    out.r = r;
  }

  // The local twists as coefficients times directions, a body's momentum being
  // computed once per direction. Of three ways to span them, the one with the
  // fewest directions (the first on a tie): one per coordinate; one per rate
  // the motion holds (a dependent parameter's pd_p has coefficients dp/dq_j:
  // the slider driven by p alone); one per screw (link6's Troty(beta - alpha),
  // in any variant).
  void add_local_twists(const std::vector<Screw>& screws, BodyTerms& out) const {
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
    const Span& fewest = *std::min_element(
        spans.begin(), spans.end(),
        [](const Span& x, const Span& y) { return x.directions.size() < y.directions.size(); });
    for (std::size_t d = 0; d < fewest.directions.size(); ++d) {
      for (std::size_t j = 0; j < nq_; ++j) {
        if (!fewest.coefficients[d][j].is_zero())
          out.local.push_back({j, fewest.coefficients[d][j], d});
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
      if (std::all_of(coefficient.begin(), coefficient.end(), [](Expr e) { return e.is_zero(); }))
        return;
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
    BodyTerms& b = bodies_[i];
    const std::string& n = model_.bodies()[i].name();
    b.inertia.mass = names_(b.inertia.mass, n + ".mass");
    names_.name_all(b.inertia.moment, n + ".h");
    names_.name_all(b.inertia.rotational, n + ".K");
    name(b.wrench, n + ".f");
    if (refs_[i] < 0) return;
    BodyTerms& B = bodies_[refs_[i]];
    B.inertia = B.inertia + to_reference(b.inertia, b.R, b.x);
    B.wrench = B.wrench + to_reference(b.wrench, b.R, b.x);
  }

  // The momenta F = I^C·l of the body's local twist directions.
  void add_momenta(std::size_t a) {
    BodyTerms& body = bodies_[a];
    for (std::size_t d = 0; d < body.directions.size(); ++d) {
      body.momenta.push_back(momentum(body.inertia, body.directions[d]));
      name(body.momenta.back(), fmt::format("{}.F{}_", model_.bodies()[a].name(), d));
    }
  }

  // For every coordinate, the local twists it drives.
  void find_movers() {
    movers_.assign(nq_, {});
    for (int i : order_) {
      for (const LocalTwist& l : bodies_[i].local)
        movers_[l.j].push_back({static_cast<std::size_t>(i), l.coefficient, l.direction});
    }
  }

  // G_k(a), the momentum q_k's rate gives a's subtree, and G'_k(a), its
  // children's part, for every body (children first).
  void gather_momenta(std::size_t k) {
    for (auto i = order_.rbegin(); i != order_.rend(); ++i) {
      const std::string& n = model_.bodies()[*i].name();
      BodyTerms& b = bodies_[*i];
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
      if (const auto& G = bodies_[m.body].gathered[k])
        terms.push_back(m.coefficient * dot(direction(m), *G));
    }
    for (const Mover& m : movers_[k]) {
      if (const auto& G = bodies_[m.body].from_children[j])
        terms.push_back(m.coefficient * dot(direction(m), *G));
    }
    return symbolic::add(terms);
  }

  const Spatial& direction(const Mover& m) const { return bodies_[m.body].directions[m.direction]; }

  const Model& model_;
  const Kinematics& k_;
  const SimplifyFunction& simplify_;
  const bool reactions_;
  const std::size_t nq_;
  const std::vector<int> refs_;
  const std::vector<int> order_;
  symbolic::TimeDerivative d_dt_;
  symbolic::Substitution at_zero_qdd_;
  IntermediateNames names_;
  std::vector<BodyTerms> bodies_;
  std::vector<std::vector<Mover>> movers_;  // (nq) the local twists of each coordinate
  Dynamics dynamics_;
};

}  // namespace

std::vector<Expr> generalized_force_symbols(const Model& model) {
  std::vector<Expr> tau;
  for (const Coordinate& c : model.coordinates())
    tau.push_back(symbolic::symbol("tau." + c.q.name(), symbolic::SymbolKind::Free));
  return tau;
}

namespace {
std::vector<Expr> per_body_symbols(const Model& model, std::string_view what) {
  std::vector<Expr> out;
  for (const Body& b : model.bodies()) {
    for (const char* c : {"x", "y", "z"})
      out.push_back(
          symbolic::symbol(fmt::format("{}.{}.{}", what, b.name(), c), symbolic::SymbolKind::Free));
  }
  return out;
}
}  // namespace

std::vector<Expr> applied_force_symbols(const Model& model) {
  return per_body_symbols(model, "F_applied");
}

std::vector<Expr> applied_moment_symbols(const Model& model) {
  return per_body_symbols(model, "M_applied");
}

Dynamics derive_dynamics(const Model& model, const Kinematics& k, const SimplifyFunction& simplify,
                         bool reactions) {
  return EquationsOfMotion(model, k, simplify, reactions).run();
}

}  // namespace symdyn::model
