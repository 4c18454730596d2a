// The rewrite engine: matching modulo commutativity and sub-multisets, and
// bottom-up application of rule tables. See rewrite.hpp for the semantics.
//
// Matching is a backtracking search written in continuation-passing style:
// match(p, t, k) calls k() once per way p matches t (with the bindings made),
// and stops as soon as k() returns true. That is what lets a sum pattern try
// every assignment of its terms and a product pattern every sub-multiset,
// while a wildcard bound in one term constrains the next.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <deque>
#include <iostream>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include <symdyn/symbolic/cost.hpp>
#include <symdyn/symbolic/detail/flat_map.hpp>
#include <symdyn/symbolic/detail/small_vector.hpp>
#include <symdyn/symbolic/rewrite.hpp>

namespace symdyn::symbolic {
namespace {

enum class WildClass { One, Cofactor, Rest };

WildClass wild_class(Expr w) {
  const char c = w.name()[1];
  if (c >= 'a' && c <= 'd') return WildClass::Cofactor;
  if (std::isupper(static_cast<unsigned char>(c)) != 0) return WildClass::Rest;
  return WildClass::One;
}

bool trace_rules() {
  static const bool enabled = [] {
    const char* v = std::getenv("SYMDYN_TRACE_RULES");
    return v != nullptr && *v != '\0' && std::string_view(v) != "0";
  }();
  return enabled;
}

struct Factor {
  Expr base;
  Number exponent;
};

// An expression seen as coefficient · factors (a lone x is 1·x, a number is
// a coefficient). For a product pattern the cofactor wildcard is set apart.
struct Product {
  Number coefficient{1};
  std::vector<Factor> factors;
  Expr cofactor;
  bool has_cofactor = false;
};

Product split_product(Expr e, bool pattern) {
  Product out;
  auto take = [&](Expr f) {
    if (f.is_number()) {
      out.coefficient = f.number();
    } else if (pattern && is_wildcard(f) && wild_class(f) != WildClass::One) {
      out.cofactor = f;
      out.has_cofactor = true;
    } else {
      auto [b, x] = split_power(f);
      out.factors.push_back({b, x});
    }
  };
  if (e.kind() == Kind::Mul) {
    for (Expr f : e.args()) take(f);
  } else {
    take(e);
  }
  return out;
}

}  // namespace

// Decompositions of the products met while matching, by node id: a rewriter
// matches the same terms against many rules and steps.
class MatchCache {
 public:
  const Product& target(Expr e) { return targets_.get(e, false); }
  const Product& pattern(Expr e) { return patterns_.get(e, true); }

 private:
  // Products by node id: a dense index into a deque (references stay valid
  // as it grows). Matching looks products up hundreds of thousands of times.
  class Table {
   public:
    const Product& get(Expr e, bool pattern) {
      const std::uint32_t slot = slot_.get(e);
      return slot != 0 ? products_[slot - 1] : add(e, pattern);
    }

   private:
    [[gnu::noinline]] const Product& add(Expr e, bool pattern) {
      products_.push_back(split_product(e, pattern));
      slot_.at(e) = static_cast<std::uint32_t>(products_.size());
      return products_.back();
    }

    detail::NodeTable<std::uint32_t> slot_;  // index in products_ + 1, 0 if absent
    std::deque<Product> products_;
  };

 public:
  // For a sum: the positions of its terms that have `base` as a factor base.
  const std::vector<std::size_t>& terms_with(Expr sum, Expr base) {
    auto it = by_base_.find(sum.id());
    if (it == by_base_.end()) {
      std::unordered_map<std::uint32_t, std::vector<std::size_t>> index;
      const auto terms = sum.args();
      for (std::size_t j = 0; j < terms.size(); ++j) {
        for (const Factor& f : target(terms[j]).factors) {
          auto& list = index[f.base.id()];
          if (list.empty() || list.back() != j) list.push_back(j);
        }
      }
      it = by_base_.emplace(sum.id(), std::move(index)).first;
    }
    static const std::vector<std::size_t> none;
    auto found = it->second.find(base.id());
    return found == it->second.end() ? none : found->second;
  }

