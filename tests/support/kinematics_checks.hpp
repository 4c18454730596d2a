#pragma once
// Checks of a model's derived kinematics against independent references, at
// given states (Catch2 checks; include from test sources only):
//   positions      against the direct product of the 4x4 matrices;
//   v, a, dw, w    against the complex step and central differences of
//                  positions along a path in (q, t) (skew(w) = dR/dt·Rᵀ);
//   dv/dqd, dw/dqd against velocity differences in qd (exact: v is affine in qd).

#include <catch2/catch.hpp>

#include <complex>
#include <string>
#include <vector>

#include "model/kinematics.hpp"
#include "symbolic/simplify.hpp"
#include "support/model_eval.hpp"

namespace symdyn::testing {

inline model::Kinematics derive_for_test(const model::Model& m, bool simplify, bool partials) {
  model::DeriveOptions options;
  static symbolic::Simplifier simplifier;
  if (simplify) options.simplify = [](model::Expr e) { return simplifier(e); };
  options.symbolic_partials = partials;
  return model::derive_kinematics(m, options);
}

// Largest |a - b| relative to max(1, |b|).
template <class A, class B>
double relative_gap(const A& a, const B& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

inline Matrix3<double> skew(const Vector3<double>& w) {
  Matrix3<double> s;
  s << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  return s;
}

using States = std::vector<ModelState<double>>;

inline void check_positions_4x4(const model::Model& m, const model::Kinematics& k, const States& states) {
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    symbolic::Evaluator<double> eval(b);
    const auto T = direct_transforms(m, b);
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      INFO("body " << m.bodies()[i].name());
      CHECK(relative_gap(eval33(k.bodies[i].R, eval), T[i].block<3, 3>(0, 0)) < 1e-13);
      CHECK(relative_gap(eval3(k.bodies[i].x, eval), T[i].block<3, 1>(0, 3)) < 1e-13);
    }
  }
}

inline void check_complex_step(const model::Model& m, const model::Kinematics& k, const States& states) {
  using Complex = std::complex<double>;
  const double h = 1e-30;
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    const auto bc = bind_state(m, k, along_path(s, Complex(0, h)));
    symbolic::Evaluator<double> eval(b);
    symbolic::Evaluator<Complex> evalc(bc);
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      INFO("body " << m.bodies()[i].name());
      const auto& body = k.bodies[i];
      const Vector3<double> v = eval3(body.v, eval);
      const Vector3<double> w = eval3(body.w, eval);
      CHECK(relative_gap(v, Vector3<double>(eval3(body.x, evalc).imag() / h)) < 1e-12);
      CHECK(relative_gap(eval3(body.a, eval), Vector3<double>(eval3(body.v, evalc).imag() / h)) < 1e-12);
      CHECK(relative_gap(eval3(body.dw, eval), Vector3<double>(eval3(body.w, evalc).imag() / h)) < 1e-12);
      const Matrix3<double> R = eval33(body.R, eval);
      const Matrix3<double> dR = eval33(body.R, evalc).imag() / h;
      CHECK(relative_gap(skew(w), Matrix3<double>(dR * R.transpose())) < 1e-12);
    }
  }
}

inline void check_central_differences(const model::Model& m, const model::Kinematics& k, const States& states) {
  const double h = 1e-5;
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    const auto ahead = bind_state(m, k, along_path(s, h));
    const auto behind = bind_state(m, k, along_path(s, -h));
    symbolic::Evaluator<double> eval(b), eval_ahead(ahead), eval_behind(behind);
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      INFO("body " << m.bodies()[i].name());
      const auto& body = k.bodies[i];
      auto central = [&](const model::Vec3& f) -> Vector3<double> {
        return (eval3(f, eval_ahead) - eval3(f, eval_behind)) / (2 * h);
      };
      CHECK(relative_gap(eval3(body.v, eval), central(body.x)) < 1e-8);
      CHECK(relative_gap(eval3(body.a, eval), central(body.v)) < 1e-8);
      CHECK(relative_gap(eval3(body.dw, eval), central(body.w)) < 1e-8);
    }
  }
}

// k must have symbolic partial velocities.
inline void check_partials_by_qd(const model::Model& m, const model::Kinematics& k, const States& states) {
  const std::size_t nq = m.coordinates().size();
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    symbolic::Evaluator<double> eval(b);
    for (std::size_t j = 0; j < nq; ++j) {
      auto moved = s;
      moved.qd[j] += 1.0;
      const auto bj = bind_state(m, k, moved);
      symbolic::Evaluator<double> eval_j(bj);
      for (std::size_t i = 0; i < k.bodies.size(); ++i) {
        INFO("body " << m.bodies()[i].name() << " qd" << j);
        const auto& body = k.bodies[i];
        CHECK(relative_gap(eval3(body.dv_dqd[j], eval), Vector3<double>(eval3(body.v, eval_j) - eval3(body.v, eval))) <
              1e-12);
        CHECK(relative_gap(eval3(body.dw_dqd[j], eval), Vector3<double>(eval3(body.w, eval_j) - eval3(body.w, eval))) <
              1e-12);
      }
    }
  }
}

// Two derivations of the same mechanism (variants, with or without
// simplification) give the same R, x, v, w, a, dw and, when both have them,
// partial velocities, body by body.
inline void check_kinematics_agree(const model::Model& ma, const model::Kinematics& ka, const model::Model& mb,
                                   const model::Kinematics& kb, const States& states, double tolerance) {
  REQUIRE(ka.bodies.size() == kb.bodies.size());
  for (const auto& s : states) {
    const auto ba = bind_state(ma, ka, s);
    const auto bb = bind_state(mb, kb, s);
    symbolic::Evaluator<double> ea(ba), eb(bb);
    for (std::size_t i = 0; i < ka.bodies.size(); ++i) {
      INFO("body " << ma.bodies()[i].name());
      const auto& x = ka.bodies[i];
      const auto& y = kb.bodies[i];
      CHECK(relative_gap(eval33(x.R, ea), eval33(y.R, eb)) < tolerance);
      for (auto field : {&model::BodyKinematics::x, &model::BodyKinematics::v, &model::BodyKinematics::w,
                         &model::BodyKinematics::a, &model::BodyKinematics::dw}) {
        CHECK(relative_gap(eval3(x.*field, ea), eval3(y.*field, eb)) < tolerance);
      }
      for (std::size_t j = 0; j < std::min(x.dv_dqd.size(), y.dv_dqd.size()); ++j) {
        CHECK(relative_gap(eval3(x.dv_dqd[j], ea), eval3(y.dv_dqd[j], eb)) < tolerance);
        CHECK(relative_gap(eval3(x.dw_dqd[j], ea), eval3(y.dw_dqd[j], eb)) < tolerance);
      }
    }
  }
}

}  // namespace symdyn::testing
