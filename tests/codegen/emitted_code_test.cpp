// The emitted C++, compiled at build time by symdyn_add_model (models/CMakeLists.txt),
// against the interpreter over the very programs it prints, against the DAG
// evaluated directly, and against a numerical assembly of the equations of motion
// (support/emitted_check.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>

#include "double_pendulum_absolute.hpp"
#include "double_pendulum_absolute_case1.hpp"
#include "double_pendulum_relative.hpp"
#include "double_pendulum_relative_only.hpp"
#include "slider_crank_dependent.hpp"
#include "slider_crank_dependent_parts.hpp"
#include "slider_crank_inline.hpp"
#include "slider_crank_inline_case1.hpp"
#include "support/emitted_check.hpp"
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/kinematics.hpp>

using namespace symdyn;
using namespace symdyn::testing;
using Catch::Matchers::Contains;

namespace {

codegen::Options case1() {
  codegen::Options o;
  o.simplify = false;
  o.symbolic_partials = false;
  o.equations_of_motion = false;
  return o;
}

// The text of entry point `name` in an emitted source of struct x.
std::string function_text(const std::string& source, const std::string& name) {
  const std::size_t begin = source.find("x::" + name + "(");
  return begin == std::string::npos ? ""
                                    : source.substr(begin, source.find("\n}\n", begin) - begin);
}

}  // namespace

TEST_CASE(
    "emitted double pendulum (absolute) matches the DAG, the interpreter and the assembled "
    "residual",
    "[codegen]") {
  check_emitted<symdyn_generated::double_pendulum_absolute>({"double_pendulum", "absolute", {}});
}
TEST_CASE("emitted double pendulum (relative) matches", "[codegen]") {
  check_emitted<symdyn_generated::double_pendulum_relative>({"double_pendulum", "relative", {}});
}
TEST_CASE("emitted slider-crank (inline) matches", "[codegen]") {
  check_emitted<symdyn_generated::slider_crank_inline>({"slider_crank", "inline", {}});
}
TEST_CASE("emitted slider-crank (dependent) matches", "[codegen]") {
  check_emitted<symdyn_generated::slider_crank_dependent>({"slider_crank", "dependent", {}});
}
TEST_CASE("emitted case 1 (numeric partial velocities, no simplification) matches", "[codegen]") {
  check_emitted<symdyn_generated::double_pendulum_absolute_case1>(
      {"double_pendulum", "absolute", case1()});
  check_emitted<symdyn_generated::slider_crank_inline_case1>({"slider_crank", "inline", case1()});
}

TEST_CASE(
    "emitted in parts (16 instructions each, values crossing through a scratch array) matches",
    "[codegen]") {
  codegen::Options parts;
  parts.part_instructions = 16;
  parts.split_above = 0;  // slider_crank is short: split it anyway
  check_emitted<symdyn_generated::slider_crank_dependent_parts>(
      {"slider_crank", "dependent", parts});
  const model::Model m = model::find_definition("slider_crank").make("dependent");
  const std::string source = codegen::generate(m, "dependent", "x", parts).source;
  CHECK_THAT(source, Contains("[[gnu::noinline]] void part1("));
  // Shared: what positions compute, velocities and accelerations compute in the same parts.
  CHECK_THAT(source, Contains(", run by positions, velocities, accelerations"));
}

namespace {

// The definition of part p in a source ("" if none), and how many sources define it.
std::string part_definition(const std::string& source, std::size_t p) {
  const std::size_t begin = source.find(fmt::format("[[gnu::noinline]] void part{}(", p));
  return begin == std::string::npos ? ""
                                    : source.substr(begin, source.find("\n}\n", begin) - begin);
}

}  // namespace

