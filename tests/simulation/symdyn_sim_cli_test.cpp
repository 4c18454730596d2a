// symdyn-sim as a user meets it: nothing lost (arguments checked before a file
// is touched, rows kept when a run fails), bounded work and output, exit codes
// (0 success, 1 failed run, 2 bad command line) and the culprit on stderr.
#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "codegen/run_command.hpp"
#include "four_bar.hpp"
#include <symdyn/runtime/runtime.hpp>

using namespace symdyn::testing;
using Catch::Matchers::Contains;

namespace {

const std::string kSim = SYMDYN_SIM;

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A directory holding results.csv with earlier results in it.
std::filesystem::path with_earlier_results() {
  const auto dir = scratch_directory("sim");
  std::ofstream(dir / "results.csv") << "earlier results\n";
  return dir;
}

}  // namespace

TEST_CASE("symdyn-sim: a typo leaves the earlier results alone", "[bad_input][sim]") {
  struct Case {
    std::vector<std::string> args;
    std::string culprit;
  };
  const Case cases[] = {
      {{"--integrator", "dopri6"}, "unknown integrator 'dopri6'; valid names: newmark"},
      {{"--variant", "nope"},
       "model 'double_pendulum' has no variant 'nope' (built variants: absolute, relative)"},
      {{"--interval", "1e-300", "--t-end", "1e9"}, "the run would write inf rows"},
      {{"--t-end", "1e6"},
       "the run would write 1e+08 rows (t-end / interval), over --max-rows 1e+07"},
      {{"--integrator", "rk4", "--step", "1e-300"},
       "integrator 'rk4': initial_step 1e-300 is below min_step 1e-12"},
      {{"--integrator", "rk4", "--step", "1e-9"},
       "a fixed step of 1e-09 s from t = 0 to 10 takes 1e+10 steps, over max_steps 100000000"},
      {{"--plot", "q.pdf"}, "--plot q.pdf: the file must end in .png or .svg"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.culprit);
    const auto dir = with_earlier_results();
    std::vector<std::string> args{kSim, "double_pendulum", "--out", (dir / "results.csv").string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CommandResult r = run_command(args);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(c.culprit));
    CHECK(read(dir / "results.csv") == "earlier results\n");
    CHECK_FALSE(std::filesystem::exists(dir / "results.csv.partial"));
    std::filesystem::remove_all(dir);
  }
}

