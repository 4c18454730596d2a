// The generators' command line under random and mutated argument lists: the
// exit code is 0, 1 or 2, never a signal (128 + n), a sanitizer report (86) or
// the time limit (124). Each run happens in a fresh directory, where whatever
// --out it was given is written.
#include <fmt/format.h>
#include <rapidcheck/catch.h>

#include <filesystem>

#include "codegen/run_command.hpp"

using namespace symdyn::testing;

namespace {

const std::vector<std::string> kGenerators = {SYMDYN_GENERATOR_DOUBLE_PENDULUM,
                                              SYMDYN_GENERATOR_CHAIN, SYMDYN_GENERATOR_BAD_MODELS};

// The seeds of the mutations: command lines that succeed, and one that names an invalid model.
const std::vector<std::vector<std::string>> kSeeds = {
    {"--out", "gen", "--model", "zero_mass"},
    {"--out", "gen", "--variant", "relative"},
    {"--out", "gen", "--model", "chain_2", "--variant", "absolute", "--stats"},
    {"--list"},
    {"--out", "gen", "--model", "valid", "--basename", "pend_a", "--part-size", "8",
     "--split-above", "0"},
    {"--out", "gen", "--no-simplify", "--partials", "numeric", "--no-eom"},
};

const std::vector<std::string> kTokens = {
    "--out",
    "--variant",
    "--basename",
    "--model",
    "--no-simplify",
    "--partials",
    "--no-eom",
    "--part-size",
    "--split-above",
    "--list",
    "--stats",
    "--help",
    "-h",
    "--",
    "-",
    "--out=",
    "--part-size=-1",
    "--model=chain_4",
    "absolute",
    "relative",
    "chain_2",
    "chain_4",
    "chain_99",
    "valid",
    "zero_mass",
    "still_coordinate",
    "bad_variant",
    "-1",
    "0",
    "1",
    "16",
    "99999999999999999999",
    "-99999999999999999999",
    "1e3",
    "abc",
    "",
    "pend-a",
    "class",
    "numeric",
    "symbolic",
    "x y",
    "gen",
    "gen/sub",
    "/dev/null",
    "\xff\xfe",
    "--variant=",
};

// No '/' nor '.' in a random token: a random --out stays inside the run's directory.
std::string token() {
  static const std::string kCharacters = "abcdefghijklmnopqrstuvwxyz0123456789-_=";
  if (*rc::gen::inRange(0, 6) == 0)
    return *rc::gen::container<std::string>(rc::gen::elementOf(kCharacters));
  return *rc::gen::elementOf(kTokens);
}

// A seed with up to two tokens dropped, inserted or replaced,
// or a list of random tokens.
std::vector<std::string> arguments() {
  if (*rc::gen::arbitrary<bool>()) {
    std::vector<std::string> args;
    const int n = *rc::gen::inRange(0, 7);
    for (int i = 0; i < n; ++i) args.push_back(token());
    return args;
  }
  std::vector<std::string> args = *rc::gen::elementOf(kSeeds);
  const int mutations = *rc::gen::inRange(0, 3);
  for (int m = 0; m < mutations; ++m) {
    const auto at = static_cast<std::ptrdiff_t>(*rc::gen::inRange<std::size_t>(0, args.size() + 1));
    switch (*rc::gen::inRange(0, 3)) {
      case 0:
        if (at < static_cast<std::ptrdiff_t>(args.size())) args.erase(args.begin() + at);
        break;
      case 1:
        args.insert(args.begin() + at, token());
        break;
      default:
        if (at < static_cast<std::ptrdiff_t>(args.size()))
          args[static_cast<std::size_t>(at)] = token();
    }
  }
  return args;
}

}  // namespace

TEST_CASE("random command lines exit with 0, 1 or 2 and never crash or hang", "[fuzz][cli]") {
  rc::prop("generator command line", [] {
    std::vector<std::string> argv = arguments();
    argv.insert(argv.begin(), *rc::gen::elementOf(kGenerators));
    const auto dir = scratch_directory("cli_fuzz");
    const CommandResult r = run_command(argv, 60, dir);
    std::filesystem::remove_all(dir);
    RC_LOG() << "exit " << r.exit_code << "\nstderr: " << r.err;
    RC_TAG(fmt::format("exit {}", r.exit_code));
    RC_ASSERT(r.exit_code >= 0);
    RC_ASSERT(r.exit_code <= 2);
    if (r.exit_code != 0) RC_ASSERT(!r.err.empty());
  });
}
