#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <symdyn/codegen/generate.hpp>
#include <symdyn/codegen/generator_cli.hpp>
#include <symdyn/detail/writable_path.hpp>
#include <symdyn/model/errors.hpp>
#include <symdyn/model/identifier.hpp>
#include <symdyn/symbolic/errors.hpp>
#include <symdyn/symbolic/print.hpp>

namespace {

using namespace symdyn;

constexpr int kExitModel = 1;
constexpr int kExitCommandLine = 2;

using codegen::CommandLineError;

struct Arguments {
  std::string out = ".";
  std::string variant;
  std::string basename;
  std::string partials = "symbolic";
  std::string dynamics = "auto";
  std::string model;
  // Signed, so that a negative count is refused rather than wrapped around.
  std::int64_t part_size = static_cast<std::int64_t>(codegen::kDefaultPartInstructions);
  std::int64_t split_above = static_cast<std::int64_t>(codegen::kSplitAbove);
  std::int64_t sources = 1;
  std::int64_t source_bytes = static_cast<std::int64_t>(codegen::kBytesPerSource);
  bool no_simplify = false;
  bool no_eom = false;
  bool derivatives = false;
  bool dynamics_derivatives = false;
  bool reactions = false;
  bool list = false;
  bool stats = false;
  bool describe = false;
  std::vector<std::string> only;
};

// What to generate, every argument checked.
struct Job {
  const model::Definition* definition = nullptr;
  std::string variant;
  std::string basename;
  codegen::Options options;
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

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const model::Definition& d : model::registry()) names.push_back(d.name);
  return names;
}

const model::Definition& choose_model(const std::string& name) {
  const auto& all = model::registry();
  if (all.empty()) throw model::ModelError("no model is linked into this generator");
  if (!name.empty()) {
    const auto it = std::find_if(all.begin(), all.end(),
                                 [&](const model::Definition& d) { return d.name == name; });
    if (it == all.end()) {
      throw CommandLineError(fmt::format("--model: no model named '{}' (models: {})", name,
                                         fmt::join(model_names(), ", ")));
    }
    return *it;
  }
  if (all.size() == 1) return all.front();
  throw CommandLineError(
      fmt::format("{} models are linked in: choose one with --model (models: {})", all.size(),
                  fmt::join(model_names(), ", ")));
}

// What generation writes, checked before the derivation (which can take
// minutes): --out a directory or one that can be made, writable, and the
// files, where they exist, regular files that are not read-only.
void check_out_directory(const std::string& out, const std::vector<std::string>& files) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path dir(out);
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw CommandLineError(fmt::format("--out: '{}' exists and is not a directory", out));
  }
  const fs::path folder = symdyn::detail::nearest_existing(dir);
  if (!fs::is_directory(folder, ec)) {
    throw CommandLineError(
        fmt::format("--out: '{}' cannot be made: '{}' is not a directory", out, folder.string()));
  }
  if (!symdyn::detail::can_create_in(folder)) {
    throw CommandLineError(fmt::format(
        "--out: '{}' cannot be written: the folder '{}' is not writable", out, folder.string()));
  }
  for (const std::string& name : files) {
    const fs::path file = dir / name;
    const fs::file_status status = fs::status(file, ec);
    if (!fs::exists(status)) continue;
    if (!fs::is_regular_file(status)) {
      throw CommandLineError(
          fmt::format("--out: '{}' exists and is not a regular file", file.string()));
    }
    if (!symdyn::detail::replaceable(file, status.permissions())) {
      throw CommandLineError(
          fmt::format("--out: '{}' is read-only: it is not replaced", file.string()));
    }
  }
}

std::size_t count(std::int64_t value, std::int64_t minimum, const char* option) {
  if (value < minimum) {
    throw CommandLineError(
        fmt::format("{}: {} is out of range (it must be at least {})", option, value, minimum));
  }
  return static_cast<std::size_t>(value);
}

