// The normal form modulo sin² + cos² = 1; see trig_polynomial.hpp.
#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/detail/small_vector.hpp>
#include <symdyn/symbolic/trig_polynomial.hpp>

namespace symdyn::symbolic {
namespace {

// An atom and its exponent.
struct Factor {
  std::uint32_t atom;
  std::uint32_t exponent;
  friend auto operator<=>(const Factor&, const Factor&) = default;
};

// Factors by atom index, inline: most monomials have a few, and the
// expansion makes thousands of them.
using Monomial = detail::SmallVector<Factor, 6>;

// Lexicographic, factor by factor.
bool before(const Monomial& a, const Monomial& b) {
  return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end());
}

struct Coefficient {
  Number value;
  double scale = 0.0;  // the largest |coefficient| added into it, for cancellation to rounding
};

struct Term {
  Monomial monomial;
  Coefficient coefficient;
};
// Distinct monomials in increasing order (so the expression built back is
// deterministic), no zero coefficient.
using Terms = std::vector<Term>;

Monomial times(const Monomial& a, const Monomial& b) {
  Monomial out;
  out.reserve(a.size() + b.size());
  std::size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    if (j == b.size() || (i < a.size() && a[i].atom < b[j].atom)) {
      out.push_back(a[i++]);
    } else if (i == a.size() || b[j].atom < a[i].atom) {
      out.push_back(b[j++]);
    } else {
      out.push_back({a[i].atom, a[i].exponent + b[j].exponent});
      ++i, ++j;
    }
  }
  return out;
}

// A stable sort for short lists.
template <class Less>
void insertion_sort(std::vector<std::uint32_t>& v, Less less) {
  for (std::size_t i = 1; i < v.size(); ++i) {
    const std::uint32_t x = v[i];
    std::size_t j = i;
    for (; j > 0 && less(x, v[j - 1]); --j) v[j] = v[j - 1];
    v[j] = x;
  }
}

bool cancels(const Coefficient& c) {
  if (c.value.is_exact()) return c.value.is_zero();
  return std::abs(c.value.to_double()) <= 32 * std::numeric_limits<double>::epsilon() * c.scale;
}

}  // namespace

struct TrigPolynomialForm::Impl {
  struct Atom {
    Expr e;
    std::uint32_t cosine = 0;  // for sin x: the index of cos x
    bool is_sine = false;
  };
  // Polynomials live in `store` as long as the form: shared by the memo and
  // the polynomials made of them without counting references.
  using Poly = const Terms*;

  std::size_t max_terms;
  std::unordered_map<Expr, Expr> definitions;
  std::vector<Atom> atoms;
  std::unordered_map<Expr, std::uint32_t> atom_index;
  // By node id: each node's polynomial once found, and whether it was kept
  // as an atom for its size.
  struct Memo {
    Poly poly = nullptr;
    bool too_big = false;
  };
  std::vector<Memo> memo;
  std::deque<Terms> store;           // every polynomial made
  Poly one = nullptr;                // the constant 1
  Terms scratch;                     // product()'s terms before finish()
  std::vector<std::uint32_t> order;  // finish()'s

  std::uint32_t atom(Expr e) {
    if (auto it = atom_index.find(e); it != atom_index.end()) return it->second;
    const auto index = static_cast<std::uint32_t>(atoms.size());
    atoms.push_back({e});
    atom_index.emplace(e, index);
    if (e.kind() == Kind::Sin) {
      const std::uint32_t c = atom(cos(e.arg(0)));
      atoms[index].cosine = c;
      atoms[index].is_sine = true;
    }
    return index;
  }

  static void add_term(Terms& terms, Monomial m, const Number& c) {
    terms.push_back({std::move(m), {c, std::abs(c.to_double())}});
  }

  // Adds c·m to terms with every sin²x of m replaced by 1 - cos²x.
  void add_reduced(Terms& terms, Monomial m, const Number& c) {
    for (auto& [index, exponent] : m) {
      if (!atoms[index].is_sine || exponent < 2) continue;
      exponent -= 2;
      const std::uint32_t cosine = atoms[index].cosine;
      Monomial rest;
      for (const auto& f : m) {
        if (f.exponent > 0) rest.push_back(f);
      }
      add_reduced(terms, rest, c);
      add_reduced(terms, times(rest, Monomial{Factor{cosine, 2}}), -c);
      return;
    }
    add_term(terms, std::move(m), c);
  }

  // Terms in any order, with repeated monomials, to a Terms: sorted (stably,
  // so that inexact coefficients are added in a deterministic order), like
  // terms collected, cancelled ones dropped.
  Poly finish(Terms& terms) {
    // Sorting positions moves less than sorting the terms.
    order.resize(terms.size());
    std::iota(order.begin(), order.end(), std::uint32_t{0});
    const auto less = [&](std::uint32_t a, std::uint32_t b) {
      return before(terms[a].monomial, terms[b].monomial);
    };
    if (order.size() <= 32) {
      insertion_sort(order, less);  // stable too, and no buffer to allocate
    } else {
      std::stable_sort(order.begin(), order.end(), less);
    }
    Terms out;
    out.reserve(terms.size());
    for (std::uint32_t k : order) {
      Term& t = terms[k];
      if (!out.empty() && out.back().monomial == t.monomial) {
        Coefficient& c = out.back().coefficient;
        c.value = c.value + t.coefficient.value;
        c.scale = std::max(c.scale, t.coefficient.scale);
      } else {
        if (!out.empty() && cancels(out.back().coefficient)) out.pop_back();
        out.push_back(std::move(t));
      }
    }
    if (!out.empty() && cancels(out.back().coefficient)) out.pop_back();
    return keep(std::move(out));
  }

