// symdyn-sim: runs the scenario of a reference model (models.md) on its
// generated code, writes the time history as CSV and prints a summary.
//
//   symdyn-sim <model> [--variant V] [--t-end T] [--integrator I] [--tolerance X] [--max-rows N]
//              [--rtol R] [--atol A] [--interval DT] [--step H] [--assembled] [--out FILE]
//   symdyn-sim --list
//
// Every argument is checked before a file is touched (an unknown variant or
// integrator, a run that would write over --max-rows rows, default 1e7). Rows
// are written as they come to FILE.partial, renamed to FILE when the run ends;
// a run that fails after its first row keeps its rows in FILE and says up to
// which time.
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
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>

namespace {

using namespace symdyn;

struct Arguments {
  std::string model;
  std::string out;
  double max_rows = 1e7;  // about 1 GB of CSV
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

// What the run would refuse (an unknown variant or integrator) is refused
// before any file is touched: a typo never empties the previous results.
void check_arguments(const sim::Scenario& scenario, const sim::RunOptions& run, double max_rows) {
  if (!run.variant.empty()) scenario.variant(run.variant);
  runtime::make_integrator(run.integrator.empty() ? scenario.integrator : run.integrator);
  const double rows = run.t_end.value_or(scenario.t_end) / run.output_interval.value_or(scenario.output_interval);
  if (rows > max_rows) {
    throw runtime::OptionError(fmt::format(
        "the run would write {:.3g} rows (t-end / interval), over --max-rows {:.3g}: raise --interval, or --max-rows "
        "to allow it",
        rows, max_rows));
  }
}

int simulate(Arguments& args) {
  const sim::Scenario& scenario = sim::find_scenario(args.model);
  check_arguments(scenario, args.run, args.max_rows);
  const std::filesystem::path path = args.out.empty() ? scenario.model + ".csv" : args.out;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  // Rows go to <file>.partial as they come, renamed to <file> when the run ends.
  std::filesystem::path partial = path;
  partial += ".partial";
  std::ofstream csv(partial);
  if (!csv) throw std::runtime_error(fmt::format("cannot write '{}'", partial.string()));
  args.run.csv = &csv;
  args.run.progress = true;
  long rows = 0;
  double last_t = 0.0;
  args.run.on_sample = [&](const sim::Sample& s) {
    ++rows;
    last_t = s.state.t;
  };
  const auto keep = [&] {
    csv.close();
    std::filesystem::rename(partial, path);
  };
  sim::RunResult r;
  try {
    r = sim::run_scenario(scenario, args.run);
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
  fmt::print("  CSV: {} ({} rows of {} columns: {})\n", path.string(), r.samples.size(), r.columns.size(),
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
  app.add_option("--max-rows", args.max_rows, "refuse a run that would write more CSV rows (default 1e7)")
      ->check(CLI::PositiveNumber);
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
