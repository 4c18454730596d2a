// Work-precision: CPU time against the final-state error of every integrator of
// make_integrator's table on the reference models (their symdyn-sim scenarios,
// force elements included), over a range of tolerances (steps for rk4 and
// midpoint); on the double pendulum over 1 s also MuJoCo's and Simbody's
// integrators on the same mechanism (bench/peers/mechanism.hpp). The problems are
// those of models/scenarios (problems.hpp).
//
//   symdyn_bench_work_precision [--reps N] [--budget S] [--problem NAME]... [--integrator NAME]...
//   (bench/work_precision/run.sh runs it and writes bench/results/work_precision.*)
// --integrator: only these of symdyn's integrators, and no peer (newmark-extrapolated:
// newmark's fixed steps halved to a global tolerance, extrapolated).
//
// Output: tab-separated rows on stdout,
//   reference <problem> <agreement> <description>
//   run       <problem> <library> <integrator> <tol|h> <setting> <error> <cpu_ms> <steps>
//   <rejected> <rhs> fail      <problem> <library> <integrator> <tol|h> <setting> <message> check
//   <problem> <library> <integrator> <setting> <error at t_end/2> <error at t_end> <ok|DISAGREES>
// error: the largest |q - q_ref|, |qd - qd_ref| at t_end; q_ref from dop853 at
// rtol = atol = 1e-13, its agreement: the same distance to dopri5 at 1e-13.
// cpu_ms: median over the repetitions of the process CPU time of one run (each
// repetition times a batch of runs lasting at least 10 ms).
#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "../peers/mechanism.hpp"
#include "peer_integration.hpp"
#include "problems.hpp"
#include "run.hpp"
#include "scenario.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using symdyn::runtime::IntegratorOptions;
using symdyn::runtime::MultibodySystem;
using symdyn::runtime::State;
using symdyn::runtime::Statistics;
using symdyn::runtime::Vector;
namespace wp = symdyn::bench::work_precision;

// A scenario's model over an interval.
struct Problem {
  std::string name;
  std::string model;  // its scenario (apps/sim)
  double t_end;
};
const Problem all_problems[] = {
    {"double_pendulum_1s", "double_pendulum", 1.0},
    {"double_pendulum_10s", "double_pendulum", 10.0},
    {"slider_crank_1s", "slider_crank", 1.0},
    {"slider_crank_100s", "slider_crank", 100.0},
    {"robot3d_10s", "robot3d", 10.0},
    {"trike_5s", "trike", 5.0},
    // robot3d's thrown motion is chaotic: over 10 s two references at 1e-13 differ by 2e-3.
    {"robot3d_1s", "robot3d", 1.0},
};

