#pragma once
// Small DynamicSystems with closed-form solutions, for the integrator tests.
// Each writes its explicit and residual forms independently (not one from the
// other), so that a mistake in either shows up as a disagreement.

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime::testing {

constexpr double two_pi = 2.0 * std::numbers::pi;

// q'' + 2·zeta·w·q' + w²·q = 0, with closed form for zeta < 1.
class Oscillator : public DynamicSystem {
 public:
  explicit Oscillator(double w = two_pi, double zeta = 0.0) : w_(w), zeta_(zeta) {}
  int num_coordinates() const override { return 1; }
  std::string coordinate_name(int) const override { return "x"; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    qdd.resize(1);
    yd.resize(0);
    qdd[0] = -2.0 * zeta_ * w_ * s.qd[0] - w_ * w_ * s.q[0];
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    f.resize(1);
    g.resize(0);
    f[0] = qdd[0] + 2.0 * zeta_ * w_ * s.qd[0] + w_ * w_ * s.q[0];
  }
  // q(t) from q(0) = q0, q'(0) = v0.
  double exact(double t, double q0, double v0) const {
    const double wd = w_ * std::sqrt(1.0 - zeta_ * zeta_);
    const double sigma = zeta_ * w_;
    return std::exp(-sigma * t) *
           (q0 * std::cos(wd * t) + (v0 + sigma * q0) / wd * std::sin(wd * t));
  }

 protected:
  double w_;
  double zeta_;
};

// EasyDyn's regression case: a unit mass moving along the unit direction u
// (x = q·u in space), held by a spring of stiffness (2π)² and free length 1 to
// the origin. The residual is written in 3-D as EasyDyn builds it (virtual power:
// inertia and spring force projected on the partial velocity u), so it reduces to
// q'' + (2π)²·(q - 1) = 0 whatever u: q = 1 + (q0 - 1)·cos 2πt.
class SpringAlongDirection : public DynamicSystem {
 public:
  explicit SpringAlongDirection(const Eigen::Vector3d& direction) : u_(direction.normalized()) {}
  int num_coordinates() const override { return 1; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    qdd.resize(1);
    yd.resize(0);
    qdd[0] = -two_pi * two_pi * (s.q[0] - 1.0);
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    const Eigen::Vector3d x = s.q[0] * u_;
    const Eigen::Vector3d a = qdd[0] * u_;
    const double k = two_pi * two_pi;
    const Eigen::Vector3d force = -k * (x.norm() - 1.0) * x.normalized();
    f.resize(1);
    g.resize(0);
    f[0] = (mass_ * a - force).dot(u_);
  }

 private:
  Eigen::Vector3d u_;
  double mass_ = 1.0;
};

// The damped oscillator q'' + 2·zeta·w·q' + w²·q = 0 driving a first-order
// low-pass filter y' = (q - y)/tau. With q = Re(C·e^(lambda·t)),
// y = Re(C/(1 + lambda·tau)·e^(lambda·t)) + (y0 - Re(C/(1 + lambda·tau)))·e^(-t/tau).
class FilteredOscillator : public Oscillator {
 public:
  FilteredOscillator(double w, double zeta, double tau) : Oscillator(w, zeta), tau_(tau) {}
  int num_extra_states() const override { return 1; }
  std::string extra_state_name(int) const override { return "filter"; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    Oscillator::accelerations(s, qdd, yd);
    yd.resize(1);
    yd[0] = (s.q[0] - s.y[0]) / tau_;
  }
  void residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f,
                Vector& g) override {
    Oscillator::residual(s, qdd, yd, f, g);
    g.resize(1);
    g[0] = tau_ * yd[0] - (s.q[0] - s.y[0]);  // a coefficient other than 1 on yd, on purpose
  }
  double exact_filter(double t, double q0, double v0, double y0) const {
    using C = std::complex<double>;
    const double wd = w_ * std::sqrt(1.0 - zeta_ * zeta_);
    const C lambda(-zeta_ * w_, wd);
    const C c(q0, -(v0 + zeta_ * w_ * q0) / wd);  // q = Re(c·e^(lambda·t))
    const C gain = c / (1.0 + lambda * tau_);
    return (gain * std::exp(lambda * t)).real() + (y0 - gain.real()) * std::exp(-t / tau_);
  }

 private:
  double tau_;
};

// Undamped pendulum theta'' = -(g/L)·sin(theta); energy per unit mass
// E = L²·theta'²/2 - g·L·cos(theta) is conserved.
class Pendulum : public DynamicSystem {
 public:
  int num_coordinates() const override { return 1; }
  std::string coordinate_name(int) const override { return "theta"; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    qdd.resize(1);
    yd.resize(0);
    qdd[0] = -g_ / l_ * std::sin(s.q[0]);
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    f.resize(1);
    g.resize(0);
    f[0] = l_ * qdd[0] + g_ * std::sin(s.q[0]);
  }
  double energy(const State& s) const {
    return 0.5 * l_ * l_ * s.qd[0] * s.qd[0] - g_ * l_ * std::cos(s.q[0]);
  }

 protected:
  double g_ = 9.81;
  double l_ = 1.0;
};

// The same with its exact Jacobians of the residual: M = L, C = 0, K = g·cos(theta)
// (the others are found by finite differences).
class PendulumWithJacobians : public Pendulum {
 public:
  void jacobians(const State& s, const Vector&, Matrix& M, Matrix& C, Matrix& K) override {
    M = Matrix::Constant(1, 1, l_);
    C = Matrix::Zero(1, 1);
    K = Matrix::Constant(1, 1, g_ * std::cos(s.q[0]));
  }
};

