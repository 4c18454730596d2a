// Tangential dips between evaluations: a motion that comes near a domain edge or a
// branch point and turns back within one step, every evaluation of the step far
// from it. Each model's coordinate is driven along a closed-form q0(t) (a
// generalized force M·a + h - Q computed by an undriven copy of the system), so
// that the time and the depth of the closest approach are known exactly.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "branch_crank.hpp"
#include "branch_crank_pointer.hpp"
#include "long_crank_asin.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace {

using namespace symdyn::runtime;

const double half_pi = std::numbers::pi / 2;

// q0(t) = q0(t0) + v·(t - t0) + a·(t - t0)²/2, its closest approach at t_star.
struct Drive {
  double a = 0.0;       // q0's acceleration
  double t_star = 0.0;  // where qd0 = 0 (a != 0), or where q0 = q_star (a = 0)
  double q_star = 0.0;  // q0 at t_star
  double v = 0.0;       // qd0, where a = 0
  double q(double t) const {
    return q_star + v * (t - t_star) + a * (t - t_star) * (t - t_star) / 2;
  }
  double qd(double t) const { return v + a * (t - t_star); }
};

// The system of `model` (one coordinate) with its coordinate driven at q0'' = a:
// the force Q_drive = M·a + h - Q, the residual of an undriven copy at qdd = a.
MultibodySystem driven(const Model& model, const Drive& drive) {
  MultibodySystem sys(model);
  auto undriven = std::make_shared<MultibodySystem>(model);
  sys.add(std::make_shared<CoordinateForce>(
      "drive", 0, [undriven, a = drive.a](double, double, double, const State& s) {
        // s is the tree's with closed loops (x = (q, p)): q0 leads it
        const State q{s.t, s.q.head(1), s.qd.head(1), s.y};
        Vector qdd = Vector::Constant(1, a), yd, f, g;
        undriven->residual(q, qdd, yd, f, g);
        return f[0];
      }));
  return sys;
}

State start_of(MultibodySystem& sys, const Drive& drive) {
  State s = sys.initial_state();
  s.t = 0.0;
  s.q[0] = drive.q(0.0);
  s.qd[0] = drive.qd(0.0);
  return s;
}

// The DynamicSystem without its check between steps: a run where nothing is refused.
class WithoutStepCheck : public DynamicSystem {
 public:
  explicit WithoutStepCheck(DynamicSystem& s) : s_(s) {}
  int num_coordinates() const override { return s_.num_coordinates(); }
  int num_extra_states() const override { return s_.num_extra_states(); }
  std::string coordinate_name(int i) const override { return s_.coordinate_name(i); }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    s_.accelerations(s, qdd, yd);
  }
  void residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f,
                Vector& g) override {
    s_.residual(s, qdd, yd, f, g);
  }
  void jacobians(const State& s, const Vector& qdd, Matrix& M, Matrix& C, Matrix& K) override {
    s_.jacobians(s, qdd, M, C, K);
  }
  bool exact_acceleration_derivatives(const State& s, const Vector& qdd, Matrix& dqdd_dq,
                                      Matrix& dqdd_dqd) override {
    return s_.exact_acceleration_derivatives(s, qdd, dqdd_dq, dqdd_dqd);
  }

 private:
  DynamicSystem& s_;
};

// Every output of a run (t, q, qd), or its error.
struct Run {
  std::vector<double> outputs;
  std::string error;
};

Run run(const std::string& integrator, IntegratorOptions o, DynamicSystem& sys, const State& start,
        double t_end) {
  Run r;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    r.outputs.push_back(s.t);
    r.outputs.insert(r.outputs.end(), s.q.begin(), s.q.end());
    r.outputs.insert(r.outputs.end(), s.qd.begin(), s.qd.end());
  };
  try {
    make_integrator(integrator, o)->integrate(sys, start, t_end);
  } catch (const NumericError& e) {
    r.error = e.what();
  }
  return r;
}

