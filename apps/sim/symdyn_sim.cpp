// symdyn-sim: runs a scenario (docs/scenarios.md) on generated code, writes
// the time history as CSV and prints a summary with the scenario's checks.
//
//   symdyn-sim <scenario.json | model> [--variant V] [--t-end T] [--integrator I] [--tolerance X]
//              [--rtol R] [--atol A] [--interval DT] [--step H] [--global-tolerance G]
//              [--assembled] [--out FILE] [--max-rows N]
//              [--html FILE] [--glb FILE] [--plot FILE.png|FILE.svg] [--easyanim STEM]
//              [--modes FILE.csv] [--modes-about equilibrium|initial] [--mode-amplitude A]
//   symdyn-sim --list
//   symdyn-sim --sweep SWEEP.json [--workers N | --scheduler ADDRESS] [--out FILE]... [--restart]
//   symdyn-sim --serve
//
// --set PATH=VALUE (repeatable) changes the scenario before the run, as a
// sweep does (overrides.hpp: forces.spring.stiffness=2e4, initial.qd.q0=5,
// integrator.name=cvode).
//
// --sweep runs a sweep file (docs/sweeps.md) with the Python package symdyn:
// every argument goes to it (python3 -m symdyn, the interpreter the build was
// given), which runs this program with --serve once per worker: the engine
// (serve.hpp) that runs the scenario with each run's changes.
//
// --html writes the HTML viewer of the run (the bodies as the scenario's shapes, else as rods
// between their joints and their inertias' solids; the coordinates plotted beside them), --glb
// the animation as glTF, --plot the coordinates and the energies against time with gnuplot (PNG
// or SVG by the extension), --easyanim EasyDyn's STEM.vol and STEM.van for EasyAnim.
// --reaction-arrows draws the closed loops' reaction forces in --html as arrows at their points.
//
// --modes linearizes the system (with its force elements at t = 0) about its
// static equilibrium found from the initial state (or about the initial state
// itself) and writes its modes as CSV; each mode is then also a clip of --html
// and --glb, and with --easyanim, STEM_modes.vol and STEM_modes.vmo.
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
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "output_files.hpp"
#include "overrides.hpp"
#include "run.hpp"
#include "serve.hpp"
#include "shapes.hpp"
#include <symdyn/runtime/easyanim.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/html_viewer.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/statics.hpp>

namespace {

using namespace symdyn;

struct Arguments {
  std::string scenario;
  std::string out;
  std::string html, glb, plot;   // pictures of the run, if asked
  bool reaction_arrows = false;  // the loops' reaction forces drawn in --html
  std::string easyanim;          // stem of EasyAnim's files
  std::string modes;             // CSV of the modes, if asked
  std::string modes_about = "equilibrium";
  double mode_amplitude = 0.2;   // rad or m: the largest coordinate's swing in a mode's clip
  double max_rows = 1e7;         // about 1 GB of CSV
  std::vector<std::string> set;  // --set PATH=VALUE
  bool list = false;
  bool serve = false;
  sim::RunOptions run;
};

// A finite number > 0. (CLI11's PositiveNumber lets NaN through and prints
// its bound, DBL_MAX, in 309 digits.)
const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
      double v = 0.0;
      if (CLI::detail::lexical_cast(text, v) && std::isfinite(v) && v > 0.0) return {};
      return fmt::format("expected a finite number > 0, found '{}'", text);
    },
    "POSITIVE");

// An output's name: not empty (an empty --out would mean the default name).
const CLI::Validator kFileName(
    [](std::string& text) -> std::string {
      return text.empty() ? "expected a file name, found ''" : "";
    },
    "FILE");

void list_scenarios() {
  for (const sim::Scenario& s : sim::builtin_scenarios()) {
    std::vector<std::string> names;
    for (const auto& m : sim::builtin_models()) {
      if (m.model == s.model) names.push_back(m.variant);
    }
    fmt::print("{:<16} variants: {:<22} {:g} s, {}, tolerance {:g}\n{:<16} {}\n", s.name,
               fmt::format("{}", fmt::join(names, ", ")), s.t_end, s.integrator, s.rtol, "",
               s.description);
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
    throw runtime::OptionError(
        fmt::format("the run would write {:.3g} rows (t-end / interval), over --max-rows {:.3g}: "
                    "raise --interval, or --max-rows "
                    "to allow it",
                    rows, max_rows));
  }
}