// The settings swept: tolerances (rtol = atol) for the adaptive integrators, steps
// per second for the fixed-step ones (h = 1 / N).
const std::vector<double> tolerances = {1e-3, 1e-4, 1e-5,  1e-6,  1e-7,
                                        1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
const std::vector<double> steps_per_second = {30, 100, 300, 1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 1e6};

bool fixed_step(const std::string& integrator) {
  return integrator == "rk4" || integrator == "midpoint";
}

// newmark at fixed steps halved from 8e-3 until the setting is met as a global tolerance,
// its last two runs extrapolated (IntegratorOptions::global_tolerance): not a scenario's.
const std::string kExtrapolated = "newmark-extrapolated";
constexpr double kHalvingFrom = 8e-3;

// A problem's system and initial state; the trike (expressions in its scenario) runs
// through symdyn::sim::Simulation instead, built at each run (a small part of its cost).
struct System {
  std::unique_ptr<MultibodySystem> system;
  State initial;
  std::string scenario;  // non-empty: run the built-in scenario of that name
};

System make_system(const std::string& model) {
  const auto from = [](symdyn::bench::ProblemSystem p) {
    return System{std::move(p.system), p.initial, ""};
  };
  if (model == "double_pendulum") return from(symdyn::bench::double_pendulum_problem());
  if (model == "slider_crank") return from(symdyn::bench::slider_crank_problem());
  if (model == "robot3d") return from(symdyn::bench::robot3d_problem());
  return System{nullptr, {}, model};
}

State solve(System& s, const std::string& integrator, double setting, double t_end,
            Statistics* stats = nullptr) {
  if (!s.scenario.empty()) {
    symdyn::sim::RunOptions ro;
    ro.t_end = t_end;
    ro.integrator = integrator;
    ro.output_interval = t_end;
    if (fixed_step(integrator))
      ro.step = setting;
    else
      ro.tolerance = setting;
    symdyn::sim::Simulation sim(symdyn::sim::find_builtin(s.scenario), ro);
    const symdyn::sim::RunResult r = sim.run();
    if (stats != nullptr) *stats = r.statistics;
    return r.final;
  }
  IntegratorOptions o;
  o.relative_tolerance = o.absolute_tolerance = fixed_step(integrator) ? 1e-6 : setting;
  if (fixed_step(integrator)) o.initial_step = setting;
  o.output_times = {t_end};
  if (integrator == kExtrapolated) {
    o.relative_tolerance = o.absolute_tolerance = 1e-6;
    o.fixed_step = true;
    o.initial_step = kHalvingFrom;
    o.global_tolerance = setting;
  }
  auto integ = symdyn::runtime::make_integrator(
      integrator == kExtrapolated ? std::string("newmark") : integrator, o);
  State end = integ->integrate(*s.system, s.initial, t_end);
  if (stats != nullptr) *stats = integ->statistics();
  return end;
}

double max_error(const Vector& q, const Vector& qd, const State& ref) {
  return std::max((q - ref.q).cwiseAbs().maxCoeff(), (qd - ref.qd).cwiseAbs().maxCoeff());
}

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The median CPU time of one call of `run` over `reps` batches of at least 10 ms.
double median_cpu(const std::function<void()>& run, int reps) {
  double t0 = cpu_seconds();
  run();
  const double once = std::max(cpu_seconds() - t0, 1e-7);
  if (once > 1.0) reps = std::min(reps, 3);
  const long batch = std::max(1L, static_cast<long>(std::ceil(0.01 / once)));
  std::vector<double> times;
  for (int r = 0; r < reps; ++r) {
    t0 = cpu_seconds();
    for (long k = 0; k < batch; ++k) run();
    times.push_back((cpu_seconds() - t0) / static_cast<double>(batch));
  }
  std::nth_element(times.begin(), times.begin() + static_cast<long>(times.size()) / 2, times.end());
  return times[times.size() / 2];
}

struct Options {
  int reps = 5;
  double budget = 1.0;  // s of CPU for one run: tighter settings of the same sweep are skipped
  std::vector<std::string> problems;
  std::vector<std::string> integrators;  // empty: every one, and the peers
};

bool chosen(const std::vector<std::string>& names, const std::string& name) {
  return names.empty() || std::find(names.begin(), names.end(), name) != names.end();
}

void sweep_symdyn(const Problem& p, System& s, const State& ref, const std::string& integrator,
                  const Options& opt) {
  const bool fixed = fixed_step(integrator);
  for (double setting : fixed ? steps_per_second : tolerances) {
    const double value = fixed ? 1.0 / setting : setting;
    const std::string kind = fixed ? "h" : integrator == kExtrapolated ? "global" : "tol";
    Statistics st;
    State end;
    try {
      end = solve(s, integrator, value, p.t_end, &st);
    } catch (const std::exception& e) {
      fmt::print("fail\t{}\tsymdyn\t{}\t{}\t{:g}\t{}\n", p.name, integrator, kind, value, e.what());
      std::fflush(stdout);
      continue;
    }
    const double cpu = median_cpu([&] { solve(s, integrator, value, p.t_end); }, opt.reps);
    fmt::print("run\t{}\tsymdyn\t{}\t{}\t{:g}\t{:.3e}\t{:.5g}\t{}\t{}\t{}\n", p.name, integrator,
               kind, value, max_error(end.q, end.qd, ref), 1e3 * cpu, st.steps, st.rejected_steps,
               st.rhs_evaluations);
    std::fflush(stdout);
    if (cpu > opt.budget) break;
  }
}

// Whether `run` returns in a child process: a library that aborts on an assertion
// (Debian builds Simbody without NDEBUG) then fails one row instead of the whole bench.
bool survives(const std::function<void()>& run) {
  std::fflush(stdout);
  const pid_t child = fork();
  if (child == 0) {
    try {
      run();
    } catch (...) {
    }
    _exit(0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// A peer's run at `setting`: its final error against the reference, and against the
// reference at t_end/2 (the trajectory check). Unused when no peer is built in.
[[maybe_unused]] void sweep_peer(
    const Problem& p, System& s, const State& ref, const State& half, const std::string& library,
    const std::string& integrator, const std::vector<double>& settings, const Options& opt,
    const std::function<std::unique_ptr<wp::PeerIntegration>(double)>& make) {
  const bool fixed = library == "MuJoCo";
  const std::string kind = fixed ? "h" : "tol";
  double finest_half = 0.0, finest_end = 0.0, finest = 0.0;
  for (double setting : settings) {
    const double value = fixed ? 1.0 / setting : setting;
    try {
      auto peer = make(value);
      if (!survives([&] { peer->run(s.initial.q, s.initial.qd, p.t_end); })) {
        fmt::print(
            "fail\t{}\t{}\t{}\t{}\t{:g}\tthe process aborted inside the library (see stderr)\n",
            p.name, library, integrator, kind, value);
        break;  // every setting aborts alike
      }
      peer->run(s.initial.q, s.initial.qd, p.t_end / 2);
      finest_half = max_error(peer->q(), peer->qd(), half);
      peer->run(s.initial.q, s.initial.qd, p.t_end);
      finest_end = max_error(peer->q(), peer->qd(), ref);
      finest = value;
      const long steps = peer->steps();
      const double cpu =
          median_cpu([&] { peer->run(s.initial.q, s.initial.qd, p.t_end); }, opt.reps);
      fmt::print("run\t{}\t{}\t{}\t{}\t{:g}\t{:.3e}\t{:.5g}\t{}\t\t\n", p.name, library, integrator,
                 kind, value, finest_end, 1e3 * cpu, steps);
      std::fflush(stdout);
      if (cpu > opt.budget) break;
    } catch (const std::exception& e) {
      fmt::print("fail\t{}\t{}\t{}\t{}\t{:g}\t{}\n", p.name, library, integrator, kind, value,
                 e.what());
    }
  }
  // The finest setting must follow the reference trajectory: 1e-4 at both instants (the
  // first-order methods reach 1e-5 only past a million steps).
  const bool ok = finest > 0.0 && finest_half < 1e-4 && finest_end < 1e-4;
  fmt::print("check\t{}\t{}\t{}\t{:g}\t{:.3e}\t{:.3e}\t{}\n", p.name, library, integrator, finest,
             finest_half, finest_end,
             finest == 0.0 ? "no run"
             : ok          ? "ok"
                           : "DISAGREES");
  std::fflush(stdout);
}

void peers_on(const Problem& p, System& s, [[maybe_unused]] const State& ref,
              [[maybe_unused]] const Options& opt) {
  [[maybe_unused]] const symdyn::bench::peers::Mechanism mech =
      symdyn::bench::peers::double_pendulum();
  [[maybe_unused]] const State half = solve(s, "dop853", 1e-13, p.t_end / 2);
#ifdef SYMDYN_HAVE_MUJOCO
  for (const std::string& integrator : wp::mujoco_integrators()) {
    sweep_peer(p, s, ref, half, "MuJoCo", integrator, steps_per_second, opt,
               [&](double h) { return wp::make_mujoco_integration(mech, integrator, h); });
  }
#endif
#ifdef SYMDYN_HAVE_SIMBODY
  for (const std::string& integrator : wp::simbody_integrators()) {
    sweep_peer(p, s, ref, half, "Simbody", integrator, tolerances, opt,
               [&](double tol) { return wp::make_simbody_integration(mech, integrator, tol); });
  }
#endif
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 < argc && a == "--reps") {
      o.reps = std::stoi(argv[++i]);
    } else if (i + 1 < argc && a == "--budget") {
      o.budget = std::stod(argv[++i]);
    } else if (i + 1 < argc && a == "--problem") {
      o.problems.emplace_back(argv[++i]);
    } else if (i + 1 < argc && a == "--integrator") {
      o.integrators.emplace_back(argv[++i]);
    } else {
      throw std::invalid_argument(
          "usage: symdyn_bench_work_precision [--reps N] [--budget S] [--problem NAME]... "
          "[--integrator NAME]...");
    }
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options opt = parse(argc, argv);
  for (const Problem& p : all_problems) {
    if (!chosen(opt.problems, p.name)) continue;
    System s = make_system(p.model);
    const State ref = solve(s, "dop853", 1e-13, p.t_end);
    const State second = solve(s, "dopri5", 1e-13, p.t_end);
    const double agreement = max_error(second.q, second.qd, ref);
    fmt::print("reference\t{}\t{:.3e}\tdop853 at 1e-13 against dopri5 at 1e-13\n", p.name,
               agreement);
    std::fflush(stdout);
    for (const std::string& integrator : symdyn::runtime::integrator_names()) {
      if (chosen(opt.integrators, integrator)) sweep_symdyn(p, s, ref, integrator, opt);
    }
    if (s.scenario.empty() && chosen(opt.integrators, kExtrapolated))
      sweep_symdyn(p, s, ref, kExtrapolated, opt);
    if (p.name == "double_pendulum_1s" && opt.integrators.empty()) peers_on(p, s, ref, opt);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "symdyn_bench_work_precision: %s\n", e.what());
  return 1;
}