TEST_CASE("definitions spread over several source files are those of one file, each once",
          "[codegen]") {
  const model::Model m = model::find_definition("slider_crank").make("dependent");
  codegen::Options options;
  options.part_instructions = 16;
  options.split_above = 0;
  const codegen::GeneratedCode one = codegen::generate(m, "dependent", "x", options);
  options.sources = 4;
  options.source_bytes = 1;  // every file used
  const codegen::GeneratedCode four = codegen::generate(m, "dependent", "x", options);
  REQUIRE(one.more_sources.empty());
  REQUIRE(four.more_sources.size() == 3);
  std::vector<std::string> files{four.source};
  files.insert(files.end(), four.more_sources.begin(), four.more_sources.end());
  std::size_t parts = 0;
  for (; !part_definition(one.source, parts).empty(); ++parts) {
    INFO("part " << parts);
    const auto defines = [&](const std::string& f) { return !part_definition(f, parts).empty(); };
    CHECK(std::count_if(files.begin(), files.end(), defines) == 1);
    const auto it = std::find_if(files.begin(), files.end(), defines);
    if (it != files.end()) CHECK(part_definition(*it, parts) == part_definition(one.source, parts));
    // The first file declares each part, for its entry points to call.
    CHECK_THAT(four.source, Contains(fmt::format("\nvoid part{}(", parts)));
  }
  REQUIRE(parts >= 4);
  // In runs of about equal size: each file after the first (which holds the entry points too)
  // some parts.
  for (std::size_t f = 1; f < files.size(); ++f) {
    INFO("file " << f + 1);
    CHECK_THAT(files[f], Contains("[[gnu::noinline]] void part"));
  }
  for (const codegen::EmittedFunction& f : one.functions)
    CHECK(function_text(four.source, f.name) == function_text(one.source, f.name));
  // <cmath> only in the files that call one of its functions: parsing it costs
  // more than a short file's definitions. (They compile: the link test below.)
  std::size_t with_cmath = 0;
  for (std::size_t f = 0; f < files.size(); ++f) {
    INFO("file " << f + 1);
    const bool calls = files[f].find("std::") != std::string::npos;
    CHECK((files[f].find("#include <cmath>\n") != std::string::npos) == calls);
    with_cmath += calls;
  }
  CHECK(with_cmath >= 1);
  CHECK(with_cmath < files.size());
  // What the header declares is the same; only the link guard's fingerprint differs.
  CHECK(one.header.substr(0, one.header.find("// Link-time guard")) ==
        four.header.substr(0, four.header.find("// Link-time guard")));
}

TEST_CASE("a short model asked for several source files fills the first, the others a comment",
          "[codegen]") {
  const model::Model m = model::find_definition("double_pendulum").make("absolute");
  codegen::Options options;
  const codegen::GeneratedCode one = codegen::generate(m, "absolute", "x", options);
  options.sources = 3;
  const codegen::GeneratedCode three = codegen::generate(m, "absolute", "x", options);
  REQUIRE(three.more_sources.size() == 2);
  CHECK(three.more_sources[0] ==
        "// Generated by symdyn from model 'double_pendulum', variant 'absolute', file 2 of 3. "
        "Do not edit.\n// Empty: the definitions fill fewer files.\n");
  CHECK_THAT(three.more_sources[1], Contains("file 3 of 3"));
  // The first file is the single one but for the link guard's fingerprint.
  const auto unguarded = [](const std::string& s) {
    return s.substr(0, s.find("symdyn_model_x_"));
  };
  CHECK(unguarded(three.source) == unguarded(one.source));
}

TEST_CASE("emitted dependent parameters are the slider-crank's alpha and x", "[codegen]") {
  using G = symdyn_generated::slider_crank_dependent;
  STATIC_REQUIRE(G::ndep == 2);
  const double q = 0.7, qd = 1.3, qdd = -0.4;
  double p[2], pd[2], pdd[2];
  G::dependent_parameters(0.0, &q, &qd, &qdd, G::param_defaults, p, pd, pdd);
  const double alpha = std::asin(0.1 * std::sin(q) / 0.3);
  CHECK(p[0] == Approx(alpha).epsilon(1e-14));
  CHECK(p[1] == Approx(0.1 * std::cos(q) + 0.3 * std::cos(alpha)).epsilon(1e-14));
  // d alpha/dt = l1 cos(q) qd / (l2 cos(alpha))
  CHECK(pd[0] == Approx(0.1 * std::cos(q) * qd / (0.3 * std::cos(alpha))).epsilon(1e-13));
}

