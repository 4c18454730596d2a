// symdyn_paper_bench: the measurements of one row of the paper tables, on one
// compiled emitted model (a shared object built by run.sh from the emitted
// code and adapter.cpp):
//
//   symdyn_paper_bench --lib LIB.so --model NAME --variant V --case 1..4 [--reps 7] [--out
//   FILE.json] symdyn_paper_bench ... --count T1|T2 [--count-evaluations N]
//
// T1: seconds for 10 000 evaluations of the kinematics of all bodies, as the
//     paper: the emitted accelerations() (positions, velocities, accelerations
//     of every body), plus partial_velocities() when the partials are symbolic
//     (cases 3 and 4). T1_partials: 10 000 partial_velocities() alone, in
//     every case (numeric partials in cases 1 and 2: nq + 1 velocity calls).
// T2: seconds for 1 000 evaluations of the equations of motion under gravity
//     (no force element): runtime::MultibodySystem::accelerations, i.e. mass
//     matrix, right-hand side and LDLT solve for qdd; assembled from the
//     kinematics and partial velocities in cases 1-3 (EasyDyn's way), from
//     the emitted mass_matrix and bias_forces in case 4.
// Each is the median of --reps runs (each at least 50 ms long, repeating the
// evaluations), in CPU time of the measuring thread
// (and the fastest run, as <name>_min). Errors: against the independent
// reference of reference.hpp at --states random states (seeded: the same
// states in every case), each as max |emitted - reference| / max(1, max |reference|)
// over the array. The qdd at those states are printed too, so that the report
// compares the cases with each other.
// --count T1|T2 runs that workload alone, warmed once, then N times inside
// counted_workload(), for valgrind --tool=callgrind
// --toggle-collect='*counted_workload*': instructions are repeatable where
// timings on a shared machine are not (run.sh records them for cases 1 and 2).
#include <dlfcn.h>
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>

#include "plugin.hpp"
#include "reference.hpp"
#include <symdyn/model/model.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn;
using nlohmann::json;

struct Arguments {
  std::string lib, model, variant, out;
  int case_number = 0;
  int reps = 7;
  int states = 3;
  int kinematics_evaluations = 10000;
  int eom_evaluations = 1000;
  std::string count;  // T1 or T2: run that workload for callgrind instead of timing
  int count_evaluations = 10;
  double amplitude = 0.1;
  unsigned seed = 2013;
};

const paper::PluginModel& load(const std::string& path) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr)
    throw std::runtime_error(fmt::format("cannot load '{}': {}", path, dlerror()));
  auto fn = reinterpret_cast<const paper::PluginModel* (*)()>(dlsym(handle, paper::plugin_symbol));
  if (fn == nullptr)
    throw std::runtime_error(fmt::format("'{}' has no symbol {}", path, paper::plugin_symbol));
  return *fn();
}

runtime::Model to_model(const paper::PluginModel& p) {
  runtime::ModelDescription d;
  d.model = p.model;
  d.variant = p.variant;
  d.nq = p.nq;
  d.nbody = p.nbody;
  d.ndep = p.ndep;
  d.nparam = p.nparam;
  d.q_names.assign(p.q_names, p.q_names + p.nq);
  d.q_initial.assign(p.q_initial, p.q_initial + p.nq);
  d.qd_initial.assign(p.qd_initial, p.qd_initial + p.nq);
  d.body_names.assign(p.body_names, p.body_names + p.nbody);
  d.reference_body.assign(p.reference_body, p.reference_body + p.nbody);
  d.param_names.assign(p.param_names, p.param_names + p.nparam);
  d.param_defaults.assign(p.param_defaults, p.param_defaults + p.nparam);
  d.gravity = runtime::Vec3(p.gravity[0], p.gravity[1], p.gravity[2]);
  d.inertia = p.inertia;
  d.positions = p.positions;
  d.velocities = p.velocities;
  d.accelerations = p.accelerations;
  d.partial_velocities = p.partial_velocities;
  d.dependent_parameters = p.dependent_parameters;
  d.mass_matrix = p.mass_matrix;
  d.bias_forces = p.bias_forces;
  return runtime::Model(std::move(d));
}

// CPU time of this thread: on a machine shared with other jobs, wall time
// counts the time spent descheduled, this does not.
double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Timing {
  double median = 0.0, min = 0.0;
};

