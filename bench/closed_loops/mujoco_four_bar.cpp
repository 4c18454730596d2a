// The four-bar (models/four_bar.cpp) against MuJoCo's equality constraint
// (connect), the same masses, inertias and geometry: the accelerations at
// the same states first, then the forward dynamics per call, a work-precision
// over 10 s and the loop's drift (bench/results/closed_loops.md).
//
// MuJoCo closes the loop with a soft constraint: its accelerations solve a
// regularized problem (impedance d, solimp) and its position error is pulled
// back by a spring-damper (solref), so the loop opens slightly and drifts.
// symdyn solves the loop's equations by Newton at every evaluation.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "four_bar.hpp"
#include "mujoco_bench.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;
using namespace symdyn_bench;

constexpr double r1 = 0.1, r2 = 0.35, r3 = 0.3, d = 0.4;  // models/four_bar.cpp

// The loop's assembly at q0 = 0 (symdyn's, from its guesses): MuJoCo's bodies
// are written in it, its qpos0, where a connect constraint holds.
struct Assembly {
  double phi0, psi0;
};

std::string mjcf(const Assembly& a, const std::string& solimp) {
  const auto rod = [](double m, double l) { return m * l * l / 12; };
  char text[4096];
  std::snprintf(text, sizeof text,
                R"(<mujoco model="four_bar">
  <option gravity="0 -9.81 0" integrator="RK4" timestep="0.001"/>
  <worldbody>
    <body name="crank">
      <joint name="q0" type="hinge" axis="0 0 1"/>
      <inertial pos="%.17g 0 0" mass="0.2" diaginertia="1e-6 %.17g %.17g"/>
      <body name="coupler" pos="%.17g 0 0" quat="%.17g 0 0 %.17g">
        <joint name="phi" type="hinge" axis="0 0 1"/>
        <inertial pos="%.17g 0 0" mass="0.5" diaginertia="1e-6 %.17g %.17g"/>
      </body>
    </body>
    <body name="rocker" pos="%.17g 0 0" quat="%.17g 0 0 %.17g">
      <joint name="psi" type="hinge" axis="0 0 1"/>
      <inertial pos="%.17g 0 0" mass="0.4" diaginertia="1e-6 %.17g %.17g"/>
    </body>
  </worldbody>
  <equality>
    <connect body1="coupler" body2="rocker" anchor="%.17g 0 0" %s/>
  </equality>
</mujoco>
)",
                r1 / 2, rod(0.2, r1), rod(0.2, r1), r1, std::cos(a.phi0 / 2), std::sin(a.phi0 / 2),
                r2 / 2, rod(0.5, r2), rod(0.5, r2), d, std::cos(a.psi0 / 2), std::sin(a.psi0 / 2),
                r3 / 2, rod(0.4, r3), rod(0.4, r3), r2, solimp.c_str());
  return text;
}

// MuJoCo's state from symdyn's extended one (x = q0, phi, psi).
void set_state(const mjModel*, mjData* data, const State& x, const Assembly& a) {
  data->time = x.t;
  data->qpos[0] = x.q(0);
  data->qpos[1] = x.q(1) - a.phi0;
  data->qpos[2] = x.q(2) - a.psi0;
  for (int j = 0; j < 3; ++j) data->qvel[j] = x.qd(j);
}

// |C_coupler - C_rocker|: the loop's opening (m), from MuJoCo's body poses.
double opening(const mjData* data) {
  double c[2][3];
  const int body[2] = {2, 3};
  const double local[2] = {r2, r3};
  for (int k = 0; k < 2; ++k) {
    const double* x = data->xpos + 3 * body[k];
    const double* R = data->xmat + 9 * body[k];
    for (int i = 0; i < 3; ++i) c[k][i] = x[i] + R[3 * i] * local[k];
  }
  return std::hypot(c[0][0] - c[1][0], c[0][1] - c[1][1], c[0][2] - c[1][2]);
}

}  // namespace

