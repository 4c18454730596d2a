#pragma once
// Random multibody systems for property tests (rapidcheck; call inside a
// property): trees of one to five bodies, each moved by one to four
// elementary motions, absolute or relative to another body (declared before
// or after it), whose angles and displacements are constants or affine,
// trigonometric or bilinear in the coordinates, time and dependent parameters
// (themselves such functions, or square roots); full inertia tensors; random
// gravity; dependent parameters kept or inlined; and what the properties
// check them with. Include from test sources only.

#include <fmt/format.h>
#include <rapidcheck.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "support/kinematics_checks.hpp"
#include <symdyn/model/model.hpp>
#include <symdyn/symbolic/print.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::testing {

// A number on a grid of `step` between lo·step and hi·step (shrinks toward 0).
inline double draw(int lo, int hi, double step) {
  return *rc::gen::inRange(lo, hi + 1) * step;
}

// Draws the scalars of one random model, and writes down what it drew.
class RandomModel {
 public:
  model::Model build() {
    using model::Expr;
    model::Model m("random");
    const bool inline_dependents = *rc::gen::arbitrary<bool>();
    m.inline_dependents(inline_dependents);
    if (inline_dependents) text_ << "dependent parameters inlined\n";
    const int nq = *rc::gen::inRange(1, 5);
    symbols_ = m.coordinates(nq);
    symbols_.push_back(m.time());
    const int ndep = *rc::gen::inRange(0, 3);
    std::vector<Expr> values;  // of the dependent parameters, in order
    for (int k = 0; k < ndep; ++k) {
      const Expr value = dependent_value();
      text_ << "p" << k << " = " << symbolic::to_infix(value) << "\n";
      values.push_back(value);
      symbols_.push_back(m.dependent(fmt::format("p{}", k), value));
    }
    std::vector<BodyDraw> bodies;
    const int nbody = *rc::gen::inRange(1, 6);
    for (int i = 0; i < nbody; ++i) bodies.push_back(draw_body(i));
    move_every_coordinate(bodies, nq, values);
    add_bodies(m, bodies, *rc::gen::arbitrary<bool>());
    m.gravity(draw(-10, 10, 1.0), draw(-10, 10, 1.0), draw(-10, 10, 1.0));
    return m;
  }

  std::string description() const { return text_.str(); }

 private:
  model::Expr symbol() { return symbols_[*rc::gen::inRange<std::size_t>(0, symbols_.size())]; }
  model::Expr coefficient() { return model::Expr(draw(-10, 10, 0.2)); }

  // A constant, or affine, trigonometric or bilinear in the symbols.
  model::Expr scalar(int first_kind) {
    switch (*rc::gen::inRange(first_kind, 5)) {
      case 0:
        return coefficient();
      case 1:
        return coefficient() + coefficient() * symbol();
      case 2:
        return coefficient() * symbol() + coefficient() * symbol();
      case 3:
        return coefficient() + coefficient() * sin(symbol() + coefficient());
      default:
        return coefficient() * symbol() * symbol();
    }
  }

  // As a varying scalar, or a square root that is always defined.
  model::Expr dependent_value() {
    if (*rc::gen::inRange(0, 4) == 0) {
      const model::Expr s = symbol();
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
    const model::Expr angle = scalar(*rc::gen::inRange(0, 5) == 0 ? 0 : 1);
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
    for (int k = 0; k < 9; ++k) out[k] = model::Expr(I(k / 3, k % 3));
    return out;
  }

  struct BodyDraw {
    std::string name;
    double mass;
    model::Mat3 inertia;
    model::Transform motion;
    int reference;  // an earlier body, or -1
  };

  BodyDraw draw_body(int i) {
    BodyDraw body{fmt::format("b{}", i), draw(1, 50, 0.1), inertia(), step(),
                  *rc::gen::inRange(-1, i)};
    const int steps = *rc::gen::inRange(1, 5);
    for (int s = 1; s < steps; ++s) body.motion = body.motion * step();
    describe(body);
    return body;
  }

  // In the order drawn (every reference before the bodies relative to it) or
  // the reverse one (every reference after them).
  void add_bodies(model::Model& m, const std::vector<BodyDraw>& bodies, bool reversed) {
    if (reversed) text_ << "declared in reverse order\n";
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      const BodyDraw& b = bodies[reversed ? bodies.size() - 1 - k : k];
      model::Body& body = m.body(b.name).mass(b.mass).inertia(b.inertia).motion(b.motion);
      if (b.reference >= 0) body.relative_to(fmt::format("b{}", b.reference));
    }
  }

  // Model::validate refuses a coordinate that moves no body: one drawn in no
  // motion (directly or through a dependent parameter) turns the first body.
  void move_every_coordinate(std::vector<BodyDraw>& bodies, int nq,
                             const std::vector<model::Expr>& values) {
    std::vector<model::Expr> used;
    for (const BodyDraw& b : bodies) {
      for (const auto& s : b.motion.steps()) {
        used.insert(used.end(), s.displacement.begin(), s.displacement.end());
        used.push_back(s.angle);
      }
    }
    const auto uses = [&](model::Expr s) {
      return std::any_of(used.begin(), used.end(),
                         [&](model::Expr e) { return symbolic::depends_on(e, s); });
    };
    for (std::size_t k = values.size(); k-- > 0;) {  // later dependent parameters use earlier ones
      const model::Expr p = symbols_[static_cast<std::size_t>(nq) + 1 + k];
      if (p.is_symbol() && uses(p)) used.push_back(values[k]);
    }
    for (int j = 0; j < nq; ++j) {
      const model::Expr q = symbols_[static_cast<std::size_t>(j)];
      if (uses(q)) continue;
      bodies.front().motion = bodies.front().motion * model::Trotx(q);
      text_ << "b0 also turns by rotx(" << q.name() << ")\n";
    }
  }

  void describe(const BodyDraw& body) {
    text_ << body.name;
    if (body.reference >= 0) text_ << " relative to b" << body.reference;
    text_ << ":";
    for (const auto& s : body.motion.steps()) {
      if (s.is_rotation) {
        text_ << " rot"
              << "xyz"[s.axis[1].is_zero() ? (s.axis[2].is_zero() ? 0 : 2) : 1] << "("
              << symbolic::to_infix(s.angle) << ")";
        continue;
      }
      text_ << " disp(";
      for (int k = 0; k < 3; ++k)
        text_ << (k > 0 ? ", " : "") << symbolic::to_infix(s.displacement[k]);
      text_ << ")";
    }
    text_ << "\n";
  }

  std::vector<model::Expr> symbols_;  // q..., t, p... : what the scalars may use
  std::ostringstream text_;
};

// Two random states (support/model_eval.hpp) from a drawn seed.
inline States random_states(const model::Model& m, unsigned seed) {
  std::mt19937 rng(seed);
  States states;
  for (int k = 0; k < 2; ++k) states.push_back(random_state(rng, m.coordinates().size()));
  return states;
}

// Fails the property unless the gap is below tolerance, saying where it is.
inline void assert_gap(const Gap& gap, double tolerance, const char* what) {
  if (!(gap.value < tolerance))
    RC_LOG() << what << ": gap " << gap.value << " at " << gap.where << "\n";
  RC_ASSERT(gap.value < tolerance);
}

}  // namespace symdyn::testing
