// symdyn_paper_tgen: Tgen of the paper tables, the generation of one model,
// variant and case in process, timed in CPU time of the thread (on a machine
// shared with other jobs, wall time counts the time spent descheduled):
//
//   symdyn_paper_tgen --model NAME --variant V --case 1..4 [--runs 5]
//
// One run is what the generator executable does between reading its command
// line and writing its files: build the model, derive, simplify, schedule and
// print the code (codegen::generate). Prints JSON: the median and every run,
// in CPU and in wall seconds.
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

}  // namespace

int main(int argc, char** argv) {
  std::string model, variant;
  int case_number = 0, runs = 5;
  CLI::App app{"symdyn_paper_tgen: in-process generation time of one model, variant and case"};
  app.add_option("--model", model, "model name (its definition is linked in)")->required();
  app.add_option("--variant", variant, "model variant")->required();
  app.add_option("--case", case_number, "case 1-4")->required()->check(CLI::Range(1, 4));
  app.add_option("--runs", runs, "generations (median)")->capture_default_str()->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    const model::Definition& definition = model::find_definition(model);
    const std::string basename = model + "_" + variant;
    std::vector<double> cpu, wall;
    std::size_t bytes = 0;
    for (int r = 0; r < runs; ++r) {
      const double c0 = thread_seconds();
      const auto w0 = std::chrono::steady_clock::now();
      const model::Model m = definition.make(variant);
      const codegen::GeneratedCode code = codegen::generate(m, variant, basename, case_options(case_number));
      wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
      cpu.push_back(thread_seconds() - c0);
      bytes = code.header.size() + code.source.size();
    }
    nlohmann::json out{{"cpu", median(cpu)}, {"wall", median(wall)}, {"cpu_runs", cpu}, {"wall_runs", wall},
                       {"bytes", bytes}};
    std::cout << out.dump() << '\n';
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "symdyn_paper_tgen: " << e.what() << '\n';
    return 1;
  }
}
