#pragma once
// Six-component linear bushing between two body frames, as in EasyDyn.
//
// Frame A is attached to body a (origin O_A and axes given in body a's
// coordinates), frame B to body b (either may be the ground). In A's axes:
//   d      = R_A^T (O_B - O_A)                     relative translation (3)
//   dd     = R_A^T (v_OB - v_OA - w_A x (O_B - O_A))
//   theta  = Cardan angles of R_A^T R_B in the chosen order (3)
//   thetad = E(theta)^-1 R_A^T (w_B - w_A)
//   f      = preload_force  - K_t d     - C_t dd         (per axis)
//   tau    = preload_torque - K_r theta - C_r thetad     (per Cardan angle)
// The force R_A f acts on body b and its opposite on body a, both at the
// mid-point of O_A and O_B (EasyDyn's choice); the moment R_A E^-T tau (the
// moment whose power on the relative rotation is tau . thetad, exact for
// large angles; EasyDyn used tau directly) acts on b and its opposite on a.

#include <array>
#include <string>

#include <symdyn/runtime/cardan.hpp>
#include <symdyn/runtime/force_element.hpp>

namespace symdyn::runtime {

// A frame fixed to a body: origin (body coordinates from G) and axes (columns,
// in body axes).
struct BodyFrame {
  int body = ground;
  Vec3 origin = Vec3::Zero();
  Mat3 axes = Mat3::Identity();
};

struct BushingProperties {
  Vec3 stiffness = Vec3::Zero();             // K_t per A axis (N/m)
  Vec3 damping = Vec3::Zero();               // C_t (N s/m)
  Vec3 rotational_stiffness = Vec3::Zero();  // K_r per Cardan angle (N m/rad)
  Vec3 rotational_damping = Vec3::Zero();    // C_r (N m s/rad)
  Vec3 preload_force = Vec3::Zero();         // on b, A axes, at zero deflection
  Vec3 preload_torque = Vec3::Zero();        // per Cardan angle
};

class Bushing : public ForceElement {
 public:
  // order: Cardan axis order such as "xyz" (ModelError otherwise).
  Bushing(std::string name, BodyFrame a, BodyFrame b, const BushingProperties& p,
          std::string_view order = "xyz");
  std::string name() const override { return "bushing '" + name_ + "'"; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // Exact: the law differentiated automatically with respect to the motions of a and b
  // (add_wrench_derivatives).
  LoadDerivatives load_derivatives() const override {
    return LoadDerivatives::exact_with_kinematics_derivatives;
  }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;
  // 1/2 d^T K_t d + 1/2 theta^T K_r theta (stored elastic energy).
  double potential_energy(const State& s, const Kinematics& k) const override;

  // Deflections: d and theta (and their rates) at the given kinematics.
  template <class T>
  struct BasicDeflection {
    Vec3T<T> d, dd, theta, thetad;
  };
  using Deflection = BasicDeflection<double>;
  Deflection deflection(const Kinematics& k) const;

 private:
  // The deflections and the wrenches on b and on a (at their centres of gravity) for the
  // motions of a and b, with any scalar.
  template <class T>
  BasicDeflection<T> deflection(const BodyMotion<T>& a, const BodyMotion<T>& b) const;
  template <class T>
  std::array<Wrench<T>, 2> wrenches(const BodyMotion<T>& a, const BodyMotion<T>& b) const;

  std::string name_;
  BodyFrame a_, b_;
  BushingProperties p_;
  CardanOrder order_;
};

}  // namespace symdyn::runtime