// Two unit masses: x0 held to the ground by a soft spring (2π)², x1 held to x0 by a
// stiff spring k and a damper c. Linear: M·qdd + C·qd + K·q = 0, exact solution
// by the eigen-decomposition of the first-order matrix.
class StiffChain : public DynamicSystem {
 public:
  StiffChain(double k, double c) {
    K_ << two_pi * two_pi + k, -k, -k, k;
    C_ << c, -c, -c, c;
  }
  int num_coordinates() const override { return 2; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    qdd = -(C_ * s.qd + K_ * s.q);
    yd.resize(0);
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    f = qdd + C_ * s.qd + K_ * s.q;
    g.resize(0);
  }
  void jacobians(const State&, const Vector&, Matrix& M, Matrix& C, Matrix& K) override {
    M = Matrix::Identity(2, 2);
    C = C_;
    K = K_;
  }
  // q(t) from the initial state: x(t) = V·exp(D·t)·V⁻¹·x(0) for x = (q, qd).
  Eigen::Vector2d exact(double t, const Eigen::Vector2d& q0, const Eigen::Vector2d& v0) const {
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    A.topRightCorner<2, 2>().setIdentity();
    A.bottomLeftCorner<2, 2>() = -K_;
    A.bottomRightCorner<2, 2>() = -C_;
    Eigen::EigenSolver<Eigen::Matrix4d> es(A);
    Eigen::Vector4d x0;
    x0 << q0, v0;
    const Eigen::Matrix4cd V = es.eigenvectors();
    const Eigen::Vector4cd coefficients = V.partialPivLu().solve(x0.cast<std::complex<double>>());
    Eigen::Vector4cd x = Eigen::Vector4cd::Zero();
    for (int i = 0; i < 4; ++i) x += coefficients[i] * std::exp(es.eigenvalues()[i] * t) * V.col(i);
    return x.head<2>().real();
  }

 private:
  Eigen::Matrix2d K_, C_;
};

// A stiff element whose stiffness depends on the configuration (as a stiff bushing
// does when it turns): unit masses q0 (soft spring (2π)² to the ground) and q1,
// tied by the potential k·(1 + q0²)·(q1 - q0)²/2 and a damper c. The stiff
// iteration matrix changes by a factor 2 as q0 swings between 0 and 1: a matrix
// kept from an earlier step must then be refreshed.
class ConfigurationStiff : public DynamicSystem {
 public:
  ConfigurationStiff(double k, double c) : k_(k), c_(c) {}
  int num_coordinates() const override { return 2; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    qdd = -forces(s);
    yd.resize(0);
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    f = qdd + forces(s);
    g.resize(0);
  }

 private:
  // dV/dq + damping, V = (2π)²·q0²/2 + k·(1 + q0²)·d²/2 with d = q1 - q0.
  Vector forces(const State& s) const {
    const double q0 = s.q[0], d = s.q[1] - s.q[0], dv = s.qd[1] - s.qd[0];
    const double stiff = k_ * (1.0 + q0 * q0) * d;
    Vector f(2);
    f[0] = two_pi * two_pi * q0 + k_ * q0 * d * d - stiff - c_ * dv;
    f[1] = stiff + c_ * dv;
    return f;
  }
  double k_;
  double c_;
};

// q'' = 2·q³ from q = 1, q' = 1: q = 1/(1 - t), which blows up at t = 1.
class BlowUp : public DynamicSystem {
 public:
  int num_coordinates() const override { return 1; }
  std::string coordinate_name(int) const override { return "runaway"; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    qdd.resize(1);
    yd.resize(0);
    qdd[0] = 2.0 * std::pow(s.q[0], 3);
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    f.resize(1);
    g.resize(0);
    f[0] = qdd[0] - 2.0 * std::pow(s.q[0], 3);
  }
};

// The oscillator, returning NaN from t = 0.5 on (a model that breaks down).
class BreaksAtHalf : public Oscillator {
 public:
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    Oscillator::accelerations(s, qdd, yd);
    if (s.t >= 0.5) qdd[0] = std::numeric_limits<double>::quiet_NaN();
  }
  void residual(const State& s, const Vector& qdd, const Vector& yd, Vector& f,
                Vector& g) override {
    Oscillator::residual(s, qdd, yd, f, g);
    if (s.t >= 0.5) f[0] = std::numeric_limits<double>::quiet_NaN();
  }
};

// q'' = 1/sqrt(1 - q) from q = 0, q' = 1: q reaches 1 at a finite speed
// (q'² = 5 - 4·sqrt(1 - q)) and passes into q > 1, where the model has no
// value (a crank longer than its rod: asin's argument beyond 1).
class DomainEdge : public DynamicSystem {
 public:
  int num_coordinates() const override { return 1; }
  std::string coordinate_name(int) const override { return "crank"; }
  void accelerations(const State& s, Vector& qdd, Vector& yd) override {
    qdd.resize(1);
    yd.resize(0);
    qdd[0] = 1.0 / std::sqrt(1.0 - s.q[0]);
  }
  void residual(const State& s, const Vector& qdd, const Vector&, Vector& f, Vector& g) override {
    f.resize(1);
    g.resize(0);
    f[0] = qdd[0] - 1.0 / std::sqrt(1.0 - s.q[0]);
  }
};

inline State initial_state(double q0, double v0, double y0 = std::nan("")) {
  State s;
  s.q = Vector::Constant(1, q0);
  s.qd = Vector::Constant(1, v0);
  s.y = std::isnan(y0) ? Vector() : Vector::Constant(1, y0);
  return s;
}

}  // namespace symdyn::runtime::testing