 private:
  Table targets_;
  Table patterns_;
  std::unordered_map<std::uint32_t, std::unordered_map<std::uint32_t, std::vector<std::size_t>>>
      by_base_;
};

namespace {

// How many units of a target factor with `remaining` exponent a pattern factor
// with exponent `wanted` takes: integer powers count as repeated factors.
bool can_take(const Number& remaining, const Number& wanted) {
  if (remaining.is_zero()) return false;
  if (remaining == wanted) return true;
  if (!remaining.is_integer() || !wanted.is_integer()) return false;
  if (remaining.is_negative() != wanted.is_negative()) return false;
  const std::int64_t r = remaining.num() < 0 ? -remaining.num() : remaining.num();
  const std::int64_t w = wanted.num() < 0 ? -wanted.num() : wanted.num();
  return r >= w;
}

// What substitute has built, by pattern node id: a pattern has a few dozen
// nodes at most, so a list searched in order beats hashing.
struct Substituted {
  std::uint32_t id;
  Expr value;
};
using SubstituteMemo = detail::SmallVector<Substituted, 32>;

Expr substitute(Expr e, const Match& m, SubstituteMemo* memo);

// A non-owning reference to a continuation `bool()`. Each continuation is a
// lambda on the caller's stack that outlives the call it is passed to; a
// std::function would copy it to the heap, once per step of the search.
class Cont {
 public:
  template <class F>
  requires(!std::is_same_v<std::remove_cvref_t<F>, Cont>)
      Cont(const F& f)  // NOLINT(google-explicit-constructor): lambdas convert implicitly
      : callable_(&f), call_([](const void* c) { return (*static_cast<const F*>(c))(); }) {}
  bool operator()() const { return call_(callable_); }

 private:
  const void* callable_;
  bool (*call_)(const void*);
};

class Matcher {
 public:
  Matcher(Match* match, int budget, MatchCache* cache)
      : m_(match), budget_(budget), cache_(cache) {}

  // Top of a rule: a sum pattern keeps the unmatched terms in Match::remainder.
  bool match_top(Expr p, Expr t, const Cont& k) {
    if (p.kind() == Kind::Add) return match_sum(p, t, true, k);
    return match(p, t, k);
  }

  bool exhausted() const { return budget_ < 0; }

 private:
  bool match(Expr p, Expr t, const Cont& k) {
    if (--budget_ < 0) return false;
    if (is_wildcard(p)) return bind(p, t, k);
    switch (p.kind()) {
      case Kind::Rational:
      case Kind::Real:
      case Kind::Symbol:
        return p == t && k();
      case Kind::Mul:
        return match_product(p, t, k);
      case Kind::Add:
        return match_sum(p, t, false, k);
      default:
        break;
    }
    if (p.kind() != t.kind()) return false;
    if (p.kind() == Kind::Pow && p.arg(1) != t.arg(1)) return false;
    return match_args(p.args(), t.args(), 0, k);
  }

  bool match_args(std::span<const Expr> ps, std::span<const Expr> ts, std::size_t i,
                  const Cont& k) {
    if (i == ps.size()) return k();
    return match(ps[i], ts[i], [&] { return match_args(ps, ts, i + 1, k); });
  }

  bool bind(Expr w, Expr value, const Cont& k) {
    if (auto bound = m_->find(w)) return *bound == value && k();
    m_->bind(w, value);
    const bool accepted = k();
    m_->unbind();
    return accepted;
  }

  // ---- products ----

  struct ProductState {
    const Product* pattern;
    const Product* target;
    detail::SmallVector<Number, 8> remaining;
  };

  bool match_product(Expr p, Expr t, const Cont& k) {
    ProductState s{&cache_->pattern(p), &cache_->target(t), {}};
    s.remaining.reserve(s.target->factors.size());
    for (const Factor& f : s.target->factors) s.remaining.push_back(f.exponent);
    return assign_factor(s, 0, k);
  }