// One step of `h` over the dip: the fixed-step methods, and dopri5 made to take it
// first (q0 is a polynomial of degree 2 or less: its error estimate is rounding).
IntegratorOptions one_step_of(double h) {
  IntegratorOptions o;
  o.relative_tolerance = o.absolute_tolerance = 1e-8;
  o.initial_step = o.max_step = h;
  return o;
}

// The time named first by a message ("t = <number>: ...").
double time_named(const std::string& message) {
  static const std::regex pattern(R"(^t = ([-+0-9.eE]+))");
  std::smatch m;
  REQUIRE(std::regex_search(message, m, pattern));
  return std::stod(m[1].str());
}

// The integrators that take the dip's step whole, exact for the drive (its samples
// all far from the edge, no evaluation near it); the others may step nearer it.
// midpoint (on (q, p = M·qd)) does not keep q0 on the drive's polynomial at these
// steps where M varies: the dip it meets is its own, its time not the closed form.
bool takes_the_step_whole(const std::string& integrator) {
  return integrator == "rk4" || integrator == "dopri5";
}
bool off_the_drive(const std::string& integrator) {
  return integrator == "midpoint";
}

// The slider-crank with its crank k = 1 - 1e-9 times its rod (as long, to 1e-9):
// asin(k·sin(q0)) comes within 1 - k of its edge at q0 = pi/2 and turns back,
// its margin 1 - k·cos(w·(t - t*)) ~ 1 - k + (w·(t - t*))²/2, for q0 turning at
// w = 14 rad/s through pi/2 at t* = 0.0375, 3/8 of the step of 0.1: the five
// samples at th = 0, 1/4, .. 1 have margins 0.135, 0.0153, 0.0153, 0.359, 0.635.
Model slider_crank(double k) {
  Model model = Model::from<symdyn_generated::long_crank_asin>();
  model.set_parameters({0.1 * k, 0.1, 0.5, 0.3});
  return model;
}
const Drive crank_through_pi_2{0.0, 0.0375, half_pi, 14.0};

// Every integrator refuses the slider-crank driven by `drive` through its touch,
// naming alpha, the time and the state; those that take the steps of 0.1 whole
// name the step `step` ("from t = 0 to 0.1") and the closed-form time.
void touch_refused(const Drive& drive, const std::string& step) {
  const Model model = slider_crank(1 - 1e-9);
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    MultibodySystem sys = driven(model, drive);
    const Run r = run(name, one_step_of(0.1), sys, start_of(sys, drive), 0.2);
    CAPTURE(r.error);
    if (off_the_drive(name)) {  // stopped at its own touch, or its iteration failed first
      CHECK(!r.error.empty());
      continue;
    }
    CHECK(r.error.find("dependent parameter 'alpha': asin(0.99999999") != std::string::npos);
    CHECK(r.error.find("from the edge of its function's domain") != std::string::npos);
    static const std::regex state(R"( at q = \(q0 = 1\.57079[0-9]+\), qd = \()");
    CHECK(std::regex_search(r.error, state));
    // Located on the step's interpolant (exact: q0 is linear in t) by golden section to
    // 1e-12 of the step; the margin's bottom is flat to rounding over |t - t*| ~ 1e-9.
    const double t = time_named(r.error);
    if (takes_the_step_whole(name)) {
      CHECK(r.error.find("between the evaluations of the step " + step) != std::string::npos);
      CHECK(t == Approx(drive.t_star).margin(1e-8));
    } else {  // an evaluation's refusal, or located between two
      CHECK(t == Approx(drive.t_star).margin(1e-3));
    }
  }
}

}  // namespace

TEST_CASE(
    "a domain edge touched between the samples of one step: refused naming the parameter, the "
    "closed-form time and the state",
    "[integrator][errors][domain]") {
  touch_refused(crank_through_pi_2, "from t = 0 to 0.1");
}

