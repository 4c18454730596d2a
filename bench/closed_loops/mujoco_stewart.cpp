// The 6-6 Stewart platform (models/stewart.cpp) against MuJoCo's equality
// constraints (six connects), the same masses, inertias and geometry, on six
// undamped leg springs (100 kN/m, free at the home length, as the scenario
// models/scenarios/stewart.json): the accelerations at the same assembled
// states first, then the forward dynamics per call, a work-precision over
// 10 s and the loops' drift (bench/results/closed_loops.md).
//
// MuJoCo's tree: the platform a free body; each leg a cylinder on two hinges
// at the base (the universal joint) and a piston on a slide joint in it, its
// end connected to the platform's joint. Each body is written in symdyn's
// assembly of the home pose, MuJoCo's qpos0, where the connects hold.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mujoco_bench.hpp"
#include "stewart.hpp"
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;
using namespace symdyn_bench;
using Vec3 = Eigen::Vector3d;

// models/stewart.cpp (docs/models.md): the legs' joints on the base and the
// platform (in its axes, from its G), and the legs' centres of mass.
Vec3 base_joint(int i) {
  const double a = (120 * (i / 2) + (i % 2 ? 15 : -15)) * M_PI / 180;
  return {0.5 * std::cos(a), 0.5 * std::sin(a), 0};
}
Vec3 platform_joint(int i) {
  const double a = (120 * (i / 2) + (i % 2 ? 45 : -45)) * M_PI / 180;
  return {0.3 * std::cos(a), 0.3 * std::sin(a), -0.05};
}
constexpr double cylinder_g = 0.275, piston_g = 0.25;
constexpr double spring_rate = 1e5;  // N/m, each leg

// printf into a string (the MJCF's numbers to 17 digits).
template <class... Args>
std::string format(const char* pattern, Args... args) {
  char text[2048];
  std::snprintf(text, sizeof text, pattern, args...);
  return text;
}

// Where symdyn's extended coordinates of the Stewart platform are, by name.
struct Layout {
  int pose[6];  // platform_x, _y, _z, _yaw, _pitch, _roll
  int a[6], b[6];
  explicit Layout(const Model& model) {
    const auto& names = model.q_names();
    const auto at = [&](const std::string& name) {
      const auto found = std::find(names.begin(), names.end(), name);
      if (found == names.end()) throw std::runtime_error("not the model of models/stewart.cpp");
      return static_cast<int>(found - names.begin());
    };
    const char* pose_names[6] = {"x", "y", "z", "yaw", "pitch", "roll"};
    for (int k = 0; k < 6; ++k) {
      pose[k] = at(format("platform_%s", pose_names[k]));
      a[k] = at(format("a%d", k));
      b[k] = at(format("b%d", k));
    }
  }
};

// Quaternions (w, x, y, z) of the rotations symdyn's models compose.
using Quat = std::array<double, 4>;
Quat product(const Quat& p, const Quat& q) {
  Quat r;
  mju_mulQuat(r.data(), p.data(), q.data());
  return r;
}
Quat about(int axis, double angle) {
  Quat q{std::cos(angle / 2), 0, 0, 0};
  q[1 + axis] = std::sin(angle / 2);
  return q;
}
// Rz(yaw)·Ry(pitch)·Rx(roll)
Quat platform_quat(double yaw, double pitch, double roll) {
  return product(product(about(2, yaw), about(1, pitch)), about(0, roll));
}

// The platform's angular velocity and acceleration (world axes) from its
// Euler angles' rates: w = yawd·z + pitchd·e2 + rolld·e1, e2 = Rz·y, e1 = Rz·Ry·x.
struct Spin {
  Vec3 w, dw;
};
Spin spin(const double* angle, const double* rate, const double* acceleration) {
  const double yaw = angle[0], pitch = angle[1];
  const Vec3 z(0, 0, 1), e2(-std::sin(yaw), std::cos(yaw), 0),
      e1(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), -std::sin(pitch));
  const Vec3 w = rate[0] * z + rate[1] * e2 + rate[2] * e1;
  // d(e2)/dt = yawd·z × e2, d(e1)/dt = (yawd·z + pitchd·e2) × e1
  const Vec3 dw = acceleration[0] * z + acceleration[1] * e2 + acceleration[2] * e1 +
                  rate[1] * rate[0] * z.cross(e2) +
                  rate[2] * (rate[0] * z + rate[1] * e2).cross(e1);
  return {w, dw};
}

