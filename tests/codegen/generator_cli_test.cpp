// The generator's command line as a user meets it: real generator executables
// run with bad arguments; each case checks the exit code (0 success, 1 invalid
// model, 2 bad command line) and the culprit named on stderr.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "codegen/run_command.hpp"

using namespace symdyn::testing;
using Catch::Matchers::Contains;

namespace {

const std::string kChain = SYMDYN_GENERATOR_CHAIN;
const std::string kPendulum = SYMDYN_GENERATOR_DOUBLE_PENDULUM;
const std::string kBad = SYMDYN_GENERATOR_BAD_MODELS;
const std::string kChainModels = "chain_2, chain_4, chain_8, chain_16, chain_32, chain_64";

// Runs the generator with --out in a fresh directory; checks that nothing was
// written unless it succeeded.
CommandResult generator(const std::string& program, std::vector<std::string> args) {
  const auto out = scratch_directory("out");
  args.insert(args.begin(), {program, "--out", (out / "gen").string()});
  const CommandResult r = run_command(args);
  INFO(r.err);
  CHECK((r.exit_code == 0) == std::filesystem::exists(out / "gen"));
  std::filesystem::remove_all(out);
  return r;
}

}  // namespace

TEST_CASE("cli: --list lists every model linked in with its variants", "[bad_input][cli]") {
  const auto r = run_command({kChain, "--list"});
  CHECK(r.exit_code == 0);
  for (const char* n : {"2", "4", "8", "16", "32", "64"}) {
    CHECK_THAT(r.out, Contains(fmt::format("chain_{}: variants relative, absolute\n", n)));
  }
  const auto bad = run_command({kBad, "--list"});
  CHECK(bad.exit_code == 0);
  CHECK_THAT(bad.out, Contains("valid: variants default, inline\nzero_mass: variants default\n"));
}

TEST_CASE("cli: --list --model lists that model only", "[bad_input][cli]") {
  const auto r = run_command({kChain, "--list", "--model", "chain_4"});
  CHECK(r.exit_code == 0);
  CHECK(r.out == "chain_4: variants relative, absolute\n");
}

TEST_CASE("cli: an unknown model is named with the valid choices", "[bad_input][cli]") {
  const auto listed = run_command({kChain, "--list", "--model", "chain_5"});
  CHECK(listed.exit_code == 2);
  CHECK(listed.err ==
        fmt::format("error: --model: no model named 'chain_5' (models: {})\n", kChainModels));
  const auto r = generator(kPendulum, {"--model", "pendulum"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --model: no model named 'pendulum' (models: double_pendulum)\n");
}

TEST_CASE("cli: several models and no --model names them", "[bad_input][cli]") {
  const auto r = generator(kChain, {});
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        fmt::format("error: 6 models are linked in: choose one with --model (models: {})\n",
                    kChainModels));
}

TEST_CASE("cli: an unknown variant is named with the valid choices", "[bad_input][cli]") {
  const auto r = generator(kPendulum, {"--variant", "nope"});
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "error: --variant: model 'double_pendulum' has no variant 'nope' (variants: absolute, "
        "relative)\n");
  const auto chain = generator(kChain, {"--model", "chain_2", "--variant", "inline"});
  CHECK(chain.exit_code == 2);
  CHECK(
      chain.err ==
      "error: --variant: model 'chain_2' has no variant 'inline' (variants: relative, absolute)\n");
}