// The modes of the linearization about a reference state (--modes).
struct ModeShapes {
  runtime::State reference;
  runtime::Linearization linearization;
  std::vector<runtime::Mode> modes;
  std::vector<runtime::Animation> clips;  // one period of each, for the pictures
};

// The system's static equilibrium from its initial state, or that state itself.
ModeShapes find_modes(runtime::MultibodySystem& system, const Arguments& args) {
  ModeShapes m;
  m.reference = system.initial_state();
  if (args.modes_about == "equilibrium") {
    m.reference = runtime::solve_statics(system, m.reference).state;
  } else {
    m.reference.qd.setZero();
  }
  m.linearization = runtime::linearize(system, m.reference);
  m.modes = runtime::modes(m.linearization);
  m.clips.reserve(m.modes.size());
  for (const runtime::Mode& mode : m.modes) {
    m.clips.push_back(
        runtime::mode_animation(system, m.reference, m.linearization, mode, args.mode_amplitude));
  }
  return m;
}

void write_modes(const ModeShapes& m, const std::string& file) {
  std::ofstream out(file);
  runtime::write_modes_csv(out, m.linearization, m.modes);
  if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", file));
}

// The animation of a run (--html, --glb, --easyanim): every output instant's
// poses, and the coordinates' histories for the viewer's plot.
struct Pictures {
  runtime::Scene scene;
  runtime::Animation animation;
  runtime::TimeSeries series;
  runtime::Arrows arrows;  // --reaction-arrows

  Pictures(runtime::Scene shapes, const runtime::Model& model)
      : scene(std::move(shapes)), animation(model) {
    series.names.push_back("t");
    for (const std::string& q : model.q_names()) series.names.push_back(q);
    series.columns.resize(series.names.size());
    series.units = runtime::coordinate_units(model);
    if (!series.units.empty()) series.units.insert(series.units.begin(), "s");
  }
  void record(const runtime::State& s) {
    animation.record(s);
    series.columns[0].push_back(s.t);
    for (Eigen::Index j = 0; j < s.q.size(); ++j) series.columns[j + 1].push_back(s.q[j]);
  }
  // Each loop's reaction force (on its body b) at its point, at s (in the
  // independent coordinates) and qdd.
  void record_arrows(runtime::MultibodySystem& system, const runtime::State& s,
                     const runtime::Vector& qdd) {
    const runtime::Model& model = system.model();
    if (arrows.names.empty()) {
      arrows.names = model.loop_names();
      arrows.points.resize(arrows.names.size());
      arrows.vectors.resize(arrows.names.size());
    }
    runtime::Vector reaction;
    if (qdd.size() == s.q.size()) {
      system.loop_reactions(s, qdd, reaction);
    } else {
      system.loop_reactions(s, reaction);
    }
    const runtime::State x = system.extended_state(s);
    runtime::Matrix points(3, model.ncon());
    model.closure_points(s.t, x.q.data(), points.data());
    std::vector<runtime::Vec3> force(arrows.names.size(), runtime::Vec3::Zero()),
        at(arrows.names.size());
    for (int k = 0; k < model.ncon(); ++k) {
      const int l = model.constraint_loop(k);
      if (model.constraint_axis(k) >= 0) force[l](model.constraint_axis(k)) = reaction(k);
      at[l] = points.col(k);
    }
    for (std::size_t l = 0; l < force.size(); ++l) {
      arrows.points[l].insert(arrows.points[l].end(), at[l].data(), at[l].data() + 3);
      arrows.vectors[l].insert(arrows.vectors[l].end(), force[l].data(), force[l].data() + 3);
    }
  }
  // The motion, then each mode named by its frequency and damping.
  std::vector<runtime::Clip> clips(const ModeShapes* modes) const {
    std::vector<runtime::Clip> all{{"motion", &animation}};
    if (modes == nullptr) return all;
    for (std::size_t k = 0; k < modes->modes.size(); ++k) {
      const runtime::Mode& mode = modes->modes[k];
      all.push_back({fmt::format("mode {}: {:.4g} Hz, damping ratio {:.3g}", k + 1,
                                 mode.natural_frequency_hz, mode.damping_ratio),
                     &modes->clips[k]});
    }
    return all;
  }
  void write(const Arguments& args, const std::string& title, const ModeShapes* modes,
             const runtime::Model& model) const {
    if (!args.glb.empty()) runtime::write_glb(std::filesystem::path(args.glb), scene, clips(modes));
    if (!args.html.empty())
      runtime::write_html(args.html, title, scene, clips(modes), series, arrows);
    if (args.easyanim.empty()) return;
    runtime::write_easyanim(args.easyanim, scene, animation, title);
    if (modes != nullptr) {
      runtime::write_easyanim_modes(args.easyanim + "_modes", scene, model, modes->reference,
                                    modes->linearization, modes->modes, args.mode_amplitude,
                                    title + " modes");
    }
  }
};

