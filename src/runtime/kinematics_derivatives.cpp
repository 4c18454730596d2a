#include <algorithm>
#include <cmath>

#include <symdyn/runtime/kinematics_derivatives.hpp>

namespace symdyn::runtime {

KinematicsDerivatives::KinematicsDerivatives(int nq, int nbody)
    : nq_(nq),
      dv_dq_(3 * std::max(nbody * nq, 1), 0.0),
      dw_dq_(dv_dq_),
      ddv_dq_(3 * std::max(nbody * nq * nq, 1), 0.0),
      ddw_dq_(ddv_dq_) {}

Vec3 KinematicsDerivatives::point_partial(const Kinematics& k, int body, const Vec3& r,
                                          int j) const {
  if (body == ground) return Vec3::Zero();
  return k.dv_dqd(body, j) + k.dw_dqd(body, j).cross(r);
}

Vec3 KinematicsDerivatives::point_partial_derivative(const Kinematics& k, int body, const Vec3& r,
                                                     int j, int kk) const {
  if (body == ground) return Vec3::Zero();
  return ddv_dq(body, j, kk) + ddw_dq(body, j, kk).cross(r) +
         k.dw_dqd(body, j).cross(k.dw_dqd(body, kk).cross(r));
}

Vec3 KinematicsDerivatives::point_velocity_derivative(const Kinematics& k, int body, const Vec3& r,
                                                      int kk) const {
  if (body == ground) return Vec3::Zero();
  return dv_dq(body, kk) + dw_dq(body, kk).cross(r) + k.w(body).cross(k.dw_dqd(body, kk).cross(r));
}

BodyMotion<double> body_motion(const Kinematics& k, int body) {
  if (body == ground) return {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Mat3::Identity()};
  return {k.x(body), k.v(body), k.w(body), k.rotation(body)};
}

template <int Bodies>
BodyMotion<MotionDual<Bodies>> seeded_motion(const Kinematics& k, int body, int slot) {
  using D = MotionDual<Bodies>;
  using Derivatives = typename D::DerType;
  const BodyMotion<double> m = body_motion(k, body);
  BodyMotion<D> out{m.x.cast<D>(), m.v.cast<D>(), m.w.cast<D>(), m.R.cast<D>()};
  if (body == ground) return out;
  const int at = 12 * slot;
  for (int c = 0; c < 3; ++c) {
    out.x(c).derivatives()(at + c) = 1.0;
    out.v(c).derivatives()(at + 6 + c) = 1.0;
    out.w(c).derivatives()(at + 9 + c) = 1.0;
  }
  // ∂R/∂δθ_c = skew(e_c)·R: column by column, e_c × R.col(col).
  for (int col = 0; col < 3; ++col) {
    for (int c = 0; c < 3; ++c) {
      const Vec3 dR = Vec3::Unit(c).cross(m.R.col(col));
      for (int r = 0; r < 3; ++r) out.R(r, col).derivatives()(at + 3 + c) = dR(r);
    }
  }
  static_assert(Derivatives::RowsAtCompileTime == 12 * Bodies);
  return out;
}

template <int Bodies>
void add_wrench_derivatives(const Kinematics& k, const KinematicsDerivatives& dk,
                            const std::array<int, Bodies>& bodies,
                            const std::array<Wrench<MotionDual<Bodies>>, Bodies>& wrenches,
                            Eigen::MatrixXd& dQ_dq, Eigen::MatrixXd& dQ_dqd) {
  constexpr int N = 12 * Bodies;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  using Motion = Eigen::Matrix<double, N, 1>;
  // The wrenches' values and their Jacobians with respect to the motions (6 x N each).
  std::array<Vec6, Bodies> W;
  std::array<Eigen::Matrix<double, 6, N>, Bodies> J;
  for (int a = 0; a < Bodies; ++a) {
    for (int c = 0; c < 3; ++c) {
      W[a](c) = wrenches[a].force(c).value();
      W[a](3 + c) = wrenches[a].moment(c).value();
      J[a].row(c) = wrenches[a].force(c).derivatives().transpose();
      J[a].row(3 + c) = wrenches[a].moment(c).derivatives().transpose();
    }
  }
  for (int kk = 0; kk < k.nq(); ++kk) {
    Motion along_q = Motion::Zero(), along_qd = Motion::Zero();  // ∂motion/∂q_k, ∂/∂qd_k
    for (int b = 0; b < Bodies; ++b) {
      const int i = bodies[b];
      if (i == ground) continue;
      along_q.template segment<3>(12 * b) = k.dv_dqd(i, kk);
      along_q.template segment<3>(12 * b + 3) = k.dw_dqd(i, kk);
      along_q.template segment<3>(12 * b + 6) = dk.dv_dq(i, kk);
      along_q.template segment<3>(12 * b + 9) = dk.dw_dq(i, kk);
      along_qd.template segment<3>(12 * b + 6) = k.dv_dqd(i, kk);
      along_qd.template segment<3>(12 * b + 9) = k.dw_dqd(i, kk);
    }
    for (int a = 0; a < Bodies; ++a) {
      const int i = bodies[a];
      if (i == ground) continue;
      const Vec6 dW_dq = J[a] * along_q, dW_dqd = J[a] * along_qd;
      for (int j = 0; j < k.nq(); ++j) {
        Vec6 partial;  // (dv_ij, dw_ij)
        partial << k.dv_dqd(i, j), k.dw_dqd(i, j);
        dQ_dq(j, kk) += dW_dq.dot(partial) + W[a].template head<3>().dot(dk.ddv_dq(i, j, kk)) +
                        W[a].template tail<3>().dot(dk.ddw_dq(i, j, kk));
        dQ_dqd(j, kk) += dW_dqd.dot(partial);
      }
    }
  }
}

template BodyMotion<MotionDual<1>> seeded_motion<1>(const Kinematics&, int, int);
template BodyMotion<MotionDual<2>> seeded_motion<2>(const Kinematics&, int, int);
template void add_wrench_derivatives<1>(const Kinematics&, const KinematicsDerivatives&,
                                        const std::array<int, 1>&,
                                        const std::array<Wrench<MotionDual<1>>, 1>&,
                                        Eigen::MatrixXd&, Eigen::MatrixXd&);
template void add_wrench_derivatives<2>(const Kinematics&, const KinematicsDerivatives&,
                                        const std::array<int, 2>&,
                                        const std::array<Wrench<MotionDual<2>>, 2>&,
                                        Eigen::MatrixXd&, Eigen::MatrixXd&);

bool KinematicsDerivatives::all_finite() const {
  const auto finite = [](const std::vector<double>& a) {
    return std::all_of(a.begin(), a.end(), [](double x) { return std::isfinite(x); });
  };
  return finite(dv_dq_) && finite(dw_dq_) && finite(ddv_dq_) && finite(ddw_dq_);
}

}  // namespace symdyn::runtime
