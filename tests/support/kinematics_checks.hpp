#pragma once
// Checks of a model's derived kinematics against independent references, at
// given states: each gives the largest relative gap and where it is (for
// property tests), and check_* the same as Catch2 checks (include from test
// sources only):
//   positions      against the direct product of the 4x4 matrices;
//   v, a, dw, w    against the complex step and central differences of
//                  positions along a path in (q, t) (skew(w) = dR/dt·Rᵀ);
//   dv/dqd, dw/dqd against velocity differences in qd (exact: v is affine in qd).

#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "support/model_eval.hpp"
#include <symdyn/model/kinematics.hpp>
#include <symdyn/symbolic/simplify.hpp>

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

// The largest relative gap of a family of comparisons, and where it is. A NaN
// is the worst gap of all.
struct Gap {
  double value = 0.0;
  std::string where;

  void add(double gap, const std::string& place) {
    if (std::isnan(value) || !(std::isnan(gap) || gap > value)) return;
    value = gap;
    where = place;
  }
};

inline std::string body_place(const model::Model& m, std::size_t i, std::string_view what) {
  return m.bodies()[i].name() + " " + std::string(what);
}

inline Gap positions_4x4_gap(const model::Model& m, const model::Kinematics& k,
                             const States& states) {
  Gap gap;
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    symbolic::Evaluator<double> eval(b);
    const auto T = direct_transforms(m, b);
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      gap.add(relative_gap(eval33(k.bodies[i].R, eval), T[i].block<3, 3>(0, 0)),
              body_place(m, i, "R"));
      gap.add(relative_gap(eval3(k.bodies[i].x, eval), T[i].block<3, 1>(0, 3)),
              body_place(m, i, "x"));
    }
  }
  return gap;
}

inline Gap complex_step_gap(const model::Model& m, const model::Kinematics& k,
                            const States& states) {
  using Complex = std::complex<double>;
  const double h = 1e-30;
  Gap gap;
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    const auto bc = bind_state(m, k, along_path(s, Complex(0, h)));
    symbolic::Evaluator<double> eval(b);
    symbolic::Evaluator<Complex> evalc(bc);
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      const auto& body = k.bodies[i];
      const Vector3<double> w = eval3(body.w, eval);
      gap.add(relative_gap(eval3(body.v, eval), Vector3<double>(eval3(body.x, evalc).imag() / h)),
              body_place(m, i, "v"));
      gap.add(relative_gap(eval3(body.a, eval), Vector3<double>(eval3(body.v, evalc).imag() / h)),
              body_place(m, i, "a"));
      gap.add(relative_gap(eval3(body.dw, eval), Vector3<double>(eval3(body.w, evalc).imag() / h)),
              body_place(m, i, "dw"));
      const Matrix3<double> R = eval33(body.R, eval);
      const Matrix3<double> dR = eval33(body.R, evalc).imag() / h;
      gap.add(relative_gap(skew(w), Matrix3<double>(dR * R.transpose())), body_place(m, i, "w"));
    }
  }
  return gap;
}

inline Gap central_differences_gap(const model::Model& m, const model::Kinematics& k,
                                   const States& states) {
  const double h = 1e-5;
  Gap gap;
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    const auto ahead = bind_state(m, k, along_path(s, h));
    const auto behind = bind_state(m, k, along_path(s, -h));
    symbolic::Evaluator<double> eval(b), eval_ahead(ahead), eval_behind(behind);
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      const auto& body = k.bodies[i];
      auto central = [&](const model::Vec3& f) -> Vector3<double> {
        return (eval3(f, eval_ahead) - eval3(f, eval_behind)) / (2 * h);
      };
      gap.add(relative_gap(eval3(body.v, eval), central(body.x)), body_place(m, i, "v"));
      gap.add(relative_gap(eval3(body.a, eval), central(body.v)), body_place(m, i, "a"));
      gap.add(relative_gap(eval3(body.dw, eval), central(body.w)), body_place(m, i, "dw"));
    }
  }
  return gap;
}

