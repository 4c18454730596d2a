// The operation count of a DAG; see cost.hpp for the model.
#include <algorithm>
#include <bit>
#include <vector>

#include <symdyn/symbolic/cost.hpp>

namespace symdyn::symbolic {
namespace {

bool is_reciprocal(Expr f) {
  return f.kind() == Kind::Pow && f.arg(1).number().is_integer() && f.arg(1).number().is_negative();
}

// Products: k - 1 multiplications between the non-numeric factors (a
// reciprocal factor is a division instead of a multiplication), plus one for
// a coefficient other than +-1, plus one for 1/(x·y) with no numerator.
int product_cost(Expr e, std::vector<Expr>* operands) {
  int cost = 0;
  int factors = 0;
  bool has_numerator = false;
  for (Expr f : e.args()) {
    if (f.is_number()) {
      const Number& c = f.number();
      if (!c.is_one() && !(-c).is_one()) {
        cost += 1;
        has_numerator = true;
      }
      continue;
    }
    ++factors;
    if (is_reciprocal(f)) {
      cost += power_multiplications(-f.arg(1).number().num());
      operands->push_back(f.arg(0));
    } else {
      has_numerator = true;
      operands->push_back(f);
    }
  }
  cost += factors - 1;
  if (!has_numerator) cost += 1;
  return cost;
}

int power_cost(const Number& exponent) {
  if (!exponent.is_integer()) return info(Kind::Pow).cost;
  const std::int64_t n = exponent.num();
  return n < 0 ? power_multiplications(-n) + 1 : power_multiplications(n);
}

// The nodes counted by one call are marked with that call's stamp, in a table
// by node id kept between calls. Why: the simplifier asks for the cost of
// small expressions millions of times in a context of millions of nodes, and
// clearing a fresh mark per node of the context dominated each call.
class CostCounter {
 public:
  CostCounter()
      : seen_(marks()),
        stamp_(++current_stamp()),
        stack_(scratch().stack),
        operands_(scratch().operands) {
    if (stamp_ == 0) {  // the stamps wrapped around: old marks could collide
      std::fill(seen_.begin(), seen_.end(), 0);
      std::fill(scratch().sincos.begin(), scratch().sincos.end(), 0);
      stamp_ = ++current_stamp();
    }
  }

  // fuse_sincos: sin(x) and cos(x) of one x count as one call.
  int total(std::span<const Expr> outputs, bool fuse_sincos = false) {
    stack_.clear();
    for (Expr e : outputs) push(e);
    while (!stack_.empty()) {
      const Expr e = stack_.back();
      stack_.pop_back();
      operands_.clear();
      const int cost = own_cost(e, &operands_);
      if (!fuse_sincos || !partner_counted(e)) total_ += cost;
      for (Expr a : operands_) push(a);
    }
    return total_;
  }

 private:
  // Whether e is sin(x) or cos(x) and the other of the two is counted already
  // (marks e's as counted). The marks are by x's id: sin in the low bit.
  bool partner_counted(Expr e) {
    if (e.kind() != Kind::Sin && e.kind() != Kind::Cos) return false;
    const std::uint32_t x = e.arg(0).id();
    std::vector<std::uint64_t>& marks = scratch().sincos;
    if (x >= marks.size()) marks.resize(std::max<std::size_t>(x + 1, Context::current().size()), 0);
    const std::uint64_t mine = e.kind() == Kind::Sin ? 1 : 2;
    std::uint64_t& mark = marks[x];
    if ((mark >> 2) != stamp_) mark = std::uint64_t{stamp_} << 2;
    const bool partner = (mark & (3 - mine)) != 0;
    mark |= mine;
    return partner;
  }

  // Queues a node unless it is already counted.
  void push(Expr e) {
    const std::uint32_t id = e.id();
    if (id >= seen_.size())
      seen_.resize(std::max<std::size_t>(id + 1, Context::current().size()), 0);
    if (seen_[id] == stamp_) return;
    seen_[id] = stamp_;
    stack_.push_back(e);
  }

  static std::vector<std::uint32_t>& marks() {
    thread_local std::vector<std::uint32_t> marks;
    return marks;
  }
  static std::uint32_t& current_stamp() {
    thread_local std::uint32_t stamp = 0;
    return stamp;
  }
  // The work lists too are kept between calls (a count calls nothing that
  // counts), so that a small count allocates nothing.
  struct Scratch {
    std::vector<Expr> stack;
    std::vector<Expr> operands;
    std::vector<std::uint64_t> sincos;  // by argument id: this count's stamp << 2 | cos << 1 | sin
  };
  static Scratch& scratch() {
    thread_local Scratch lists;
    return lists;
  }

  std::vector<std::uint32_t>& seen_;
  std::uint32_t stamp_;
  std::vector<Expr>& stack_;
  std::vector<Expr>& operands_;
  int total_ = 0;
};

}  // namespace

int own_cost(Expr e, std::vector<Expr>* operands) {
  switch (e.kind()) {
    case Kind::Rational:
    case Kind::Real:
    case Kind::Symbol:
      return 0;
    case Kind::Mul:
      return product_cost(e, operands);
    default:
      break;
  }
  operands->insert(operands->end(), e.args().begin(), e.args().end());
  if (e.kind() == Kind::Add) return static_cast<int>(e.args().size()) - 1;
  if (e.kind() == Kind::Pow) return power_cost(e.arg(1).number());
  return info(e.kind()).cost;
}

int power_multiplications(std::int64_t n) {
  const auto u = static_cast<std::uint64_t>(n);
  return static_cast<int>(std::bit_width(u)) - 1 + std::popcount(u) - 1;
}

int operation_cost(std::span<const Expr> outputs) {
  return CostCounter().total(outputs);
}

int operation_cost(Expr e) {
  return operation_cost(std::span<const Expr>(&e, 1));
}

int fused_operation_cost(std::span<const Expr> outputs) {
  return CostCounter().total(outputs, true);
}

}  // namespace symdyn::symbolic
