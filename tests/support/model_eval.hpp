#pragma once
// Numeric evaluation of a model's derived kinematics, and of its positions by
// a direct product of 4x4 matrices, for tests. Templated on the scalar so the
// complex step works through it.

#include <Eigen/Dense>
#include <complex>
#include <random>
#include <span>
#include <vector>

#include <symdyn/model/kinematics.hpp>
#include <symdyn/symbolic/eval.hpp>

namespace symdyn::testing {

template <class S>
struct ModelState {
  S t = S(0);
  std::vector<S> q, qd, qdd;
};

// Bindings of every symbol of the model at a state, dependent parameters
// (values, rates, accelerations, Jacobians) and intermediates computed in
// dependency order.
template <class S>
symbolic::Bindings<S> bind_state(const model::Model& m, const model::Kinematics& k,
                                 const ModelState<S>& s) {
  symbolic::Bindings<S> b;
  b.emplace(m.time(), s.t);
  for (std::size_t i = 0; i < m.coordinates().size(); ++i) {
    const auto& c = m.coordinates()[i];
    b.emplace(c.q, s.q[i]);
    b.emplace(c.qd, s.qd[i]);
    b.emplace(c.qdd, s.qdd[i]);
  }
  for (const auto& p : m.parameters()) b.emplace(p.symbol, S(p.value));
  auto eval = [&](symbolic::Expr e) { return symbolic::evaluate(e, b); };
  for (const auto& d : k.dependents) b.emplace(d.symbols.symbol, eval(d.value));
  for (const auto& d : k.dependents) b.emplace(d.symbols.rate, eval(d.rate));
  for (const auto& d : k.dependents) b.emplace(d.symbols.acceleration, eval(d.acceleration));
  for (const auto& d : k.dependents) {
    for (std::size_t j = 0; j < d.jacobian.size(); ++j) {
      if (d.jacobian_symbols[j] != d.jacobian[j])
        b.emplace(d.jacobian_symbols[j], eval(d.jacobian[j]));
    }
  }
  for (const auto& i : k.intermediates) b.emplace(i.symbol, eval(i.value));
  return b;
}

template <class S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using Matrix3 = Eigen::Matrix<S, 3, 3>;
template <class S>
using Matrix4 = Eigen::Matrix<S, 4, 4>;

template <class S>
Vector3<S> eval3(const model::Vec3& v, const symbolic::Bindings<S>& b) {
  return {symbolic::evaluate(v[0], b), symbolic::evaluate(v[1], b), symbolic::evaluate(v[2], b)};
}

template <class S>
Matrix3<S> eval33(const model::Mat3& m, const symbolic::Bindings<S>& b) {
  Matrix3<S> out;
  for (int i = 0; i < 9; ++i) out(i / 3, i % 3) = symbolic::evaluate(m[i], b);
  return out;
}

// The same through one Evaluator, whose memo shares the nodes common to many
// expressions (a big model's bodies share most of their DAG).
template <class S>
Vector3<S> eval3(const model::Vec3& v, symbolic::Evaluator<S>& e) {
  return {e(v[0]), e(v[1]), e(v[2])};
}

template <class S>
Matrix3<S> eval33(const model::Mat3& m, symbolic::Evaluator<S>& e) {
  Matrix3<S> out;
  for (int i = 0; i < 9; ++i) out(i / 3, i % 3) = e(m[i]);
  return out;
}

// T0G of every body by multiplying the 4x4 matrices of its elementary motions
// numerically (Rodrigues for each rotation), independently of the symbolic path.
template <class S>
std::vector<Matrix4<S>> direct_transforms(const model::Model& m, const symbolic::Bindings<S>& b) {
  const auto refs = m.reference_indices();
  std::vector<Matrix4<S>> T(m.bodies().size());
  for (int i : m.topological_order()) {
    Matrix4<S> local = Matrix4<S>::Identity();
    for (const auto& step : m.bodies()[i].motion().steps()) {
      Matrix4<S> E = Matrix4<S>::Identity();
      if (step.is_rotation) {
        const S angle = symbolic::evaluate(step.angle, b);
        Vector3<S> k;
        for (int j = 0; j < 3; ++j) k(j) = S(step.axis[j].number().to_double());
        Matrix3<S> K;
        K << S(0), -k(2), k(1), k(2), S(0), -k(0), -k(1), k(0), S(0);
        using std::cos;
        using std::sin;
        E.template block<3, 3>(0, 0) =
            Matrix3<S>::Identity() + sin(angle) * K + (S(1) - cos(angle)) * (K * K);
      } else {
        E.template block<3, 1>(0, 3) = eval3(step.displacement, b);
      }
      local = local * E;
    }
    T[i] = refs[i] < 0 ? local : Matrix4<S>(T[refs[i]] * local);
  }
  return T;
}

// A random state with every coordinate, rate and acceleration in [-1, 1].
inline ModelState<double> random_state(std::mt19937& rng, std::size_t nq) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ModelState<double> s;
  s.t = u(rng);
  for (std::size_t i = 0; i < nq; ++i) {
    s.q.push_back(u(rng));
    s.qd.push_back(u(rng));
    s.qdd.push_back(u(rng));
  }
  return s;
}

// A random state near the model's initial configuration: q = q_initial + amplitude·u,
// qd, qdd and t = u, with every u drawn uniformly in [-1, 1] (in the order of
// random_state, which this is for a model starting at q = 0 and amplitude 1).
// Models whose dependent parameters exist only near their initial
// configuration (a closed loop that must close) need a small amplitude.
inline ModelState<double> random_state_near(std::mt19937& rng, std::span<const double> q_initial,
                                            double amplitude) {
  ModelState<double> s = random_state(rng, q_initial.size());
  for (std::size_t i = 0; i < s.q.size(); ++i) s.q[i] = q_initial[i] + amplitude * s.q[i];
  return s;
}

inline ModelState<double> random_state_near(std::mt19937& rng, const model::Model& m,
                                            double amplitude) {
  std::vector<double> q_initial;
  for (const auto& c : m.coordinates()) q_initial.push_back(c.initial);
  return random_state_near(rng, q_initial, amplitude);
}

// The state moved along its own path by tau (complex tau for the complex step):
// q(tau) = q + qd·tau + qdd·tau²/2, qd(tau) = qd + qdd·tau, t + tau.
template <class S>
ModelState<S> along_path(const ModelState<double>& s, S tau) {
  ModelState<S> out;
  out.t = S(s.t) + tau;
  for (std::size_t i = 0; i < s.q.size(); ++i) {
    out.q.push_back(S(s.q[i]) + S(s.qd[i]) * tau + S(0.5 * s.qdd[i]) * tau * tau);
    out.qd.push_back(S(s.qd[i]) + S(s.qdd[i]) * tau);
    out.qdd.push_back(S(s.qdd[i]));
  }
  return out;
}

}  // namespace symdyn::testing