// k must have symbolic partial velocities.
inline Gap partials_by_qd_gap(const model::Model& m, const model::Kinematics& k,
                              const States& states) {
  const std::size_t nq = m.coordinates().size();
  Gap gap;
  for (const auto& s : states) {
    const auto b = bind_state(m, k, s);
    symbolic::Evaluator<double> eval(b);
    for (std::size_t j = 0; j < nq; ++j) {
      auto moved = s;
      moved.qd[j] += 1.0;
      const auto bj = bind_state(m, k, moved);
      symbolic::Evaluator<double> eval_j(bj);
      for (std::size_t i = 0; i < k.bodies.size(); ++i) {
        const auto& body = k.bodies[i];
        const std::string qd = " qd" + std::to_string(j);
        gap.add(relative_gap(eval3(body.dv_dqd[j], eval),
                             Vector3<double>(eval3(body.v, eval_j) - eval3(body.v, eval))),
                body_place(m, i, "dv/d" + qd));
        gap.add(relative_gap(eval3(body.dw_dqd[j], eval),
                             Vector3<double>(eval3(body.w, eval_j) - eval3(body.w, eval))),
                body_place(m, i, "dw/d" + qd));
      }
    }
  }
  return gap;
}

// Two derivations of the same mechanism (variants, with or without
// simplification) give the same R, x, v, w, a, dw and, when both have them,
// partial velocities, body by body.
inline Gap kinematics_agreement_gap(const model::Model& ma, const model::Kinematics& ka,
                                    const model::Model& mb, const model::Kinematics& kb,
                                    const States& states) {
  Gap gap;
  if (ka.bodies.size() != kb.bodies.size()) {
    gap.add(INFINITY, "the numbers of bodies");
    return gap;
  }
  for (const auto& s : states) {
    const auto ba = bind_state(ma, ka, s);
    const auto bb = bind_state(mb, kb, s);
    symbolic::Evaluator<double> ea(ba), eb(bb);
    for (std::size_t i = 0; i < ka.bodies.size(); ++i) {
      const auto& x = ka.bodies[i];
      const auto& y = kb.bodies[i];
      gap.add(relative_gap(eval33(x.R, ea), eval33(y.R, eb)), body_place(ma, i, "R"));
      for (auto [field, name] : {std::pair{&model::BodyKinematics::x, "x"},
                                 {&model::BodyKinematics::v, "v"},
                                 {&model::BodyKinematics::w, "w"},
                                 {&model::BodyKinematics::a, "a"},
                                 {&model::BodyKinematics::dw, "dw"}}) {
        gap.add(relative_gap(eval3(x.*field, ea), eval3(y.*field, eb)), body_place(ma, i, name));
      }
      for (std::size_t j = 0; j < std::min(x.dv_dqd.size(), y.dv_dqd.size()); ++j) {
        gap.add(relative_gap(eval3(x.dv_dqd[j], ea), eval3(y.dv_dqd[j], eb)),
                body_place(ma, i, "dv/dqd"));
        gap.add(relative_gap(eval3(x.dw_dqd[j], ea), eval3(y.dw_dqd[j], eb)),
                body_place(ma, i, "dw/dqd"));
      }
    }
  }
  return gap;
}

// The same as Catch2 checks, at the tolerances the references allow.
inline void check_gap(const Gap& gap, double tolerance) {
  INFO("largest gap at " << gap.where);
  CHECK(gap.value < tolerance);
}

inline void check_positions_4x4(const model::Model& m, const model::Kinematics& k,
                                const States& states) {
  check_gap(positions_4x4_gap(m, k, states), 1e-13);
}

inline void check_complex_step(const model::Model& m, const model::Kinematics& k,
                               const States& states) {
  check_gap(complex_step_gap(m, k, states), 1e-12);
}

inline void check_central_differences(const model::Model& m, const model::Kinematics& k,
                                      const States& states) {
  check_gap(central_differences_gap(m, k, states), 1e-8);
}

inline void check_partials_by_qd(const model::Model& m, const model::Kinematics& k,
                                 const States& states) {
  check_gap(partials_by_qd_gap(m, k, states), 1e-12);
}

inline void check_kinematics_agree(const model::Model& ma, const model::Kinematics& ka,
                                   const model::Model& mb, const model::Kinematics& kb,
                                   const States& states, double tolerance) {
  check_gap(kinematics_agreement_gap(ma, ka, mb, kb, states), tolerance);
}

}  // namespace symdyn::testing