Job check_arguments(const Arguments& args) {
  Job job;
  job.definition = &choose_model(args.model);
  const auto& variants = job.definition->variants;
  if (variants.empty())
    throw model::ModelError(fmt::format("model '{}' declares no variant", job.definition->name));
  job.variant = args.variant.empty() ? variants.front() : args.variant;
  if (std::find(variants.begin(), variants.end(), job.variant) == variants.end()) {
    throw CommandLineError(fmt::format("--variant: model '{}' has no variant '{}' (variants: {})",
                                       job.definition->name, job.variant,
                                       fmt::join(variants, ", ")));
  }
  if (!args.basename.empty()) {
    if (auto problem = model::identifier_problem(args.basename)) {
      throw CommandLineError(fmt::format("--basename: '{}' {}", args.basename, *problem));
    }
  }
  job.basename = args.basename.empty() ? fmt::format("{}_{}", job.definition->name, job.variant)
                                       : args.basename;
  job.options.simplify = !args.no_simplify;
  job.options.symbolic_partials = args.partials == "symbolic";
  job.options.equations_of_motion = !args.no_eom;
  job.options.derivatives = args.derivatives            ? codegen::Derivatives::all
                            : args.dynamics_derivatives ? codegen::Derivatives::dynamics
                                                        : codegen::Derivatives::none;
  job.options.joint_reactions = args.reactions;
  job.options.dynamics = args.dynamics == "recursive"     ? codegen::DynamicsMethod::recursive
                         : args.dynamics == "mass-matrix" ? codegen::DynamicsMethod::mass_matrix
                                                          : codegen::DynamicsMethod::automatic;
  job.options.part_instructions = count(args.part_size, 1, "--part-size");
  job.options.split_above = count(args.split_above, 0, "--split-above");
  job.options.sources = count(args.sources, 1, "--sources");
  if (job.options.sources > codegen::kMaxSources) {
    throw CommandLineError(fmt::format("--sources: {} is out of range (it must be at most {})",
                                       args.sources, codegen::kMaxSources));
  }
  job.options.source_bytes = count(args.source_bytes, 1, "--source-bytes");
  job.options.entry_points = args.only;
  if (args.out.empty()) throw CommandLineError("--out: the directory name is empty");
  return job;
}

// Every model linked in (or the one --model names), with its variants.
int list(const std::string& name) {
  if (!name.empty()) {
    const model::Definition& d = choose_model(name);
    fmt::print("{}: variants {}\n", d.name, fmt::join(d.variants, ", "));
    return 0;
  }
  if (model::registry().empty()) throw model::ModelError("no model is linked into this generator");
  for (const model::Definition& d : model::registry())
    fmt::print("{}: variants {}\n", d.name, fmt::join(d.variants, ", "));
  return 0;
}

// A JSON string: names and expressions hold no quote, backslash or control
// character, but escape them anyway.
std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
    } else {
      out += c;
    }
  }
  return out + '"';
}

std::string json_expr(symbolic::Expr e) {
  return json_string(symbolic::to_infix(e));
}

std::string json_vec3(const model::Vec3& v) {
  return fmt::format("[{}, {}, {}]", json_expr(v[0]), json_expr(v[1]), json_expr(v[2]));
}