TEST_CASE("generation is deterministic", "[codegen]") {
  for (const auto& d : model::registry()) {
    for (const auto& variant : d.variants) {
      std::string first;
      for (int run = 0; run < 2; ++run) {
        symbolic::Context context;  // fresh nodes, fresh addresses
        symbolic::Context::Scope scope(context);
        const model::Model m = d.make(variant);
        const auto code = codegen::generate(m, variant, "x");
        if (run == 0) first = code.header + code.source;
        INFO(d.name << " " << variant);
        CHECK(code.header + code.source == first);
      }
    }
  }
}

TEST_CASE("an entry point simplification does not shorten is emitted as without simplification",
          "[codegen]") {
  auto generate = [](const model::Definition& d, const std::string& variant, bool simplify) {
    symbolic::Context context;  // fresh nodes: as the generator, one derivation per process
    symbolic::Context::Scope scope(context);
    codegen::Options o = case1();
    o.simplify = simplify;
    return codegen::generate(d.make(variant), variant, "x", o);
  };
  for (const auto& d : model::registry()) {
    for (const auto& variant : d.variants) {
      const auto plain = generate(d, variant, false);
      const auto simplified = generate(d, variant, true);
      REQUIRE(plain.functions.size() == simplified.functions.size());
      for (std::size_t i = 0; i < plain.functions.size(); ++i) {
        const auto& a = plain.functions[i].operations;
        const auto& b = simplified.functions[i].operations;
        INFO(d.name << " " << variant << " " << plain.functions[i].name);
        CHECK(std::pair(b.total(), b.weighted()) <= std::pair(a.total(), a.weighted()));
        if (b.total() == a.total() && b.weighted() == a.weighted()) {
          CHECK(function_text(simplified.source, plain.functions[i].name) ==
                function_text(plain.source, plain.functions[i].name));
        }
      }
    }
  }
}

TEST_CASE("each entry point computes only what it needs", "[codegen]") {
  const model::Model m = model::find_definition("slider_crank").make("dependent");
  const auto code = codegen::generate(m, "dependent", "x");
  for (const auto& f : code.functions) {
    if (f.name == "positions") {
      const auto& positions = f.operations;
      for (const auto& g : code.functions) {
        if (g.name == "velocities") CHECK(positions.total() < g.operations.total());
      }
    }
  }
  // positions() takes no rate: its signature has no qd.
  CHECK_THAT(code.header, Contains("static void positions(double t, const double* q, const double* "
                                   "param, double* R, double* x);"));
}

TEST_CASE("entry points emitted alone compute what the whole model's do", "[codegen]") {
  using Only = symdyn_generated::double_pendulum_relative_only;  // ONLY positions forward_dynamics
  using All = symdyn_generated::double_pendulum_relative;
  STATIC_REQUIRE(Only::has_forward_dynamics);
  STATIC_REQUIRE_FALSE(Only::has_equations_of_motion);
  const double t = 0.0, q[2] = {0.4, -1.1}, qd[2] = {0.7, 2.0}, tau[2] = {0.3, -0.2};
  double R[18], x[6], R_all[18], x_all[6];
  Only::positions(t, q, All::param_defaults, R, x);
  All::positions(t, q, All::param_defaults, R_all, x_all);
  for (int i = 0; i < 18; ++i) CHECK(R[i] == R_all[i]);
  for (int i = 0; i < 6; ++i) CHECK(x[i] == x_all[i]);
  // The articulated-body algorithm's qdd, put back into recursive Newton-Euler, gives tau.
  double qdd[2], tau_back[2];
  REQUIRE(Only::forward_dynamics(t, q, qd, tau, All::param_defaults, qdd) == -1);
  All::inverse_dynamics(t, q, qd, qdd, All::param_defaults, tau_back);
  CHECK(tau_back[0] == Approx(tau[0]).margin(1e-13));
  CHECK(tau_back[1] == Approx(tau[1]).margin(1e-13));
}