TEST_CASE(
    "a domain edge touched just after a step's start sample: the end sample's parabola locates it",
    "[integrator][errors][domain]") {
  // At 15 rad/s through pi/2 at t = 0.11, a tenth into the second step of 0.1: the
  // first step's samples decrease to its end (margin 0.0112 at t = 0.1; its parabola
  // puts the minimum beyond it), the second's start 0.0112, then 0.0252 and 0.175.
  touch_refused(Drive{0.0, 0.11, half_pi, 15.0}, "from t = 0.1 to 0.2");
}

TEST_CASE(
    "a dip that stays 0.1 from the domain edge is not refused: every run as without the check",
    "[integrator][errors][domain]") {
  const Model model = slider_crank(0.9);
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    MultibodySystem checked = driven(model, crank_through_pi_2),
                    unchecked = driven(model, crank_through_pi_2);
    WithoutStepCheck without(unchecked);
    const State start = start_of(checked, crank_through_pi_2);
    const Run with_check = run(name, one_step_of(0.1), checked, start, 0.2);
    const Run without_check = run(name, one_step_of(0.1), without, start, 0.2);
    CAPTURE(with_check.error);
    CHECK(with_check.error == without_check.error);
    CHECK(with_check.outputs == without_check.outputs);
    if (off_the_drive(name)) continue;  // its iteration fails at the second step, checked or not
    CHECK(with_check.error.empty());
    REQUIRE(with_check.outputs.size() >= 3);
    CHECK(with_check.outputs.end()[-2] == Approx(crank_through_pi_2.q(0.2)).epsilon(1e-9));
  }
}

namespace {

// The folded crank (models/error_models.cpp), its crank driven up towards the branch
// point at q0 = pi/2 and back: q0 = pi/2 - d - (42 rad/s²)·(t - t*)², t* = 0.05 in a
// step of 0.2, where r = 0.1·|cos(q0)| = 0.1·sin(d + 42·(t - t*)²) has its minimum
// 0.1·sin(d). The three samples of the step (th = 0, 1/2, 1) are 0.105 + d, 0.105 + d
// and 0.945 + d from it (r = 0.0105, 0.0105, 0.081 for d = 5e-4). (M is constant.)
Drive crank_to_branch(double d) {
  return Drive{-84.0, 0.05, half_pi - d, 0.0};
}

}  // namespace

TEST_CASE(
    "a branch point touched inside one step whose samples stay far from it: refused naming the "
    "loop and the closed-form time",
    "[integrator][errors][loops]") {
  const Model model = Model::from<symdyn_generated::branch_crank>();
  const Drive drive = crank_to_branch(5e-4);  // r dips to 5e-5
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    MultibodySystem sys = driven(model, drive);
    const Run r = run(name, one_step_of(0.2), sys, start_of(sys, drive), 0.2);
    CAPTURE(r.error);
    CHECK(r.error.find("loop 'crank_pin' at a branch point") != std::string::npos);
    static const std::regex state(R"(at \(q0 = 1\.5[67][0-9]+, rod_angle = 1\.57)");
    CHECK(std::regex_search(r.error, state));
    const double t = time_named(r.error);
    if (takes_the_step_whole(name)) {
      CHECK(r.error.find("between the evaluations of the step from t = 0 to 0.2") !=
            std::string::npos);
      // r - r_min = 4.2·(t - t*)² near t*: r located to about 1e-12 puts t within 1e-6
      CHECK(t == Approx(drive.t_star).margin(1e-6));
    } else {  // r < 1e-4 within 3.5e-3 s of t*
      CHECK(t == Approx(drive.t_star).margin(3.5e-3));
    }
  }
}