// Pictures are refused before the run when they cannot be made.
void check_pictures(const Arguments& args) {
  if (!args.html.empty() && !runtime::html_viewer_available()) {
    throw runtime::OptionError(
        "--html: this symdyn was built without the HTML viewer (npm was not found)");
  }
  if (args.plot.empty()) return;
  const std::string ext = std::filesystem::path(args.plot).extension().string();
  if (ext != ".png" && ext != ".svg") {
    throw runtime::OptionError(
        fmt::format("--plot {}: the file must end in .png or .svg", args.plot));
  }
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    throw runtime::OptionError(
        "--plot: gnuplot is not installed (Debian: apt-get install gnuplot-nox)");
  }
}

// A text inside gnuplot's single quotes, where a quote is written twice.
std::string gnuplot_text(const std::string& text) {
  std::string out;
  for (char c : text) {
    out += c;
    if (c == '\'') out += c;
  }
  return out;
}

// Ten colours told apart by most eyes (Tableau's), then the same dashed.
std::string gnuplot_line_types() {
  static constexpr const char* colours[] = {"#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2",
                                            "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
  std::string out;
  for (int dash = 0; dash < 2; ++dash) {
    for (int k = 0; k < 10; ++k) {
      out += fmt::format("set linetype {} lc rgb '{}' lw 1.5 dt {}\n", 10 * dash + k + 1,
                         colours[k], dash + 1);
    }
  }
  return out + "set linetype cycle 20\n";
}

// The coordinates against time by gnuplot, a panel per unit (m, rad), and
// below them the energies when the CSV has them.
void plot(const std::filesystem::path& csv, const std::string& file, const sim::RunResult& r,
          const std::string& title, const std::vector<std::string>& units) {
  const bool svg = std::filesystem::path(file).extension() == ".svg";
  const bool energies =
      std::find(r.columns.begin(), r.columns.end(), "total_energy") != r.columns.end();
  // The coordinates by unit, in order of first appearance.
  std::vector<std::pair<std::string, std::vector<std::string>>> groups;
  for (std::size_t j = 0; j < r.coordinates.size(); ++j) {
    const std::string unit = j < units.size() ? units[j] : "";
    auto group =
        std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == unit; });
    if (group == groups.end()) group = groups.insert(groups.end(), {unit, {}});
    group->second.push_back(r.coordinates[j]);
  }
  const std::size_t panels = groups.size() + (energies ? 1 : 0);
  std::string script = fmt::format(
      "set terminal {} size 1000,{} noenhanced\nset output '{}'\nset datafile separator ','\n"
      "set key outside right top Left reverse\nset grid\nset xlabel 't (s)'\n"
      "set lmargin at screen 0.09\nset rmargin at screen 0.72\n{}",
      svg ? "svg" : "pngcairo", 150 + 300 * panels, gnuplot_text(file), gnuplot_line_types());
  script += fmt::format("set multiplot layout {},1 title '{}'\n", panels, gnuplot_text(title));
  const std::string data = gnuplot_text(csv.string());
  for (const auto& [unit, names] : groups) {
    const std::string kind = unit == "m" ? "lengths" : unit == "rad" ? "angles" : "coordinates";
    script += fmt::format(
        "set title '{0}'\nset ylabel '{1}'\nplot for [c in '{2}'] '{3}' using 1:c with lines "
        "title c\n",
        kind, unit.empty() ? "" : fmt::format("{} ({})", kind, unit), fmt::join(names, " "), data);
  }
  if (energies) {
    script += fmt::format(
        "set title 'energies'\nset ylabel 'energy (J)'\nplot for [c in 'kinetic_energy "
        "gravitational_energy elastic_energy total_energy'] '{}' using 1:c with lines title c\n",
        data);
  }
  script += "unset multiplot\n";
  FILE* gnuplot = popen("gnuplot", "w");
  if (gnuplot == nullptr) throw std::runtime_error("--plot: cannot start gnuplot");
  std::fputs(script.c_str(), gnuplot);
  if (pclose(gnuplot) != 0)
    throw std::runtime_error(fmt::format("--plot: gnuplot failed to write '{}'", file));
}