TEST_CASE("entry points alone: only those asked for and what they call, an unknown one named",
          "[codegen][bad_input]") {
  const model::Model m = model::find_definition("slider_crank").make("dependent");
  codegen::Options o = case1();
  o.entry_points = {"partial_velocities"};  // numeric: a loop over velocities()
  std::vector<std::string> names;
  for (const auto& f : codegen::generate(m, "dependent", "x", o).functions) names.push_back(f.name);
  CHECK(names == std::vector<std::string>{"velocities", "partial_velocities"});
  o.entry_points = {"positions", "mass_matrix"};
  CHECK_THROWS_WITH(codegen::generate(m, "dependent", "x", o),
                    Contains("entry point 'mass_matrix' is not emitted with these options") &&
                        Contains("positions"));
  o = codegen::Options{};
  o.entry_points = {"relative_accelerations_partials"};
  const auto code = codegen::generate(m, "dependent", "x", o);
  REQUIRE(code.functions.size() == 1);
  CHECK_THAT(code.header, Contains("has_equations_of_motion = false"));
  CHECK_THAT(code.header, Contains("only relative_accelerations_partials"));
}

TEST_CASE("run-time parameters are inputs of the emitted programs", "[codegen]") {
  model::Model m("swing");
  const model::Expr q0 = m.coordinate("q0");
  const model::Expr length = m.parameter("length", 1.0, true);
  m.body("bob")
      .mass(2.0)
      .inertia(0.01, 0.01, 0.01)
      .motion(model::Trotz(q0) * model::Tdisp(length, 0, 0));
  const auto code = codegen::generate(m, "default", "swing");
  CHECK_THAT(code.header, Contains("static constexpr const char* param_names[1] = {\"length\"};"));
  for (const auto& f : code.functions) {
    if (f.name != "positions") continue;
    // inputs: t, q0, length; outputs: R (9), x (3)
    const std::vector<double> out = f.program->evaluate<double>(std::vector<double>{0.0, 0.4, 2.5});
    CHECK(out[9] == Approx(2.5 * std::cos(0.4)).epsilon(1e-15));
    CHECK(out[10] == Approx(2.5 * std::sin(0.4)).epsilon(1e-15));
  }
}

TEST_CASE("the partial velocities are written sparsely, the positions whole", "[codegen]") {
  // A rod turning about z: dv = (-l sin q, l cos q, 0), dw = (0, 0, 1), R[2] = R[5] = 0.
  model::Model m("rod");
  const model::Expr q = m.coordinate("q");
  m.body("rod")
      .mass(1.0)
      .inertia(0.001, 0.08, 0.08)
      .motion(model::Trotz(q) * model::Tdisp(0.5, 0, 0));
  const auto definition = [](const codegen::GeneratedCode& code, const std::string& name) {
    const std::size_t begin = code.source.find(code.struct_name + "::" + name + "(");
    return code.source.substr(begin, code.source.find("\n}\n", begin) - begin);
  };
  const codegen::GeneratedCode symbolic = codegen::generate(m, "v", "rod_v");
  // Their structural zeros are the caller's, and the header says so; R's zeros are written.
  CHECK_THAT(symbolic.header,
             Contains("//   dv (1 x 1 x 3), sparse: only its nonzeros are written, zero it once"));
  const std::string partials = definition(symbolic, "partial_velocities");
  CHECK_THAT(partials, Contains("  dv[1] = ") && Contains("  dw[2] = 1.0;"));
  CHECK_THAT(partials, !Contains("dv[2] = ") && !Contains("dw[0] = ") && !Contains("dw[1] = ") &&
                           !Contains("for ("));
  CHECK_THAT(definition(symbolic, "positions"), Contains("  R[2] = 0.0;"));
  // Numeric partial velocities are a loop over velocities that writes every entry.
  codegen::Options numeric;
  numeric.symbolic_partials = false;
  const codegen::GeneratedCode differenced = codegen::generate(m, "v", "rod_n", numeric);
  CHECK_THAT(differenced.header, Contains("//   dv (1 x 1 x 3)\n"));
  CHECK_THAT(differenced.header, !Contains("sparse"));
}
