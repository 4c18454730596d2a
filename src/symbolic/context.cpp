// The node arena and the intern table.
#include <fmt/format.h>

#include <array>
#include <deque>
#include <memory_resource>
#include <unordered_map>
#include <vector>

#include <symdyn/symbolic/expr.hpp>

namespace symdyn::symbolic {
namespace {

std::size_t mix(std::size_t h, std::size_t v) {
  return h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2));
}

std::size_t hash_number(const Number& n) {
  if (n.is_exact())
    return mix(std::hash<std::int64_t>{}(n.num()), std::hash<std::int64_t>{}(n.den()));
  return mix(0x51ed27, std::hash<double>{}(n.to_double()));
}

// The interned nodes by their cached hash, in one open-addressed array
// (linear probing, at most half full). Why: a map from hash to a vector of
// nodes allocated a bucket and a vector per node, and every construction
// chased three pointers to find a node that usually already exists. Each slot
// keeps the hash beside the node, so probing past other nodes reads no node.
class InternTable {
 public:
  InternTable() : slots_(1024), mask_(1023) {}

  // The node with hash h for which same(node) holds, or nullptr.
  template <class Same>
  const Node* find(std::size_t h, const Same& same) const {
    for (std::size_t i = slot_of(h);; i = (i + 1) & mask_) {
      const Slot& slot = slots_[i];
      if (slot.node == nullptr) return nullptr;
      if (slot.hash == h && same(slot.node)) return slot.node;
    }
  }

  void insert(const Node* n) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    place({n->hash(), n});
    ++size_;
  }

  std::size_t bytes() const { return slots_.capacity() * sizeof(Slot); }

 private:
  struct Slot {
    std::size_t hash = 0;
    const Node* node = nullptr;
  };

  // Fibonacci hashing: the high bits of h·φ, whatever the quality of h's low bits.
  std::size_t slot_of(std::size_t h) const { return (h * 0x9e3779b97f4a7c15ULL) >> shift_; }

  void place(Slot s) {
    std::size_t i = slot_of(s.hash);
    while (slots_[i].node != nullptr) i = (i + 1) & mask_;
    slots_[i] = s;
  }

  void grow() {
    std::vector<Slot> old(2 * slots_.size());
    old.swap(slots_);
    mask_ = slots_.size() - 1;
    --shift_;
    for (const Slot& s : old) {
      if (s.node != nullptr) place(s);
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_;
  int shift_ = 64 - 10;
  std::size_t size_ = 0;
};

}  // namespace

struct Context::Impl {
  std::deque<Node> nodes;  // stable addresses
  std::pmr::monotonic_buffer_resource args_arena;
  std::deque<std::string> names;
  InternTable table;  // numbers and compound nodes; symbols are found by name
  std::unordered_map<std::string, const Node*> symbols;
  std::size_t symbol_count = 0;
  std::size_t args_bytes = 0;
  Expr zero{nullptr};
  // The integers -16..16 once interned, by value + 16: most coefficients and
  // exponents are among them, found here without hashing and comparing.
  std::array<const Node*, 33> small_integers{};
};

namespace {
Context* g_current = nullptr;
Context& default_context() {
  static Context context;
  return context;
}
}  // namespace

Context::Context() : impl_(std::make_unique<Impl>()) {
  Scope scope(*this);
  impl_->zero = intern_number(Number(0));
}
Context::~Context() = default;

Context& Context::current() {
  return g_current != nullptr ? *g_current : default_context();
}
std::size_t Context::size() const {
  return impl_->nodes.size();
}
std::size_t Context::symbol_count() const {
  return impl_->symbol_count;
}
std::size_t Context::memory_bytes() const {
  return impl_->nodes.size() * sizeof(Node) + impl_->args_bytes + impl_->table.bytes();
}

Context::Scope::Scope(Context& context) : previous_(g_current) {
  g_current = &context;
}
Context::Scope::~Scope() {
  g_current = previous_;
}

Expr intern_node(Kind kind, std::span<const Expr> args) {
  Context::Impl& impl = *Context::current().impl_;
  std::size_t h = mix(0x1234567, static_cast<std::size_t>(kind));
  for (Expr a : args) h = mix(h, a.hash());
  const Node* found = impl.table.find(h, [&](const Node* n) {
    return n->kind() == kind && n->n_args_ == args.size() &&
           std::equal(args.begin(), args.end(), n->args_);
  });
  if (found != nullptr) return Expr(found);
  auto* stored =
      static_cast<Expr*>(impl.args_arena.allocate(args.size() * sizeof(Expr), alignof(Expr)));
  std::uninitialized_copy(args.begin(), args.end(), stored);
  impl.args_bytes += args.size() * sizeof(Expr);
  Node& node = impl.nodes.emplace_back();
  node.kind_ = kind;
  node.id_ = static_cast<std::uint32_t>(impl.nodes.size() - 1);
  node.n_args_ = static_cast<std::uint32_t>(args.size());
  node.hash_ = h;
  node.args_ = stored;
  impl.table.insert(&node);
  return Expr(&node);
}