// Every file the run would write, by the option that names it.
std::vector<std::pair<std::string, std::filesystem::path>> output_files(
    const Arguments& args, const std::filesystem::path& csv) {
  std::vector<std::pair<std::string, std::filesystem::path>> files{{"--out", csv}};
  std::filesystem::path partial = csv;
  files.emplace_back("--out", partial += ".partial");
  for (const auto& [option, file] : {std::pair{"--html", &args.html},
                                     {"--glb", &args.glb},
                                     {"--plot", &args.plot},
                                     {"--modes", &args.modes}}) {
    if (!file->empty()) files.emplace_back(option, *file);
  }
  if (!args.easyanim.empty()) {
    std::vector<std::string> stems{args.easyanim};
    if (!args.modes.empty()) stems.push_back(args.easyanim + "_modes");
    for (const std::string& stem : stems) {
      for (const char* ext : {".vol", stem == args.easyanim ? ".van" : ".vmo"})
        files.emplace_back("--easyanim", stem + ext);
    }
  }
  return files;
}

// Each output a regular file that can be written, none named twice, none the
// scenario itself: refused before the run, not after it.
void check_outputs(const Arguments& args, const std::filesystem::path& csv) {
  const auto files = output_files(args, csv);
  std::vector<std::filesystem::path> seen;
  const auto same = [](const std::filesystem::path& a, const std::filesystem::path& b) {
    std::error_code ec;
    return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
  };
  for (std::size_t i = 0; i < files.size(); ++i) {
    const auto& [option, file] = files[i];
    sim::check_output_file(option, file);
    if (is_file(args.scenario) && same(file, args.scenario)) {
      throw runtime::OptionError(fmt::format(
          "{} '{}' is the scenario file: it would be overwritten", option, file.string()));
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (same(file, files[j].second)) {
        throw runtime::OptionError(
            fmt::format("{} '{}' and {} '{}' are the same file: one would overwrite the other",
                        files[j].first, files[j].second.string(), option, file.string()));
      }
    }
  }
}

// The scenario named on the command line, changed by --set.
sim::Scenario read_scenario(const Arguments& args) {
  sim::Scenario scenario =
      is_file(args.scenario) ? sim::load_scenario(args.scenario) : sim::find_builtin(args.scenario);
  if (args.set.empty()) return scenario;
  std::vector<sim::Override> changes;
  for (const std::string& s : args.set) changes.push_back(sim::parse_override(s));
  try {
    return sim::with_overrides(scenario, sim::make_model(scenario, args.run.variant), changes);
  } catch (const sim::OverrideError& e) {
    throw runtime::OptionError(fmt::format("--set {}", e.what()));
  }
}

