#pragma once
// The motion of a model's bodies over time, for the animation writers
// (gltf.hpp, easyanim.hpp): at each recorded instant, every body's rotation
// (a unit quaternion) and the position of its G, from the emitted positions()
// alone, the cheapest entry point.

#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>
#include <symdyn/runtime/kinematics.hpp>
#include <symdyn/runtime/linearization.hpp>

namespace symdyn::runtime {

class MultibodySystem;

class Model;

class Animation {
 public:
  // The model must outlive the animation.
  explicit Animation(const Model& model);

  // Appends the poses at s (times must increase); NumericError if a pose is not finite.
  void record(const State& s);

  std::size_t frames() const { return times_.size(); }
  int nbody() const { return nbody_; }
  double time(std::size_t frame) const { return times_[frame]; }
  // Successive quaternions of a body are on the same side (q and -q are one
  // rotation), so that interpolating between frames takes the short way.
  Eigen::Quaterniond rotation(std::size_t frame, int body) const;
  Vec3 translation(std::size_t frame, int body) const;
  // The rotation matrix and position of G, as positions() gave them.
  Mat3 R(std::size_t frame, int body) const { return rotation(frame, body).toRotationMatrix(); }

 private:
  const double* pose(std::size_t frame, int body) const {
    return &poses_[7 * (frame * nbody_ + body)];
  }

  const Model& model_;
  int nbody_;
  Kinematics k_;
  std::vector<double> times_;
  std::vector<double> poses_;  // per frame and body: qx, qy, qz, qw, x, y, z
};

// One period of a mode of a linearization about `reference`, as EasyDyn's .vmo
// files showed it: q(t) = q_ref + a·Re(psi·e^(i·omega·t)), damping left out, the
// shape scaled so that its largest coordinate moves by `amplitude`; a mode
// that does not oscillate (omega = 0) swings as cos over one second. With
// closed loops, each frame's loops closed (q the independent coordinates).
Animation mode_animation(MultibodySystem& system, const State& reference, const Linearization& lin,
                         const Mode& mode, double amplitude, int frames = 48);

}  // namespace symdyn::runtime
