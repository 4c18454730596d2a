// The whole generation of every registered model (models/*.cpp are linked in),
// every variant, in the four cases of the paper: derive, simplify, schedule,
// emit, in a fresh symbolic::Context per iteration. See bench/README.md.
//
// --dump=DIR (ours) writes the emitted files of every model, variant and case
// (those whose benchmark name matches --benchmark_filter, if given) to
// DIR/<model>_<variant>_case<k>.{hpp,cpp} instead of timing: diff two dumps to
// check that a change of the engine left the output byte for byte as it was.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/codegen/generate.hpp>

namespace {

using namespace symdyn;

// The paper's cases (its Tables 1-7).
struct Case {
  int number;
  const char* what;
  codegen::Options options;
};

codegen::Options options(bool simplify, bool symbolic_partials, bool equations_of_motion) {
  codegen::Options o;
  o.simplify = simplify;
  o.symbolic_partials = symbolic_partials;
  o.equations_of_motion = equations_of_motion;
  return o;
}

const std::array<Case, 4> kCases = {{
    {1, "no simplification, numeric partials", options(false, false, false)},
    {2, "simplification, numeric partials", options(true, false, false)},
    {3, "simplification, symbolic partials", options(true, true, false)},
    {4, "simplification, symbolic partials, equations of motion", options(true, true, true)},
}};

// One generation from the model's definition, in the current context.
codegen::GeneratedCode generate(const model::Definition& definition, const std::string& variant,
                                const Case& c) {
  const model::Model m = definition.make(variant);
  return codegen::generate(
      m, variant, fmt::format("{}_{}_case{}", definition.name, variant, c.number), c.options);
}

void BM_generate(benchmark::State& state, const model::Definition* definition, std::string variant,
                 Case c) {
  for (auto _ : state) {
    symbolic::Context context;  // a fresh one per iteration: nothing is reused
    symbolic::Context::Scope scope(context);
    const codegen::GeneratedCode code = generate(*definition, variant, c);
    benchmark::DoNotOptimize(code.source.data());
  }
  // Sizes from one more run, outside the timed loop.
  symbolic::Context context;
  symbolic::Context::Scope scope(context);
  const codegen::GeneratedCode code = generate(*definition, variant, c);
  int operations = 0;
  for (const auto& f : code.functions) operations += f.operations.total();
  state.counters["bytes"] = static_cast<double>(code.header.size() + code.source.size());
  state.counters["operations"] = operations;
  state.counters["context_nodes"] = static_cast<double>(context.size());
}

std::string benchmark_name(const model::Definition& definition, const std::string& variant,
                           const Case& c) {
  return fmt::format("generate/{}/{}/case{}", definition.name, variant, c.number);
}

void register_all() {
  for (const model::Definition& definition : model::registry()) {
    for (const std::string& variant : definition.variants) {
      for (const Case& c : kCases) {
        benchmark::RegisterBenchmark(benchmark_name(definition, variant, c).c_str(), BM_generate,
                                     &definition, variant, c)
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
}

void write(const std::filesystem::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary);
  out << content;
  if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", path.string()));
}

void dump_all(const std::filesystem::path& dir, const std::regex& filter) {
  std::filesystem::create_directories(dir);
  for (const model::Definition& definition : model::registry()) {
    for (const std::string& variant : definition.variants) {
      for (const Case& c : kCases) {
        if (!std::regex_search(benchmark_name(definition, variant, c), filter)) continue;
        symbolic::Context context;
        symbolic::Context::Scope scope(context);
        const codegen::GeneratedCode code = generate(definition, variant, c);
        const std::string base = fmt::format("{}_{}_case{}", definition.name, variant, c.number);
        write(dir / (base + ".hpp"), code.header);
        write(dir / (base + ".cpp"), code.source);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Our own flag first: Google Benchmark rejects flags it does not know.
  constexpr std::string_view kDump = "--dump=";
  constexpr std::string_view kFilter = "--benchmark_filter=";
  std::string dump_dir;
  std::string filter = ".";
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.starts_with(kDump)) dump_dir = arg.substr(kDump.size());
    if (arg.starts_with(kFilter)) filter = arg.substr(kFilter.size());
  }
  if (!dump_dir.empty()) {
    dump_all(dump_dir, std::regex(filter));
    return 0;
  }
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
