// Force laws given as C++ functions, with their derivatives and without: the
// trike's scenario (models/scenarios/trike.json, every element exact) with two
// laws more, a rolling resistance on the front wheel's spin (a CoordinateForce,
// Q = -c·tanh(qd/v0)) and the chassis' quadratic air drag at a point (a
// UserForce reading the velocities, F = -c·|v_P|·v_P), each given with its
// derivatives ("laws exact": CoordinateForce's LawDerivatives, UserForce's
// Jacobian) or not ("laws differenced": central differences of their Q alone,
// as MultibodySystem::jacobian_method says).
//
//   symdyn_bench_law_jacobians [--reps N]
//
// Output: tab-separated rows on stdout,
//   jacobian <laws exact|laws differenced> <us> <calls> <method>
//   run newmark <tol> <laws exact|laws differenced> <distance> <cpu_ms> <steps> <newton>
//       <residuals> <jacobians> <law calls>
// us: the median over 21 rounds of the CPU time of one MultibodySystem::jacobians
// at the scenario's end state (about 2 ms of calls per round, the two kinds
// interleaved); cpu_ms: the median over N repetitions (5) of one Newmark run over
// the scenario's 5 s (set-up excluded), interleaved; distance: the largest
// |q - q'|, |qd - qd'| at t_end between the run and the other kind's last run;
// law calls: evaluations of the two laws (their derivatives not counted).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>

namespace {

using namespace symdyn::runtime;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size()) / 2, v.end());
  return v[v.size() / 2];
}

constexpr double rolling = 20.0, rolling_speed = 0.5;  // N·m, rad/s
constexpr double drag = 0.4;                           // N·s²/m²
const Vec3 nose(0.5, 0.0, 0.2);                        // chassis axes, from G

// Adds the two laws to the scenario's system, with their derivatives or not; counts
// their evaluations.
void add_laws(MultibodySystem& system, bool with_derivatives, std::shared_ptr<long> calls) {
  const int spin = system.model().coordinate_index("front_spin");
  const int chassis = system.model().body_index("chassis");
  CoordinateForce::LawDerivatives rolling_derivatives;
  UserForce::Jacobian drag_jacobian;
  if (with_derivatives) {
    rolling_derivatives = [spin](double, double, double qd, const State&, Vector&, Vector& dQ_dqd) {
      const double th = std::tanh(qd / rolling_speed);
      dQ_dqd(spin) = -rolling / rolling_speed * (1.0 - th * th);
    };
    // Q_j = F·J_j, ∂F/∂v_P = -c·(|v_P|·I + v_P·v_Pᵀ/|v_P|).
    drag_jacobian = [chassis](const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                              Matrix& dQ_dq, Matrix& dQ_dqd) {
      const Vec3 v = k.point_velocity(chassis, nose), r = k.to_global(chassis, nose);
      const double speed = v.norm();
      const Vec3 F = -drag * speed * v;
      const Mat3 dF_dv = speed > 0.0
                             ? Mat3(-drag * (speed * Mat3::Identity() + v * v.transpose() / speed))
                             : Mat3::Zero();
      const auto n = static_cast<int>(s.q.size());
      for (int kk = 0; kk < n; ++kk) {
        const Vec3 dF_dq = dF_dv * dk.point_velocity_derivative(k, chassis, r, kk);
        const Vec3 dF_dqd = dF_dv * dk.point_partial(k, chassis, r, kk);
        for (int j = 0; j < n; ++j) {
          const Vec3 J = dk.point_partial(k, chassis, r, j);
          dQ_dq(j, kk) = dF_dq.dot(J) + F.dot(dk.point_partial_derivative(k, chassis, r, j, kk));
          dQ_dqd(j, kk) = dF_dqd.dot(J);
        }
      }
    };
  }
  system.add<CoordinateForce>(
      "rolling", spin,
      [calls](double, double, double qd, const State&) {
        ++*calls;
        return -rolling * std::tanh(qd / rolling_speed);
      },
      rolling_derivatives);
  system.add<UserForce>(
      "aero",
      [calls, chassis](const State&, const Kinematics& k, Loads& loads) {
        ++*calls;
        const Vec3 v = k.point_velocity(chassis, nose);
        loads.add_force_at(chassis, k, k.point_position(chassis, nose), -drag * v.norm() * v);
      },
      KinematicsLevel::velocities, drag_jacobian);
}