// The assembled home pose (symdyn's extended initial state): MuJoCo's qpos0.
struct Home {
  double pose[6];
  double a[6], b[6], length[6];
  Home(const Layout& at, const State& x) {
    for (int k = 0; k < 6; ++k) {
      pose[k] = x.q(at.pose[k]);
      a[k] = x.q(at.a[k]), b[k] = x.q(at.b[k]), length[k] = x.q(k);
    }
  }
};

std::string mjcf(const Home& home, const std::string& constraint) {
  const Quat p = platform_quat(home.pose[3], home.pose[4], home.pose[5]);
  std::string xml = format(R"(<mujoco model="stewart">
  <option gravity="0 0 -9.81" integrator="RK4" timestep="0.001"/>
  <worldbody>
    <body name="platform" pos="%.17g %.17g %.17g" quat="%.17g %.17g %.17g %.17g">
      <freejoint name="platform"/>
      <inertial pos="0 0 0" mass="40" diaginertia="1.3 1.3 2.4"/>
    </body>
)",
                           home.pose[0], home.pose[1], home.pose[2], p[0], p[1], p[2], p[3]);
  std::string equalities;
  for (int i = 0; i < 6; ++i) {
    // The cylinder's frame at its base joint, turned by Rx(a)·Ry(b) of the
    // home pose; its first hinge is the base's x (Ry(-b)·x in that frame),
    // its second the cylinder's y: R = Rx(a0 + qa)·Ry(b0 + qb).
    const Quat q = product(about(0, home.a[i]), about(1, home.b[i]));
    const Vec3 base = base_joint(i);
    const double b = home.b[i], l = home.length[i];
    xml += format(
        R"(    <body name="cylinder%d" pos="%.17g %.17g %.17g" quat="%.17g %.17g %.17g %.17g">
      <joint name="a%d" type="hinge" axis="%.17g 0 %.17g"/>
      <joint name="b%d" type="hinge" axis="0 1 0"/>
      <inertial pos="0 0 %.17g" mass="3" diaginertia="0.077 0.077 0.004"/>
      <body name="piston%d">
        <joint name="l%d" type="slide" axis="0 0 1" stiffness="%.17g"/>
        <inertial pos="0 0 %.17g" mass="1.5" diaginertia="0.032 0.032 0.001"/>
      </body>
    </body>
)",
        i, base.x(), base.y(), base.z(), q[0], q[1], q[2], q[3], i, std::cos(b), std::sin(b), i,
        cylinder_g, i, i, spring_rate, l - piston_g);
    equalities += format(R"(    <connect body1="piston%d" body2="platform" anchor="0 0 %.17g" %s/>
)",
                         i, l, constraint.c_str());
  }
  return xml + "  </worldbody>\n  <equality>\n" + equalities + "  </equality>\n</mujoco>\n";
}

// MuJoCo's addresses of the platform's free joint and of each leg's joints.
struct MjLayout {
  int platform_qpos, platform_dof, platform_body;
  int qpos[6][3], dof[6][3], piston_body[6];  // hinges a, b and slide l
  explicit MjLayout(const mjModel* m) {
    const int free = mj_name2id(m, mjOBJ_JOINT, "platform");
    platform_qpos = m->jnt_qposadr[free], platform_dof = m->jnt_dofadr[free];
    platform_body = mj_name2id(m, mjOBJ_BODY, "platform");
    for (int i = 0; i < 6; ++i) {
      const std::string n = std::to_string(i);
      const std::string joints[3] = {"a" + n, "b" + n, "l" + n};
      for (int k = 0; k < 3; ++k) {
        const int j = mj_name2id(m, mjOBJ_JOINT, joints[k].c_str());
        qpos[i][k] = m->jnt_qposadr[j], dof[i][k] = m->jnt_dofadr[j];
      }
      piston_body[i] = mj_name2id(m, mjOBJ_BODY, ("piston" + n).c_str());
    }
  }
};

// R (row-major) of a quaternion, and Rᵀ·v.
std::array<double, 9> rotation(const double* quat) {
  std::array<double, 9> R;
  mju_quat2Mat(R.data(), quat);
  return R;
}
Vec3 in_body(const std::array<double, 9>& R, const Vec3& v) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R.data()).transpose() * v;
}