Expr intern_number(const Number& value) {
  Context::Impl& impl = *Context::current().impl_;
  const bool small = value.is_integer() && value.num() >= -16 && value.num() <= 16;
  const Node** cached =
      small ? &impl.small_integers[static_cast<std::size_t>(value.num() + 16)] : nullptr;
  if (cached != nullptr && *cached != nullptr) return Expr(*cached);
  const Kind kind = value.is_exact() ? Kind::Rational : Kind::Real;
  const std::size_t h = mix(static_cast<std::size_t>(kind), hash_number(value));
  const Node* found =
      impl.table.find(h, [&](const Node* n) { return n->kind() == kind && n->number_ == value; });
  if (found == nullptr) {
    Node& node = impl.nodes.emplace_back();
    node.kind_ = kind;
    node.id_ = static_cast<std::uint32_t>(impl.nodes.size() - 1);
    node.hash_ = h;
    node.number_ = value;
    impl.table.insert(&node);
    found = &node;
  }
  if (cached != nullptr) *cached = found;
  return Expr(found);
}

Expr symbol(std::string_view name, SymbolKind kind) {
  if (name.empty()) throw UsageError("symbol: empty name");
  Context::Impl& impl = *Context::current().impl_;
  const std::string key(name);
  if (auto it = impl.symbols.find(key); it != impl.symbols.end()) {
    const Node* n = it->second;
    if (n->symbol_kind_ != kind) {
      throw UsageError(fmt::format("symbol '{}' is already declared as {}, not {}", name,
                                   to_string(n->symbol_kind_), to_string(kind)));
    }
    return Expr(n);
  }
  const std::string& stored_name = impl.names.emplace_back(key);
  Node& node = impl.nodes.emplace_back();
  node.kind_ = Kind::Symbol;
  node.symbol_kind_ = kind;
  node.id_ = static_cast<std::uint32_t>(impl.nodes.size() - 1);
  node.symbol_index_ = static_cast<std::uint32_t>(impl.symbol_count++);
  node.hash_ = mix(std::hash<std::string>{}(key), static_cast<std::size_t>(Kind::Symbol));
  node.name_ = &stored_name;
  impl.symbols.emplace(key, &node);
  return Expr(&node);
}

// --- Expr accessors -------------------------------------------------------------

Expr::Expr() : node_(Context::current().impl_->zero.node_) {}
Expr::Expr(int value) : Expr(intern_number(Number(value))) {}
Expr::Expr(std::int64_t value) : Expr(intern_number(Number(value))) {}
Expr::Expr(double value) : node_(nullptr) {
  if (!std::isfinite(value)) throw DomainError(fmt::format("constant {} is not finite", value));
  node_ = intern_number(Number::from_double(value)).node_;
}
Expr::Expr(const Number& value) : Expr(intern_number(value)) {}

void Expr::throw_not_a(std::string_view what) const {
  throw UsageError(fmt::format("'{}' is not a {}", str(), what));
}

std::string_view to_string(SymbolKind kind) {
  switch (kind) {
    case SymbolKind::Variable:
      return "variable";
    case SymbolKind::Rate:
      return "rate";
    case SymbolKind::Acceleration:
      return "acceleration";
    case SymbolKind::Dependent:
      return "dependent";
    case SymbolKind::DependentRate:
      return "dependent rate";
    case SymbolKind::DependentAcceleration:
      return "dependent acceleration";
    case SymbolKind::Parameter:
      return "parameter";
    case SymbolKind::Time:
      return "time";
    case SymbolKind::Intermediate:
      return "intermediate";
    case SymbolKind::Free:
      return "free";
  }
  return "?";
}

const KindInfo& info(Kind kind) {
  static const KindInfo table[] = {
#define SYMDYN_KIND_INFO(kind, name, arity, cpp, cost) {name, arity, cpp, cost},
      SYMDYN_FOR_EACH_KIND(SYMDYN_KIND_INFO)
#undef SYMDYN_KIND_INFO
  };
  return table[static_cast<int>(kind)];
}

bool is_function(Kind kind) {
  return kind >= Kind::Sin;
}

}  // namespace symdyn::symbolic
