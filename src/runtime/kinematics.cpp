#include <Eigen/Geometry>
#include <algorithm>

#include <symdyn/runtime/kinematics.hpp>

namespace symdyn::runtime {

Kinematics::Kinematics(int nq, int nbody, int ndep)
    : nq_(nq),
      nbody_(nbody),
      R_(9 * std::max(nbody, 1), 0.0),
      x_(3 * std::max(nbody, 1), 0.0),
      v_(x_),
      w_(x_),
      a_(x_),
      dw_(x_),
      dv_(3 * std::max(nbody * nq, 1), 0.0),
      dwq_(dv_),
      p_(std::max(ndep, 1), 0.0),
      pd_(p_),
      pdd_(p_) {}

Vec3 Kinematics::point_position(int body, const Vec3& p_body) const {
  if (body == ground) return p_body;
  return x(body) + R(body) * p_body;
}

Vec3 Kinematics::point_velocity(int body, const Vec3& p_body) const {
  if (body == ground) return Vec3::Zero();
  return v(body) + w(body).cross(R(body) * p_body);
}

Vec3 Kinematics::velocity_at(int body, const Vec3& X) const {
  if (body == ground) return Vec3::Zero();
  return v(body) + w(body).cross(X - x(body));
}

Vec3 Kinematics::to_global(int body, const Vec3& p_body) const {
  if (body == ground) return p_body;
  return R(body) * p_body;
}

Mat3 Kinematics::rotation(int body) const {
  if (body == ground) return Mat3::Identity();
  return R(body);
}

namespace {
bool finite(const std::vector<double>& a) {
  return Eigen::Map<const Eigen::VectorXd>(a.data(), static_cast<Eigen::Index>(a.size()))
      .allFinite();
}
}  // namespace

bool Kinematics::all_finite(bool accelerations) const {
  for (const auto* a : {&R_, &x_, &v_, &w_, &dv_, &dwq_}) {
    if (!finite(*a)) return false;
  }
  return !accelerations || (finite(a_) && finite(dw_));
}

bool Kinematics::finite_up_to(KinematicsLevel level) const {
  if (level == KinematicsLevel::none) return true;
  if (!finite(R_) || !finite(x_)) return false;
  return level == KinematicsLevel::positions || (finite(v_) && finite(w_));
}

void Kinematics::clear_rates() {
  std::fill(v_.begin(), v_.end(), 0.0);
  std::fill(w_.begin(), w_.end(), 0.0);
  std::fill(a_.begin(), a_.end(), 0.0);
  std::fill(dw_.begin(), dw_.end(), 0.0);
}

}  // namespace symdyn::runtime
