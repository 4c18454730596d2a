// Derived kinematics against independent references: a direct numerical
// product of the 4x4 matrices (positions), the complex step along a path in
// (q, t) (velocities, accelerations, angular velocities and accelerations),
// and finite differences in qd (partial velocities, exact since v is affine in qd).
#include <catch2/catch.hpp>

#include "model/kinematics.hpp"
#include "symbolic/simplify.hpp"
#include "support/model_eval.hpp"

using namespace symdyn;
using namespace symdyn::testing;
using model::Expr;
using Complex = std::complex<double>;

namespace {

// A body carried by a frame spinning at a prescribed rate about z, with a
// coordinate inside it: accelerations contain every mixed q-t term.
void prescribed(model::Model& m, std::string_view) {
  const auto q = m.coordinates(2);
  const Expr t = m.time();
  m.body("carrier").mass(2.0).inertia(0.1, 0.1, 0.2).motion(model::Trotz(3 * t + sin(t)) * model::Tdisp(0.5, 0, 0));
  m.body("slider").mass(1.0).inertia(0.01, 0.02, 0.02)
      .motion(model::Tdisp(q[0] * t, 0, 0.1) * model::Troty(q[1] + 2 * t) * model::Tdisp(0.2, 0, 0))
      .relative_to("carrier");
  // A rotation about an oblique constant axis (Rodrigues), with a run-time parameter.
  const Expr arm = m.parameter("arm", 0.3, true);
  const model::Vec3 axis{symbolic::rational(1, 3), symbolic::rational(2, 3), symbolic::rational(2, 3)};
  m.body("tilted").mass(0.5).inertia(0.01, 0.01, 0.01)
      .motion(model::Trot(axis, q[0] - q[1]) * model::Tdisp(arm, 0, 0) * model::Trotx(q[1]))
      .relative_to("slider");
}

const model::Registration registration({"prescribed_spin", {"default"}, prescribed});

struct Case {
  std::string model;
  std::string variant;
  bool simplify;
  bool symbolic_partials;
};

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const auto& d : model::registry()) {
    for (const auto& v : d.variants) {
      for (bool simplify : {false, true}) cases.push_back({d.name, v, simplify, true});
    }
  }
  return cases;
}

model::Kinematics derive(const model::Model& m, bool simplify, bool partials) {
  model::DeriveOptions options;
  static symbolic::Simplifier simplifier;
  if (simplify) options.simplify = [](Expr e) { return simplifier(e); };
  options.symbolic_partials = partials;
  return model::derive_kinematics(m, options);
}

// Largest |a - b| relative to max(1, |b|).
template <class A, class B>
double relative_gap(const A& a, const B& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

Matrix3<double> skew(const Vector3<double>& w) {
  Matrix3<double> s;
  s << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  return s;
}

}  // namespace

TEST_CASE("positions equal the direct product of the 4x4 matrices", "[kinematics]") {
  std::mt19937 rng(42);
  for (const Case& c : all_cases()) {
    const model::Model m = model::find_definition(c.model).make(c.variant);
    const model::Kinematics k = derive(m, c.simplify, false);
    INFO(c.model << " " << c.variant << " simplify=" << c.simplify);
    for (int trial = 0; trial < 20; ++trial) {
      const auto s = random_state(rng, m.coordinates().size());
      const auto b = bind_state(m, k, s);
      const auto T = direct_transforms(m, b);
      for (std::size_t i = 0; i < k.bodies.size(); ++i) {
        INFO("body " << m.bodies()[i].name());
        CHECK(relative_gap(eval33(k.bodies[i].R, b), T[i].block<3, 3>(0, 0)) < 1e-13);
        CHECK(relative_gap(eval3(k.bodies[i].x, b), T[i].block<3, 1>(0, 3)) < 1e-13);
      }
    }
  }
}

TEST_CASE("velocities and accelerations equal the complex step of positions along a path", "[kinematics]") {
  std::mt19937 rng(7);
  const double h = 1e-30;
  for (const Case& c : all_cases()) {
    const model::Model m = model::find_definition(c.model).make(c.variant);
    const model::Kinematics k = derive(m, c.simplify, false);
    INFO(c.model << " " << c.variant << " simplify=" << c.simplify);
    for (int trial = 0; trial < 10; ++trial) {
      const auto s = random_state(rng, m.coordinates().size());
      const auto b = bind_state(m, k, s);
      const auto bc = bind_state(m, k, along_path(s, Complex(0, h)));
      for (std::size_t i = 0; i < k.bodies.size(); ++i) {
        INFO("body " << m.bodies()[i].name());
        const auto& body = k.bodies[i];
        const Vector3<double> v = eval3(body.v, b);
        const Vector3<double> w = eval3(body.w, b);
        CHECK(relative_gap(v, Vector3<double>(eval3(body.x, bc).imag() / h)) < 1e-12);
        CHECK(relative_gap(eval3(body.a, b), Vector3<double>(eval3(body.v, bc).imag() / h)) < 1e-12);
        CHECK(relative_gap(eval3(body.dw, b), Vector3<double>(eval3(body.w, bc).imag() / h)) < 1e-12);
        // skew(w) = dR/dt·Rᵀ
        const Matrix3<double> R = eval33(body.R, b);
        const Matrix3<double> dR = eval33(body.R, bc).imag() / h;
        CHECK(relative_gap(skew(w), Matrix3<double>(dR * R.transpose())) < 1e-12);
      }
    }
  }
}