TEST_CASE(
    "a dip to within 2e-3 of the branch point (above its 1e-4) is not refused: every run as "
    "without the check",
    "[integrator][errors][loops]") {
  const Model model = Model::from<symdyn_generated::branch_crank>();
  for (double d : {0.02, 0.01}) {  // r dips to 2e-3, 1e-3
    const Drive drive = crank_to_branch(d);
    for (const auto& name : integrator_names()) {
      CAPTURE(d, name);
      MultibodySystem checked = driven(model, drive), unchecked = driven(model, drive);
      WithoutStepCheck without(unchecked);
      const State start = start_of(checked, drive);
      const Run with_check = run(name, one_step_of(0.2), checked, start, 0.2);
      const Run without_check = run(name, one_step_of(0.2), without, start, 0.2);
      CAPTURE(with_check.error);
      CHECK(with_check.error.empty());
      CHECK(without_check.error.empty());
      CHECK(with_check.outputs == without_check.outputs);
      REQUIRE(with_check.outputs.size() >= 3);
      CHECK(with_check.outputs.end()[-2] == Approx(drive.q(0.2)).epsilon(1e-8));
    }
  }
}

namespace {

// The folded crank with its pointer (models/error_models.cpp), k = 1 - 1e-9:
// beta = asin(k·cos(q0)) comes within 1e-9 of its edge at q0 = 0, its margin
// 1 - k·cos(w·(t - t*)) for q0 turning at w = 3 rad/s through 0 at t* = 0.05 in
// a step of 0.2 (th = 1/4): margins 0.0112, 0.0112, 0.0995 at the three samples,
// the loops far from their branch point (r = 0.1·cos(q0) >= 0.09).
Model pointed_crank(double k) {
  Model model = Model::from<symdyn_generated::branch_crank_pointer>();
  model.set_parameters({k});
  return model;
}
const Drive crank_through_0{0.0, 0.05, 0.0, 3.0};

}  // namespace

TEST_CASE(
    "closed loops: a dependent parameter's domain edge touched between the samples of a step is "
    "refused naming it, the closed-form time and the state",
    "[integrator][errors][loops][domain]") {
  const Model model = pointed_crank(1 - 1e-9);
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    MultibodySystem sys = driven(model, crank_through_0);
    const Run r = run(name, one_step_of(0.2), sys, start_of(sys, crank_through_0), 0.2);
    CAPTURE(r.error);
    CHECK(r.error.find("dependent parameter 'beta': asin(0.99999999") != std::string::npos);
    CHECK(r.error.find("from the edge of its function's domain") != std::string::npos);
    static const std::regex state(R"( at q = \(q0 = [-0-9.e]+, rod_angle = 3\.141[0-9]+, )");
    CHECK(std::regex_search(r.error, state));
    const double t = time_named(r.error);
    if (takes_the_step_whole(name)) {
      CHECK(r.error.find("between the evaluations of the step from t = 0 to 0.2") !=
            std::string::npos);
      // the margin's bottom is flat to its rounding (2e-16) over |t - t*| < sqrt(4e-16)/w
      CHECK(t == Approx(crank_through_0.t_star).margin(1e-8));
    } else if (!off_the_drive(name)) {
      CHECK(t == Approx(crank_through_0.t_star).margin(1e-3));
    }
  }
  // 0.1 from the edge: not refused, the run as without the check.
  const Model far = pointed_crank(0.9);
  for (const auto& name : integrator_names()) {
    CAPTURE(name);
    MultibodySystem checked = driven(far, crank_through_0),
                    unchecked = driven(far, crank_through_0);
    WithoutStepCheck without(unchecked);
    const State start = start_of(checked, crank_through_0);
    const Run with_check = run(name, one_step_of(0.2), checked, start, 0.2);
    const Run without_check = run(name, one_step_of(0.2), without, start, 0.2);
    CAPTURE(with_check.error);
    CHECK(with_check.error == without_check.error);
    CHECK(with_check.outputs == without_check.outputs);
    if (!off_the_drive(name)) CHECK(with_check.error.empty());
  }
}
