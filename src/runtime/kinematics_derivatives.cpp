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

bool KinematicsDerivatives::all_finite() const {
  const auto finite = [](const std::vector<double>& a) {
    return std::all_of(a.begin(), a.end(), [](double x) { return std::isfinite(x); });
  };
  return finite(dv_dq_) && finite(dw_dq_) && finite(ddv_dq_) && finite(ddw_dq_);
}

}  // namespace symdyn::runtime