  bool assign_factor(ProductState& s, std::size_t i, const Cont& k) {
    if (i == s.pattern->factors.size()) return finish_product(s, k);
    const Factor& pf = s.pattern->factors[i];
    const bool whole = is_wildcard(pf.base) && pf.exponent.is_one();
    for (std::size_t j = 0; j < s.target->factors.size(); ++j) {
      const Number before = s.remaining[j];
      if (before.is_zero()) continue;
      const Factor& tf = s.target->factors[j];
      if (whole) {
        s.remaining[j] = Number(0);
        const bool accepted =
            match(pf.base, pow(tf.base, Expr(before)), [&] { return assign_factor(s, i + 1, k); });
        s.remaining[j] = before;
        if (accepted) return true;
        continue;
      }
      if (!is_wildcard(pf.base) && pf.base.kind() != tf.base.kind()) continue;
      if (!can_take(before, pf.exponent)) continue;
      s.remaining[j] = before - pf.exponent;
      const bool accepted = match(pf.base, tf.base, [&] { return assign_factor(s, i + 1, k); });
      s.remaining[j] = before;
      if (accepted) return true;
      if (exhausted()) return false;
    }
    return false;
  }

  bool finish_product(ProductState& s, const Cont& k) {
    const Number coefficient = s.target->coefficient / s.pattern->coefficient;
    if (!s.pattern->has_cofactor) {
      // Without a cofactor the target must be used up exactly.
      if (!coefficient.is_one()) return false;
      for (const Number& r : s.remaining) {
        if (!r.is_zero()) return false;
      }
      return k();
    }
    if (auto bound = m_->find(s.pattern->cofactor); bound && !needs_building(s, coefficient)) {
      return same_product(cache_->target(*bound), coefficient, s) && k();
    }
    detail::SmallVector<Expr, 8> rest;
    rest.push_back(Expr(coefficient));
    detail::SmallVector<Expr, 8> bases;
    for (std::size_t j = 0; j < s.target->factors.size(); ++j) {
      if (s.remaining[j].is_zero()) continue;
      rest.push_back(pow(s.target->factors[j].base, Expr(s.remaining[j])));
      bases.push_back(s.target->factors[j].base);
    }
    return bind(s.pattern->cofactor, leftover_product(coefficient, rest, bases), k);
  }

  // mul(rest), rest = {coefficient, the leftover factors}, whose bases are
  // those of a canonical product: distinct and in canonical order. Then mul
  // would only sort what is sorted and intern the product (and the product
  // scaled by the coefficient): that is done directly, making the same nodes
  // in the same order. Anything else (one factor, a factor folded into a
  // number or a product, a changed base) goes through mul.
  static Expr leftover_product(const Number& coefficient, std::span<const Expr> rest,
                               std::span<const Expr> bases) {
    const auto factors = rest.subspan(1);
    bool plain = factors.size() >= 2 && !coefficient.is_zero();
    for (std::size_t j = 0; plain && j < factors.size(); ++j) {
      const Expr f = factors[j];
      plain = f == bases[j] || (f.kind() == Kind::Pow && f.arg(0) == bases[j]);
      plain = plain && !bases[j].is_number() && bases[j].kind() != Kind::Mul &&
              bases[j].kind() != Kind::Pow;
    }
    if (!plain) return mul(rest);
    const Expr monomial = intern_node(Kind::Mul, factors);
    if (coefficient.is_one()) return monomial;
    return intern_node(Kind::Mul, rest);  // the coefficient, then the factors
  }

  // The leftover coefficient · factors is the canonical product of its parts,
  // except that a coefficient times a lone sum is distributed over the sum.
  static bool needs_building(const ProductState& s, const Number& coefficient) {
    if (coefficient.is_one()) return false;
    int left = 0;
    bool sum = false;
    for (std::size_t j = 0; j < s.remaining.size(); ++j) {
      if (s.remaining[j].is_zero()) continue;
      ++left;
      sum = s.target->factors[j].base.kind() == Kind::Add && s.remaining[j].is_one();
    }
    return left == 1 && sum;
  }

  // Whether the leftover equals the already bound product, compared part by
  // part (both lists are in canonical order), without making a node.
  static bool same_product(const Product& bound, const Number& coefficient, const ProductState& s) {
    if (!(bound.coefficient == coefficient)) return false;
    std::size_t i = 0;
    for (std::size_t j = 0; j < s.remaining.size(); ++j) {
      if (s.remaining[j].is_zero()) continue;
      if (i == bound.factors.size()) return false;
      const Factor& b = bound.factors[i++];
      if (b.base != s.target->factors[j].base || !(b.exponent == s.remaining[j])) return false;
    }
    return i == bound.factors.size();
  }