int simulate(Arguments& args) {
  const sim::Scenario scenario = read_scenario(args);
  // Rows go to <file>.partial as they come, renamed to <file> when the run ends
  // (through a symbolic link, to the file it names).
  std::filesystem::path path = args.out.empty() ? scenario.name + ".csv" : args.out;
  check_outputs(args, path);
  if (std::filesystem::is_symlink(path)) path = std::filesystem::canonical(path);
  std::filesystem::path partial = path;
  partial += ".partial";
  std::ofstream csv;
  args.run.csv = &csv;
  args.run.progress = true;
  long rows = 0;
  double last_t = 0.0;
  std::optional<Pictures> pictures;
  runtime::MultibodySystem* system = nullptr;
  // Drawn in the tree's coordinates: with closed loops, q and the parameters p solved.
  args.run.on_sample = [&](const runtime::State& s, const runtime::Vector& qdd) {
    ++rows;
    last_t = s.t;
    if (!pictures) return;
    pictures->record(system->extended_state(s));
    if (args.reaction_arrows) pictures->record_arrows(*system, s, qdd);
  };
  sim::Simulation simulation(scenario, args.run);
  system = &simulation.system();
  if (args.reaction_arrows && (args.html.empty() || !system->model().has_loops())) {
    throw runtime::OptionError(fmt::format(
        "--reaction-arrows: {}",
        args.html.empty() ? "draws in --html, which is not asked"
                          : fmt::format("model '{}' has no closed loops", system->model().name())));
  }
  runtime::Scene scene = sim::read_scene(scenario, simulation.system().model());
  check_rows(simulation, args.max_rows);
  check_pictures(args);
  // The modes first: a failed equilibrium touches no file.
  std::optional<ModeShapes> modes;
  if (!args.modes.empty()) modes = find_modes(simulation.system(), args);
  if (!args.html.empty() || !args.glb.empty() || !args.easyanim.empty()) {
    pictures.emplace(std::move(scene), simulation.system().model());
  }
  for (const auto& [option, file] : output_files(args, path)) sim::create_folders(file);
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
    if (rows ==
        0) {  // refused before its first row (an option the integrator checks): the old file stays
      csv.close();
      std::filesystem::remove(partial);
      throw;
    }
    keep();
    std::cerr << "error: " << e.what() << '\n';
    std::cerr << fmt::format("  the run stopped; CSV: {} keeps its {} rows up to t = {}\n",
                             path.string(), rows, last_t);
    return 1;
  }
  if (!csv) throw std::runtime_error(fmt::format("cannot write '{}'", partial.string()));
  keep();
  fmt::print("{}", sim::summary(r));
  fmt::print("  CSV: {} ({} rows of {} columns: {})\n", path.string(), r.rows, r.columns.size(),
             fmt::join(r.columns, ", "));
  if (modes) {
    write_modes(*modes, args.modes);
    fmt::print("  modes about the {} (t = {}):\n",
               args.modes_about == "equilibrium" ? "static equilibrium" : "initial state",
               modes->reference.t);
    for (std::size_t k = 0; k < modes->modes.size(); ++k) {
      fmt::print("    mode {}: {:.6g} Hz, damping ratio {:.4g}\n", k + 1,
                 modes->modes[k].natural_frequency_hz, modes->modes[k].damping_ratio);
    }
  }
  if (pictures)
    pictures->write(args, scenario.name, modes ? &*modes : nullptr, simulation.system().model());
  if (!args.plot.empty()) {
    plot(path, args.plot, r, scenario.name, runtime::coordinate_units(simulation.system().model()));
  }
  for (const std::string* file : {&args.html, &args.glb, &args.plot, &args.modes}) {
    if (!file->empty()) fmt::print("  wrote {}\n", *file);
  }
  if (!args.easyanim.empty()) {
    fmt::print("  wrote {0}.vol, {0}.van{1}\n", args.easyanim,
               modes ? fmt::format(", {0}_modes.vol, {0}_modes.vmo", args.easyanim) : "");
  }
  const bool ok =
      std::all_of(r.checks.begin(), r.checks.end(), [](const sim::Check& c) { return c.ok(); });
  return ok ? 0 : 1;
}

