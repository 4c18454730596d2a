#include <fmt/format.h>

#include <cmath>
#include <complex>
#include <numbers>

#include <symdyn/runtime/animation.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::runtime {

Animation::Animation(const Model& model)
    : model_(model), nbody_(model.nbody()), k_(model.make_kinematics()) {}

void Animation::record(const State& s) {
  if (!times_.empty() && !(s.t > times_.back())) {
    throw OptionError(fmt::format("animation: frame at t = {} after t = {}: times must increase",
                                  s.t, times_.back()));
  }
  if (s.q.size() != model_.nq()) {
    // A model with closed loops is drawn in the tree's coordinates x = (q, p).
    throw ModelError(fmt::format(
        "animation: model '{}': a state of {} coordinates, expected {}{}", model_.name(),
        s.q.size(), model_.nq(),
        model_.has_loops() ? " (closed loops: record MultibodySystem::extended_state(s))" : ""));
  }
  model_.positions(s.t, s.q.data(), k_);
  for (int i = 0; i < nbody_; ++i) {
    Eigen::Quaterniond q(Mat3(k_.R(i)));
    q.normalize();
    if (frames() > 0 && q.coeffs().dot(rotation(frames() - 1, i).coeffs()) < 0)
      q.coeffs() = -q.coeffs();
    const Vec3 x = k_.x(i);
    if (!q.coeffs().allFinite() || !x.allFinite()) {
      throw NumericError(fmt::format("animation: t = {}: the pose of body '{}' is not finite", s.t,
                                     model_.body_names()[i]));
    }
    poses_.insert(poses_.end(), {q.x(), q.y(), q.z(), q.w(), x.x(), x.y(), x.z()});
  }
  times_.push_back(s.t);
}

Eigen::Quaterniond Animation::rotation(std::size_t frame, int body) const {
  const double* p = pose(frame, body);
  return Eigen::Quaterniond(p[3], p[0], p[1], p[2]);
}

Vec3 Animation::translation(std::size_t frame, int body) const {
  const double* p = pose(frame, body);
  return Vec3(p[4], p[5], p[6]);
}

Animation mode_animation(MultibodySystem& system, const State& reference, const Linearization& lin,
                         const Mode& mode, double amplitude, int frames) {
  const double omega = std::abs(mode.pole.imag());
  const double period = omega > 0 ? 2 * std::numbers::pi / omega : 1.0;
  const double largest = mode.shape.cwiseAbs().maxCoeff();
  const double scale = largest > 0 ? amplitude / largest : 0.0;
  const bool loops = system.model().has_loops();
  Animation animation(system.model());
  for (int k = 0; k <= frames; ++k) {
    const double t = period * k / frames;
    const std::complex<double> phase = std::polar(1.0, 2 * std::numbers::pi * k / frames);
    State s = reference;
    s.t = reference.t + t;
    for (std::size_t j = 0; j < lin.kept.size(); ++j) {
      s.q[lin.kept[j]] += scale * (mode.shape[static_cast<Eigen::Index>(j)] * phase).real();
    }
    animation.record(loops ? system.extended_state(s) : s);
  }
  return animation;
}

}  // namespace symdyn::runtime