  Poly keep(Terms terms) {
    store.push_back(std::move(terms));
    return &store.back();
  }

  static bool is_constant(const Terms& p) { return p.size() == 1 && p[0].monomial.empty(); }

  // The product of p and a constant c (c·p if c_first, else p·c), as
  // product() makes it: the monomials stay sorted and distinct, nothing to
  // collect, each scale the coefficient's own.
  Poly scaled(Poly p, const Number& c, bool c_first) {
    const auto own_scale = [](const Term& t) {
      return t.coefficient.scale == std::abs(t.coefficient.value.to_double());
    };
    if (c.is_exact() && c.is_one() && std::all_of(p->begin(), p->end(), own_scale)) return p;
    Terms out;
    out.reserve(p->size());
    for (const Term& t : *p) {
      const Number v = c_first ? c * t.coefficient.value : t.coefficient.value * c;
      const Coefficient k{v, std::abs(v.to_double())};
      if (!cancels(k)) out.push_back({t.monomial, k});
    }
    return keep(std::move(out));
  }

  Poly constant(const Number& c) {
    Terms t;
    if (!c.is_zero()) add_term(t, {}, c);
    return keep(std::move(t));
  }

  Poly of_atom(Expr e) {
    Terms t;
    add_term(t, {{atom(e), 1}}, Number(1));
    return keep(std::move(t));
  }

  // The product, or nothing if it would have more than max_terms terms.
  Poly product(Poly a, Poly b) {
    if (a->size() * b->size() > 4 * max_terms) return nullptr;
    if (is_constant(*a)) return scaled(b, (*a)[0].coefficient.value, true);
    if (is_constant(*b)) return scaled(a, (*b)[0].coefficient.value, false);
    scratch.clear();
    scratch.reserve(a->size() * b->size());
    for (const Term& ta : *a) {
      for (const Term& tb : *b) {
        add_reduced(scratch, times(ta.monomial, tb.monomial),
                    ta.coefficient.value * tb.coefficient.value);
      }
    }
    Poly p = finish(scratch);
    return p->size() > max_terms ? nullptr : p;
  }

  Poly sum(std::span<const Expr> terms) {
    std::vector<Poly> polys;
    polys.reserve(terms.size());
    std::size_t n = 0;
    for (Expr t : terms) {
      polys.push_back(of(t));
      n += polys.back()->size();
    }
    Terms out;
    out.reserve(n);
    for (Poly p : polys) out.insert(out.end(), p->begin(), p->end());
    Poly p = finish(out);
    return p->size() > max_terms ? nullptr : p;
  }

  Poly compute(Expr e) {
    switch (e.kind()) {
      case Kind::Rational:
      case Kind::Real:
        return constant(e.number());
      case Kind::Symbol: {
        const auto it = definitions.find(e);
        if (it == definitions.end()) return of_atom(e);
        // A value too big to expand stays behind its symbol.
        Poly value = of(it->second);
        return value->size() <= max_terms / 4 && !memo[it->second.id()].too_big ? value
                                                                                : of_atom(e);
      }
      case Kind::Add:
        return sum(e.args());
      case Kind::Mul: {
        if (!one) one = constant(Number(1));
        Poly p = one;
        for (Expr f : e.args()) {
          if (!(p = product(p, of(f)))) return nullptr;
        }
        return p;
      }
      case Kind::Pow: {
        const Number& n = e.arg(1).number();
        if (!n.is_integer() || n.num() < 2 || n.num() > 8) return of_atom(e);
        Poly base = of(e.arg(0));
        Poly p = base;
        for (std::int64_t k = 1; k < n.num() && p; ++k) p = product(p, base);
        return p;
      }
      default:
        return of_atom(e);
    }
  }

  // e's polynomial; e itself as an atom when that would be too big.
  Poly of(Expr e) {
    if (e.id() < memo.size() && memo[e.id()].poly) return memo[e.id()].poly;
    Poly p = compute(e);
    const bool too_big = !p;
    if (too_big) p = of_atom(e);
    // Grown after compute(), which may make nodes (atom() makes cos x for sin x).
    if (e.id() >= memo.size())
      memo.resize(std::max<std::size_t>(e.id() + 1, Context::current().size()));
    memo[e.id()] = {p, too_big};
    return p;
  }