// --sweep: the Python package symdyn runs the sweep, with this program as its
// engine (SYMDYN_SIM). SYMDYN_PYTHON overrides the interpreter.
int sweep(int argc, char** argv) {
  const char* python = std::getenv("SYMDYN_PYTHON");
  if (python == nullptr || *python == '\0') python = SYMDYN_PYTHON_EXECUTABLE;
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::canonical("/proc/self/exe", ec);
  // Installed, the package is at a fixed place from this program; else it is the build's.
  const std::filesystem::path installed = self.parent_path() / SYMDYN_PYTHON_PACKAGE_DIR_FROM_BIN;
  std::string path = !ec && std::filesystem::exists(installed / "symdyn" / "__main__.py")
                         ? installed.lexically_normal().string()
                         : SYMDYN_PYTHON_PACKAGE_DIR;
  if (const char* old = std::getenv("PYTHONPATH"); old != nullptr && *old != '\0')
    path += std::string(":") + old;
  setenv("PYTHONPATH", path.c_str(), 1);
  if (!ec) setenv("SYMDYN_SIM", self.c_str(), 1);
  std::vector<char*> command{const_cast<char*>(python), const_cast<char*>("-m"),
                             const_cast<char*>("symdyn")};
  for (int k = 1; k < argc; ++k) command.push_back(argv[k]);
  command.push_back(nullptr);
  execv(python, command.data());
  std::cerr << fmt::format(
      "error: --sweep: cannot run {} ({}); set SYMDYN_PYTHON to a python3 with symdyn's "
      "dependencies (docs/sweeps.md)\n",
      python, std::strerror(errno));
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string_view a = argv[k];
    if (a == "--sweep" || a.starts_with("--sweep=")) return sweep(argc, argv);
  }
  Arguments args;
  CLI::App app{
      "symdyn-sim: runs a scenario (a JSON file, or a reference model's name) on generated code",
      "symdyn-sim"};
  app.set_version_flag("--version", "symdyn-sim " SYMDYN_VERSION);
  app.add_option("scenario", args.scenario,
                 "scenario file (*.json) or built-in model name (see --list)");
  app.add_flag("--list", args.list, "list the built-in scenarios and their models' variants");
  app.add_option("--set", args.set,
                 "change the scenario: PATH=VALUE (forces.spring.stiffness=2e4; docs/sweeps.md)");
  std::string sweep_file;  // for --help only: --sweep is handed over before parsing
  app.add_option("--sweep", sweep_file,
                 "run a sweep file (docs/sweeps.md); every other argument is the sweep's (--sweep "
                 "FILE --help)");
  app.add_flag("--serve", args.serve,
               "run scenarios on requests from stdin (the engine of sweeps; serve.hpp)");
  app.add_option("--variant", args.run.variant,
                 "generated variant (default: the scenario's, else the model's first)");
  app.add_option("--t-end", args.run.t_end, "end time in s (default: the scenario's)")
      ->check(kPositive);
  app.add_option("--integrator", args.run.integrator,
                 fmt::format("one of {}", fmt::join(runtime::integrator_names(), ", ")));
  app.add_option("--tolerance", args.run.tolerance, "relative and absolute tolerance")
      ->check(kPositive);
  app.add_option("--rtol", args.run.rtol, "relative tolerance (over --tolerance)")
      ->check(kPositive);
  app.add_option("--atol", args.run.atol, "absolute tolerance (over --tolerance)")
      ->check(kPositive);
  app.add_option("--interval", args.run.output_interval, "output interval in s")->check(kPositive);
  app.add_option("--step", args.run.step,
                 "initial step in s; rk4, midpoint: the fixed step, required (with "
                 "--global-tolerance: the first, halved "
                 "until met)")
      ->check(kPositive);
  app.add_option("--global-tolerance", args.run.global_tolerance,
                 "bound on the error of the result, estimated by solving again (tighter "
                 "tolerances, or halved fixed "
                 "steps); the summary says whether it was met")
      ->check(kPositive);
  app.add_flag("--assembled", args.run.assembled,
               "assemble M and h from the kinematics instead of the emitted ones");
  app.add_option("--out", args.out, "CSV file (default: <scenario>.csv)")->check(kFileName);
  app.add_option("--html", args.html, "write the HTML viewer of the run (open it in a browser)")
      ->check(kFileName);
  app.add_flag("--reaction-arrows", args.reaction_arrows,
               "draw the closed loops' reaction forces in --html as arrows at their points");
  app.add_option("--glb", args.glb, "write the animation as glTF binary (Blender, glTF viewers)")
      ->check(kFileName);
  app.add_option("--plot", args.plot,
                 "plot the coordinates against time with gnuplot (.png or .svg)")
      ->check(kFileName);
  app.add_option("--easyanim", args.easyanim,
                 "write EasyDyn's STEM.vol and STEM.van of the run (EasyAnim)")
      ->check(kFileName);
  CLI::Option* modes =
      app.add_option("--modes", args.modes,
                     "write the modes of the linearization as CSV (also clips of --html, --glb)")
          ->check(kFileName);
  app.add_option("--modes-about", args.modes_about,
                 "linearize about the static equilibrium (default) or the initial state")
      ->check(CLI::IsMember({"equilibrium", "initial"}))
      ->needs(modes);
  app.add_option("--mode-amplitude", args.mode_amplitude,
                 "largest coordinate's swing in a mode's clip (default 0.2)")
      ->check(kPositive)
      ->needs(modes);
  app.add_option("--max-rows", args.max_rows,
                 "refuse a run that would write more CSV rows (default 1e7)")
      ->check(kPositive);
  try {
    app.parse(argc, argv);
    if (!args.list && !args.serve && args.scenario.empty()) throw CLI::RequiredError("scenario");
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (args.list) {
      list_scenarios();
      return 0;
    }
    if (args.serve) {
      std::ios::sync_with_stdio(false);
      return sim::serve(std::cin, std::cout);
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
