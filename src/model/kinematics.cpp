#include <fmt/format.h>

#include <unordered_map>

#include <symdyn/model/detail/intermediates.hpp>
#include <symdyn/model/kinematics.hpp>
#include <symdyn/symbolic/diff.hpp>

namespace symdyn::model {
namespace {

using symbolic::SymbolKind;

class Deriver {
 public:
  Deriver(const Model& model, const DeriveOptions& options) : model_(model), options_(options) {
    d_dt_ = std::make_unique<symbolic::TimeDerivative>(model.rates());
  }

  Kinematics run() {
    Kinematics k;
    for (const Dependent& d : model_.dependents())
      k.dependents.push_back(derive_dependent(d, k.dependents));
    const std::vector<int> refs = model_.reference_indices();
    k.bodies.resize(model_.bodies().size());
    if (options_.symbolic_partials) {
      for (const Coordinate& c : model_.coordinates()) by_qd_.emplace_back(c.qd);
      for (const DependentKinematics& d : k.dependents) by_pd_.emplace_back(d.symbols.rate);
    }
    const std::vector<bool> is_reference = model_.referenced();
    for (int i : model_.topological_order()) {
      BodyKinematics& b = k.bodies[i];
      b.relative = derive_local(model_.bodies()[i].motion());
      const bool composed = refs[i] >= 0 && !options_.relative_only;
      if (composed) compose(k.bodies[refs[i]], b);
      if (options_.symbolic_partials) add_local_partials(k.dependents, b.relative);
      if (composed && options_.symbolic_partials) compose_partials(k.bodies[refs[i]], b);
      if (refs[i] < 0) static_cast<Motion&>(b) = b.relative;
      if (is_reference[i] && !options_.relative_only) name_quantities(model_.bodies()[i].name(), b);
    }
    k.intermediates = names_.take_definitions();
    return k;
  }

 private:
  Expr simplify(Expr e) const { return options_.simplify ? options_.simplify(e) : e; }
  Vec3 simplify(const Vec3& v) const { return {simplify(v[0]), simplify(v[1]), simplify(v[2])}; }
  Mat3 simplify(const Mat3& m) const {
    Mat3 out;
    for (int i = 0; i < 9; ++i) out[i] = simplify(m[i]);
    return out;
  }
  Vec3 d_dt(const Vec3& v) const { return {(*d_dt_)(v[0]), (*d_dt_)(v[1]), (*d_dt_)(v[2])}; }

  DependentKinematics derive_dependent(const Dependent& d,
                                       const std::vector<DependentKinematics>& earlier) {
    DependentKinematics out;
    out.symbols = d;
    out.value = simplify(d.expression);
    out.rate = simplify((*d_dt_)(out.value));
    out.acceleration = simplify((*d_dt_)(out.rate));
    // dp/dq_j = ∂p/∂q_j + Σ_l ∂p/∂p_l · dp_l/dq_j over earlier dependent parameters.
    for (const Coordinate& c : model_.coordinates()) {
      Expr total = symbolic::diff(out.value, c.q);
      for (const DependentKinematics& e : earlier) {
        const std::size_t j = out.jacobian.size();
        total += symbolic::diff(out.value, e.symbols.symbol) * e.jacobian_symbols[j];
      }
      out.jacobian.push_back(simplify(total));
      const Expr entry = out.jacobian.back();
      out.jacobian_symbols.push_back(
          entry.is_number() || entry.is_symbol()
              ? entry
              : symbolic::symbol(fmt::format("{}__d{}", d.symbol.name(), c.q.name()),
                                 SymbolKind::Dependent));
    }
    return out;
  }

  Motion derive_local(const Transform& T) const {
    Motion k;
    const Transform::Pose pose = T.pose();
    k.R = simplify(pose.R);
    k.x = simplify(pose.x);
    k.v = simplify(d_dt(k.x));
    Vec3 w = zero3();
    for (const auto& [axis, angle] : pose.axes) w = w + (*d_dt_)(angle)*axis;
    k.w = simplify(w);
    k.a = simplify(d_dt(k.v));
    k.dw = simplify(d_dt(k.w));
    return k;
  }

