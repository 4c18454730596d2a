#pragma once
// Penalty contact with a plane: a body point or sphere, and the simple tyre of
// docs/models.md (the trike's).

#include <string>

#include <symdyn/runtime/force_element.hpp>

namespace symdyn::runtime {

// A fixed plane: a point on it and its unit normal (pointing out of the
// ground, into the free space).
struct Plane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
};

// A plane's point finite and its normal a direction (PropertyError naming
// `element` and plane_point or plane_normal).
void check_plane(const std::string& element, const Plane& plane);

// How friction is regularized near zero slip speed v_s:
//   linear: Ft = -mu N vt / max(|vt|, v_s)       (EasyDyn: linear below v_s)
//   smooth: Ft = -mu N vt / sqrt(|vt|^2 + v_s^2)  (docs/models.md's contacts)
enum class FrictionRegularization { linear, smooth };

struct ContactProperties {
  double stiffness = 0.0;         // Kn
  double stiffness_exponent = 1;  // pk
  double damping = 0.0;           // Cd
  double damping_exponent = 0;    // pd
  double friction = 0.0;          // mu
  double slip_speed = 1e-3;       // v_s (m/s), > 0
  FrictionRegularization regularization = FrictionRegularization::linear;
};

// Contact of a sphere of radius r (0 for a point) centred at a body point
// with a plane. Penetration delta = r - (X - O).n with X the centre; contact
// point C = X - r n; with vC the velocity of the body's material point at C,
// deltad = -vC.n and vt = vC - (vC.n) n:
//   N  = max(0, Kn delta^pk + Cd delta^pd deltad)   (0 when delta <= 0)
//   Ft = -mu N vt / reg(|vt|)
// The force N n + Ft acts at C on the body.
class PlaneContact : public ForceElement {
 public:
  PlaneContact(std::string name, int body, const Vec3& point, double radius, const Plane& plane,
               const ContactProperties& p);
  std::string name() const override { return "contact '" + name_ + "'"; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // Exact: the law differentiated automatically with respect to the body's motion
  // (add_wrench_derivatives), C moving with the sphere's centre, not with the body; on the
  // side of each switch (contact, N > 0, |vt| against v_s) where the state is.
  LoadDerivatives load_derivatives() const override {
    return LoadDerivatives::exact_with_kinematics_derivatives;
  }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;

  // The contact quantities at the given kinematics.
  template <class T>
  struct BasicResult {
    T penetration = T(0.0), penetration_rate = T(0.0), normal_force = T(0.0);
    Vec3T<T> contact_point = Vec3T<T>::Zero(), force = Vec3T<T>::Zero();
  };
  using Result = BasicResult<double>;
  Result evaluate(const Kinematics& k) const;

 private:
  template <class T>
  BasicResult<T> evaluate(const BodyMotion<T>& body) const;

  std::string name_;
  int body_;
  Vec3 point_;
  double radius_;
  Plane plane_;
  ContactProperties p_;
};

// The simple tyre of docs/models.md. Wheel centre C = the body point `centre`,
// spin axis e = R . axis (the wheel's local y axis by default), radius R:
//   d = unit(n - (n.e) e);  P = C - R d;  delta = -(P - O).n
//   vP = velocity of the wheel's material point at P
//   N  = max(0, k delta - c vP.n) if delta > 0, else 0
//   vt = vP - (vP.n) n;  Ft = -mu N vt / sqrt(|vt|^2 + eps^2)
// The force N n + Ft acts at P on the wheel.
struct SimpleTyreProperties {
  double radius = 0.3;
  double stiffness = 2e5;
  double damping = 500.0;
  double friction = 0.9;
  double epsilon = 0.05;
  Vec3 axis = Vec3::UnitY();   // spin axis in body axes
  Vec3 centre = Vec3::Zero();  // wheel centre in body coordinates
};

class SimpleTyre : public ForceElement {
 public:
  SimpleTyre(std::string name, int body, const SimpleTyreProperties& p, const Plane& ground = {});
  std::string name() const override { return "tyre '" + name_ + "'"; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // Exact: the law differentiated automatically with respect to the wheel's motion
  // (add_wrench_derivatives), P moving with the wheel's centre and axis; on the side of each
  // switch (contact, N > 0) where the state is.
  LoadDerivatives load_derivatives() const override {
    return LoadDerivatives::exact_with_kinematics_derivatives;
  }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;

  template <class T>
  struct BasicResult {
    Vec3T<T> contact_point = Vec3T<T>::Zero(), contact_velocity = Vec3T<T>::Zero(),
             force = Vec3T<T>::Zero();
    T penetration = T(0.0), normal_force = T(0.0);
  };
  using Result = BasicResult<double>;
  Result evaluate(const Kinematics& k) const;

 private:
  template <class T>
  BasicResult<T> evaluate(const BodyMotion<T>& wheel) const;

  std::string name_;
  int body_;
  SimpleTyreProperties p_;
  Plane ground_;
};

}  // namespace symdyn::runtime