// Seconds (thread CPU time) per `evaluations` calls of f, over `reps` runs:
// the median, and the fastest run (least disturbed by other jobs' use of
// caches). A run repeats the `evaluations` calls until it lasts at least
// 50 ms, so that the small models' runs (0.5 ms for 10 000 kinematics) are
// not mostly timer and scheduler noise.
template <class F>
Timing time_runs(int reps, int evaluations, F&& f) {
  const double warm_start = thread_seconds();
  for (int i = 0; i < std::max(1, evaluations / 10); ++i) f();  // warm caches and branch predictors
  const double per_call = (thread_seconds() - warm_start) / std::max(1, evaluations / 10);
  const int batches =
      std::max(1, static_cast<int>(std::ceil(0.05 / std::max(1e-12, per_call * evaluations))));
  std::vector<double> runs;
  for (int r = 0; r < reps; ++r) {
    const double start = thread_seconds();
    for (int b = 0; b < batches; ++b) {
      for (int i = 0; i < evaluations; ++i) f();
    }
    runs.push_back((thread_seconds() - start) / batches);
  }
  std::sort(runs.begin(), runs.end());
  return {runs[runs.size() / 2], runs.front()};
}

double error(const double* emitted, const std::vector<double>& reference) {
  double scale = 1.0, worst = 0.0;
  for (double r : reference) scale = std::max(scale, std::abs(r));
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const double e = std::abs(emitted[k] - reference[k]);
    worst = std::max(worst, std::isfinite(e) ? e : INFINITY);
  }
  return worst / scale;
}

std::vector<paper::StateSample> random_states(const Arguments& args, const runtime::Model& m) {
  std::mt19937 rng(args.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<paper::StateSample> states;
  const int nq = m.nq();
  for (int k = 0; k < args.states; ++k) {
    paper::StateSample s;
    s.t = u(rng);
    s.q.resize(nq);
    s.qd.resize(nq);
    s.qdd.resize(nq);
    // Near the initial configuration: a closed loop (amru5's legs) must close.
    for (int j = 0; j < nq; ++j) s.q(j) = m.initial_state().q(j) + args.amplitude * u(rng);
    for (int j = 0; j < nq; ++j) s.qd(j) = u(rng);
    for (int j = 0; j < nq; ++j) s.qdd(j) = u(rng);
    states.push_back(s);
  }
  return states;
}

runtime::State to_state(const paper::StateSample& s) {
  runtime::State state;
  state.t = s.t;
  state.q = s.q;
  state.qd = s.qd;
  return state;
}

json errors(const Arguments& args, runtime::Model& m, runtime::MultibodySystem& system,
            const paper::Reference& reference, const std::vector<paper::StateSample>& states) {
  json out;
  double pos = 0, vel = 0, acc = 0, pv = 0, qdd = 0;
  json qdds = json::array();
  runtime::Kinematics k = m.make_kinematics();
  for (const auto& s : states) {
    const paper::BodyKinematics r = reference.kinematics(s);
    m.accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), k);
    m.partial_velocities(s.t, s.q.data(), k);
    pos = std::max({pos, error(k.R_data(), r.R), error(k.x_data(), r.x)});
    vel = std::max({vel, error(k.v_data(), r.v), error(k.w_data(), r.w)});
    acc = std::max({acc, error(k.a_data(), r.a), error(k.dw_data(), r.dw)});
    pv = std::max({pv, error(k.dv_dqd_data(), r.dv), error(k.dw_dqd_data(), r.dwq)});
    runtime::Vector a(m.nq()), yd(0);
    system.accelerations(to_state(s), a, yd);
    const Eigen::VectorXd expected = reference.accelerations(s);
    qdd = std::max(qdd, error(a.data(), std::vector<double>(expected.data(),
                                                            expected.data() + expected.size())));
    qdds.push_back(std::vector<double>(a.data(), a.data() + a.size()));
  }
  out["positions"] = pos;
  out["velocities"] = vel;
  out["accelerations"] = acc;
  out["partial_velocities"] = pv;
  out["qdd"] = qdd;
  out["max"] = std::max({pos, vel, acc, pv, qdd});
  out["qdd_at_states"] = qdds;
  out["states"] = args.states;
  return out;
}

// T1's kinematics: accelerations, and symbolic partial velocities in cases 3-4.
void kinematics_workload(const Arguments& args, runtime::Model& m, const paper::StateSample& s,
                         runtime::Kinematics& k) {
  m.accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), k);
  if (args.case_number >= 3) m.partial_velocities(s.t, s.q.data(), k);
}