TEST_CASE("velocities and accelerations equal central differences along a path", "[kinematics]") {
  std::mt19937 rng(17);
  const double h = 1e-5;
  for (const Case& c : all_cases()) {
    const model::Model m = model::find_definition(c.model).make(c.variant);
    const model::Kinematics k = derive(m, c.simplify, false);
    INFO(c.model << " " << c.variant << " simplify=" << c.simplify);
    for (int trial = 0; trial < 5; ++trial) {
      const auto s = random_state(rng, m.coordinates().size());
      const auto b = bind_state(m, k, s);
      const auto ahead = bind_state(m, k, along_path(s, h));
      const auto behind = bind_state(m, k, along_path(s, -h));
      for (std::size_t i = 0; i < k.bodies.size(); ++i) {
        INFO("body " << m.bodies()[i].name());
        const auto& body = k.bodies[i];
        auto central = [&](const model::Vec3& f) -> Vector3<double> {
          return (eval3(f, ahead) - eval3(f, behind)) / (2 * h);
        };
        CHECK(relative_gap(eval3(body.v, b), central(body.x)) < 1e-8);
        CHECK(relative_gap(eval3(body.a, b), central(body.v)) < 1e-8);
        CHECK(relative_gap(eval3(body.dw, b), central(body.w)) < 1e-8);
      }
    }
  }
}

TEST_CASE("symbolic partial velocities equal velocity differences in qd", "[kinematics]") {
  std::mt19937 rng(11);
  for (const Case& c : all_cases()) {
    const model::Model m = model::find_definition(c.model).make(c.variant);
    const model::Kinematics k = derive(m, c.simplify, true);
    INFO(c.model << " " << c.variant << " simplify=" << c.simplify);
    const std::size_t nq = m.coordinates().size();
    for (int trial = 0; trial < 5; ++trial) {
      const auto s = random_state(rng, nq);
      const auto b = bind_state(m, k, s);
      for (std::size_t j = 0; j < nq; ++j) {
        auto moved = s;
        moved.qd[j] += 1.0;
        const auto bj = bind_state(m, k, moved);
        for (std::size_t i = 0; i < k.bodies.size(); ++i) {
          INFO("body " << m.bodies()[i].name() << " qd" << j);
          const auto& body = k.bodies[i];
          CHECK(relative_gap(eval3(body.dv_dqd[j], b), Vector3<double>(eval3(body.v, bj) - eval3(body.v, b))) < 1e-12);
          CHECK(relative_gap(eval3(body.dw_dqd[j], b), Vector3<double>(eval3(body.w, bj) - eval3(body.w, b))) < 1e-12);
        }
      }
    }
  }
}

TEST_CASE("variants of a model agree", "[kinematics]") {
  const std::vector<std::pair<std::string, std::pair<std::string, std::string>>> pairs = {
      {"double_pendulum", {"absolute", "relative"}}, {"slider_crank", {"inline", "dependent"}}};
  std::mt19937 rng(3);
  for (const auto& [name, variants] : pairs) {
    const model::Model a = model::find_definition(name).make(variants.first);
    const model::Model b = model::find_definition(name).make(variants.second);
    const model::Kinematics ka = derive(a, true, true);
    const model::Kinematics kb = derive(b, false, true);
    for (int trial = 0; trial < 10; ++trial) {
      const auto s = random_state(rng, a.coordinates().size());
      const auto ba = bind_state(a, ka, s);
      const auto bb = bind_state(b, kb, s);
      for (std::size_t i = 0; i < ka.bodies.size(); ++i) {
        INFO(name << " body " << a.bodies()[i].name());
        const auto& x = ka.bodies[i];
        const auto& y = kb.bodies[i];
        CHECK(relative_gap(eval33(x.R, ba), eval33(y.R, bb)) < 1e-12);
        for (auto field : {&model::BodyKinematics::x, &model::BodyKinematics::v, &model::BodyKinematics::w,
                           &model::BodyKinematics::a, &model::BodyKinematics::dw}) {
          CHECK(relative_gap(eval3(x.*field, ba), eval3(y.*field, bb)) < 1e-12);
        }
        for (std::size_t j = 0; j < a.coordinates().size(); ++j) {
          CHECK(relative_gap(eval3(x.dv_dqd[j], ba), eval3(y.dv_dqd[j], bb)) < 1e-12);
          CHECK(relative_gap(eval3(x.dw_dqd[j], ba), eval3(y.dw_dqd[j], bb)) < 1e-12);
        }
      }
    }
  }
}

TEST_CASE("the angular velocity of the double pendulum's second rod is qd0 + qd1", "[kinematics]") {
  for (const std::string variant : {"absolute", "relative"}) {
    const model::Model m = model::find_definition("double_pendulum").make(variant);
    const model::Kinematics k = derive(m, true, false);
    const Expr qd0 = m.coordinates()[0].qd;
    const Expr qd1 = m.coordinates()[1].qd;
    INFO(variant);
    CHECK(k.bodies[1].w[0] == Expr(0));
    CHECK(k.bodies[1].w[1] == Expr(0));
    CHECK(k.bodies[1].w[2] == qd0 + qd1);
  }
}
