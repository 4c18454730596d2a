#include <Eigen/Geometry>

#include <symdyn/runtime/energy.hpp>

namespace symdyn::runtime {

double kinetic_energy(const Model& m, const Kinematics& k) {
  double T = 0.0;
  for (int i = 0; i < m.nbody(); ++i) {
    const Vec3 w = k.w(i);
    T += 0.5 * m.mass(i) * k.v(i).squaredNorm() + 0.5 * w.dot(m.global_inertia(i, k) * w);
  }
  return T;
}

double gravitational_energy(const Model& m, const Kinematics& k) {
  double V = 0.0;
  for (int i = 0; i < m.nbody(); ++i) V -= m.mass(i) * k.x(i).dot(m.gravity());
  return V;
}

Momentum momentum(const Model& m, const Kinematics& k) {
  Momentum p;
  for (int i = 0; i < m.nbody(); ++i) {
    const Vec3 mv = m.mass(i) * k.v(i);
    p.linear += mv;
    p.angular += k.x(i).cross(mv) + m.global_inertia(i, k) * k.w(i);
  }
  return p;
}

}  // namespace symdyn::runtime