TEST_CASE(
    "symdyn-sim: --max-rows allows a long output, and a run replaces the results when it ends",
    "[bad_input][sim]") {
  const auto dir = with_earlier_results();
  const CommandResult r =
      run_command({kSim, "double_pendulum", "--t-end", "0.1", "--interval", "1e-5", "--max-rows",
                   "2e4", "--out", (dir / "results.csv").string()});
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("(10001 rows of 11 columns"));
  CHECK(read(dir / "results.csv").rfind("t,theta1,theta2,", 0) == 0);
  CHECK_FALSE(std::filesystem::exists(dir / "results.csv.partial"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("symdyn-sim: a run that fails keeps its rows and says how far it got",
          "[bad_input][sim]") {
  // RK4 with a step of 0.9 s on the double pendulum (periods about 1.2 s) diverges.
  const auto dir = with_earlier_results();
  const auto csv = dir / "results.csv";
  const CommandResult r = run_command({kSim, "double_pendulum", "--integrator", "rk4", "--step",
                                       "0.9", "--t-end", "200", "--out", csv.string()});
  CHECK(r.exit_code == 1);
  // Blamed on the step (the rates grew from 0 to 4e16), the failure it led to named after.
  CHECK_THAT(r.err,
             Contains("error: t = 1.8: the run diverged at its fixed step of 0.9 s: the rate "
                      "of coordinate 'theta2' grew to 4.09e+16"));
  CHECK_THAT(r.err, Contains("(then: t = 2.7: bias force on coordinate 'theta1' is not finite"));
  CHECK_THAT(r.err,
             Contains(fmt::format("the run stopped; CSV: {} keeps its 181 rows up to t = 1.8",
                                  csv.string())));
  const std::string rows = read(csv);
  CHECK(std::count(rows.begin(), rows.end(), '\n') == 182);  // the header and 181 rows
  CHECK_FALSE(std::filesystem::exists(dir / "results.csv.partial"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("symdyn-sim: a bad scenario file is refused with its culprit, the earlier results kept",
          "[bad_input][sim]") {
  struct Case {
    std::string scenario, culprit;
    int exit_code;
  };
  const Case cases[] = {
      {"", "error: cannot read scenario file 'missing.json'", 2},
      {R"j({"model": "double_pendulum", "forces": [{"type": "plane_contact", "name": "c", "body": "rod3", "stiffness": 1}]})j",
       "error: scenario.json: /forces/0/body (force element 'c'): unknown body 'rod3' (bodies: "
       "rod1, rod2, or ground)",
       2},
      {R"j({"model": "double_pendulum", "t_end": 1e9})j",
       "error: the run would write 1e+11 rows (t-end / interval), over --max-rows 1e+07", 2},
      {R"j({"model": {"name": "double_pendulum", "module": "pendulum.so"}})j",
       "error: model module 'pendulum.so' not found", 2},
      // A check out of its band: the run is complete, its CSV written, the exit code says so.
      {R"j({"model": "double_pendulum", "checks": [{"name": "still", "value": "drift(theta1)", "band": [0, 0.1]}]})j",
       "still: 2.77851 (expected 0 .. 0.1) OUT OF RANGE", 1},
  };
  for (const Case& c : cases) {
    CAPTURE(c.scenario);
    const auto dir = with_earlier_results();
    const std::string file = c.scenario.empty() ? "missing.json" : "scenario.json";
    if (!c.scenario.empty()) std::ofstream(dir / file) << c.scenario;
    const CommandResult r = run_command({kSim, file, "--out", "results.csv"}, 120, dir);
    CHECK(r.exit_code == c.exit_code);
    CHECK_THAT(r.exit_code == 2 ? r.err : r.out, Contains(c.culprit));
    if (c.exit_code == 2) CHECK(read(dir / "results.csv") == "earlier results\n");
    CHECK_FALSE(std::filesystem::exists(dir / "results.csv.partial"));
    std::filesystem::remove_all(dir);
  }
}

TEST_CASE("symdyn-sim: --glb, --html and --plot write the run's pictures", "[sim]") {
  const auto dir = scratch_directory("sim_pictures");
  const auto at = [&](const char* name) { return (dir / name).string(); };
  std::vector<std::string> args{kSim,     "double_pendulum", "--t-end", "1",
                                "--out",  at("run.csv"),     "--glb",   at("run.glb"),
                                "--plot", at("run.svg")};
  const bool viewer = run_command({kSim, "double_pendulum", "--t-end", "0.1", "--out",
                                   at("probe.csv"), "--html", at("probe.html")})
                          .exit_code == 0;
  if (viewer) args.insert(args.end(), {"--html", at("run.html")});
  const CommandResult r = run_command(args);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(read(dir / "run.glb").substr(0, 4) == "glTF");  // the binary glTF header
  CHECK_THAT(read(dir / "run.svg"), Contains("<svg") && Contains("theta1") && Contains("theta2") &&
                                        Contains("total_energy"));
  if (viewer) {
    const std::string html = read(dir / "run.html");
    CHECK_THAT(html, Contains("<script id=\"symdyn-data\""));
    CHECK_THAT(html, Contains("\"names\":[\"t\",\"theta1\",\"theta2\"]"));
  }
}

namespace {

// The natural frequencies (Hz) in a modes CSV (column natural_frequency_hz).
std::vector<double> frequencies(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // the header
  std::vector<double> f;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string field;
    for (int k = 0; k < 4; ++k) std::getline(fields, field, ',');
    f.push_back(std::stod(field));
  }
  return f;
}

}  // namespace

TEST_CASE("symdyn-sim: --modes about the equilibrium, as clips and EasyAnim files", "[sim]") {
  const auto dir = scratch_directory("sim_modes");
  const auto at = [&](const char* name) { return (dir / name).string(); };
  const CommandResult r =
      run_command({kSim, "double_pendulum", "--t-end", "0.2", "--out", at("run.csv"), "--modes",
                   at("modes.csv"), "--glb", at("run.glb"), "--easyanim", at("run")});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  // Two uniform rods (m = 1, L = 1) hanging from a hinge: M = [4/3 1/2; 1/2 1/3],
  // K = g·[3/2 0; 0 1/2], so ω² = g·(3 ∓ 6/√7).
  const double g = 9.81;
  const std::vector<double> f = frequencies(read(dir / "modes.csv"));
  REQUIRE(f.size() == 2);
  CHECK(f[0] ==
        Approx(std::sqrt(g * (3 - 6 / std::sqrt(7.0))) / (2 * std::numbers::pi)).epsilon(1e-9));
  CHECK(f[1] ==
        Approx(std::sqrt(g * (3 + 6 / std::sqrt(7.0))) / (2 * std::numbers::pi)).epsilon(1e-9));
  CHECK_THAT(r.out, Contains("modes about the static equilibrium") && Contains("mode 1: 0.4265"));
  // The glTF holds the motion and one clip per mode; EasyAnim's files are there.
  CHECK_THAT(read(dir / "run.glb"),
             Contains("\"motion\"") && Contains("mode 1: ") && Contains("mode 2: "));
  for (const char* file : {"run.vol", "run.van", "run_modes.vol", "run_modes.vmo"}) {
    CAPTURE(file);
    CHECK(std::filesystem::file_size(dir / file) > 0);
  }
}

TEST_CASE("symdyn-sim: --modes of a model with closed loops, in its independent coordinates",
          "[sim][loops]") {
  const auto dir = scratch_directory("sim_modes_loops");
  const auto at = [&](const char* name) { return (dir / name).string(); };
  const CommandResult r = run_command({kSim, "four_bar", "--out", at("run.csv"), "--modes",
                                       at("modes.csv"), "--glb", at("run.glb")});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  // One degree of freedom about the hanging equilibrium: omega² = -dqdd/dq,
  // by central differences of the accelerations there.
  using namespace symdyn::runtime;
  MultibodySystem system(Model::from<symdyn_generated::four_bar>());
  State s = solve_statics(system, system.initial_state()).state;
  const double h = 1e-5, q = s.q(0);
  Vector plus, minus, yd;
  s.q(0) = q + h;
  system.accelerations(s, plus, yd);
  s.q(0) = q - h;
  system.accelerations(s, minus, yd);
  const double omega2 = -(plus(0) - minus(0)) / (2 * h);
  const std::vector<double> f = frequencies(read(dir / "modes.csv"));
  REQUIRE(f.size() == 1);
  CHECK(f[0] == Approx(std::sqrt(omega2) / (2 * std::numbers::pi)).epsilon(1e-7));
  CHECK_THAT(read(dir / "run.glb"), Contains("mode 1: "));
}

TEST_CASE("symdyn-sim: --modes-about and --mode-amplitude need --modes", "[bad_input][sim]") {
  const auto dir = with_earlier_results();
  for (const char* option : {"--modes-about", "--mode-amplitude"}) {
    CAPTURE(option);
    const std::string value = option == std::string("--modes-about") ? "initial" : "0.1";
    const CommandResult r = run_command(
        {kSim, "double_pendulum", "--out", (dir / "results.csv").string(), option, value});
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(fmt::format("{} requires --modes", option)));
    CHECK(read(dir / "results.csv") == "earlier results\n");
  }
}

TEST_CASE("symdyn-sim: results go to regular files only, refused before the run",
          "[bad_input][sim]") {
  const auto dir = with_earlier_results();
  const auto at = [&](const char* name) { return (dir / name).string(); };
  std::filesystem::create_directory(dir / "folder");
  REQUIRE(::mkfifo(at("pipe").c_str(), 0644) == 0);
  std::ofstream(dir / "locked.csv") << "kept\n";
  std::filesystem::permissions(
      dir / "locked.csv", std::filesystem::perms::owner_read | std::filesystem::perms::group_read);
  std::filesystem::create_directory(dir / "anim.vol");
  std::filesystem::create_symlink(dir / "nowhere" / "x.csv", dir / "dangling.csv");
  struct Case {
    std::vector<std::string> args;
    std::string culprit;
  };
  const Case cases[] = {
      // Written to FILE.partial and renamed over FILE, /dev/full became a regular file.
      {{"--out", "/dev/full"},
       "--out '/dev/full' is a character device: results are written to regular files only"},
      {{"--html", "/dev/full"}, "--html '/dev/full' is a character device"},
      {{"--glb", "/dev/null"}, "--glb '/dev/null' is a character device"},
      {{"--out", at("pipe")},
       fmt::format("--out '{}' is a FIFO: results are written to regular files only", at("pipe"))},
      {{"--out", at("folder")},
       fmt::format("--out '{}' is a directory: name a file in it", at("folder"))},
      {{"--out", at("folder") + "/"}, "names a folder: name a file in it"},
      {{"--out", ""}, "--out: expected a file name, found ''"},
      {{"--easyanim", ""}, "--easyanim: expected a file name, found ''"},
      {{"--modes", at("locked.csv")},
       fmt::format(
           "--modes '{}' is read-only: it is not replaced (make it writable, or name another file)",
           at("locked.csv"))},
      {{"--out", at("locked.csv")}, "is read-only"},
      {{"--html", "/proc/run.html"},
       "--html '/proc/run.html' cannot be written: the folder '/proc' is not writable"},
      {{"--plot", at("results.csv") + "/run.svg"},
       fmt::format("--plot '{}/run.svg' cannot be made: '{}' is a regular file, not a folder",
                   at("results.csv"), at("results.csv"))},
      {{"--easyanim", at("anim")}, fmt::format("--easyanim '{}.vol' is a directory", at("anim"))},
      {{"--out", at("dangling.csv")}, "is a symbolic link to nothing"},
      {{"--modes", at("results.csv")},
       fmt::format("--out '{0}' and --modes '{0}' are the same file: one would overwrite the other",
                   at("results.csv"))},
      {{"--html", at("run.view"), "--glb", at("run.view")},
       "--html '" + at("run.view") + "' and --glb '"},
      {{"--easyanim", at("results"), "--modes", at("results.van")}, "are the same file"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args);
    std::vector<std::string> args{kSim, "double_pendulum", "--t-end", "0.5"};
    if (c.args.front() != "--out") args.insert(args.end(), {"--out", at("results.csv")});
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CommandResult r = run_command(args);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(c.culprit));
    CHECK(r.out.empty());  // refused before the run: no summary
    CHECK(read(dir / "results.csv") == "earlier results\n");
    CHECK_FALSE(std::filesystem::exists(dir / "results.csv.partial"));
  }
  // Each special file is left as it was.
  CHECK(std::filesystem::is_character_file("/dev/full"));
  CHECK(std::filesystem::is_fifo(dir / "pipe"));
  CHECK(read(dir / "locked.csv") == "kept\n");
  CHECK(std::filesystem::is_directory(dir / "anim.vol"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("symdyn-sim: a scenario file is never an output", "[bad_input][sim]") {
  const auto dir = scratch_directory("sim_self");
  const std::string scenario = R"j({"model": "double_pendulum", "t_end": 0.1})j";
  std::ofstream(dir / "swing.json") << scenario;
  for (const char* option : {"--out", "--html", "--modes"}) {
    CAPTURE(option);
    const CommandResult r = run_command({kSim, "swing.json", option, "swing.json"}, 120, dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err,
               Contains(fmt::format("{} 'swing.json' is the scenario file: it would be overwritten",
                                    option)));
    CHECK(read(dir / "swing.json") == scenario);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("symdyn-sim: numbers on the command line are finite and positive, said in a few digits",
          "[bad_input][sim]") {
  const auto dir = with_earlier_results();
  struct Case {
    std::vector<std::string> args;
    std::string culprit;
  };
  const Case cases[] = {
      // CLI11's PositiveNumber lets NaN through, and printed DBL_MAX in 309 digits.
      {{"--t-end", "nan"}, "--t-end: expected a finite number > 0, found 'nan'"},
      {{"--t-end", "-1"}, "--t-end: expected a finite number > 0, found '-1'"},
      {{"--tolerance", "inf"}, "--tolerance: expected a finite number > 0, found 'inf'"},
      {{"--rtol", "0"}, "--rtol: expected a finite number > 0, found '0'"},
      {{"--atol", "NaN"}, "--atol: expected a finite number > 0, found 'NaN'"},
      {{"--interval", "1e999"}, "--interval: expected a finite number > 0, found '1e999'"},
      {{"--step", "-0.001"}, "--step: expected a finite number > 0, found '-0.001'"},
      {{"--max-rows", "nan"}, "--max-rows: expected a finite number > 0, found 'nan'"},
      {{"--modes", (dir / "m.csv").string(), "--mode-amplitude", "0"},
       "--mode-amplitude: expected a finite number > 0"},
      {{"--t-end", "ten"}, "--t-end: expected a finite number > 0, found 'ten'"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args);
    std::vector<std::string> args{kSim, "double_pendulum", "--out", (dir / "results.csv").string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CommandResult r = run_command(args);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(c.culprit));
    CHECK(r.err.find("0000000000") == std::string::npos);
    CHECK(read(dir / "results.csv") == "earlier results\n");
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("symdyn-sim: outputs through a link, in new folders, with a quote in the name", "[sim]") {
  const auto dir = scratch_directory("sim_paths");
  std::ofstream(dir / "target.csv") << "earlier\n";
  std::filesystem::create_symlink(dir / "target.csv", dir / "link.csv");
  const CommandResult linked = run_command(
      {kSim, "double_pendulum", "--t-end", "0.1", "--out", (dir / "link.csv").string()});
  CHECK(linked.exit_code == 0);
  CHECK(std::filesystem::is_symlink(dir / "link.csv"));  // the link kept, the file it names written
  CHECK(read(dir / "target.csv").rfind("t,theta1,theta2,", 0) == 0);
  // Missing folders are made when the run starts; gnuplot reads a name with a quote.
  const auto nested = dir / "a" / "b";
  std::vector<std::string> args{kSim,  "double_pendulum", "--t-end",
                                "0.1", "--out",           (nested / "it's.csv").string()};
  const bool gnuplot = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  if (gnuplot) args.insert(args.end(), {"--plot", (nested / "it's.svg").string()});
  const CommandResult made = run_command(args);
  INFO(made.err);
  CHECK(made.exit_code == 0);
  CHECK(std::filesystem::file_size(nested / "it's.csv") > 0);
  if (gnuplot) CHECK_THAT(read(nested / "it's.svg"), Contains("<svg"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("symdyn-sim: a directory or an empty file as the scenario is named as such",
          "[bad_input][sim]") {
  const auto dir = scratch_directory("sim_scenario");
  std::filesystem::create_directory(dir / "runs.json");
  std::ofstream(dir / "empty.json") << "\n";
  const CommandResult folder = run_command({kSim, "runs.json"}, 120, dir);
  CHECK(folder.exit_code == 2);
  CHECK_THAT(folder.err,
             Contains("error: scenario file 'runs.json' is a directory: name a JSON file"));
  const CommandResult empty = run_command({kSim, "empty.json"}, 120, dir);
  CHECK(empty.exit_code == 2);
  CHECK_THAT(empty.err,
             Contains("error: empty.json: the file is empty: a scenario is a JSON object"));
  std::filesystem::remove_all(dir);
}