  // ---- sums ----

  struct SumState {
    detail::SmallVector<Expr, 8> pattern;  // structural terms first, bare wildcards last
    Expr rest;
    bool has_rest = false;
    bool top = false;
    std::span<const Expr> target;
    Expr sum;
    detail::SmallVector<bool, 64> used;
  };

  bool match_sum(Expr p, Expr t, bool top, const Cont& k) {
    if (t.kind() != Kind::Add) return false;
    SumState s;
    s.top = top;
    detail::SmallVector<Expr, 8> wild_terms;
    for (Expr term : p.args()) {
      if (is_wildcard(term) && wild_class(term) == WildClass::Rest) {
        s.rest = term;
        s.has_rest = true;
      } else if (is_wildcard(term)) {
        wild_terms.push_back(term);
      } else {
        s.pattern.push_back(term);
      }
    }
    for (Expr w : wild_terms) s.pattern.push_back(w);
    s.target = t.args();
    s.sum = t;
    if (s.target.size() < s.pattern.size()) return false;
    for (std::size_t j = 0; j < s.target.size(); ++j) s.used.push_back(false);
    return assign_term(s, 0, k);
  }

  bool assign_term(SumState& s, std::size_t i, const Cont& k) {
    if (i == s.pattern.size()) return finish_sum(s, k);
    // Once the wildcards of a factor are bound, only the terms that have that
    // factor can match: look them up instead of scanning the sum.
    if (auto base = bound_factor(s.pattern[i])) {
      for (std::size_t j : cache_->terms_with(s.sum, *base)) {
        if (try_term(s, i, j, k)) return true;
        if (exhausted()) return false;
      }
      return false;
    }
    for (std::size_t j = 0; j < s.target.size(); ++j) {
      if (try_term(s, i, j, k)) return true;
      if (exhausted()) return false;
    }
    return false;
  }

  bool try_term(SumState& s, std::size_t i, std::size_t j, const Cont& k) {
    if (s.used[j] || !could_match(s.pattern[i], s.target[j])) return false;
    s.used[j] = true;
    const bool accepted =
        match(s.pattern[i], s.target[j], [&] { return assign_term(s, i + 1, k); });
    s.used[j] = false;
    return accepted;
  }

  // The first factor base of a product (or power, or call) pattern term whose
  // wildcards are all bound, with the bindings substituted.
  std::optional<Expr> bound_factor(Expr p) {
    if (is_wildcard(p) ||
        (p.kind() != Kind::Mul && p.kind() != Kind::Pow && !is_function(p.kind())))
      return std::nullopt;
    for (const Factor& f : cache_->pattern(p).factors) {
      if (is_wildcard(f.base)) continue;
      if (all_bound(f.base)) {
        SubstituteMemo memo;
        return substitute(f.base, *m_, &memo);
      }
    }
    return std::nullopt;
  }

  bool all_bound(Expr e) const {
    if (is_wildcard(e)) return m_->find(e).has_value();
    for (Expr a : e.args()) {
      if (!all_bound(a)) return false;
    }
    return true;
  }

  bool finish_sum(SumState& s, const Cont& k) {
    std::vector<Expr> leftover;
    std::vector<Expr> matched;
    for (std::size_t j = 0; j < s.target.size(); ++j) {
      (s.used[j] ? matched : leftover).push_back(s.target[j]);
    }
    if (s.has_rest) return bind(s.rest, add(leftover), k);
    if (!s.top) return leftover.empty() && k();
    std::vector<Expr> saved = std::move(m_->remainder);
    std::vector<Expr> saved_matched = std::move(m_->matched);
    m_->remainder = std::move(leftover);
    m_->matched = std::move(matched);
    const bool accepted = k();
    m_->remainder = std::move(saved);
    m_->matched = std::move(saved_matched);
    return accepted;
  }

  // A cheap necessary condition: every non-wildcard factor base of a product
  // pattern term has a factor of the same kind in the target term.
  bool could_match(Expr p, Expr t) {
    if (is_wildcard(p)) return true;
    if (p.kind() != Kind::Mul && p.kind() != Kind::Pow && !is_function(p.kind())) return true;
    const Product& target = cache_->target(t);
    for (const Factor& f : cache_->pattern(p).factors) {
      if (is_wildcard(f.base)) continue;
      bool found = false;
      for (const Factor& g : target.factors) found = found || g.base.kind() == f.base.kind();
      if (!found) return false;
    }
    return true;
  }