int main() {
  MultibodySystem system(Model::from<symdyn_generated::four_bar>());
  const State start = system.initial_state();  // q0 = 0, qd0 = 5 rad/s
  const State x0 = system.extended_state(start);
  const Assembly a{x0.q(1), x0.q(2)};
  const std::vector<ConstraintSetting> settings = constraint_settings();

  // 1. The accelerations at the same states, q0 around the circle, at rest
  // (gravity alone) and moving (qd0 from 5 to -1.3 rad/s).
  std::printf("## Accelerations at the same states\n\n");
  std::printf(
      "| MuJoCo constraint | max rel. difference of qdd0, at rest | the same, moving |\n"
      "|---|---:|---:|\n");
  for (const auto& [name, solimp] : settings) {
    mjModel* m = load_mjcf(mjcf(a, solimp), "four_bar");
    mjData* data = mj_makeData(m);
    double worst[2] = {0, 0}, scale[2] = {0, 0};
    State s = start;
    Vector qdd, yd;
    system.reset_loops();
    for (int k = 0; k < 64; ++k) {
      for (int moving = 0; moving < 2; ++moving) {
        s.q(0) = 2 * M_PI * k / 64;
        s.qd(0) = moving ? 5.0 - 0.1 * k : 0.0;
        system.accelerations(s, qdd, yd);
        set_state(m, data, system.extended_state(s), a);
        mj_forward(m, data);
        worst[moving] = std::max(worst[moving], std::abs(data->qacc[0] - qdd(0)));
        scale[moving] = std::max(scale[moving], std::abs(qdd(0)));
      }
    }
    std::printf("| %s | %.2g | %.2g |\n", name, worst[0] / scale[0], worst[1] / scale[1]);
    mj_deleteData(data);
    mj_deleteModel(m);
  }

  // 2. Forward dynamics per call along a slow trajectory (q0 advancing 1e-4 rad a call).
  std::printf("\n## Forward dynamics per call (CPU, median of 5 x 200000 calls)\n\n");
  std::printf("| engine | ns per call |\n|---|---:|\n");
  {
    State s = start;
    Vector qdd, yd;
    system.reset_loops();
    const double ns = per_call_ns(
        [&](int k) {
          s.q(0) = 1e-4 * (k % 100000);
          system.accelerations(s, qdd, yd);
        },
        200000);
    std::printf("| symdyn accelerations() | %.0f |\n", ns);
  }
  for (const auto& [name, solimp] : settings) {
    mjModel* m = load_mjcf(mjcf(a, solimp), "four_bar");
    mjData* data = mj_makeData(m);
    system.reset_loops();
    set_state(m, data, x0, a);
    const double ns = per_call_ns(
        [&](int k) {
          data->qpos[0] = 1e-4 * (k % 100000);
          mj_forward(m, data);
        },
        200000);
    std::printf("| MuJoCo mj_forward, %s | %.0f |\n", name, ns);
    mj_deleteData(data);
    mj_deleteModel(m);
  }

  // 3. Work-precision over 10 s from the initial state: the crank angle's
  // error at 10 s against symdyn's dop853 at tolerance 1e-13, CPU time, and
  // the loop's largest opening along the run.
  constexpr double kEnd = 10.0;
  State reference;
  {
    IntegratorOptions o;
    o.relative_tolerance = o.absolute_tolerance = 1e-13;
    system.reset_loops();
    reference = make_integrator("dop853", o)->integrate(system, start, kEnd);
  }
  std::printf("\n## Work-precision over %g s (error of q0 at %g s, CPU, largest loop opening)\n\n",
              kEnd, kEnd);
  std::printf("| engine | setting | |q0 error| (rad) | CPU (ms) | largest opening (m) |\n");
  std::printf("|---|---|---:|---:|---:|\n");
  for (const char* method : {"dopri5", "dop853"}) {
    for (double tol : {1e-4, 1e-6, 1e-8, 1e-10}) {
      IntegratorOptions o;
      o.relative_tolerance = o.absolute_tolerance = tol;
      double drift = 0.0;
      system.reset_loops();
      const double t0 = cpu_seconds();
      const State end = make_integrator(method, o)->integrate(system, start, kEnd);
      const double cpu = cpu_seconds() - t0;
      // The opening after the run (the loops are closed at every evaluation):
      // |g| at 100 states along it.
      IntegratorOptions check = o;
      check.output_interval = kEnd / 100;
      check.on_output = [&](const State& s, const Vector&, const Vector&) {
        const State x = system.extended_state(s);
        Vector g(2), g_t(2);
        Matrix g_q(1, 2), g_p(2, 2);
        system.model().constraints(s.t, x.q.data(), g.data(), g_q.data(), g_p.data(), g_t.data());
        drift = std::max(drift, g.norm());
      };
      system.reset_loops();
      make_integrator(method, check)->integrate(system, start, kEnd);
      std::printf("| symdyn | %s tol %.0e | %.2e | %.2f | %.1e |\n", method, tol,
                  std::abs(end.q(0) - reference.q(0)), cpu * 1e3, drift);
    }
  }
  for (const auto& [name, solimp] : settings) {
    for (double h : {1e-3, 5e-4, 2e-4, 1e-4}) {
      mjModel* m = load_mjcf(mjcf(a, solimp), "four_bar");
      m->opt.timestep = h;
      mjData* data = mj_makeData(m);
      set_state(m, data, x0, a);
      mj_forward(m, data);
      double drift = 0.0;
      const int steps = static_cast<int>(std::lround(kEnd / h));
      const double t0 = cpu_seconds();
      for (int k = 0; k < steps; ++k) mj_step(m, data);
      const double cpu = cpu_seconds() - t0;
      // The opening along the same run again, without timing it.
      set_state(m, data, x0, a);
      mj_forward(m, data);
      for (int k = 0; k < steps; ++k) {
        mj_step(m, data);
        drift = std::max(drift, opening(data));
      }
      std::printf("| MuJoCo RK4 | %s, h %.0e | %.2e | %.2f | %.1e |\n", name, h,
                  std::abs(data->qpos[0] - reference.q(0)), cpu * 1e3, drift);
      mj_deleteData(data);
      mj_deleteModel(m);
    }
  }
  return 0;
}
