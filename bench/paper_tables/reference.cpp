#include "reference.hpp"

#include <array>

#include <symdyn/symbolic/eval.hpp>

namespace symdyn::paper {

namespace {

using Eigen::Matrix3d;
using Eigen::Matrix4d;
using Eigen::Vector3d;

// Steps of the central differences: fourth-order formulas balance truncation
// (h^4) against rounding (eps/h, eps/h^2) at these.
constexpr double h_first = 1e-3;
constexpr double h_second = 5e-3;

// f'(0) and f''(0) from f(-2h), f(-h), f(0), f(h), f(2h), fourth order.
template <class T>
T first_derivative(const std::array<T, 5>& f, double h) {
  return (8.0 * (f[3] - f[1]) - (f[4] - f[0])) / (12.0 * h);
}
template <class T>
T second_derivative(const std::array<T, 5>& f, double h) {
  return (-f[4] + 16.0 * f[3] - 30.0 * f[2] + 16.0 * f[1] - f[0]) / (12.0 * h * h);
}

Vector3d unskew(const Matrix3d& S) {
  return 0.5 * Vector3d(S(2, 1) - S(1, 2), S(0, 2) - S(2, 0), S(1, 0) - S(0, 1));
}

void put(std::vector<double>& out, int index, const Vector3d& v) {
  for (int k = 0; k < 3; ++k) out[3 * index + k] = v(k);
}

}  // namespace

Reference::Reference(const model::Model& model)
    : model_(model),
      nq_(static_cast<int>(model.coordinates().size())),
      nbody_(static_cast<int>(model.bodies().size())) {
  symbolic::Bindings<double> constants;
  for (const auto& p : model.parameters()) constants.emplace(p.symbol, p.value);
  symbolic::Evaluator<double> eval(constants);
  for (const auto& b : model.bodies()) {
    mass_.push_back(eval(b.mass()));
    Matrix3d J;
    for (int i = 0; i < 9; ++i) J(i / 3, i % 3) = eval(b.inertia()[i]);
    inertia_.push_back(J);
  }
  for (int k = 0; k < 3; ++k) gravity_(k) = eval(model.gravity()[k]);
}

std::vector<Matrix4d> Reference::transforms(double t, const Eigen::VectorXd& q) const {
  symbolic::Bindings<double> b;
  b.emplace(model_.time(), t);
  for (int j = 0; j < nq_; ++j) b.emplace(model_.coordinates()[j].q, q(j));
  for (const auto& p : model_.parameters()) b.emplace(p.symbol, p.value);
  // Dependent parameters in declaration order, which is dependency order.
  for (const auto& d : model_.dependents())
    b.emplace(d.symbol, symbolic::evaluate(d.expression, b));
  symbolic::Evaluator<double> eval(b);
  const std::vector<int> refs = model_.reference_indices();
  std::vector<Matrix4d> T(nbody_);
  for (int i : model_.topological_order()) {
    Matrix4d local = Matrix4d::Identity();
    for (const auto& step : model_.bodies()[i].motion().steps()) {
      Matrix4d E = Matrix4d::Identity();
      if (step.is_rotation) {
        const double angle = eval(step.angle);
        const Vector3d k(eval(step.axis[0]), eval(step.axis[1]), eval(step.axis[2]));
        Matrix3d K;
        K << 0, -k(2), k(1), k(2), 0, -k(0), -k(1), k(0), 0;
        E.block<3, 3>(0, 0) =
            Matrix3d::Identity() + std::sin(angle) * K + (1 - std::cos(angle)) * (K * K);
      } else {
        E.block<3, 1>(0, 3) = Vector3d(eval(step.displacement[0]), eval(step.displacement[1]),
                                       eval(step.displacement[2]));
      }
      local = local * E;
    }
    T[i] = refs[i] < 0 ? local : Matrix4d(T[refs[i]] * local);
  }
  return T;
}

BodyKinematics Reference::kinematics(const StateSample& s) const {
  BodyKinematics k;
  const auto n3 = static_cast<std::size_t>(3 * nbody_);
  k.R.resize(3 * n3);
  k.x.resize(n3);
  k.v.resize(n3);
  k.w.resize(n3);
  k.a.resize(n3);
  k.dw.resize(n3);
  k.dv.resize(n3 * nq_);
  k.dwq.resize(n3 * nq_);
  // The five points of each stencil along the path.
  auto along = [&](double h) {
    std::array<std::vector<Matrix4d>, 5> T;
    for (int m = -2; m <= 2; ++m) {
      const double tau = m * h;
      T[m + 2] = transforms(s.t + tau, s.q + s.qd * tau + 0.5 * s.qdd * tau * tau);
    }
    return T;
  };
  const auto T1 = along(h_first);
  const auto T2 = along(h_second);
  for (int i = 0; i < nbody_; ++i) {
    std::array<Matrix4d, 5> f1, f2;
    for (int m = 0; m < 5; ++m) {
      f1[m] = T1[m][i];
      f2[m] = T2[m][i];
    }
    const Matrix4d T = T1[2][i];
    const Matrix3d R = T.block<3, 3>(0, 0);
    const Matrix4d Td = first_derivative(f1, h_first);
    const Matrix4d Tdd = second_derivative(f2, h_second);
    const Matrix3d Rd = Td.block<3, 3>(0, 0);
    for (int e = 0; e < 9; ++e) k.R[9 * i + e] = R(e / 3, e % 3);
    put(k.x, i, T.block<3, 1>(0, 3));
    put(k.v, i, Td.block<3, 1>(0, 3));
    put(k.a, i, Tdd.block<3, 1>(0, 3));
    put(k.w, i, unskew(Rd * R.transpose()));
    put(k.dw, i, unskew(Tdd.block<3, 3>(0, 0) * R.transpose() + Rd * Rd.transpose()));
  }
  // Partial velocities: derivatives of the pose in each coordinate.
  for (int j = 0; j < nq_; ++j) {
    std::array<std::vector<Matrix4d>, 5> T;
    for (int m = -2; m <= 2; ++m) {
      Eigen::VectorXd q = s.q;
      q(j) += m * h_first;
      T[m + 2] = transforms(s.t, q);
    }
    for (int i = 0; i < nbody_; ++i) {
      std::array<Matrix4d, 5> f;
      for (int m = 0; m < 5; ++m) f[m] = T[m][i];
      const Matrix4d dT = first_derivative(f, h_first);
      const Matrix3d R = T[2][i].block<3, 3>(0, 0);
      put(k.dv, i * nq_ + j, dT.block<3, 1>(0, 3));
      put(k.dwq, i * nq_ + j, unskew(dT.block<3, 3>(0, 0) * R.transpose()));
    }
  }
  return k;
}

Eigen::VectorXd Reference::accelerations(const StateSample& s) const {
  StateSample at_rest = s;
  at_rest.qdd.setZero();
  const BodyKinematics k = kinematics(at_rest);
  // M_jk = sum_i m_i dv_ij.dv_ik + dw_ij.J_i dw_ik,
  // h_j  = sum_i m_i (a_i - g).dv_ij + (J_i dw_i + w_i x J_i w_i).dw_ij   (a, dw at qdd = 0).
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(nq_, nq_);
  Eigen::VectorXd h = Eigen::VectorXd::Zero(nq_);
  auto vec = [](const std::vector<double>& a, int index) {
    return Vector3d(a[3 * index], a[3 * index + 1], a[3 * index + 2]);
  };
  for (int i = 0; i < nbody_; ++i) {
    const Matrix3d R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&k.R[9 * i]);
    const Matrix3d J = R * inertia_[i] * R.transpose();
    const Vector3d w = vec(k.w, i);
    const Vector3d force = mass_[i] * (vec(k.a, i) - gravity_);
    const Vector3d moment = J * vec(k.dw, i) + w.cross(J * w);
    for (int j = 0; j < nq_; ++j) {
      const Vector3d dvj = vec(k.dv, i * nq_ + j), dwj = vec(k.dwq, i * nq_ + j);
      h(j) += force.dot(dvj) + moment.dot(dwj);
      for (int l = 0; l < nq_; ++l) {
        M(j, l) +=
            mass_[i] * dvj.dot(vec(k.dv, i * nq_ + l)) + dwj.dot(J * vec(k.dwq, i * nq_ + l));
      }
    }
  }
  return M.ldlt().solve(-h);
}

}  // namespace symdyn::paper
