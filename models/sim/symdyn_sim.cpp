// symdyn-sim: runs a scenario (docs/scenarios.md) on generated code, writes
// the time history as CSV and prints a summary with the scenario's checks.
//
//   symdyn-sim <scenario.json | model> [--variant V] [--t-end T] [--integrator I] [--tolerance X]
//              [--rtol R] [--atol A] [--interval DT] [--step H] [--assembled] [--out FILE] [--max-rows N]
//   symdyn-sim --list
//
// A scenario file names its model: built in, or a model module (a shared
// library from symdyn_add_model(... SIM_MODULE)) next to it. A bare model name
// runs the built-in scenario of a reference model (models/scenarios).
//
// Every argument and every name of the scenario is checked before a file is
// touched (an unknown variant, integrator, body or coordinate; a run that
// would write over --max-rows rows, default 1e7). Rows are written as they
// come to FILE.partial, renamed to FILE when the run ends; a run that fails
// after its first row keeps its rows in FILE and says up to which time.
//
// Exit codes: 0 success, 1 the run failed (numeric or model error) or a check
// is outside its band, 2 bad command line or scenario.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "run.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>

namespace {

using namespace symdyn;

struct Arguments {
  std::string scenario;
  std::string out;
  double max_rows = 1e7;  // about 1 GB of CSV
  bool list = false;
  sim::RunOptions run;
};

void list_scenarios() {
  for (const sim::Scenario& s : sim::builtin_scenarios()) {
    std::vector<std::string> names;
    for (const auto& m : sim::builtin_models()) {
      if (m.model == s.model) names.push_back(m.variant);
    }
    fmt::print("{:<16} variants: {:<22} {:g} s, {}, tolerance {:g}\n{:<16} {}\n", s.name,
               fmt::format("{}", fmt::join(names, ", ")), s.t_end, s.integrator, s.rtol, "", s.description);
  }
}

bool is_file(const std::string& argument) {
  return argument.ends_with(".json") || argument.find('/') != std::string::npos;
}

// What the run would refuse is refused before any file is touched: a typo
// never empties the previous results.
void check_rows(const sim::Simulation& simulation, double max_rows) {
  const double rows = simulation.expected_rows();
  if (rows > max_rows) {
    throw runtime::OptionError(fmt::format(
        "the run would write {:.3g} rows (t-end / interval), over --max-rows {:.3g}: raise --interval, or --max-rows "
        "to allow it",
        rows, max_rows));
  }
}

int simulate(Arguments& args) {
  const sim::Scenario scenario =
      is_file(args.scenario) ? sim::load_scenario(args.scenario) : sim::find_builtin(args.scenario);
  // Rows go to <file>.partial as they come, renamed to <file> when the run ends.
  const std::filesystem::path path = args.out.empty() ? scenario.name + ".csv" : args.out;
  std::filesystem::path partial = path;
  partial += ".partial";
  std::ofstream csv;
  args.run.csv = &csv;
  args.run.progress = true;
  long rows = 0;
  double last_t = 0.0;
  args.run.on_sample = [&](const runtime::State& s, const runtime::Vector&) {
    ++rows;
    last_t = s.t;
  };
  sim::Simulation simulation(scenario, args.run);
  check_rows(simulation, args.max_rows);
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  csv.open(partial);
  if (!csv) throw std::runtime_error(fmt::format("cannot write '{}'", partial.string()));
  const auto keep = [&] {
    csv.close();
    std::filesystem::rename(partial, path);
  };
  sim::RunResult r;
  try {
    r = simulation.run();
  } catch (const std::exception& e) {
    if (rows == 0) {  // refused before its first row (an option the integrator checks): the old file stays
      csv.close();
      std::filesystem::remove(partial);
      throw;
    }
    keep();
    std::cerr << "error: " << e.what() << '\n';
    std::cerr << fmt::format("  the run stopped; CSV: {} keeps its {} rows up to t = {}\n", path.string(), rows, last_t);
    return 1;
  }
  if (!csv) throw std::runtime_error(fmt::format("cannot write '{}'", partial.string()));
  keep();
  fmt::print("{}", sim::summary(r));
  fmt::print("  CSV: {} ({} rows of {} columns: {})\n", path.string(), r.rows, r.columns.size(),
             fmt::join(r.columns, ", "));
  const bool ok = std::all_of(r.checks.begin(), r.checks.end(), [](const sim::Check& c) { return c.ok(); });
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  CLI::App app{"symdyn-sim: runs a scenario (a JSON file, or a reference model's name) on generated code"};
  app.add_option("scenario", args.scenario, "scenario file (*.json) or built-in model name (see --list)");
  app.add_flag("--list", args.list, "list the built-in scenarios and their models' variants");
  app.add_option("--variant", args.run.variant, "generated variant (default: the scenario's, else the model's first)");
  app.add_option("--t-end", args.run.t_end, "end time in s (default: the scenario's)")->check(CLI::PositiveNumber);
  app.add_option("--integrator", args.run.integrator,
                 fmt::format("one of {}", fmt::join(runtime::integrator_names(), ", ")));
  app.add_option("--tolerance", args.run.tolerance, "relative and absolute tolerance")->check(CLI::PositiveNumber);
  app.add_option("--rtol", args.run.rtol, "relative tolerance (over --tolerance)")->check(CLI::PositiveNumber);
  app.add_option("--atol", args.run.atol, "absolute tolerance (over --tolerance)")->check(CLI::PositiveNumber);
  app.add_option("--interval", args.run.output_interval, "output interval in s")->check(CLI::PositiveNumber);
  app.add_option("--step", args.run.step, "initial step in s (rk4: the fixed step)")->check(CLI::PositiveNumber);
  app.add_flag("--assembled", args.run.assembled, "assemble M and h from the kinematics instead of the emitted ones");
  app.add_option("--out", args.out, "CSV file (default: <scenario>.csv)");
  app.add_option("--max-rows", args.max_rows, "refuse a run that would write more CSV rows (default 1e7)")
      ->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
    if (!args.list && args.scenario.empty()) throw CLI::RequiredError("scenario");
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
