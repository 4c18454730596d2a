// Generation of the reference models with and without trigonometric
// simplification. Relative motions compose partial velocities numerically
// from the reference body's (model/kinematics.hpp): simplification only ever
// sees the short local expressions, so it must never make the emitted partial
// velocities or equations of motion costlier than leaving them alone.
#include <catch2/catch.hpp>
#include <map>
#include <utility>

#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/dynamics.hpp>
#include <symdyn/model/trig_reduction.hpp>
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/simplify.hpp>

using namespace symdyn;

namespace {

std::map<std::string, std::size_t> operation_counts(const model::Model& m, std::string_view variant,
                                                    bool simplify) {
  codegen::Options options;
  options.simplify = simplify;
  std::map<std::string, std::size_t> counts;
  for (const auto& f : codegen::generate(m, variant, "x", options).functions)
    counts[f.name] = f.operations.total();
  return counts;
}

}  // namespace

TEST_CASE("simplification never makes partial velocities or equations of motion costlier",
          "[models]") {
  const std::pair<const char*, const char*> cases[] = {{"robot3d", "relative"},
                                                       {"trike", "default"},
                                                       {"hexapod_tree", "default"},
                                                       {"chain_8", "relative"}};
  for (const auto& [name, variant] : cases) {
    const model::Model m = model::find_definition(name).make(variant);
    const auto plain = operation_counts(m, variant, false);
    const auto simplified = operation_counts(m, variant, true);
    for (const char* entry : {"partial_velocities", "mass_matrix", "bias_forces"}) {
      INFO(name << " " << variant << " " << entry << ": " << simplified.at(entry)
                << " operations simplified, " << plain.at(entry) << " not");
      CHECK(simplified.at(entry) <= plain.at(entry));
    }
  }
}

// Each body's quantities are composed from its reference's as named
// intermediates (model/kinematics.hpp), so the kinematics of a chain grow
// linearly with its length; merged into one expression they grew as N².
TEST_CASE("the relative kinematics of chain_N grow linearly in N", "[models]") {
  auto accelerations = [](const char* name) {
    const model::Model m = model::find_definition(name).make("relative");
    codegen::Options options;
    options.equations_of_motion = false;
    options.symbolic_partials = false;
    for (const auto& f : codegen::generate(m, "relative", "x", options).functions) {
      if (f.name == "accelerations") return f.operations.total();
    }
    FAIL("no accelerations entry point");
    return 0;
  };
  const int n16 = accelerations("chain_16"), n32 = accelerations("chain_32"),
            n64 = accelerations("chain_64");
  INFO("accelerations: chain_16 " << n16 << ", chain_32 " << n32 << ", chain_64 " << n64
                                  << " operations");
  CHECK(n64 - n32 <=
        2.05 * (n32 - n16));  // the same cost per body added (quadratic growth would give 4x)
  CHECK(n64 < 64 * 130);      // measured 120 per body: R, x, v, w, a, dw composed in 3D
}

// Described from the ground, each link's motion begins with the previous
// link's: the generator makes it relative to that link
// (Model::with_shared_motions_relative), so the code is the relative chain's.
TEST_CASE("a chain described from the ground emits the chain described link by link", "[models]") {
  auto source = [](const char* variant) {
    const std::string code =
        codegen::generate(model::find_definition("chain_8").make(variant), variant, "x").source;
    // Past the comment naming the variant, up to the link-time guard that names it too.
    const std::size_t begin = code.find('\n'), end = code.find("\n// Link-time guard");
    REQUIRE(end != std::string::npos);
    return code.substr(begin, end - begin);
  };
  CHECK(source("absolute") == source("relative"));
}

// The equations of motion gather each subtree's inertia and wrench body by
// body, each in its own axes (model/dynamics.hpp): h then costs the same per body added,
// and M, for each coordinate, one transform of its momentum (about 24
// operations) per level it is carried up the chain and a short dot product
// per entry: N²/2 of each, where summing body by body over every partial
// velocity grew as N³.
TEST_CASE("the equations of motion of chain_N grow as N² (M) and N (h)", "[models]") {
  auto equations = [](const char* name) {
    const model::Model m = model::find_definition(name).make("relative");
    std::map<std::string, std::size_t> counts = operation_counts(m, "relative", true);
    return std::pair<int, int>(counts.at("mass_matrix"), counts.at("bias_forces"));
  };
  const auto [m8, h8] = equations("chain_8");
  const auto [m16, h16] = equations("chain_16");
  const auto [m32, h32] = equations("chain_32");
  INFO("M: chain_8 " << m8 << ", chain_16 " << m16 << ", chain_32 " << m32
                     << " operations; h: " << h8 << ", " << h16 << ", " << h32);
  CHECK(h32 - h16 <= 2.1 * (h16 - h8));  // measured 1 421 and 699
  CHECK(m32 - m16 <= 4.2 * (m16 - m8));  // measured 8 507 and 2 188; 8 times for N³
  for (const auto& [n, ops] : {std::pair(8, m8), std::pair(16, m16), std::pair(32, m32)}) {
    CHECK(ops <= 24 * n * (n + 1) / 2 + 60 * n);  // measured chain_16 2 906, chain_32 11 413
  }
}

// The double pendulum (unit masses and lengths): M_00 = 5/3 + cos q1 once
// the sums over its rods are reduced modulo sin² + cos² = 1, one addition
// and a cosine the kinematics computes anyway.
TEST_CASE("the double pendulum's M_00 is 5/3 + cos q1", "[models]") {
  const model::Model m = model::find_definition("double_pendulum").make("absolute");
  symbolic::Simplifier simplifier;
  model::DeriveOptions options;
  options.simplify = [&simplifier](model::Expr e) { return simplifier(e); };
  const model::Kinematics k = model::derive_kinematics(m, options);
  model::Dynamics d = model::derive_dynamics(m, k, options.simplify);
  model::reduce_trigonometry(d, k);
  symbolic::Substitution inline_all({});
  for (const std::vector<symbolic::Definition>* defs :
       {&k.intermediates, &std::as_const(d.definitions)}) {
    for (const symbolic::Definition& def : *defs) inline_all.add(def.symbol, inline_all(def.value));
  }
  const model::Expr m00 = inline_all(d.mass_matrix[0]);
  INFO("M_00 = " << m00);
  REQUIRE(m00.kind() == symbolic::Kind::Add);
  REQUIRE(m00.args().size() == 2);
  CHECK(m00.arg(0).number().to_double() == Approx(5.0 / 3.0).epsilon(1e-15));
  CHECK(m00.arg(1) == symbolic::cos(m.coordinates()[1].q));
}