  Match* m_;
  int budget_;
  MatchCache* cache_;
};

// The sine and cosine factors of an expression seen as a product (a power
// counted that many times, at most 3 each). A product pattern's factor
// sin(_x) matches only a sine factor of the target, so a target term with
// fewer sines or cosines than a pattern term cannot match it: that is checked
// before the backtracking search, which would find out term by term.
struct TrigFactors {
  int sin = 0, cos = 0;
  bool covers(TrigFactors need) const { return sin >= need.sin && cos >= need.cos; }
  bool none() const { return sin == 0 && cos == 0; }
};

TrigFactors trig_factors(Expr product) {
  TrigFactors out;
  const std::span<const Expr> factors =
      product.kind() == Kind::Mul ? product.args() : std::span<const Expr>(&product, 1);
  for (Expr f : factors) {
    int times = 1;
    if (f.kind() == Kind::Pow) {
      const Expr exponent = f.args()[1];
      if (!exponent.is_number() || !exponent.number().is_integer() || exponent.number().num() < 1)
        continue;
      times = static_cast<int>(std::min<std::int64_t>(exponent.number().num(), 3));
      f = f.args()[0];
    }
    if (f.kind() == Kind::Sin) out.sin = std::min(3, out.sin + times);
    if (f.kind() == Kind::Cos) out.cos = std::min(3, out.cos + times);
  }
  return out;
}

// The cost of a sum under the removal of some terms and the addition of
// others, without building the new sum: reference counts over the sum's DAG
// say which nodes a removed term alone needed (saved) and which nodes an added
// term brings (paid). Exact but for the merging of like terms, which only
// lowers the cost further. Building the sum and rewriting its new parts is the
// expensive part of a step, so only matches that pass this test pay for it.
class SumCost {
 public:
  explicit SumCost(Expr sum) : terms_(static_cast<int>(sum.args().size())) {
    for (Expr t : sum.args()) add_ref(t, nullptr);
  }

  // Change of cost when `removed` terms leave and `added` terms join.
  int delta(std::span<const Expr> removed, std::span<const Expr> added) {
    int change = 0;
    for (Expr t : removed) change -= drop_ref(t);
    for (Expr t : added) change += add_ref(t, &log_);
    change += static_cast<int>(added.size()) - static_cast<int>(removed.size());
    if (terms_ - static_cast<int>(removed.size()) + static_cast<int>(added.size()) <= 1)
      change -= 1;  // no sum left
    undo();
    return change;
  }

 private:
  int& refs(Expr e) { return *refs_.try_emplace(e.id()).first; }  // valid until the next call

  // References e once more; returns the cost of the nodes that were absent.
  int add_ref(Expr e, std::vector<std::uint32_t>* log) {
    if (log) log->push_back(e.id());
    if (refs(e)++ > 0) return 0;
    const std::size_t first = operands_.size();
    int cost = own_cost(e, &operands_);
    const std::size_t last = operands_.size();
    for (std::size_t i = first; i < last; ++i) cost += add_ref(operands_[i], log);
    operands_.resize(first);
    return cost;
  }

  // Drops one reference to e; returns the cost of the nodes no longer needed.
  int drop_ref(Expr e) {
    dropped_.push_back(e.id());
    if (--refs(e) > 0) return 0;
    const std::size_t first = operands_.size();
    int cost = own_cost(e, &operands_);
    const std::size_t last = operands_.size();
    for (std::size_t i = first; i < last; ++i) cost += drop_ref(operands_[i]);
    operands_.resize(first);
    return cost;
  }

  void undo() {
    for (std::uint32_t id : log_) --*refs_.try_emplace(id).first;
    for (std::uint32_t id : dropped_) ++*refs_.try_emplace(id).first;
    log_.clear();
    dropped_.clear();
  }

