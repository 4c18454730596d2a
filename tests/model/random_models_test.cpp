// Random multibody systems (rapidcheck): trees of one to five bodies, each
// moved by one to four elementary motions, absolute or relative to an earlier
// body, whose angles and displacements are constants or affine, trigonometric
// or bilinear in the coordinates, time and dependent parameters (themselves
// such functions, or square roots); full inertia tensors; random gravity;
// dependent parameters kept or inlined. Every derivation, with and without
// simplification, must match the independent references: positions against
// the 4x4 products, velocities and accelerations against the complex step,
// partial velocities against differences in qd, the equations of motion
// against the direct sums over bodies; and the model with its shared motions
// made relative must move as the model as written. A failure prints the
// smallest model rapidcheck finds that still fails.
#include <rapidcheck/catch.h>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <sstream>

#include "support/equations_checks.hpp"
#include "symbolic/print.hpp"

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;

namespace {

// A number on a grid of `step` between lo·step and hi·step (shrinks toward 0).
double draw(int lo, int hi, double step) { return *rc::gen::inRange(lo, hi + 1) * step; }

// Draws the scalars of one random model, and writes down what it drew.
class RandomModel {
 public:
  model::Model build() {
    model::Model m("random");
    const bool inline_dependents = *rc::gen::arbitrary<bool>();
    m.inline_dependents(inline_dependents);
    if (inline_dependents) text_ << "dependent parameters inlined\n";
    const int nq = *rc::gen::inRange(1, 5);
    symbols_ = m.coordinates(nq);
    symbols_.push_back(m.time());
    const int ndep = *rc::gen::inRange(0, 3);
    for (int k = 0; k < ndep; ++k) {
      const Expr value = dependent_value();
      text_ << "p" << k << " = " << symbolic::to_infix(value) << "\n";
      symbols_.push_back(m.dependent(fmt::format("p{}", k), value));
    }
    const int nbody = *rc::gen::inRange(1, 6);
    for (int i = 0; i < nbody; ++i) add_body(m, i);
    m.gravity(draw(-10, 10, 1.0), draw(-10, 10, 1.0), draw(-10, 10, 1.0));
    return m;
  }

  std::string description() const { return text_.str(); }

 private:
  Expr symbol() { return symbols_[*rc::gen::inRange<std::size_t>(0, symbols_.size())]; }
  Expr coefficient() { return Expr(draw(-10, 10, 0.2)); }

  // A constant, or affine, trigonometric or bilinear in the symbols.
  Expr scalar(int first_kind) {
    switch (*rc::gen::inRange(first_kind, 5)) {
      case 0: return coefficient();
      case 1: return coefficient() + coefficient() * symbol();
      case 2: return coefficient() * symbol() + coefficient() * symbol();
      case 3: return coefficient() + coefficient() * sin(symbol() + coefficient());
      default: return coefficient() * symbol() * symbol();
    }
  }

  // As a varying scalar, or a square root that is always defined.
  Expr dependent_value() {
    if (*rc::gen::inRange(0, 4) == 0) {
      const Expr s = symbol();
      return sqrt(1 + s * s);
    }
    return scalar(1);
  }

  model::Transform step() {
    const int kind = *rc::gen::inRange(0, 4);
    if (kind == 3) {
      // Mostly constant components, as in real offsets.
      auto component = [&] { return *rc::gen::inRange(0, 3) == 0 ? scalar(1) : coefficient(); };
      return model::Tdisp(component(), component(), component());
    }
    const Expr angle = scalar(*rc::gen::inRange(0, 5) == 0 ? 0 : 1);
    return kind == 0 ? model::Trotx(angle) : kind == 1 ? model::Troty(angle) : model::Trotz(angle);
  }

  // Full inertia tensor: principal moments satisfying the triangle
  // inequalities, turned by three random angles.
  static model::Mat3 inertia() {
    const double a = draw(1, 50, 0.02), b = draw(1, 50, 0.02);
    const double c = std::abs(a - b) + (a + b - std::abs(a - b)) * draw(1, 9, 0.1);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(draw(-15, 15, 0.2), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(draw(-15, 15, 0.2), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(draw(-15, 15, 0.2), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    Eigen::Matrix3d I = R * Eigen::Vector3d(a, b, c).asDiagonal() * R.transpose();
    I = 0.5 * (I + I.transpose()).eval();
    model::Mat3 out;
    for (int k = 0; k < 9; ++k) out[k] = Expr(I(k / 3, k % 3));
    return out;
  }

  void add_body(model::Model& m, int i) {
    const std::string name = fmt::format("b{}", i);
    model::Body& body = m.body(name).mass(draw(1, 50, 0.1)).inertia(inertia());
    model::Transform motion = step();
    const int steps = *rc::gen::inRange(1, 5);
    for (int s = 1; s < steps; ++s) motion = motion * step();
    body.motion(motion);
    const int reference = *rc::gen::inRange(-1, i);
    if (reference >= 0) body.relative_to(fmt::format("b{}", reference));
    text_ << name;
    if (reference >= 0) text_ << " relative to b" << reference;
    text_ << ":";
    for (const auto& s : motion.steps()) {
      if (s.is_rotation) {
        text_ << " rot" << "xyz"[s.axis[1].is_zero() ? (s.axis[2].is_zero() ? 0 : 2) : 1] << "("
              << symbolic::to_infix(s.angle) << ")";
        continue;
      }
      text_ << " disp(";
      for (int k = 0; k < 3; ++k) text_ << (k > 0 ? ", " : "") << symbolic::to_infix(s.displacement[k]);
      text_ << ")";
    }
    text_ << "\n";
  }

  std::vector<Expr> symbols_;  // q..., t, p... : what the scalars may use
  std::ostringstream text_;
};

States random_states(const model::Model& m, unsigned seed) {
  std::mt19937 rng(seed);
  States states;
  for (int k = 0; k < 2; ++k) states.push_back(random_state(rng, m.coordinates().size()));
  return states;
}

// The gap, with where it is and the model, when it is not below tolerance.
void assert_gap(const Gap& gap, double tolerance, const char* what) {
  if (!(gap.value < tolerance)) RC_LOG() << what << ": gap " << gap.value << " at " << gap.where << "\n";
  RC_ASSERT(gap.value < tolerance);
}

}  // namespace

TEST_CASE("random models match the independent references", "[kinematics][dynamics][random]") {
  rc::prop("kinematics and equations of motion", [] {
    RandomModel random;
    const model::Model m = random.build();
    RC_LOG() << random.description();
    const States states = random_states(m, *rc::gen::arbitrary<unsigned>());
    for (bool simplify : {false, true}) {
      RC_LOG() << "simplify=" << simplify << "\n";
      const model::Kinematics k = derive_for_test(m, simplify, true);
      assert_gap(positions_4x4_gap(m, k, states), 1e-12, "positions");
      assert_gap(complex_step_gap(m, k, states), 1e-10, "velocities and accelerations");
      assert_gap(partials_by_qd_gap(m, k, states), 1e-10, "partial velocities");
      assert_gap(equations_gap(m, k, model::derive_dynamics(m, k), states), 1e-10, "equations of motion");
    }
    const model::Model shared = m.with_shared_motions_relative();
    assert_gap(kinematics_agreement_gap(shared, derive_for_test(shared, true, true), m, derive_for_test(m, false, true),
                                        states),
               1e-10, "shared motions made relative");
  });
}