  // A lower bound of the operation count of the expanded form: an addition
  // per term but one, a multiplication per factor but one and per
  // coefficient other than ±1 (powers shared between terms counted once: free).
  static int cost_lower_bound(const Terms& terms) {
    int cost = terms.empty() ? 0 : static_cast<int>(terms.size()) - 1;
    for (const Term& t : terms) {
      if (t.monomial.empty()) continue;
      cost += static_cast<int>(t.monomial.size()) - 1;
      if (!t.coefficient.value.is_one() && !(-t.coefficient.value).is_one()) ++cost;
    }
    return cost;
  }

  Expr to_expr(const Terms& terms) const {
    std::vector<Expr> sum;
    sum.reserve(terms.size());
    for (const Term& t : terms) {
      std::vector<Expr> product{Expr(t.coefficient.value)};
      for (const auto& [index, exponent] : t.monomial) {
        product.push_back(pow(atoms[index].e, static_cast<int>(exponent)));
      }
      sum.push_back(mul(product));
    }
    return add(sum);
  }
};

TrigPolynomialForm::TrigPolynomialForm(std::span<const Definition> definitions,
                                       std::size_t max_terms)
    : impl_(std::make_unique<Impl>()) {
  impl_->max_terms = max_terms;
  for (const Definition& d : definitions) impl_->definitions.emplace(d.symbol, d.value);
}

TrigPolynomialForm::~TrigPolynomialForm() = default;

Expr TrigPolynomialForm::operator()(Expr e) {
  return impl_->to_expr(*impl_->of(e));
}

std::size_t TrigPolynomialForm::terms(Expr e) {
  return impl_->of(e)->size();
}

int TrigPolynomialForm::cost_lower_bound(Expr e) {
  return Impl::cost_lower_bound(*impl_->of(e));
}

namespace {

// The function calls (sin, cos, ...) among the nodes of some roots, outside
// sums, products and powers; each node visited once.
class CallFinder {
 public:
  std::vector<Expr> operator()(std::initializer_list<Expr> roots) {
    ++visit_;
    std::vector<Expr> out;
    for (Expr e : roots) find(e, &out);
    return out;
  }

 private:
  void find(Expr e, std::vector<Expr>* out) {
    // Stamped by node id: a table reused from root to root, never cleared.
    if (e.id() >= visited_.size()) visited_.resize(2 * e.id() + 64, 0);
    if (visited_[e.id()] == visit_) return;
    visited_[e.id()] = visit_;
    if (e.kind() == Kind::Add || e.kind() == Kind::Mul || e.kind() == Kind::Pow) {
      for (Expr a : e.args()) find(a, out);
    } else if (is_function(e.kind())) {
      out->push_back(e);
    }
  }

  std::vector<std::uint32_t> visited_;  // (by node id) the visit that saw it last
  std::uint32_t visit_ = 0;
};

}  // namespace

PythagoreanReduction reduce_pythagorean(std::span<const Expr> outputs,
                                        std::span<const Definition> definitions,
                                        std::span<const Definition> context_definitions) {
  std::vector<Definition> all(context_definitions.begin(), context_definitions.end());
  all.insert(all.end(), definitions.begin(), definitions.end());
  TrigPolynomialForm form(all);
  std::unordered_map<Expr, bool> trig_symbols;  // definitions whose value holds sin or cos
  // Whether e depends on sin or cos, through the definitions too.
  std::unordered_map<std::uint32_t, bool> deep_memo;
  std::function<bool(Expr)> deep = [&](Expr x) {
    if (x.kind() == Kind::Sin || x.kind() == Kind::Cos) return true;
    if (x.is_symbol()) {
      auto it = trig_symbols.find(x);
      return it != trig_symbols.end() && it->second;
    }
    if (x.args().empty()) return false;
    if (auto it = deep_memo.find(x.id()); it != deep_memo.end()) return it->second;
    bool held = false;
    for (Expr a : x.args()) held = held || deep(a);
    deep_memo.emplace(x.id(), held);
    return held;
  };
  for (const Definition& d : all) trig_symbols[d.symbol] = deep(d.value);

  CallFinder calls_of;
  // The cheaper of e and its reduced form, the calls the reduced form makes
  // counted as free: e computes them too, or their sines and cosines.
  auto reduce = [&](Expr e) {
    if (e.args().empty() || !deep(e)) return e;
    std::vector<Expr> calls = calls_of({e});
    const int own_calls = operation_cost(calls);
    calls.push_back(e);
    const int original_cost = operation_cost(calls) - own_calls;
    // Most entries are not shorter expanded: the bound tells without building.
    if (form.cost_lower_bound(e) >= original_cost) return e;
    const Expr candidate = form(e);
    calls = calls_of({candidate, e});
    const int base = operation_cost(calls);
    calls.push_back(candidate);
    const int candidate_cost = operation_cost(calls) - base;
    calls.back() = e;
    return candidate_cost < operation_cost(calls) - base ? candidate : e;
  };

  PythagoreanReduction out;
  for (const Definition& d : definitions) out.definitions.push_back({d.symbol, reduce(d.value)});
  for (Expr e : outputs) out.outputs.push_back(reduce(e));
  return out;
}

}  // namespace symdyn::symbolic