  // Composition of b.relative with the reference body B (docs/design.md).
  static void compose(const BodyKinematics& B, BodyKinematics& b) {
    const Motion& l = b.relative;
    const Vec3 r = B.R * l.x;
    const Vec3 v_rel = B.R * l.v;
    const Vec3 w_rel = B.R * l.w;
    b.R = B.R * l.R;
    b.x = B.x + r;
    b.w = B.w + w_rel;
    b.v = B.v + cross(B.w, r) + v_rel;
    b.a =
        B.a + cross(B.dw, r) + cross(B.w, cross(B.w, r)) + Expr(2) * cross(B.w, v_rel) + B.R * l.a;
    b.dw = B.dw + cross(B.w, w_rel) + B.R * l.dw;
  }

  // Partial velocities of the local motion (simplified: they are short).
  // A local partial is total: dv_rel/dqd_j = ∂v_rel/∂qd_j + Σ_k ∂v_rel/∂pd_k · dp_k/dq_j.
  void add_local_partials(const std::vector<DependentKinematics>& dependents, Motion& l) {
    for (std::size_t j = 0; j < by_qd_.size(); ++j) {
      auto partial = [&](Expr e) {
        Expr total = by_qd_[j](e);
        for (std::size_t m = 0; m < by_pd_.size(); ++m)
          total += by_pd_[m](e) * dependents[m].jacobian_symbols[j];
        return simplify(total);
      };
      l.dv_dqd.push_back({partial(l.v[0]), partial(l.v[1]), partial(l.v[2])});
      l.dw_dqd.push_back({partial(l.w[0]), partial(l.w[1]), partial(l.w[2])});
    }
  }

  // The local partials composed with the reference's like the velocities
  // themselves, since r does not depend on qd:
  //   dv/dqd_j = dv_B/dqd_j + dw_B/dqd_j × r + R_B·dv_rel/dqd_j,
  //   dw/dqd_j = dw_B/dqd_j + R_B·dw_rel/dqd_j.
  // Differentiating the composed velocities instead would hand the simplifier
  // the whole chain above the body, whose expansion costs time and operations.
  static void compose_partials(const BodyKinematics& B, BodyKinematics& b) {
    const Motion& l = b.relative;
    const Vec3 r = B.R * l.x;
    // Most of a body's partials are zero (the coordinates that do not move it):
    // products by them are skipped, not built.
    const auto turned = [&](const Vec3& v) { return is_zero(v) ? v : B.R * v; };
    for (std::size_t j = 0; j < l.dv_dqd.size(); ++j) {
      const Vec3 carried = is_zero(B.dw_dqd[j]) ? zero3() : cross(B.dw_dqd[j], r);
      b.dv_dqd.push_back(B.dv_dqd[j] + carried + turned(l.dv_dqd[j]));
      b.dw_dqd.push_back(B.dw_dqd[j] + turned(l.dw_dqd[j]));
    }
  }

  // Names every entry of a reference body's quantities (intermediates.hpp):
  // "<body>.<quantity><index>".
  void name_quantities(const std::string& body, BodyKinematics& b) {
    names_.name_all(b.R, body + ".R"), names_.name_all(b.x, body + ".x"),
        names_.name_all(b.v, body + ".v");
    names_.name_all(b.w, body + ".w"), names_.name_all(b.a, body + ".a"),
        names_.name_all(b.dw, body + ".dw");
    for (std::size_t j = 0; j < b.dv_dqd.size(); ++j) {
      names_.name_all(b.dv_dqd[j], fmt::format("{}.dv_dqd{}_", body, j));
      names_.name_all(b.dw_dqd[j], fmt::format("{}.dw_dqd{}_", body, j));
    }
  }

  const Model& model_;
  const DeriveOptions& options_;
  IntermediateNames names_;
  std::unique_ptr<symbolic::TimeDerivative> d_dt_;
  // d/dqd_j and d/dpd_k, memoized across bodies.
  std::vector<symbolic::Differentiator> by_qd_, by_pd_;
};

}  // namespace

Kinematics derive_kinematics(const Model& model, const DeriveOptions& options) {
  model.validate();
  return Deriver(model, options).run();
}

}  // namespace symdyn::model
