#pragma once
// Gim's brush tyre (the UA tyre documented for ADAMS, as EasyDyn used it) on a
// flat ground.
//
// Geometry. Torus tyre: outer radius r1, section radius r2, centre C, spin
// axis e (global). With n the ground normal, d = unit(n - (n.e) e) points
// from C towards the ground in the wheel plane; the lowest point is
// P = C - (r1 - r2) d - r2 n; penetration pen = -(P - O).n. Contact frame:
// x = unit(e x n) (longitudinal), y = n x x (lateral), z = n. Camber
// gamma = asin(e.n): positive when the wheel's top leans towards -y.
//
// Kinematics. vP: velocity of the wheel's material point at P; vC: of the
// centre. Reference speed V = max(|vC.x|, 1e-3). Slips (sliding velocity over
// V): s_long = vP.x / V, s_lat = vP.y / V.
//
// Forces (contact frame, acting on the wheel at P):
//   Fz = max(0, Kz pen - sqrt(Kz pen / Fznom) Cz vP.n) when pen > 0 (no pull)
//   a  = sqrt(2 r1 pen)                          half contact length
//   mu = mu_s - (mu_s - mu_d) min(1, sqrt(s_long^2 + s_lat^2))
//   C_long = Clongnom (Fz/Fznom)^nlong, C_lat, C_camber likewise
// then gim_brush() below gives Fx, Fy and the aligning moment Mz. No rolling
// resistance.
//
// The brush (derivation in gim_tyre.cpp). Parabolic pressure over the contact
// length, xi in [0, 1] from the leading edge; bristle stress, per unit xi, of
// 2 X xi along x and 2 Y xi + 6 G xi (1 - xi) along y, with X = C_long s_long,
// Y = C_lat s_lat, G = C_camber gamma, and the friction limit
// 6 mu Fz xi (1 - xi). Bristles adhere from the leading edge up to xi_s and
// slide behind it. With u = 1 - xi the limit is reached where
//   (X)^2 + (Y + 3 G u)^2 = (3 mu Fz u)^2        (a quadratic in u),
// so full sliding (xi_s = 0) holds when X^2 + (Y + 3 G)^2 >= (3 mu Fz)^2.
// The sliding stress has the direction of the bristle stress at xi_s,
// t = unit(X, Y + 3 G (1 - xi_s)). With S = 1 - 3 xi_s^2 + 2 xi_s^3:
//   Fx = -(X xi_s^2 + mu Fz t_x S)
//   Fy = -(Y xi_s^2 + G (3 xi_s^2 - 2 xi_s^3) + mu Fz t_y S)
//   Mz = -a (Y (xi_s^2 - 4/3 xi_s^3) + 3 (G - mu Fz t_y) xi_s^2 (1 - xi_s)^2)
// (small slips: Fx = -X, Fy = -Y - G, pneumatic trail a/3; at the boundary of
// full sliding xi_s -> 0 continuously: |F| = mu Fz, Mz = 0).

#include <string>

#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/force_element.hpp>

namespace symdyn::runtime {

template <class T>
struct BasicBrushInput {
  T normal_force = T(0.0);      // Fz >= 0
  T slip_long = T(0.0);         // s_long
  T slip_lat = T(0.0);          // s_lat
  T camber = T(0.0);            // gamma (rad)
  T friction = T(1.0);          // mu
  T stiffness_long = T(0.0);    // C_long (N per unit slip)
  T stiffness_lat = T(0.0);     // C_lat (N per unit slip)
  T stiffness_camber = T(0.0);  // C_camber (N/rad)
  T half_length = T(0.0);       // a (m)
};
using BrushInput = BasicBrushInput<double>;

template <class T>
struct BasicBrushOutput {
  T Fx = T(0.0), Fy = T(0.0), Mz = T(0.0);
  T adhesion = T(1.0);   // xi_s: adhesion fraction of the contact length
  bool sliding = false;  // full sliding
};
using BrushOutput = BasicBrushOutput<double>;

BrushOutput gim_brush(const BrushInput& in);
// The same for any scalar T (the automatic differentiation of GimTyre's loads).
template <class T>
BasicBrushOutput<T> gim_brush(const BasicBrushInput<T>& in);

struct GimTyreProperties {
  double r1 = 0.3;        // outer radius (m)
  double r2 = 0.1;        // section radius (m)
  double Kz = 2e5;        // vertical stiffness (N/m)
  double Cz = 500.0;      // vertical damping at Fznom (N s/m)
  double Fznom = 3000.0;  // nominal load (N)
  double Clongnom = 5e4, nlong = 1.0;
  double Clatnom = 4e4, nlat = 1.0;
  double Ccambernom = 2e3, ncamber = 1.0;
  double mu_static = 1.0, mu_dynamic = 0.8;
  Vec3 axis = Vec3::UnitY();   // spin axis in body axes
  Vec3 centre = Vec3::Zero();  // wheel centre in body coordinates
};

class GimTyre : public ForceElement {
 public:
  GimTyre(std::string name, int body, const GimTyreProperties& p, const Plane& ground = {});
  std::string name() const override { return "Gim tyre '" + name_ + "'"; }
  void apply(const State& s, const Kinematics& k, Loads& loads) const override;
  // Exact: the law differentiated automatically with respect to the wheel's motion
  // (add_wrench_derivatives), P moving with the wheel's centre and axis; on the side of each
  // switch where the state is (contact, Fz > 0, adhesion or full sliding, the adhesion
  // length clamped, |vC.x| against 1e-3, the slip against 1 in mu; at zero slip, mu's cone,
  // the derivative 0).
  LoadDerivatives load_derivatives() const override {
    return LoadDerivatives::exact_with_kinematics_derivatives;
  }
  void add_load_derivatives(const State& s, const Kinematics& k, const KinematicsDerivatives& dk,
                            Matrix& dQ_dq, Matrix& dQ_dqd) const override;

  template <class T>
  struct BasicResult {
    Vec3T<T> contact_point = Vec3T<T>::Zero();
    Vec3T<T> x = Vec3T<T>::Zero(), y = Vec3T<T>::Zero();  // contact frame axes
    T penetration = T(0.0), slip_long = T(0.0), slip_lat = T(0.0), camber = T(0.0),
      friction = T(0.0);
    T Fz = T(0.0);
    BasicBrushOutput<T> brush;
    Vec3T<T> force = Vec3T<T>::Zero(), moment = Vec3T<T>::Zero();  // global, at the contact point
  };
  using Result = BasicResult<double>;
  Result evaluate(const Kinematics& k) const;

 private:
  template <class T>
  BasicResult<T> evaluate(const BodyMotion<T>& wheel) const;

  std::string name_;
  int body_;
  GimTyreProperties p_;
  Plane ground_;
};

}  // namespace symdyn::runtime
