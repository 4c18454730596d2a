// Simbody: one mobilized body per link (Pin or Slider, reoriented onto the
// link's axis), gravity as Force::UniformGravity; each operation realizes the
// state to the stage it needs, as Simbody's users do.
#include <Simbody.h>

#include "peer.hpp"

namespace symdyn::bench::peers {

namespace {

using namespace SimTK;

// A rotation taking Pin's z axis (Slider's x axis) onto the link's axis: for
// ±x, ±y, ±z a cyclic permutation of the axes (after a half turn for -), exact.
Rotation onto(int from, const Eigen::Vector3d& axis) {
  for (int to = 0; to < 3; ++to) {
    for (double sign : {1.0, -1.0}) {
      if (axis != sign * Eigen::Vector3d::Unit(to)) continue;
      Mat33 r(0);
      for (int k = 0; k < 3; ++k) r((k + to) % 3, (k + from) % 3) = 1;
      Mat33 half(0);  // a half turn about the axis after `from`: from -> -from
      for (int k = 0; k < 3; ++k) half(k, k) = k == (from + 1) % 3 ? 1 : sign;
      return Rotation(r * half, true);
    }
  }
  return Rotation(UnitVec3(axis.x(), axis.y(), axis.z()), CoordinateAxis(from));
}

class SimbodyPeer final : public Peer {
 public:
  explicit SimbodyPeer(const Mechanism& mech)
      : matter_(system_),
        forces_(system_),
        gravity_(forces_, matter_, Vec3(mech.gravity.x(), mech.gravity.y(), mech.gravity.z())),
        nq_(mech.nq()) {
    for (const Link& l : mech.links) {
      const Vec3 com(l.com.x(), l.com.y(), l.com.z());
      const Body::Rigid body(
          MassProperties(l.mass, com,
                         Inertia(Vec3(l.inertia.x(), l.inertia.y(), l.inertia.z()))
                             .shiftFromMassCenter(com, l.mass)));
      MobilizedBody& parent =
          l.parent < 0 ? matter_.updGround() : links_[static_cast<std::size_t>(l.parent)];
      Mat33 r;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) r(i, j) = l.R(i, j);
      }
      const Rotation offset(r, true);
      const Vec3 p(l.p.x(), l.p.y(), l.p.z());
      if (l.type == JointType::revolute) {
        const Rotation a = onto(2, l.axis);
        links_.push_back(MobilizedBody::Pin(parent, Transform(offset * a, p), body, Transform(a)));
      } else {
        const Rotation a = onto(0, l.axis);
        links_.push_back(
            MobilizedBody::Slider(parent, Transform(offset * a, p), body, Transform(a)));
      }
      if (l.mass > 0) bodies_.emplace_back(links_.back(), com);
    }
    system_.realizeTopology();
    state_ = system_.getDefaultState();
    for (int i = 0; i < nq_; ++i) {
      if (links_[static_cast<std::size_t>(i)].getFirstQIndex(state_) != i ||
          links_[static_cast<std::size_t>(i)].getFirstUIndex(state_) != i) {
        throw std::runtime_error("Simbody: coordinate order");
      }
    }
    M_.resize(nq_, nq_);
    udot_.resize(nq_);
    residual_.resize(nq_);
  }

  std::string name() const override { return "Simbody"; }
  double total_mass() const override {
    system_.realize(state_, Stage::Instance);
    return matter_.calcSystemMass(state_);
  }

  void forward_dynamics(const double* q, const double* qd, double* qdd) override {
    set(q, qd);
    system_.realize(state_, Stage::Acceleration);
    const Vector& udot = state_.getUDot();
    for (int i = 0; i < nq_; ++i) qdd[i] = udot[i];
  }
  void mass_matrix(const double* q) override {
    set(q, nullptr);
    system_.realize(state_, Stage::Position);
    matter_.calcM(state_, M_);
  }
  void read_mass_matrix(double* M) const override {
    for (int i = 0; i < nq_; ++i) {
      for (int j = 0; j < nq_; ++j) M[i * nq_ + j] = M_(i, j);
    }
  }
  // tau = M·udot + C - (applied forces: gravity), Simbody's inverse dynamics.
  void inverse_dynamics(const double* q, const double* qd, const double* qdd,
                        double* tau) override {
    set(q, qd);
    system_.realize(state_, Stage::Dynamics);
    for (int i = 0; i < nq_; ++i) udot_[i] = qdd[i];
    matter_.calcResidualForceIgnoringConstraints(
        state_, system_.getMobilityForces(state_, Stage::Dynamics),
        system_.getRigidBodyForces(state_, Stage::Dynamics), udot_, residual_);
    for (int i = 0; i < nq_; ++i) tau[i] = residual_[i];
  }
  void positions(const double* q) override {
    set(q, nullptr);
    system_.realize(state_, Stage::Position);
  }
  void read_positions(double* R, double* x) const override {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const Transform& X = bodies_[b].first.getBodyTransform(state_);
      const Vec3 c = X * bodies_[b].second;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
          R[9 * b + 3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(j)] =
              X.R().asMat33()(i, j);
        x[3 * b + static_cast<std::size_t>(i)] = c[i];
      }
    }
  }

 private:
  void set(const double* q, const double* qd) {
    Vector& Q = state_.updQ();
    for (int i = 0; i < nq_; ++i) Q[i] = q[i];
    if (qd != nullptr) {
      Vector& U = state_.updU();
      for (int i = 0; i < nq_; ++i) U[i] = qd[i];
    }
  }

  MultibodySystem system_;
  SimbodyMatterSubsystem matter_;
  GeneralForceSubsystem forces_;
  Force::UniformGravity gravity_;
  int nq_;
  std::vector<MobilizedBody> links_;
  std::vector<std::pair<MobilizedBody, Vec3>> bodies_;  // massive links and their centres of mass
  mutable State state_;
  Matrix M_;
  Vector udot_, residual_;
};

}  // namespace

std::unique_ptr<Peer> make_simbody(const Mechanism& m, std::string&) {
  return std::make_unique<SimbodyPeer>(m);
}

}  // namespace symdyn::bench::peers