  int terms_;
  detail::FlatMap64<int> refs_;  // by node id
  // The operands of the nodes being visited, a stack shared by the recursion:
  // each call appends those of its node and truncates back on return.
  std::vector<Expr> operands_;
  std::vector<std::uint32_t> log_;
  std::vector<std::uint32_t> dropped_;
};

void trace(const Rule& r) {
  if (trace_rules()) std::cerr << "symdyn rule: " << r.name << '\n';
}

std::span<const Expr> terms_of(const Expr& e) {
  return e.kind() == Kind::Add ? e.args() : std::span<const Expr>(&e, 1);
}

// The trig factors of a target, once for all the rules tried at it: of each
// of its terms (itself if not a sum), and of itself seen as a product.
struct TrigProfile {
  explicit TrigProfile(Expr target) : product(trig_factors(target)) {
    for (Expr t : terms_of(target)) terms.push_back(trig_factors(t));
  }
  detail::SmallVector<TrigFactors, 8> terms;
  TrigFactors product;
};

// Necessary for a match of a sum or product pattern: each of its terms (the
// pattern as one term if a product) has a target term with at least its
// sines and cosines.
bool may_match(Expr pattern, const TrigProfile& target) {
  if (pattern.kind() == Kind::Mul) return target.product.covers(trig_factors(pattern));
  if (pattern.kind() != Kind::Add) return true;
  for (Expr term : pattern.args()) {
    const TrigFactors need = trig_factors(term);
    if (need.none()) continue;
    if (std::none_of(target.terms.begin(), target.terms.end(),
                     [&](TrigFactors t) { return t.covers(need); }))
      return false;
  }
  return true;
}

void collect_wildcards(Expr e, std::vector<Expr>* out) {
  if (is_wildcard(e)) {
    for (Expr w : *out) {
      if (w == e) return;
    }
    out->push_back(e);
    return;
  }
  for (Expr a : e.args()) collect_wildcards(a, out);
}

Expr substitute(Expr e, const Match& m, SubstituteMemo* memo) {
  if (is_wildcard(e)) return m[e];
  if (e.args().empty()) return e;
  for (const Substituted& done : *memo) {
    if (done.id == e.id()) return done.value;
  }
  detail::SmallVector<Expr, 8> args;
  for (Expr a : e.args()) args.push_back(substitute(a, m, memo));
  const Expr out = make(e.kind(), args);
  memo->push_back({e.id(), out});
  return out;
}

void check_rule(const Rule& r) {
  if (is_wildcard(r.pattern))
    throw UsageError(fmt::format("rule '{}': the pattern is a bare wildcard", r.name));
  std::vector<Expr> bound;
  collect_wildcards(r.pattern, &bound);
  std::vector<Expr> used;
  collect_wildcards(r.replacement, &used);
  for (Expr w : used) {
    if (std::find(bound.begin(), bound.end(), w) == bound.end()) {
      throw UsageError(
          fmt::format("rule '{}': the replacement uses '{}', which the pattern does not bind",
                      r.name, w.name()));
    }
  }
  // At most one cofactor per product and one rest per sum, anywhere in the pattern.
  std::function<void(Expr)> check = [&](Expr e) {
    if (e.kind() == Kind::Mul || e.kind() == Kind::Add) {
      int n = 0;
      for (Expr a : e.args())
        n += is_wildcard(a) && wild_class(a) != WildClass::One &&
             (e.kind() == Kind::Mul || wild_class(a) == WildClass::Rest);
      if (n > 1) {
        throw UsageError(fmt::format(
            "rule '{}': '{}' has {} rest wildcards, at most one is allowed", r.name, e.str(), n));
      }
    }
    for (Expr a : e.args()) check(a);
  };
  check(r.pattern);
}

}  // namespace

Expr wildcard(std::string_view name) {
  if (name.size() < 2 || name[0] != '_') {
    throw UsageError(fmt::format("wildcard '{}': a wildcard name is '_' followed by a name", name));
  }
  return symbol(name, SymbolKind::Free);
}

bool is_wildcard(Expr e) {
  return e.is_symbol() && e.symbol_kind() == SymbolKind::Free && e.name().size() >= 2 &&
         e.name()[0] == '_';
}

std::optional<Expr> Match::find(Expr wildcard) const {
  for (const auto& [w, v] : bindings_) {
    if (w == wildcard) return v;
  }
  return std::nullopt;
}

Expr Match::operator[](Expr wildcard) const {
  if (auto v = find(wildcard)) return *v;
  throw UsageError(fmt::format("match: wildcard '{}' is unbound", wildcard.str()));
}

Expr Match::operator[](std::string_view wildcard_name) const {
  return (*this)[wildcard(wildcard_name)];
}

Rule rule(std::string name, Expr pattern, Expr replacement, Condition condition) {
  Rule r{std::move(name), pattern, replacement, std::move(condition)};
  check_rule(r);
  return r;
}

bool is_nonnegative(Expr e) {
  switch (e.kind()) {
    case Kind::Rational:
    case Kind::Real:
      return !e.number().is_negative();
    case Kind::Pow: {
      const Number& x = e.arg(1).number();
      // Even powers are squares; a fractional power is real only for a base >= 0.
      if (!x.is_integer()) return true;
      return x.num() % 2 == 0 || is_nonnegative(e.arg(0));
    }
    case Kind::Exp:
    case Kind::Abs:
      return true;
    case Kind::Add:
    case Kind::Mul: {
      for (Expr a : e.args()) {
        if (!is_nonnegative(a)) return false;
      }
      return true;
    }
    default:
      return false;
  }
}

Condition nonnegative(std::string_view wildcard_name) {
  const Expr w = wildcard(wildcard_name);
  return [w](const Match& m) { return is_nonnegative(m[w]); };
}

Condition integer_coefficient(std::string_view wildcard_name) {
  const Expr w = wildcard(wildcard_name);
  return [w](const Match& m) {
    const Expr e = m[w];
    return e.kind() != Kind::Add && split_coefficient(e).first.is_integer();
  };
}

std::vector<Match> find_matches(Expr pattern, Expr target, std::size_t limit) {
  std::vector<Match> out;
  Match m;
  MatchCache cache;
  Matcher matcher(&m, 1 << 20, &cache);
  matcher.match_top(pattern, target, [&] {
    out.push_back(m);
    return out.size() >= limit;
  });
  return out;
}

Expr instantiate(Expr replacement, const Match& match) {
  SubstituteMemo memo;
  const Expr core = substitute(replacement, match, &memo);
  if (match.remainder.empty()) return core;
  std::vector<Expr> terms = match.remainder;
  terms.push_back(core);
  return add(terms);
}

Rewriter::Rewriter(std::vector<Rule> rules, Strategy strategy, Budget budget)
    : rules_(std::move(rules)),
      strategy_(strategy),
      budget_(budget),
      cache_(std::make_unique<MatchCache>()) {}

Rewriter::~Rewriter() = default;
Rewriter::Rewriter(Rewriter&&) noexcept = default;

Expr Rewriter::operator()(Expr e) {
  return rewrite(e);
}

Expr Rewriter::rewrite(Expr e) {
  if (e.args().empty()) return e;
  if (const Node* done = memo_.find(e)) return Expr(done);
  // A node met again while it is being rewritten (a rule rebuilt it inside
  // its own replacement) is left as it is: that keeps the recursion finite.
  if (in_progress_.get(e) != 0) return e;
  in_progress_.at(e) = 1;
  const Expr out = apply_at(rewrite_children(e));
  in_progress_.at(e) = 0;
  memo_.set(e, out);
  return out;
}

Expr Rewriter::rewrite_children(Expr e) {
  if (e.args().empty()) return e;
  detail::SmallVector<Expr, 8> args;
  args.reserve(e.args().size());
  bool changed = false;
  for (Expr a : e.args()) {
    args.push_back(rewrite(a));
    changed = changed || args.back() != a;
  }
  return changed ? make(e.kind(), args) : e;
}

Expr Rewriter::apply_at(Expr e) {
  Expr current = e;
  int cost = strategy_ == Strategy::Improve ? operation_cost(current) : 0;
  for (int i = 0; i < budget_.steps_per_node; ++i) {
    auto next = step(current, cost);
    if (!next) break;
    current = *next;
    if (strategy_ == Strategy::Improve) cost = operation_cost(current);
  }
  return current;
}

// One rule application at the root of e: the first match whose result is
// accepted by the strategy, or nothing.
std::optional<Expr> Rewriter::step(Expr e, int cost) {
  if (e.args().empty()) return std::nullopt;
  const bool sum_rules_done = strategy_ == Strategy::Improve && e.kind() == Kind::Add;
  if (sum_rules_done) {
    if (auto better = improve_sum(e, cost)) return better;
  }
  const TrigProfile profile(e);
  for (const Rule& r : rules_) {
    if ((sum_rules_done && r.pattern.kind() == Kind::Add) || !may_match(r.pattern, profile))
      continue;
    Match m;
    Matcher matcher(&m, budget_.attempts_per_rule, cache_.get());
    std::optional<Expr> accepted;
    matcher.match_top(r.pattern, e, [&] {
      if (r.condition && !r.condition(m)) return false;
      const Expr candidate = instantiate(r.replacement, m);
      if (candidate == e) return false;
      if (strategy_ == Strategy::Normalize) {
        accepted = candidate;
        return true;
      }
      const Expr rewritten = rewrite_children(candidate);
      if (operation_cost(rewritten) >= cost) return false;
      accepted = rewritten;
      return true;
    });
    if (accepted) {
      trace(r);
      if (strategy_ == Strategy::Normalize) return rewrite_children(*accepted);
      return accepted;
    }
  }
  return std::nullopt;
}

// Sum rules on a sum, Improve strategy. Every match is scored by the cost
// change it would make (SumCost, without building anything); the improving
// ones are applied together, best first, as long as they use disjoint terms.
// One step then does the work of many, which matters on long sums where
// restarting the search after each rewrite would repeat it over and over.
// If the batch is not cheaper after all (sharing), single rewrites are tried.
std::optional<Expr> Rewriter::improve_sum(Expr e, int cost) {
  struct Found {
    int delta;
    const Rule* rule;
    std::vector<Expr> matched;
    Expr replacement;
  };
  SumCost sum_cost(e);
  const TrigProfile profile(e);
  std::vector<Found> found;
  for (const Rule& r : rules_) {
    if (r.pattern.kind() != Kind::Add || !may_match(r.pattern, profile)) continue;
    Match m;
    Matcher matcher(&m, budget_.attempts_per_rule, cache_.get());
    matcher.match_top(r.pattern, e, [&] {
      if (r.condition && !r.condition(m)) return false;
      Match core = m;
      core.remainder.clear();
      const Expr replacement = instantiate(r.replacement, core);
      const std::span<const Expr> added =
          replacement.is_zero() ? std::span<const Expr>() : terms_of(replacement);
      const int delta = sum_cost.delta(m.matched, added);
      if (delta < 0) found.push_back({delta, &r, m.matched, replacement});
      return false;
    });
  }
  if (found.empty()) return std::nullopt;
  std::stable_sort(found.begin(), found.end(),
                   [](const Found& a, const Found& b) { return a.delta < b.delta; });
  auto build = [&](std::span<const Found* const> chosen) {
    std::unordered_set<std::uint32_t> removed;
    std::vector<Expr> terms;
    for (const Found* f : chosen) {
      for (Expr t : f->matched) removed.insert(t.id());
      terms.push_back(f->replacement);
    }
    for (Expr t : e.args()) {
      if (!removed.contains(t.id())) terms.push_back(t);
    }
    return rewrite_children(add(terms));
  };
  // The batch: best first, skipping matches that overlap a chosen one.
  std::vector<const Found*> batch;
  std::unordered_set<std::uint32_t> taken;
  for (const Found& f : found) {
    const bool overlaps = std::any_of(f.matched.begin(), f.matched.end(),
                                      [&](Expr t) { return taken.contains(t.id()); });
    if (overlaps) continue;
    for (Expr t : f.matched) taken.insert(t.id());
    batch.push_back(&f);
  }
  const Expr all = build(batch);
  if (operation_cost(all) < cost) {
    for (const Found* f : batch) trace(*f->rule);
    return all;
  }
  const std::size_t singles = std::min<std::size_t>(found.size(), 8);
  for (std::size_t i = 0; i < singles; ++i) {
    const Found* f = &found[i];
    const Expr one = build(std::span<const Found* const>(&f, 1));
    if (operation_cost(one) < cost) {
      trace(*f->rule);
      return one;
    }
  }
  return std::nullopt;
}

}  // namespace symdyn::symbolic