TEST_CASE("cli: part sizes out of range are refused", "[bad_input][cli]") {
  auto r = generator(kPendulum, {"--part-size", "-5"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --part-size: -5 is out of range (it must be at least 1)\n");
  r = generator(kPendulum, {"--part-size", "0"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --part-size: 0 is out of range (it must be at least 1)\n");
  r = generator(kPendulum, {"--split-above", "-1"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --split-above: -1 is out of range (it must be at least 0)\n");
  r = generator(kPendulum, {"--part-size", "12x"});
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--part-size"));
  CHECK(generator(kPendulum, {"--part-size", "16", "--split-above", "0"}).exit_code == 0);
}

TEST_CASE("cli: --sources writes that many source files; 0 is refused", "[bad_input][cli]") {
  auto r = generator(kPendulum, {"--sources", "0"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --sources: 0 is out of range (it must be at least 1)\n");
  r = generator(kPendulum, {"--sources", "1000000000"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --sources: 1000000000 is out of range (it must be at most 256)\n");
  r = generator(kPendulum, {"--sources", "3", "--source-bytes", "0"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --source-bytes: 0 is out of range (it must be at least 1)\n");
  const auto out = scratch_directory("sources");
  r = run_command({kPendulum, "--out", out.string(), "--basename", "p", "--sources", "3",
                   "--part-size", "16", "--split-above", "0", "--source-bytes", "1"});
  CHECK(r.exit_code == 0);
  for (const char* file : {"p.hpp", "p.cpp", "p.2.cpp", "p.3.cpp"}) {
    INFO(file);
    CHECK(std::filesystem::is_regular_file(out / file));
  }
  CHECK_FALSE(std::filesystem::exists(out / "p.4.cpp"));
  std::ifstream third(out / "p.3.cpp");
  const std::string text((std::istreambuf_iterator<char>(third)), std::istreambuf_iterator<char>());
  CHECK_THAT(text, Contains("[[gnu::noinline]] void part"));
  std::filesystem::remove_all(out);
}

TEST_CASE("cli: a basename that is not an identifier is refused before generation",
          "[bad_input][cli]") {
  auto r = generator(kPendulum, {"--basename", "pend-a"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --basename: 'pend-a' is not a C++ identifier (character '-' at 4)\n");
  r = generator(kPendulum, {"--basename", "struct"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --basename: 'struct' is a C++ keyword\n");
  r = generator(kPendulum, {"--basename", "_Pend"});
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "error: --basename: '_Pend' is reserved to the C++ implementation (starts with '_')\n");
  r = generator(kPendulum, {"--basename", "9lives"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "error: --basename: '9lives' is not a C++ identifier (starts with a digit)\n");
}

TEST_CASE("cli: --out that is a file is refused", "[bad_input][cli]") {
  const auto dir = scratch_directory("file");
  std::ofstream(dir / "file") << "x";
  const auto r = run_command({kPendulum, "--out", (dir / "file").string()});
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        fmt::format("error: --out: '{}' exists and is not a directory\n", (dir / "file").string()));
  const auto empty = run_command({kPendulum, "--out", ""}, 120, dir);
  CHECK(empty.exit_code == 2);
  CHECK(empty.err == "error: --out: the directory name is empty\n");
  std::filesystem::remove_all(dir);
}

TEST_CASE("cli: an --out that cannot be written is refused before the derivation",
          "[bad_input][cli]") {
  const auto dir = scratch_directory("out");
  std::ofstream(dir / "file") << "x";
  auto r = run_command({kPendulum, "--out", (dir / "file" / "gen").string()});
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        fmt::format("error: --out: '{0}/file/gen' cannot be made: '{0}/file' is not a directory\n",
                    dir.string()));
  r = run_command({kPendulum, "--out", "/proc/gen"});
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "error: --out: '/proc/gen' cannot be written: the folder '/proc' is not writable\n");
  // An emitted file that is a directory, or read-only, is not replaced.
  std::filesystem::create_directories(dir / "gen" / "pendulum.hpp");
  r = run_command({kPendulum, "--out", (dir / "gen").string(), "--basename", "pendulum"});
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains(fmt::format("--out: '{}' exists and is not a regular file",
                                         (dir / "gen" / "pendulum.hpp").string())));
  std::ofstream(dir / "gen" / "locked.cpp") << "kept";
  std::filesystem::permissions(dir / "gen" / "locked.cpp", std::filesystem::perms::owner_read);
  r = run_command({kPendulum, "--out", (dir / "gen").string(), "--basename", "locked"});
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("locked.cpp' is read-only: it is not replaced"));
  CHECK(read_text(dir / "gen" / "locked.cpp") == "kept");
  std::filesystem::remove_all(dir);
}

TEST_CASE("cli: malformed options exit with 2", "[bad_input][cli]") {
  auto r = generator(kPendulum, {"--partials", "sometimes"});
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--partials: sometimes not in"));
  r = generator(kPendulum, {"--frobnicate"});
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--frobnicate"));
  r = generator(kPendulum, {"--variant"});
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--variant"));
}

TEST_CASE("cli: --help and a valid run exit with 0", "[bad_input][cli]") {
  CHECK(run_command({kPendulum, "--help"}).exit_code == 0);
  const auto r = generator(kPendulum, {"--basename", "pend_a", "--variant", "relative"});
  CHECK(r.exit_code == 0);
  CHECK(r.err.empty());
}

TEST_CASE("cli: invalid models exit with 1 naming the culprit", "[bad_input][cli]") {
  const auto expect = [](const std::string& model, const std::string& message) {
    const auto r = generator(kBad, {"--model", model});
    CHECK(r.exit_code == 1);
    CHECK(r.err == fmt::format("error: {}\n", message));
  };
  expect("zero_mass", "body 'arm': mass 0 is not positive");
  expect("still_coordinate",
         "coordinate 'q1' moves no body: no body's position or rotation depends on it (its mass "
         "matrix row would be zero)");
  expect("nan_gravity", "gravity y is not finite (nan)");
  expect(
      "mass_of_q",
      "body 'arm': mass depends on coordinate 'q0'; a mass or inertia may use only constants and "
      "run-time parameters");
  expect("constant_asin",
         "model 'constant_asin' variant 'default': asin(2) is outside the function's real domain");
  expect("dependent_domain",
         "dependent parameter 'alpha': asin(2.5) is not defined at the initial configuration "
         "(t = 0, coordinates at their initial values)");
  expect("bad_variant", "variant 'two words' is not a C++ identifier (character ' ' at 3)");
  CHECK(generator(kBad, {"--model", "valid", "--variant", "inline"}).exit_code == 0);
}

TEST_CASE("cli: --only emits those entry points; one not emitted is named with those that are",
          "[bad_input][cli]") {
  CHECK(generator(kPendulum, {"--only", "positions,velocities"}).exit_code == 0);
  const auto r = generator(kPendulum, {"--no-eom", "--only", "positions,inverse_dynamics"});
  CHECK(r.exit_code == 1);
  CHECK_THAT(
      r.err,
      Contains(
          "entry point 'inverse_dynamics' is not emitted with these options (emitted: inertia, "
          "positions, velocities,"));
}

TEST_CASE("cli: --describe prints the model as JSON and generates nothing", "[cli]") {
  const auto out = scratch_directory("describe");
  const auto r = run_command(
      {kPendulum, "--describe", "--variant", "relative", "--out", (out / "gen").string()});
  CHECK_FALSE(std::filesystem::exists(out / "gen"));
  CHECK(r.exit_code == 0);
  CHECK(r.err.empty());
  CHECK_THAT(r.out, Contains(R"("model": "double_pendulum",)"));
  CHECK_THAT(r.out,
             Contains(R"("coordinates": [{"q": "theta1", "qd": "theta1_d", "qdd": "theta1_dd"}, )"
                      R"({"q": "theta2", "qd": "theta2_d", "qdd": "theta2_dd"}],)"));
  CHECK_THAT(r.out, Contains(R"("gravity": ["0", "-9.81", "0"],)"));
  CHECK_THAT(
      r.out,
      Contains(
          R"({"name": "rod1", "reference": null, "motion": [{"rotation": ["0", "0", "1"], "angle": "theta1"}, )"
          R"({"translation": ["1/2", "0", "0"]}]})"));
  CHECK_THAT(
      r.out,
      Contains(
          R"({"name": "rod2", "reference": "rod1", "motion": [{"translation": ["1/2", "0", "0"]}, )"
          R"({"rotation": ["0", "0", "1"], "angle": "theta2"}, {"translation": ["1/2", "0", "0"]}]})"));
  // The same choices as a generation: several models need --model.
  CHECK(run_command({kChain, "--describe"}).exit_code == 2);
  CHECK_THAT(run_command({kChain, "--describe", "--model", "chain_2"}).out,
             Contains(R"("model": "chain_2",)"));
  std::filesystem::remove_all(out);
}
