// symdyn_paper_tgen: Tgen of the paper tables, the generation of one model,
// variant and case in process, timed in CPU time of the thread (on a machine
// shared with other jobs, wall time counts the time spent descheduled):
//
//   symdyn_paper_tgen --model NAME --variant V --case 1..4 [--runs 5]
//
// One run is what the generator executable does between reading its command
// line and writing its files: build the model, derive, simplify, schedule and
// print the code (codegen::generate). In cases 1-3 each run also generates
// CAGeM's scope alone (Options::entry_points), what cagem_sympy.py and
// cagem_giac.py derive: every body relative to the reference the model file
// gives it (relative_accelerations, fused with the partial velocities in
// case 3), or, when every body moves from the ground and the generator made
// some relative, the absolute accelerations. Prints JSON: the medians and
// every run, in CPU and in wall seconds, and the scope's operations (a fused
// sin/cos pair once) and sin/cos pairs.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <ctime>
#include <iostream>
#include <nlohmann/json.hpp>

#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn;

double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The options of the paper's cases (docs/design.md) and of case 4.
codegen::Options case_options(int c) {
  codegen::Options o;
  o.simplify = c >= 2;
  o.symbolic_partials = c >= 3;
  o.equations_of_motion = c == 4;
  return o;
}

struct Timing {
  std::vector<double> cpu, wall;
  std::size_t bytes = 0, operations = 0, sincos = 0;  // of the last generation's entry points
  nlohmann::json json() const {
    return {{"cpu", median(cpu)},
            {"wall", median(wall)},
            {"cpu_runs", cpu},
            {"wall_runs", wall},
            {"bytes", bytes}};
  }
};

// One generation, timed into `timing`.
void generate_timed(const model::Definition& definition, const std::string& variant,
                    const codegen::Options& options, Timing& timing) {
  const double c0 = thread_seconds();
  const auto w0 = std::chrono::steady_clock::now();
  const model::Model m = definition.make(variant);
  const codegen::GeneratedCode code =
      codegen::generate(m, variant, definition.name + "_" + variant, options);
  timing.wall.push_back(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
  timing.cpu.push_back(thread_seconds() - c0);
  timing.bytes = code.header.size() + code.source.size();
  timing.operations = timing.sincos = 0;
  for (const codegen::EmittedFunction& f : code.functions) {
    timing.operations += static_cast<std::size_t>(f.operations.total());
    timing.sincos += static_cast<std::size_t>(f.operations.sincos);
  }
}

// The entry points of CAGeM's scope (as report.py's cagem_scope), or none.
std::vector<std::string> cagem_scope(const model::Definition& definition,
                                     const std::string& variant, int case_number) {
  if (case_number > 3) return {};
  const model::Model m = definition.make(variant);
  const std::vector<int> written = m.reference_indices();
  std::string kinematics;
  if (m.with_shared_motions_relative().reference_indices() == written) {
    kinematics = "relative_accelerations";
  } else if (std::all_of(written.begin(), written.end(), [](int r) { return r < 0; })) {
    kinematics = "accelerations";
  } else {
    return {};
  }
  return {case_number == 3 ? kinematics + "_partials" : kinematics};
}

}  // namespace

int main(int argc, char** argv) {
  std::string model, variant;
  int case_number = 0, runs = 5;
  CLI::App app{"symdyn_paper_tgen: in-process generation time of one model, variant and case"};
  app.add_option("--model", model, "model name (its definition is linked in)")->required();
  app.add_option("--variant", variant, "model variant")->required();
  app.add_option("--case", case_number, "case 1-4")->required()->check(CLI::Range(1, 4));
  app.add_option("--runs", runs, "generations (median)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    const model::Definition& definition = model::find_definition(model);
    codegen::Options scope_options = case_options(case_number);
    scope_options.entry_points = cagem_scope(definition, variant, case_number);
    Timing all, scope;
    for (int r = 0; r < runs; ++r) {
      generate_timed(definition, variant, case_options(case_number), all);
      if (!scope_options.entry_points.empty())
        generate_timed(definition, variant, scope_options, scope);
    }
    nlohmann::json out = all.json();
    if (!scope_options.entry_points.empty()) {
      out["cagem_scope"] = scope.json();
      out["cagem_scope"]["entry_points"] = scope_options.entry_points;
      out["cagem_scope"]["operations"] = scope.operations;
      out["cagem_scope"]["sincos"] = scope.sincos;
    }
    std::cout << out.dump() << '\n';
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "symdyn_paper_tgen: " << e.what() << '\n';
    return 1;
  }
}