json timings(const Arguments& args, runtime::Model& m, runtime::MultibodySystem& system,
             const paper::StateSample& s) {
  runtime::Kinematics k = m.make_kinematics();
  json out;
  auto record = [&](const char* name, Timing timing) {
    out[name] = timing.median;
    out[std::string(name) + "_min"] = timing.min;
  };
  record("T1", time_runs(args.reps, args.kinematics_evaluations,
                         [&] { kinematics_workload(args, m, s, k); }));
  record("T1_accelerations", time_runs(args.reps, args.kinematics_evaluations, [&] {
           m.accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), k);
         }));
  record("T1_partials", time_runs(args.reps, args.kinematics_evaluations,
                                  [&] { m.partial_velocities(s.t, s.q.data(), k); }));
  const runtime::State state = to_state(s);
  runtime::Vector qdd(m.nq()), yd(0);
  record("T2",
         time_runs(args.reps, args.eom_evaluations, [&] { system.accelerations(state, qdd, yd); }));
  out["reps"] = args.reps;
  out["kinematics_evaluations"] = args.kinematics_evaluations;
  out["eom_evaluations"] = args.eom_evaluations;
  return out;
}

// The loop callgrind counts (--toggle-collect); not inlined, so that it has a name.
[[gnu::noinline]] void counted_workload(int evaluations, const std::function<void()>& f) {
  for (int i = 0; i < evaluations; ++i) f();
}

// One workload for callgrind: warmed by a first call (lazy symbol binding,
// first-touch allocations), then counted.
json count(const Arguments& args, runtime::Model& m, runtime::MultibodySystem& system,
           const paper::StateSample& s) {
  runtime::Kinematics k = m.make_kinematics();
  const runtime::State state = to_state(s);
  runtime::Vector qdd(m.nq()), yd(0);
  std::function<void()> f = [&] { kinematics_workload(args, m, s, k); };
  if (args.count == "T2") f = [&] { system.accelerations(state, qdd, yd); };
  f();
  counted_workload(args.count_evaluations, f);
  return {{"count", args.count}, {"evaluations", args.count_evaluations}};
}

int run(const Arguments& args) {
  const paper::PluginModel& plugin = load(args.lib);
  runtime::Model m = to_model(plugin);
  const model::Model definition = model::find_definition(args.model).make(args.variant);
  const paper::Reference reference(definition);
  if (reference.nq() != m.nq() || reference.nbody() != m.nbody()) {
    throw std::runtime_error(
        fmt::format("'{}' is not model {} variant {}", args.lib, args.model, args.variant));
  }
  const auto source = args.case_number == 4 ? runtime::EquationsSource::emitted
                                            : runtime::EquationsSource::assembled;
  runtime::MultibodySystem system(m, source);
  const auto states = random_states(args, m);
  json out;
  if (!args.count.empty()) {
    std::cout << count(args, m, system, states.front()).dump() << '\n';
    return 0;
  }
  out["model"] = args.model;
  out["variant"] = args.variant;
  out["case"] = args.case_number;
  out["nq"] = m.nq();
  out["nbody"] = m.nbody();
  out["ndep"] = m.ndep();
  out["equations"] = args.case_number == 4 ? "emitted" : "assembled";
  out["errors"] = errors(args, m, system, reference, states);
  out["timings"] = timings(args, m, system, states.front());
  if (args.out.empty()) {
    std::cout << out.dump(2) << '\n';
  } else {
    std::ofstream(args.out) << out.dump(2) << '\n';
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  CLI::App app{"symdyn_paper_bench: T1, T2 and errors of one compiled emitted model"};
  app.add_option("--lib", args.lib, "shared object of the emitted code and adapter.cpp")
      ->required();
  app.add_option("--model", args.model, "model name (its definition is linked in)")->required();
  app.add_option("--variant", args.variant, "model variant")->required();
  app.add_option("--case", args.case_number, "the paper's case 1-3, or 4 (emitted equations)")
      ->required()
      ->check(CLI::Range(1, 4));
  app.add_option("--reps", args.reps, "timed repetitions (median)")->capture_default_str();
  app.add_option("--states", args.states, "random states for the errors")->capture_default_str();
  app.add_option("--kinematics-evaluations", args.kinematics_evaluations, "calls per T1 run")
      ->capture_default_str();
  app.add_option("--eom-evaluations", args.eom_evaluations, "calls per T2 run")
      ->capture_default_str();
  app.add_option("--count", args.count, "run workload T1 or T2 for callgrind instead of timing")
      ->check(CLI::IsMember({"T1", "T2"}));
  app.add_option("--count-evaluations", args.count_evaluations, "calls of the counted workload")
      ->capture_default_str();
  app.add_option("--amplitude", args.amplitude, "random q = q_initial + amplitude*U(-1,1)")
      ->capture_default_str();
  app.add_option("--seed", args.seed, "seed of the random states")->capture_default_str();
  app.add_option("--out", args.out, "JSON output file (default: stdout)");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(args);
  } catch (const std::exception& e) {
    std::cerr << "symdyn_paper_bench: " << e.what() << '\n';
    return 1;
  }
}