// MuJoCo's state from symdyn's extended one (x, its rates xd).
void set_state(mjData* data, const MjLayout& mj, const Layout& at, const Home& home,
               const State& x) {
  data->time = x.t;
  double angles[3], rates[3];
  for (int k = 0; k < 3; ++k) {
    data->qpos[mj.platform_qpos + k] = x.q(at.pose[k]);
    data->qvel[mj.platform_dof + k] = x.qd(at.pose[k]);
    angles[k] = x.q(at.pose[3 + k]), rates[k] = x.qd(at.pose[3 + k]);
  }
  const Quat q = platform_quat(angles[0], angles[1], angles[2]);
  std::copy(q.begin(), q.end(), data->qpos + mj.platform_qpos + 3);
  const Vec3 w = in_body(rotation(q.data()), spin(angles, rates, rates).w);  // MuJoCo: body axes
  for (int k = 0; k < 3; ++k) data->qvel[mj.platform_dof + 3 + k] = w(k);
  for (int i = 0; i < 6; ++i) {
    const int index[3] = {at.a[i], at.b[i], i};
    const double origin[3] = {home.a[i], home.b[i], home.length[i]};
    for (int k = 0; k < 3; ++k) {
      data->qpos[mj.qpos[i][k]] = x.q(index[k]) - origin[k];
      data->qvel[mj.dof[i][k]] = x.qd(index[k]);
    }
  }
}

// The legs' lengths in MuJoCo's state.
Vector lengths(const mjData* data, const MjLayout& mj, const Home& home) {
  Vector l(6);
  for (int i = 0; i < 6; ++i) l(i) = home.length[i] + data->qpos[mj.qpos[i][2]];
  return l;
}

// The loops' largest opening (m): |piston end - platform joint|, from
// MuJoCo's body poses and its connects' anchors on either body.
double opening(const mjModel* m, const mjData* data, const MjLayout& mj) {
  double worst = 0;
  for (int i = 0; i < 6; ++i) {
    const int body[2] = {mj.piston_body[i], mj.platform_body};
    Vec3 end[2];
    for (int k = 0; k < 2; ++k) {
      const double* anchor = m->eq_data + mjNEQDATA * i + 3 * k;
      Vec3 p;
      mju_rotVecMat(p.data(), anchor, data->xmat + 9 * body[k]);
      end[k] = p + Eigen::Map<const Vec3>(data->xpos + 3 * body[k]);
    }
    worst = std::max(worst, (end[0] - end[1]).norm());
  }
  return worst;
}

// The leg springs of the scenario: undamped, free at the home lengths.
void add_leg_springs(MultibodySystem& system, const Home& home) {
  for (int i = 0; i < 6; ++i)
    system.add<CoordinateSpringDamper>("leg" + std::to_string(i), i, spring_rate, 0.0,
                                       home.length[i]);
}

// The leg accelerations, the platform's linear and angular accelerations (rad/s², body axes).
struct Accelerations {
  Vector legs = Vector(6);
  Vec3 linear, angular;
};
Accelerations symdyn_accelerations(MultibodySystem& system, const Layout& at, const State& s) {
  Vector qdd, yd;
  system.accelerations(s, qdd, yd);
  const State x = system.extended_state(s);
  const Vector xdd = system.extended_accelerations(s, qdd);
  Accelerations out;
  out.legs = qdd;
  double angles[3], rates[3], accelerations[3];
  for (int k = 0; k < 3; ++k) {
    out.linear(k) = xdd(at.pose[k]);
    angles[k] = x.q(at.pose[3 + k]), rates[k] = x.qd(at.pose[3 + k]);
    accelerations[k] = xdd(at.pose[3 + k]);
  }
  const Quat q = platform_quat(angles[0], angles[1], angles[2]);
  out.angular = in_body(rotation(q.data()), spin(angles, rates, accelerations).dw);
  return out;
}
Accelerations mujoco_accelerations(const mjData* data, const MjLayout& mj) {
  Accelerations out;
  for (int i = 0; i < 6; ++i) out.legs(i) = data->qacc[mj.dof[i][2]];
  for (int k = 0; k < 3; ++k) {
    out.linear(k) = data->qacc[mj.platform_dof + k];
    out.angular(k) = data->qacc[mj.platform_dof + 3 + k];
  }
  return out;
}

}  // namespace

