// Bad input to codegen::generate (names the emitted code declares) and the
// link-time guard against two models of one struct name in a program.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "codegen/run_command.hpp"
#include <symdyn/codegen/generate.hpp>

using namespace symdyn;
using Catch::Matchers::Contains;

namespace {

model::Model pendulum(double length) {
  model::Model m("pendulum");
  const model::Expr q0 = m.coordinate("q0");
  m.body("rod")
      .mass(1.0)
      .inertia(0.001, 0.08, 0.08)
      .motion(model::Trotz(q0) * model::Tdisp(length / 2, 0, 0));
  m.gravity(0, -9.81, 0);
  return m;
}

codegen::Options in_namespace(std::string name_space) {
  codegen::Options o;
  o.name_space = std::move(name_space);
  return o;
}

std::string generate_error(std::string_view variant, std::string_view basename,
                           const codegen::Options& o = {}) {
  try {
    codegen::generate(pendulum(1.0), variant, basename, o);
  } catch (const model::ModelError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("generate: a basename the struct cannot be named is refused", "[bad_input]") {
  CHECK(generate_error("v", "pend-a") ==
        "basename 'pend-a' is not a C++ identifier (character '-' at 4)");
  CHECK(generate_error("v", "class") == "basename 'class' is a C++ keyword");
  CHECK(generate_error("v", "and_eq") == "basename 'and_eq' is a C++ keyword");
  CHECK(generate_error("v", "2pend") ==
        "basename '2pend' is not a C++ identifier (starts with a digit)");
  CHECK(generate_error("v", "pend__a") ==
        "basename 'pend__a' is reserved to the C++ implementation (contains '__')");
  CHECK(generate_error("v", "_Pend") ==
        "basename '_Pend' is reserved to the C++ implementation (starts with '_')");
  CHECK(generate_error("v", "") == "basename '' is empty");
  CHECK(generate_error("v", "pend\xc3\xa9") ==
        "basename 'pend\xc3\xa9' is not a C++ identifier (character '\xc3' at 4)");
}

TEST_CASE("generate: a namespace that cannot be declared is refused", "[bad_input]") {
  CHECK(generate_error("v", "pend", in_namespace("")) ==
        "namespace is empty (the code would be in an anonymous namespace)");
  CHECK(generate_error("v", "pend", in_namespace("my-ns")) ==
        "namespace 'my-ns': 'my-ns' is not a C++ identifier (character '-' at 2)");
  CHECK(generate_error("v", "pend", in_namespace("sim::int")) ==
        "namespace 'sim::int': 'int' is a C++ keyword");
  CHECK(generate_error("v", "pend", in_namespace("sim::")) == "namespace 'sim::': '' is empty");
  CHECK(generate_error("v", "pend", in_namespace("__sim")) ==
        "namespace '__sim': '__sim' is reserved to the C++ implementation (contains '__')");
  CHECK_NOTHROW(codegen::generate(pendulum(1.0), "v", "pend", in_namespace("sim::generated")));
}

TEST_CASE("generate: a number of source files out of range is refused", "[bad_input]") {
  codegen::Options o;
  o.sources = 0;
  CHECK(generate_error("v", "pend", o) == "sources is 0 (it must be 1 to 256)");
  o.sources = 257;
  CHECK(generate_error("v", "pend", o) == "sources is 257 (it must be 1 to 256)");
  o.sources = 256;
  o.source_bytes = 0;
  CHECK(generate_error("v", "pend", o) == "source_bytes is 0 (it must be at least 1)");
  o.source_bytes = 1;
  CHECK(codegen::generate(pendulum(1.0), "v", "pend", o).more_sources.size() == 255);
}

TEST_CASE("generate: a variant printed in the code must have an identifier's shape",
          "[bad_input]") {
  CHECK(generate_error("two words", "pend") ==
        "variant 'two words' is not a C++ identifier (character ' ' at 3)");
  CHECK(generate_error("a\"b", "pend") ==
        "variant 'a\"b' is not a C++ identifier (character '\"' at 1)");
  // Only ever inside a string literal: a keyword is harmless (slider_crank's "inline").
  CHECK_NOTHROW(codegen::generate(pendulum(1.0), "inline", "pend"));
}

TEST_CASE("generate: the names are checked before the model", "[bad_input]") {
  model::Model invalid("invalid");
  invalid.coordinate("q0");
  CHECK_THROWS_WITH(codegen::generate(invalid, "v", "bad-name"), Contains("basename 'bad-name'"));
  CHECK_THROWS_WITH(codegen::generate(invalid, "v", "good"), "model 'invalid' has no body");
}

TEST_CASE("generate: the link guard is deterministic and differs between models", "[bad_input]") {
  const auto a = codegen::generate(pendulum(1.0), "v", "pend_a");
  const auto again = codegen::generate(pendulum(1.0), "v", "pend_a");
  const auto b = codegen::generate(pendulum(2.0), "v", "pend_a");
  CHECK(a.header == again.header);
  CHECK(a.source == again.source);
  CHECK_THAT(a.source,
             Contains("const char symdyn_model_pend_a[] = \"model 'pendulum', variant 'v'\";"));
  CHECK_THAT(b.source,
             Contains("const char symdyn_model_pend_a[] = \"model 'pendulum', variant 'v'\";"));
  const auto guard = [](const std::string& header) {
    const auto at = header.find("extern const char symdyn_model_pend_a_");
    return header.substr(at, header.find('\n', at) - at);
  };
  CHECK(guard(a.header) != guard(b.header));
}

namespace {

// Compiles and links with the compiler CMake uses; returns what the linker said.
struct Toolchain {
  std::filesystem::path dir = testing::scratch_directory("link");

  void write(const std::string& name, const std::string& text) const {
    std::filesystem::create_directories((dir / name).parent_path());
    std::ofstream(dir / name, std::ios::binary) << text;
  }
  // A static library of the emitted sources, as symdyn_add_model makes it.
  void library(const std::string& sub, const codegen::GeneratedCode& code) const {
    write(fmt::format("{}/{}.hpp", sub, code.struct_name), code.header);
    std::vector<std::string> archive{SYMDYN_TEST_AR, "qc", (dir / sub / "libmodel.a").string()};
    for (std::size_t f = 0; f <= code.more_sources.size(); ++f) {
      const std::string name =
          f == 0 ? code.struct_name : fmt::format("{}.{}", code.struct_name, f + 1);
      write(fmt::format("{}/{}.cpp", sub, name), f == 0 ? code.source : code.more_sources[f - 1]);
      compile(fmt::format("{}/{}.cpp", sub, name), sub, fmt::format("{}/{}.o", sub, name));
      archive.push_back((dir / sub / fmt::format("{}.o", name)).string());
    }
    REQUIRE(testing::run_command(archive).exit_code == 0);
  }
  void compile(const std::string& source, const std::string& include,
               const std::string& object) const {
    const auto r = testing::run_command(
        {SYMDYN_TEST_CXX, "-std=c++20", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-I",
         (dir / include).string(), "-c", (dir / source).string(), "-o", (dir / object).string()});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  testing::CommandResult link(const std::vector<std::string>& objects_and_libraries) const {
    std::vector<std::string> argv{SYMDYN_TEST_CXX, "-o", (dir / "program").string()};
    for (const auto& f : objects_and_libraries) argv.push_back((dir / f).string());
    return testing::run_command(argv);
  }
};

// A file of the program using the model of the struct in `sub`.
std::string user(const std::string& function) {
  return fmt::format(
      "#include \"pend_a.hpp\"\n"
      "void {}(double* m, double* I) {{ symdyn_generated::pend_a::inertia(nullptr, m, I); }}\n",
      function);
}

}  // namespace

TEST_CASE("two different models of one struct name in one program fail to link, naming it",
          "[bad_input][link]") {
  const Toolchain tc;
  tc.library("a", codegen::generate(pendulum(1.0), "v", "pend_a"));
  tc.library("b", codegen::generate(pendulum(2.0), "v", "pend_a"));
  tc.write("use_a.cpp", user("use_a"));
  tc.write("use_b.cpp", user("use_b"));
  tc.write("main.cpp",
           "void use_a(double*, double*);\nvoid use_b(double*, double*);\n"
           "int main() { double m[1], I[9]; use_a(m, I); use_b(m, I); }\n");
  tc.write("main_a.cpp",
           "void use_a(double*, double*);\nint main() { double m[1], I[9]; use_a(m, I); }\n");
  tc.compile("use_a.cpp", "a", "use_a.o");
  tc.compile("use_b.cpp", "b", "use_b.o");
  tc.compile("main.cpp", ".", "main.o");
  tc.compile("main_a.cpp", ".", "main_a.o");
  // One model alone links: the guard refuses only the collision.
  CHECK(tc.link({"main_a.o", "use_a.o", "a/libmodel.a"}).exit_code == 0);
  // Without the guard the linker would take pend_a from the first library only, silently.
  const auto both = tc.link({"main.o", "use_a.o", "use_b.o", "a/libmodel.a", "b/libmodel.a"});
  CHECK(both.exit_code != 0);
  CHECK_THAT(both.err, Contains("multiple definition of `symdyn_generated::symdyn_model_pend_a'"));
  std::filesystem::remove_all(tc.dir);
}

TEST_CASE("a model spread over three source files links and computes what one file computes",
          "[bad_input][link]") {
  const Toolchain tc;
  const model::Model m = model::find_definition("slider_crank").make("dependent");
  codegen::Options options;
  options.part_instructions = 16;  // parts to spread: slider_crank is short
  options.split_above = 0;
  tc.library("one", codegen::generate(m, "dependent", "crank_one", options));
  options.sources = 3;
  options.source_bytes = 1;
  tc.library("three", codegen::generate(m, "dependent", "crank_three", options));
  tc.write("main.cpp", R"(#include "one/crank_one.hpp"
#include "three/crank_three.hpp"
using One = symdyn_generated::crank_one;
using Three = symdyn_generated::crank_three;
int main() {
  constexpr int n = One::nq;
  double q[n], qd[n], qdd[n], M[2][n * n], h[2][n], tau[2][n];
  for (int i = 0; i < n; ++i) q[i] = 0.3 + 0.2 * i, qd[i] = 0.7 - 0.1 * i, qdd[i] = 1.1;
  One::dynamics(0.0, q, qd, One::param_defaults, M[0], h[0]);
  Three::dynamics(0.0, q, qd, Three::param_defaults, M[1], h[1]);
  One::inverse_dynamics(0.0, q, qd, qdd, One::param_defaults, tau[0]);
  Three::inverse_dynamics(0.0, q, qd, qdd, Three::param_defaults, tau[1]);
  int differ = 0;
  for (int i = 0; i < n * n; ++i) differ += M[0][i] != M[1][i];
  for (int i = 0; i < n; ++i) differ += (h[0][i] != h[1][i]) + (tau[0][i] != tau[1][i]);
  return differ;
}
)");
  tc.compile("main.cpp", ".", "main.o");
  REQUIRE(tc.link({"main.o", "one/libmodel.a", "three/libmodel.a"}).exit_code == 0);
  CHECK(testing::run_command({(tc.dir / "program").string()}).exit_code == 0);
  std::filesystem::remove_all(tc.dir);
}