// The model as its file describes it, for tools that derive it another way
// (bench/paper_tables' computer algebra scripts): symbols, dependent
// parameters, and each body's reference and elementary motions, expressions
// in to_infix's notation (docs/builder.md, "The model as JSON").
std::string describe(const Job& job) {
  const model::Model m = job.definition->make(job.variant);
  m.validate();
  std::vector<std::string> coordinates, dependents, inlined, parameters, bodies;
  for (const model::Coordinate& c : m.coordinates()) {
    // An implicit dependent parameter of a closed loop, with its guess.
    const std::string implicit = c.implicit ? fmt::format(", \"implicit\": true, \"guess\": {}",
                                                          symbolic::cpp_literal(c.initial))
                                            : "";
    coordinates.push_back(fmt::format("{{\"q\": {}, \"qd\": {}, \"qdd\": {}{}}}", json_expr(c.q),
                                      json_expr(c.qd), json_expr(c.qdd), implicit));
  }
  // Closed loops, only in a model that has them: each with its equations g = 0.
  std::string loops;
  for (const model::Loop& l : m.loops()) {
    std::vector<std::string> equations;
    for (model::Expr g : l.equations) equations.push_back(json_expr(g));
    loops += fmt::format("{}{{\"name\": {}, \"equations\": [{}]}}", loops.empty() ? "" : ", ",
                         json_string(l.name), fmt::join(equations, ", "));
  }
  if (!loops.empty()) loops = fmt::format("  \"loops\": [{}],\n", loops);
  for (const model::Dependent& d : m.dependents()) {
    dependents.push_back(fmt::format("{{\"p\": {}, \"pd\": {}, \"pdd\": {}, \"expression\": {}}}",
                                     json_expr(d.symbol), json_expr(d.rate),
                                     json_expr(d.acceleration), json_expr(d.expression)));
  }
  for (const model::InlinedDependent& d : m.inlined_dependents()) {
    inlined.push_back(fmt::format("{{\"name\": {}, \"expression\": {}}}", json_string(d.name),
                                  json_expr(d.expression)));
  }
  for (const model::Parameter& p : m.parameters()) {
    parameters.push_back(fmt::format("{{\"symbol\": {}, \"value\": {}}}", json_expr(p.symbol),
                                     symbolic::cpp_literal(p.value)));
  }
  for (const model::Body& b : m.bodies()) {
    std::vector<std::string> steps;
    for (const model::Transform::Step& s : b.motion().steps()) {
      steps.push_back(s.is_rotation
                          ? fmt::format("{{\"rotation\": {}, \"angle\": {}}}", json_vec3(s.axis),
                                        json_expr(s.angle))
                          : fmt::format("{{\"translation\": {}}}", json_vec3(s.displacement)));
    }
    bodies.push_back(fmt::format(
        "    {{\"name\": {}, \"reference\": {}, \"motion\": [{}]}}", json_string(b.name()),
        b.reference() ? json_string(*b.reference()) : "null", fmt::join(steps, ", ")));
  }
  return fmt::format(
      "{{\n  \"model\": {},\n  \"variant\": {},\n  \"time\": {},\n  \"coordinates\": [{}],\n"
      "  \"parameters\": [{}],\n  \"dependents\": [{}],\n  \"inlined_dependents\": [{}],\n"
      "{}  \"gravity\": {},\n  \"bodies\": [\n{}\n  ]\n}}\n",
      json_string(job.definition->name), json_string(job.variant), json_expr(m.time()),
      fmt::join(coordinates, ", "), fmt::join(parameters, ", "), fmt::join(dependents, ", "),
      fmt::join(inlined, ", "), loops, json_vec3(m.gravity()), fmt::join(bodies, ",\n"));
}

// The files a job writes: <basename>.hpp, <basename>.cpp, then <basename>.2.cpp ...
std::vector<std::string> file_names(const Job& job) {
  std::vector<std::string> names{job.basename + ".hpp", job.basename + ".cpp"};
  for (std::size_t f = 2; f <= job.options.sources; ++f)
    names.push_back(fmt::format("{}.{}.cpp", job.basename, f));
  return names;
}

int generate(const Job& job, const Arguments& args) {
  const auto start = std::chrono::steady_clock::now();
  const model::Model m = job.definition->make(job.variant);
  const codegen::GeneratedCode code = codegen::generate(m, job.variant, job.basename, job.options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::filesystem::create_directories(args.out);
  const std::vector<std::string> names = file_names(job);
  std::vector<const std::string*> texts{&code.header, &code.source};
  for (const std::string& more : code.more_sources) texts.push_back(&more);
  std::size_t source_bytes = 0;
  for (std::size_t f = 0; f < names.size(); ++f) {
    write_if_changed(std::filesystem::path(args.out) / names[f], *texts[f]);
    if (f > 0) source_bytes += texts[f]->size();
  }
  if (args.stats) {
    fmt::print("model {} variant {}: generated in {:.4f} s, {} bytes ({} header + {} source{})\n",
               job.definition->name, job.variant, seconds, code.header.size() + source_bytes,
               code.header.size(), source_bytes,
               names.size() > 2 ? fmt::format(" in {} files", names.size() - 1) : "");
    for (const auto& e : code.functions) {
      fmt::print("  {:<22} {:>7} operations  {}\n", e.name, e.operations.total(),
                 e.operations.str());
    }
    if (!code.dynamics.reason.empty()) fmt::print("  accelerations: {}\n", code.dynamics.reason);
    if (!code.derivatives.empty()) fmt::print("  derivatives: {}\n", code.derivatives);
  }
  return 0;
}

int run(const Arguments& args, const codegen::GeneratorHooks& hooks) {
  try {
    if (hooks.prepare) hooks.prepare();
    if (args.list) return list(args.model);
    if (args.describe) {
      fmt::print("{}", describe(check_arguments(args)));
      return 0;
    }
    const Job job = check_arguments(args);
    check_out_directory(args.out, file_names(job));
    return generate(job, args);
  } catch (const CommandLineError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return kExitCommandLine;
  } catch (const model::ModelError& e) {
    std::cerr << "error: " << e.what() << '\n';
  } catch (const symbolic::SymbolicError& e) {
    std::cerr << "error: " << e.what() << '\n';
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
  }
  return kExitModel;
}

}  // namespace