int main() {
  MultibodySystem system(Model::from<symdyn_generated::stewart>());
  const Layout at(system.model());
  const State home_state = system.initial_state();  // the home pose, at rest
  const Home home(at, system.extended_state(home_state));
  add_leg_springs(system, home);
  const std::vector<ConstraintSetting> settings = constraint_settings();

  // 1. The accelerations at the same assembled states: leg lengths within 5 cm
  // of home, at rest and moving (leg rates within 0.3 m/s).
  std::printf("## Accelerations at the same states (max |difference| / max |symdyn's|)\n\n");
  std::printf(
      "| MuJoCo constraint | legs, at rest | platform linear | angular "
      "| legs, moving | platform linear | angular |\n|---|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& [name, constraint] : settings) {
    mjModel* m = load_mjcf(mjcf(home, constraint), "stewart");
    mjData* data = mj_makeData(m);
    const MjLayout mj(m);
    // MuJoCo's connects hold at the home pose (its qpos0) as symdyn assembled it.
    set_state(data, mj, at, home, system.extended_state(home_state));
    mj_forward(m, data);
    for (int i = 0; i < 6; ++i) {  // the connects' anchors on the platform are its joints
      const Vec3 anchor = Eigen::Map<const Vec3>(m->eq_data + mjNEQDATA * i + 3);
      if ((anchor - platform_joint(i)).norm() > 1e-12 || opening(m, data, mj) > 1e-12)
        throw std::runtime_error("MuJoCo's model is not assembled at its qpos0");
    }
    double worst[2][3] = {}, scale[2][3] = {};
    std::mt19937 rng(7u);
    const auto uniform = [&](double half_width) {
      return std::uniform_real_distribution<double>(-half_width, half_width)(rng);
    };
    system.reset_loops();
    for (int k = 0; k < 64; ++k) {
      State s = home_state;
      for (int i = 0; i < 6; ++i) s.q(i) += uniform(0.05);
      for (int moving = 0; moving < 2; ++moving) {
        for (int i = 0; i < 6; ++i) s.qd(i) = moving ? uniform(0.3) : 0.0;
        const Accelerations a = symdyn_accelerations(system, at, s);
        set_state(data, mj, at, home, system.extended_state(s));
        mj_forward(m, data);
        const Accelerations b = mujoco_accelerations(data, mj);
        const double difference[3] = {(a.legs - b.legs).cwiseAbs().maxCoeff(),
                                      (a.linear - b.linear).cwiseAbs().maxCoeff(),
                                      (a.angular - b.angular).cwiseAbs().maxCoeff()};
        const double size[3] = {a.legs.cwiseAbs().maxCoeff(), a.linear.cwiseAbs().maxCoeff(),
                                a.angular.cwiseAbs().maxCoeff()};
        for (int c = 0; c < 3; ++c) {
          worst[moving][c] = std::max(worst[moving][c], difference[c]);
          scale[moving][c] = std::max(scale[moving][c], size[c]);
        }
      }
    }
    std::printf("| %s |", name);
    for (int moving = 0; moving < 2; ++moving)
      for (int c = 0; c < 3; ++c) std::printf(" %.2g |", worst[moving][c] / scale[moving][c]);
    std::printf("\n");
    mj_deleteData(data);
    mj_deleteModel(m);
  }

  // 2. Forward dynamics per call: leg 0 through 1 cm in 1000 calls, at rest
  // (symdyn_bench_closed_loops' stewart_accelerations, the springs added);
  // MuJoCo at the same 1000 assembled states.
  constexpr int kStates = 1000, kCalls = 20000;
  const auto along = [&](int k) {
    State s = home_state;
    s.q(0) += 0.01 * (k % kStates) / kStates;
    return s;
  };
  std::printf("\n## Forward dynamics per call (CPU, median of 5 x %d calls)\n\n", kCalls);
  std::printf("| engine | ns per call |\n|---|---:|\n");
  {
    Vector qdd, yd;
    system.reset_loops();
    State s = home_state;
    const double ns = per_call_ns(
        [&](int k) {
          s.q(0) = home_state.q(0) + 0.01 * (k % kStates) / kStates;
          system.accelerations(s, qdd, yd);
        },
        kCalls);
    std::printf("| symdyn accelerations() | %.0f |\n", ns);
  }
  for (const auto& [name, constraint] : settings) {
    mjModel* m = load_mjcf(mjcf(home, constraint), "stewart");
    mjData* data = mj_makeData(m);
    const MjLayout mj(m);
    std::vector<double> qpos(static_cast<size_t>(kStates * m->nq));
    system.reset_loops();
    for (int k = 0; k < kStates; ++k) {
      set_state(data, mj, at, home, system.extended_state(along(k)));
      std::copy(data->qpos, data->qpos + m->nq, qpos.begin() + k * m->nq);
    }
    const double ns = per_call_ns(
        [&](int k) {
          mju_copy(data->qpos, qpos.data() + (k % kStates) * m->nq, m->nq);
          mj_forward(m, data);
        },
        kCalls);
    std::printf("| MuJoCo mj_forward, %s | %.0f |\n", name, ns);
    mj_deleteData(data);
    mj_deleteModel(m);
  }

  // 3. Work-precision over 10 s, leg 0 started 1 cm long, at rest: the legs'
  // largest length error at 10 s against symdyn's dop853 at tolerance 1e-13,
  // the CPU time, and the loops' largest opening along the run.
  constexpr double kEnd = 10.0;
  State start = home_state;
  start.q(0) += 0.01;
  State reference;
  {
    IntegratorOptions o;
    o.relative_tolerance = o.absolute_tolerance = 1e-13;
    system.reset_loops();
    reference = make_integrator("dop853", o)->integrate(system, start, kEnd);
  }
  std::printf(
      "\n## Work-precision over %g s (legs' length error at %g s, CPU, largest loop opening)\n\n",
      kEnd, kEnd);
  std::printf("| engine | setting | max |l error| (m) | CPU (ms) | largest opening (m) |\n");
  std::printf("|---|---|---:|---:|---:|\n");
  const auto symdyn_run = [&](const char* method, IntegratorOptions o, const char* setting) {
    system.reset_loops();
    const double t0 = cpu_seconds();
    const State end = make_integrator(method, o)->integrate(system, start, kEnd);
    const double cpu = cpu_seconds() - t0;
    // The opening along the same run again (the loops are closed at every
    // evaluation): |g| at 100 states along it.
    double drift = 0.0;
    o.output_interval = kEnd / 100;
    o.on_output = [&](const State& s, const Vector&, const Vector&) {
      const Model& model = system.model();
      const State x = system.extended_state(s);
      const int n = model.nindependent(), nc = model.ncon();
      Vector g(nc), g_t(nc);
      Matrix g_q(n, nc), g_p(nc, nc);
      model.constraints(s.t, x.q.data(), g.data(), g_q.data(), g_p.data(), g_t.data());
      drift = std::max(drift, g.cwiseAbs().maxCoeff());
    };
    system.reset_loops();
    make_integrator(method, o)->integrate(system, start, kEnd);
    std::printf("| symdyn | %s %s | %.2e | %.1f | %.1e |\n", method, setting,
                (end.q - reference.q).cwiseAbs().maxCoeff(), cpu * 1e3, drift);
  };
  for (const char* method : {"dopri5", "dop853"}) {
    for (double tol : {1e-4, 1e-6, 1e-8, 1e-10}) {
      IntegratorOptions o;
      o.relative_tolerance = o.absolute_tolerance = tol;
      char setting[32];
      std::snprintf(setting, sizeof setting, "tol %.0e", tol);
      symdyn_run(method, o, setting);
    }
  }
  for (double h : {1e-3, 5e-4}) {
    IntegratorOptions o;
    o.initial_step = h;
    char setting[32];
    std::snprintf(setting, sizeof setting, "h %.0e", h);
    symdyn_run("rk4", o, setting);
  }
  for (const auto& [name, constraint] : settings) {
    for (double h : {1e-3, 5e-4, 2e-4, 1e-4}) {
      mjModel* m = load_mjcf(mjcf(home, constraint), "stewart");
      m->opt.timestep = h;
      mjData* data = mj_makeData(m);
      const MjLayout mj(m);
      system.reset_loops();
      const State x0 = system.extended_state(start);
      set_state(data, mj, at, home, x0);
      mj_forward(m, data);
      const int steps = static_cast<int>(std::lround(kEnd / h));
      const double t0 = cpu_seconds();
      for (int k = 0; k < steps; ++k) mj_step(m, data);
      const double cpu = cpu_seconds() - t0;
      const double error = (lengths(data, mj, home) - reference.q).cwiseAbs().maxCoeff();
      // The opening along the same run again, without timing it.
      set_state(data, mj, at, home, x0);
      mj_forward(m, data);
      double drift = opening(m, data, mj);
      for (int k = 0; k < steps; ++k) {
        mj_step(m, data);
        drift = std::max(drift, opening(m, data, mj));
      }
      std::printf("| MuJoCo RK4 | %s, h %.0e | %.2e | %.1f | %.1e |\n", name, h, error, cpu * 1e3,
                  drift);
      mj_deleteData(data);
      mj_deleteModel(m);
    }
  }
  return 0;
}
