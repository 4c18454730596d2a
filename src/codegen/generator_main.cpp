// The generator's main. A model file (models/*.cpp) linked with this main is
// the generator for that model:
//
//   double_pendulum_generator --out DIR [--variant V] [--no-simplify]
//                             [--partials numeric|symbolic] [--no-eom] [--basename NAME]
//                             [--part-size N] [--split-above N]
//   double_pendulum_generator --list
//
// Exit codes: 0 success, 1 invalid model or generation failure, 2 bad command line.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "codegen/generate.hpp"
#include "model/errors.hpp"
#include "symbolic/errors.hpp"

namespace {

using namespace symdyn;

struct Arguments {
  std::string out = ".";
  std::string variant;
  std::string basename;
  std::string partials = "symbolic";
  std::string model;
  std::size_t part_size = codegen::kDefaultPartInstructions;
  std::size_t split_above = codegen::kSplitAbove;
  bool no_simplify = false;
  bool no_eom = false;
  bool list = false;
  bool stats = false;
};

// Writes a file only when its content changes, so that builds stay incremental.
void write_if_changed(const std::filesystem::path& path, const std::string& content) {
  {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (old == content) return;
    }
  }
  std::ofstream out(path, std::ios::binary);
  out << content;
  if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", path.string()));
}

const model::Definition& choose_model(const Arguments& args) {
  if (!args.model.empty()) return model::find_definition(args.model);
  const auto& all = model::registry();
  if (all.size() == 1) return all.front();
  if (all.empty()) throw model::ModelError("no model is linked into this generator");
  throw model::ModelError(fmt::format("{} models are linked in: choose one with --model", all.size()));
}

int generate(const Arguments& args) {
  const model::Definition& definition = choose_model(args);
  if (args.list) {
    fmt::print("{}: variants {}\n", definition.name, fmt::join(definition.variants, ", "));
    return 0;
  }
  const auto start = std::chrono::steady_clock::now();
  const std::string variant = args.variant.empty() ? definition.variants.front() : args.variant;
  const model::Model m = definition.make(variant);
  codegen::Options options;
  options.simplify = !args.no_simplify;
  options.symbolic_partials = args.partials == "symbolic";
  options.equations_of_motion = !args.no_eom;
  options.part_instructions = args.part_size;
  options.split_above = args.split_above;
  const std::string basename = args.basename.empty() ? fmt::format("{}_{}", definition.name, variant) : args.basename;
  const codegen::GeneratedCode code = codegen::generate(m, variant, basename, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::filesystem::create_directories(args.out);
  write_if_changed(std::filesystem::path(args.out) / (basename + ".hpp"), code.header);
  write_if_changed(std::filesystem::path(args.out) / (basename + ".cpp"), code.source);
  if (args.stats) {
    fmt::print("model {} variant {}: generated in {:.4f} s, {} bytes ({} header + {} source)\n", definition.name,
               variant, seconds, code.header.size() + code.source.size(), code.header.size(), code.source.size());
    for (const auto& e : code.functions) {
      fmt::print("  {:<22} {:>7} operations  {}\n", e.name, e.operations.total(), e.operations.str());
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  CLI::App app{"symdyn generator: derives the model's kinematics and equations of motion and emits C++"};
  app.add_option("--out", args.out, "directory for <basename>.hpp and <basename>.cpp")->capture_default_str();
  app.add_option("--variant", args.variant, "model variant (default: the model's first)");
  app.add_option("--basename", args.basename, "file name without extension (default: <model>_<variant>)");
  app.add_option("--model", args.model, "model name, when several are linked in");
  app.add_flag("--no-simplify", args.no_simplify, "skip trigonometric simplification");
  app.add_option("--partials", args.partials, "partial velocities")
      ->check(CLI::IsMember({"numeric", "symbolic"}))
      ->capture_default_str();
  app.add_flag("--no-eom", args.no_eom, "do not emit the mass matrix and bias forces");
  app.add_option("--part-size", args.part_size,
                 "emit the entry points as shared functions of at most N statements each (0: each entry point whole)")
      ->capture_default_str();
  app.add_option("--split-above", args.split_above,
                 "share functions only if all entry points together are longer than N statements")
      ->capture_default_str();
  app.add_flag("--list", args.list, "list the model and its variants, generate nothing");
  app.add_flag("--stats", args.stats, "print generation time, size and operation counts");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    return generate(args);
  } catch (const model::ModelError& e) {
    std::cerr << "error: " << e.what() << '\n';
  } catch (const symbolic::SymbolicError& e) {
    std::cerr << "error: " << e.what() << '\n';
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
  }
  return 1;
}
