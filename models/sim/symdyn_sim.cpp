// symdyn-sim: runs the scenario of a reference model (models.md) on its
// generated code, writes the time history as CSV and prints a summary.
//
//   symdyn-sim <model> [--variant V] [--t-end T] [--integrator I] [--tolerance X]
//              [--rtol R] [--atol A] [--interval DT] [--step H] [--assembled] [--out FILE]
//   symdyn-sim --list
//
// Exit codes: 0 success, 1 the run failed (numeric or model error) or a headline
// number is outside its band, 2 bad command line.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "run.hpp"
#include "runtime/errors.hpp"

namespace {

using namespace symdyn;

struct Arguments {
  std::string model;
  std::string out;
  bool list = false;
  sim::RunOptions run;
};

void list_scenarios() {
  for (const sim::Scenario* s : sim::scenarios()) {
    std::vector<std::string> names;
    for (const auto& v : s->variants) names.push_back(v.name);
    fmt::print("{:<16} variants: {:<22} {:g} s, {}, tolerance {:g}\n{:<16} {}\n", s->model,
               fmt::format("{}", fmt::join(names, ", ")), s->t_end, s->integrator, s->tolerance, "",
               s->description);
  }
}

int simulate(Arguments& args) {
  const sim::Scenario& scenario = sim::find_scenario(args.model);
  const std::string path = args.out.empty() ? scenario.model + ".csv" : args.out;
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  std::ofstream csv(path);
  if (!csv) throw std::runtime_error(fmt::format("cannot write '{}'", path));
  args.run.csv = &csv;
  args.run.progress = true;
  const sim::RunResult r = sim::run_scenario(scenario, args.run);
  csv.close();
  if (!csv) throw std::runtime_error(fmt::format("cannot write '{}'", path));
  fmt::print("{}", sim::summary(r));
  fmt::print("  CSV: {} ({} rows of {} columns: {})\n", path, r.samples.size(), r.columns.size(),
             fmt::join(r.columns, ", "));
  const bool ok = std::all_of(r.headlines.begin(), r.headlines.end(), [](const sim::Headline& h) { return h.ok(); });
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  CLI::App app{"symdyn-sim: simulates a reference model on its generated code (scenarios of models.md)"};
  app.add_option("model", args.model, "model name (see --list)");
  app.add_flag("--list", args.list, "list the models and variants built in, with their scenarios");
  app.add_option("--variant", args.run.variant, "generated variant (default: the model's first)");
  app.add_option("--t-end", args.run.t_end, "end time in s (default: the scenario's)")->check(CLI::PositiveNumber);
  app.add_option("--integrator", args.run.integrator,
                 fmt::format("one of {}", fmt::join(runtime::integrator_names(), ", ")));
  app.add_option("--tolerance", args.run.tolerance, "relative and absolute tolerance")->check(CLI::PositiveNumber);
  app.add_option("--rtol", args.run.rtol, "relative tolerance (over --tolerance)")->check(CLI::PositiveNumber);
  app.add_option("--atol", args.run.atol, "absolute tolerance (over --tolerance)")->check(CLI::PositiveNumber);
  app.add_option("--interval", args.run.output_interval, "output interval in s")->check(CLI::PositiveNumber);
  app.add_option("--step", args.run.step, "initial step in s (rk4: the fixed step)")->check(CLI::PositiveNumber);
  app.add_flag("--assembled", args.run.assembled, "assemble M and h from the kinematics instead of the emitted ones");
  app.add_option("--out", args.out, "CSV file (default: <model>.csv)");
  try {
    app.parse(argc, argv);
    if (!args.list && args.model.empty()) throw CLI::RequiredError("model");
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (args.list) {
      list_scenarios();
      return 0;
    }
    return simulate(args);
  } catch (const runtime::OptionError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
  }
  return 1;
}
