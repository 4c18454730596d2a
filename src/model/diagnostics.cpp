#include <algorithm>
#include <optional>

#include <symdyn/model/diagnostics.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::model {
namespace {

using symbolic::Kind;

// The function an operation with a restricted domain is known by, or nothing.
std::optional<std::string> restricted_function(Expr node) {
  switch (node.kind()) {
    case Kind::Asin:
      return "asin";
    case Kind::Acos:
      return "acos";
    case Kind::Log:
      return "log";
    case Kind::Pow: {
      const Expr e = node.arg(1);
      if (e == Expr(symbolic::Number(1, 2))) return "sqrt";
      // x^n for a positive integer n is defined everywhere.
      if (e.is_number() && e.number().is_integer() && !e.number().is_negative() &&
          !e.number().is_zero()) {
        return std::nullopt;
      }
      return "pow";
    }
    default:
      return std::nullopt;
  }
}

// Sum of |term| over the terms of x (|x| when x is not a sum).
Expr magnitude_of_terms(Expr x) {
  if (x.kind() != Kind::Add) return symbolic::abs(x);
  std::vector<Expr> terms;
  for (Expr term : x.args()) terms.push_back(symbolic::abs(term));
  return symbolic::add(terms);
}

// 'x', 'y' or 'z' for an elementary axis, else 0.
char elementary_axis(const Vec3& a) {
  for (int k = 0; k < 3; ++k) {
    bool match = true;
    for (int i = 0; i < 3; ++i) match = match && a[i] == Expr(i == k ? 1 : 0);
    if (match) return static_cast<char>('x' + k);
  }
  return 0;
}

int coordinate_index(const Model& model, Expr angle) {
  const auto& cs = model.coordinates();
  const auto it =
      std::find_if(cs.begin(), cs.end(), [&](const Coordinate& c) { return c.q == angle; });
  return it == cs.end() ? -1 : static_cast<int>(it - cs.begin());
}

// The first angle sequence among a motion's rotations, if any.
std::optional<AngleSequence> first_sequence(const Model& model, const Transform& motion) {
  struct Rotation {
    char axis;
    int coordinate;  // -1: not a coordinate (breaks a sequence)
  };
  std::vector<Rotation> rotations;
  for (const Transform::Step& s : motion.steps()) {
    if (s.is_rotation)
      rotations.push_back({elementary_axis(s.axis), coordinate_index(model, s.angle)});
  }
  for (std::size_t k = 0; k + 2 < rotations.size(); ++k) {
    const Rotation &a = rotations[k], &b = rotations[k + 1], &c = rotations[k + 2];
    const bool coordinates = a.coordinate >= 0 && b.coordinate >= 0 && c.coordinate >= 0 &&
                             a.coordinate != b.coordinate && b.coordinate != c.coordinate &&
                             a.coordinate != c.coordinate;
    const bool axes =
        a.axis != 0 && b.axis != 0 && c.axis != 0 && a.axis != b.axis && b.axis != c.axis;
    if (coordinates && axes) {
      AngleSequence seq;
      seq.coordinates = {a.coordinate, b.coordinate, c.coordinate};
      seq.axes = {a.axis, b.axis, c.axis};
      return seq;
    }
  }
  return std::nullopt;
}

}  // namespace

std::vector<DomainCheck> domain_checks(const Model& model) {
  std::vector<std::pair<std::string, Expr>>
      named;  // declared, then inlined (a model has one kind or both)
  for (const Dependent& d : model.dependents()) named.emplace_back(d.symbol.name(), d.expression);
  for (const InlinedDependent& d : model.inlined_dependents())
    named.emplace_back(d.name, d.expression);
  std::vector<DomainCheck> checks;
  std::vector<Expr> seen;  // an inlined parameter's operations reappear in the later ones
  for (const auto& [name, root] : named) {
    // postorder: innermost first, each distinct node once.
    for (Expr node : symbolic::postorder(std::span<const Expr>(&root, 1))) {
      const auto function = restricted_function(node);
      if (!function || std::find(seen.begin(), seen.end(), node) != seen.end()) continue;
      seen.push_back(node);
      const bool power = node.kind() == Kind::Pow;
      checks.push_back({name, *function, node.arg(0), power ? node.arg(1) : Expr(0),
                        magnitude_of_terms(node.arg(0))});
    }
  }
  return checks;
}

std::string AngleSequence::name() const {
  std::string out;
  for (char a : axes) {
    if (!out.empty()) out += '-';
    out += static_cast<char>(a - 'a' + 'A');
  }
  return out;
}

std::vector<AngleSequence> angle_sequences(const Model& model) {
  std::vector<AngleSequence> out;
  const auto& bodies = model.bodies();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (auto seq = first_sequence(model, bodies[i].motion())) {
      seq->body = static_cast<int>(i);
      out.push_back(*seq);
    }
  }
  return out;
}

}  // namespace symdyn::model
