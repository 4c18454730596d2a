// DART: the mechanism as a Skeleton, one RevoluteJoint or PrismaticJoint and
// BodyNode per link; forward dynamics by Skeleton::computeForwardDynamics
// (articulated bodies), M by getMassMatrix, inverse dynamics by
// computeInverseDynamics, poses by each BodyNode's getWorldTransform.
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Inertia.hpp>
#include <dart/dynamics/PrismaticJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <stdexcept>

#include "peer.hpp"

namespace symdyn::bench::peers {

namespace {

using namespace dart::dynamics;

template <class J>
BodyNode* add_link(const SkeletonPtr& skel, BodyNode* parent, const Link& l) {
  typename J::Properties joint;
  joint.mName = l.name;
  joint.mAxis = l.axis;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = l.R;
  T.translation() = l.p;
  joint.mT_ParentBodyToJoint = T;
  BodyNode::Properties body;
  body.mName = l.name;
  body.mInertia = Inertia(l.mass, l.com, l.inertia.asDiagonal().toDenseMatrix());
  return skel->createJointAndBodyNodePair<J>(parent, joint, body).second;
}

class DartPeer final : public Peer {
 public:
  explicit DartPeer(const Mechanism& mech) : skel_(Skeleton::create(mech.name)), nq_(mech.nq()) {
    for (const Link& l : mech.links) {
      BodyNode* parent = l.parent < 0 ? nullptr : links_[static_cast<std::size_t>(l.parent)];
      links_.push_back(l.type == JointType::revolute ? add_link<RevoluteJoint>(skel_, parent, l)
                                                     : add_link<PrismaticJoint>(skel_, parent, l));
      if (l.mass > 0) bodies_.emplace_back(links_.back(), l.com);
    }
    skel_->setGravity(mech.gravity);
    for (int i = 0; i < nq_; ++i) {
      if (links_[static_cast<std::size_t>(i)]->getParentJoint()->getIndexInSkeleton(0) !=
          static_cast<std::size_t>(i)) {
        throw std::runtime_error("DART: coordinate order");
      }
    }
    q_.resize(nq_);
    qd_.resize(nq_);
  }

  std::string name() const override { return "DART"; }
  double total_mass() const override { return skel_->getMass(); }

  void forward_dynamics(const double* q, const double* qd, double* qdd) override {
    set(q, qd);
    skel_->computeForwardDynamics();
    Eigen::Map<Eigen::VectorXd>(qdd, nq_) = skel_->getAccelerations();
  }
  void mass_matrix(const double* q) override {
    set(q, nullptr);
    skel_->getMassMatrix();
  }
  void read_mass_matrix(double* M) const override {
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        M, nq_, nq_) = skel_->getMassMatrix();
  }
  void inverse_dynamics(const double* q, const double* qd, const double* qdd,
                        double* tau) override {
    set(q, qd);
    skel_->setAccelerations(Eigen::Map<const Eigen::VectorXd>(qdd, nq_));
    skel_->computeInverseDynamics();
    Eigen::Map<Eigen::VectorXd>(tau, nq_) = skel_->getForces();
  }
  // DART updates transforms lazily: asking for each body's is the computation.
  void positions(const double* q) override {
    set(q, nullptr);
    for (auto& b : bodies_) b.first->getWorldTransform();
  }
  void read_positions(double* R, double* x) const override {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const Eigen::Isometry3d& T = bodies_[b].first->getWorldTransform();
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R + 9 * b) = T.linear();
      Eigen::Map<Eigen::Vector3d>(x + 3 * b) = T * bodies_[b].second;
    }
  }

 private:
  void set(const double* q, const double* qd) {
    q_ = Eigen::Map<const Eigen::VectorXd>(q, nq_);
    skel_->setPositions(q_);
    if (qd != nullptr) {
      qd_ = Eigen::Map<const Eigen::VectorXd>(qd, nq_);
      skel_->setVelocities(qd_);
    }
  }

  SkeletonPtr skel_;
  int nq_;
  std::vector<BodyNode*> links_;
  std::vector<std::pair<BodyNode*, Eigen::Vector3d>>
      bodies_;  // massive links and their centres of mass
  Eigen::VectorXd q_, qd_;
};

}  // namespace

std::unique_ptr<Peer> make_dart(const Mechanism& m, std::string&) {
  return std::make_unique<DartPeer>(m);
}

}  // namespace symdyn::bench::peers