const char* label(bool exact) {
  return exact ? "laws exact" : "laws differenced";
}

struct Outcome {
  State final;
  Statistics stats;
  long law_calls = 0;
  double cpu = 0.0;  // s
};

Outcome run(bool exact, double tolerance) {
  symdyn::sim::RunOptions o;
  o.t_end = 5.0;
  o.integrator = "newmark";
  o.tolerance = tolerance;
  o.output_interval = o.t_end;
  symdyn::sim::Simulation sim(symdyn::sim::find_builtin("trike"), o);
  auto calls = std::make_shared<long>(0);
  add_laws(sim.system(), exact, calls);
  const double start = cpu_seconds();
  const symdyn::sim::RunResult r = sim.run();
  return {r.final, r.statistics, *calls, cpu_seconds() - start};
}

double distance(const State& a, const State& b) {
  return std::max((a.q - b.q).cwiseAbs().maxCoeff(), (a.qd - b.qd).cwiseAbs().maxCoeff());
}

// One Jacobian at s, each kind in a system of its own.
void time_jacobians(const State& s) {
  symdyn::sim::Simulation exact(symdyn::sim::find_builtin("trike")),
      differenced(symdyn::sim::find_builtin("trike"));
  MultibodySystem* systems[] = {&exact.system(), &differenced.system()};
  add_laws(*systems[0], true, std::make_shared<long>(0));
  add_laws(*systems[1], false, std::make_shared<long>(0));
  Vector qdd, yd;
  systems[0]->accelerations(s, qdd, yd);
  Matrix M, C, K;
  systems[0]->jacobians(s, qdd, M, C, K);
  const double once = cpu_seconds();
  systems[0]->jacobians(s, qdd, M, C, K);
  const int calls =
      std::clamp(static_cast<int>(2e-3 / std::max(cpu_seconds() - once, 1e-9)), 1, 1000);
  std::vector<double> times[2];
  for (int round = 0; round < 21; ++round) {
    for (int m = 0; m < 2; ++m) {
      const double start = cpu_seconds();
      for (int c = 0; c < calls; ++c) systems[m]->jacobians(s, qdd, M, C, K);
      times[m].push_back((cpu_seconds() - start) / calls);
    }
  }
  for (int m = 0; m < 2; ++m) {
    fmt::print("jacobian\t{}\t{:.2f}\t{}\t{}\n", label(m == 0), 1e6 * median(times[m]), calls,
               systems[m]->jacobian_method());
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  int reps = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc) {
      reps = std::stoi(argv[++i]);
    } else {
      fmt::print(stderr, "usage: symdyn_bench_law_jacobians [--reps N]\n");
      return 2;
    }
  }
  try {
    time_jacobians(run(true, 1e-4).final);
    for (const double tol : {1e-4, 1e-6}) {
      Outcome last[2];
      std::vector<double> cpu[2];
      for (int r = 0; r < reps; ++r) {
        for (int m = 0; m < 2; ++m) {
          last[m] = run(m == 0, tol);
          cpu[m].push_back(last[m].cpu);
        }
      }
      for (int m = 0; m < 2; ++m) {
        const Statistics& s = last[m].stats;
        fmt::print("run\tnewmark\t{:g}\t{}\t{:.3g}\t{:.2f}\t{}\t{}\t{}\t{}\t{}\n", tol,
                   label(m == 0), distance(last[0].final, last[1].final), 1e3 * median(cpu[m]),
                   s.steps, s.newton_iterations, s.residual_evaluations, s.jacobian_evaluations,
                   last[m].law_calls);
      }
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "symdyn_bench_law_jacobians: {}\n", e.what());
    return 1;
  }
  return 0;
}
