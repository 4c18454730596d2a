#include <unordered_map>

#include <symdyn/model/constraints.hpp>
#include <symdyn/symbolic/diff.hpp>

namespace symdyn::model {
namespace {

// The rates (or the accelerations) of the coordinates set to zero.
std::unordered_map<Expr, Expr> zero(const Model& model, bool accelerations) {
  std::unordered_map<Expr, Expr> out;
  for (const Coordinate& c : model.coordinates()) out.emplace(accelerations ? c.qdd : c.qd, 0);
  return out;
}

// With them, each explicit dependent parameter's rate (or acceleration)
// symbol becomes its value there, in dependency order.
void add_dependents(const Kinematics& k, bool accelerations, symbolic::Substitution& at_zero) {
  for (const DependentKinematics& d : k.dependents) {
    const Expr symbol = accelerations ? d.symbols.acceleration : d.symbols.rate;
    at_zero.add(symbol, at_zero(accelerations ? d.acceleration : d.rate));
  }
}

}  // namespace

Constraints derive_constraints(const Model& model, const Kinematics& k,
                               const SimplifyFunction& simplify) {
  const auto simplified = [&](Expr e) { return simplify ? simplify(e) : e; };
  Constraints out;
  symbolic::TimeDerivative d_dt(model.rates());
  symbolic::Substitution zero_rates(zero(model, false)), zero_accelerations(zero(model, true));
  add_dependents(k, false, zero_rates);
  add_dependents(k, true, zero_accelerations);
  std::vector<symbolic::Differentiator> by_x, by_dependent;
  for (const Coordinate& c : model.coordinates()) by_x.emplace_back(c.q);
  for (const DependentKinematics& d : k.dependents) by_dependent.emplace_back(d.symbols.symbol);
  const std::size_t nq = model.num_independent();
  std::vector<Expr> g_p;
  for (const Loop& loop : model.loops()) {
    for (Expr equation : loop.equations) {
      const Expr g = simplified(equation);
      out.g.push_back(g);
      // dg/dx_j = ∂g/∂x_j + Σ_k ∂g/∂p_k · dp_k/dx_j over the explicit dependent parameters.
      for (std::size_t j = 0; j < by_x.size(); ++j) {
        Expr total = by_x[j](g);
        for (std::size_t m = 0; m < by_dependent.size(); ++m)
          total += by_dependent[m](g) * k.dependents[m].jacobian_symbols[j];
        (j < nq ? out.g_q : g_p).push_back(simplified(total));
      }
      const Expr rate = d_dt(g);
      out.g_t.push_back(simplified(zero_rates(rate)));
      out.gamma.push_back(simplified(zero_accelerations(d_dt(rate))));
      for (Expr c : loop.point) out.point.push_back(loop.body_a >= 0 ? simplified(c) : Expr(0));
    }
  }
  out.g_p = std::move(g_p);
  return out;
}

}  // namespace symdyn::model