namespace symdyn::codegen {

int run_generator(int argc, char** argv, const GeneratorHooks& hooks) {
  Arguments args;
  CLI::App app{
      hooks.description.empty()
          ? "symdyn generator: derives the model's kinematics and equations of motion and emits C++"
          : hooks.description,
      argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "generator"};
  app.set_version_flag("--version", app.get_name() + " " SYMDYN_VERSION);
  app.add_option("--out", args.out, "directory for <basename>.hpp and <basename>.cpp")
      ->capture_default_str();
  app.add_option("--variant", args.variant, "model variant (default: the model's first)");
  app.add_option("--basename", args.basename,
                 "file and struct name, a C++ identifier (default: <model>_<variant>)");
  app.add_option("--model", args.model, "model name, when several are linked in");
  app.add_flag("--no-simplify", args.no_simplify, "skip trigonometric simplification");
  app.add_option("--partials", args.partials, "partial velocities")
      ->check(CLI::IsMember({"numeric", "symbolic"}))
      ->capture_default_str();
  app.add_flag("--no-eom", args.no_eom,
               "do not emit the mass matrix, bias forces and inverse dynamics");
  app.add_flag("--derivatives", args.derivatives,
               "also emit the exact derivatives of the equations of motion "
               "(inverse_dynamics_derivatives, and inverse_dynamics_jacobians with M) and of "
               "the kinematics force elements read (kinematics_derivatives), which the runtime "
               "uses wherever it "
               "needs a Jacobian");
  app.add_flag("--dynamics-derivatives", args.dynamics_derivatives,
               "only those of the equations of motion: growing as nq², where the kinematics' grow "
               "as nbody·nq²");
  app.add_flag("--reactions", args.reactions,
               "also emit joint_reactions: the force and moment every body's joint transmits");
  app.add_option(
         "--dynamics", args.dynamics,
         "accelerations by the mass matrix (Cholesky at run time) or the emitted recursive forward "
         "dynamics where it applies; auto: the one of fewer operations")
      ->check(CLI::IsMember({"auto", "mass-matrix", "recursive"}))
      ->capture_default_str();
  app.add_option("--part-size", args.part_size,
                 "emit long entry points as shared functions of at most N statements each (N >= 1)")
      ->capture_default_str();
  app.add_option(
         "--split-above", args.split_above,
         "share functions only if all entry points together are longer than N statements (N >= 0)")
      ->capture_default_str();
  app.add_option("--sources", args.sources,
                 "spread the definitions over up to N source files, to compile in parallel: "
                 "<basename>.cpp, <basename>.2.cpp ... <basename>.N.cpp, those left over empty "
                 "(N >= 1)")
      ->capture_default_str();
  app.add_option("--source-bytes", args.source_bytes,
                 "with --sources: at least N bytes of definitions in each file used (N >= 1)")
      ->capture_default_str();
  app.add_option(
         "--only", args.only,
         "emit only these entry points (comma-separated) and what they call, to call them directly "
         "(MultibodySystem needs them all)")
      ->delimiter(',');
  app.add_flag("--list", args.list,
               "list the models linked in and their variants, generate nothing");
  app.add_flag("--stats", args.stats, "print generation time, size and operation counts");
  app.add_flag("--describe", args.describe,
               "print the model (symbols, dependent parameters, each body's reference and "
               "elementary motions) as "
               "JSON, generate nothing");
  if (hooks.add_options) hooks.add_options(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitCommandLine;
  }
  return run(args, hooks);
}

}  // namespace symdyn::codegen
