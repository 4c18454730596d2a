#include <fmt/format.h>

#include <utility>

#include <symdyn/runtime/element_parameters.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/point_forces.hpp>

namespace symdyn::runtime {

PointSpringDamper::PointSpringDamper(std::string name, BodyPoint a, BodyPoint b, double stiffness,
                                     double free_length, double damping)
    : name_(std::move(name)), a_(a), b_(b), k_(stiffness), L0_(free_length), c_(damping) {
  check_property(this->name(), "point_a", a_.point);
  check_property(this->name(), "point_b", b_.point);
  check_parameter(this->name(), "point_spring_damper", "stiffness", k_);
  check_parameter(this->name(), "point_spring_damper", "free_length", L0_);
  check_parameter(this->name(), "point_spring_damper", "damping", c_);
}

double PointSpringDamper::length(const Kinematics& k) const {
  return (k.point_position(b_.body, b_.point) - k.point_position(a_.body, a_.point)).norm();
}

void PointSpringDamper::apply(const State& s, const Kinematics& k, Loads& loads) const {
  const Vec3 Pa = k.point_position(a_.body, a_.point);
  const Vec3 Pb = k.point_position(b_.body, b_.point);
  const Vec3 d = Pb - Pa;
  const double L = d.norm();
  if (!(L > 0.0)) {
    throw NumericError(
        fmt::format("t = {}: {}: its two points coincide (direction undefined)", s.t, name()));
  }
  const Vec3 u = d / L;
  // Ld = u . (v_Pb - v_Pa)
  const double Ld =
      c_ == 0.0 ? 0.0
                : u.dot(k.point_velocity(b_.body, b_.point) - k.point_velocity(a_.body, a_.point));
  const double tension = k_ * (L - L0_) + c_ * Ld;
  loads.add_force_at(b_.body, k, Pb, -tension * u);
  loads.add_force_at(a_.body, k, Pa, tension * u);
}

// With Δ = P_b - P_a, L = |Δ|, u = Δ/L, G_j = ∂Δ/∂q_j and g_j = u·G_j = ∂L/∂q_j:
//   ∂u/∂q_k = (G_k - u·g_k)/L,   ∂Ld/∂q_k = ∂u/∂q_k·ΔṖ + u·∂ΔṖ/∂q_k,   ∂Ld/∂qd_k = g_k,
//   ∂²L/∂q_j∂q_k = (G_j·G_k - g_j·g_k)/L + u·∂G_j/∂q_k.
void PointSpringDamper::add_load_derivatives(const State& /*s*/, const Kinematics& k,
                                             const KinematicsDerivatives& dk, Matrix& dQ_dq,
                                             Matrix& dQ_dqd) const {
  const Vec3 Pa = k.point_position(a_.body, a_.point), Pb = k.point_position(b_.body, b_.point);
  const Vec3 ra = k.to_global(a_.body, a_.point), rb = k.to_global(b_.body, b_.point);  // from G
  const Vec3 d = Pb - Pa;
  const double L = d.norm();
  const Vec3 u = d / L;
  const Vec3 dPd = k.point_velocity(b_.body, b_.point) - k.point_velocity(a_.body, a_.point);
  const double tension = k_ * (L - L0_) + c_ * u.dot(dPd);
  const auto G = [&](int j) {
    return Vec3(dk.point_partial(k, b_.body, rb, j) - dk.point_partial(k, a_.body, ra, j));
  };
  for (int kk = 0; kk < k.nq(); ++kk) {
    const Vec3 Gk = G(kk);
    const double gk = u.dot(Gk);
    const Vec3 du = (Gk - u * gk) / L;
    const double dLd = du.dot(dPd) + u.dot(dk.point_velocity_derivative(k, b_.body, rb, kk) -
                                           dk.point_velocity_derivative(k, a_.body, ra, kk));
    const double dT_dq = k_ * gk + c_ * dLd, dT_dqd = c_ * gk;
    for (int j = 0; j < k.nq(); ++j) {
      const Vec3 Gj = G(j);
      const double gj = u.dot(Gj);
      const Vec3 dGj = dk.point_partial_derivative(k, b_.body, rb, j, kk) -
                       dk.point_partial_derivative(k, a_.body, ra, j, kk);
      const double d2L = (Gj.dot(Gk) - gj * gk) / L + u.dot(dGj);
      dQ_dq(j, kk) -= dT_dq * gj + tension * d2L;
      dQ_dqd(j, kk) -= dT_dqd * gj;
    }
  }
}

double PointSpringDamper::potential_energy(const State& /*s*/, const Kinematics& k) const {
  const double e = length(k) - L0_;
  return 0.5 * k_ * e * e;
}

PointLoad::PointLoad(std::string name, BodyPoint at, const Vec3& force, const Vec3& torque)
    : name_(std::move(name)), at_(at), force_(force), torque_(torque) {
  check_property(this->name(), "point", at_.point);
  check_property(this->name(), "force", force_);
  check_property(this->name(), "torque", torque_);
}

PointLoad::PointLoad(std::string name, BodyPoint at, Law law, LawDerivatives derivatives)
    : name_(std::move(name)),
      at_(at),
      force_(Vec3::Zero()),
      torque_(Vec3::Zero()),
      law_(std::move(law)),
      derivatives_(std::move(derivatives)) {
  check_property(this->name(), "point", at_.point);
}

void PointLoad::apply(const State& s, const Kinematics& k, Loads& loads) const {
  Vec3 f = force_;
  Vec3 m = torque_;
  if (law_) law_(s, k, f, m);
  loads.add_force_at(at_.body, k, k.point_position(at_.body, at_.point), f);
  loads.add_moment(at_.body, m);
}

void PointLoad::add_load_derivatives(const State& s, const Kinematics& k,
                                     const KinematicsDerivatives& dk, Matrix& dQ_dq,
                                     Matrix& dQ_dqd) const {
  if (at_.body == ground) return;
  Vec3 f = force_, m = torque_;
  if (law_) {
    dW_dq_.setZero(6, k.nq());
    dW_dqd_.setZero(6, k.nq());
    derivatives_(s, k, dk, f, m, dW_dq_, dW_dqd_);
    check_law_derivatives(name(), s, dW_dq_, dW_dqd_, 6, k.nq());
  }
  const Vec3 r = k.to_global(at_.body, at_.point);
  for (int j = 0; j < k.nq(); ++j) {
    const Vec3 J = dk.point_partial(k, at_.body, r, j);
    const Vec3 dw = k.dw_dqd(at_.body, j);
    for (int kk = 0; kk < k.nq(); ++kk) {
      dQ_dq(j, kk) += f.dot(dk.point_partial_derivative(k, at_.body, r, j, kk)) +
                      m.dot(dk.ddw_dq(at_.body, j, kk));
      if (!law_) continue;
      dQ_dq(j, kk) += dW_dq_.col(kk).head<3>().dot(J) + dW_dq_.col(kk).tail<3>().dot(dw);
      dQ_dqd(j, kk) += dW_dqd_.col(kk).head<3>().dot(J) + dW_dqd_.col(kk).tail<3>().dot(dw);
    }
  }
}

UserForce::UserForce(std::string name, Callback callback, KinematicsLevel reads, Jacobian jacobian)
    : name_(std::move(name)),
      callback_(std::move(callback)),
      reads_(reads),
      jacobian_(std::move(jacobian)) {}

void UserForce::apply(const State& s, const Kinematics& k, Loads& loads) const {
  callback_(s, k, loads);
}

void UserForce::add_load_derivatives(const State& s, const Kinematics& k,
                                     const KinematicsDerivatives& dk, Matrix& dQ_dq,
                                     Matrix& dQ_dqd) const {
  const auto nq = s.q.size();
  dQ_dq_.setZero(nq, nq);
  dQ_dqd_.setZero(nq, nq);
  jacobian_(s, k, dk, dQ_dq_, dQ_dqd_);
  check_law_derivatives(name(), s, dQ_dq_, dQ_dqd_, nq, nq);
  dQ_dq += dQ_dq_;
  dQ_dqd += dQ_dqd_;
}

}  // namespace symdyn::runtime
