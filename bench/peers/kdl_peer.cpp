// KDL (Orocos): a chain as a KDL::Chain, one segment per link; forward dynamics
// by ChainFdSolver_RNE, M by ChainDynParam, inverse dynamics by
// ChainIdSolver_RNE, poses by ChainFkSolverPos_recursive. A tree as a KDL::Tree:
// inverse dynamics by TreeIdSolver_RNE and poses by TreeFkSolverPos_recursive,
// KDL having no forward dynamics nor mass matrix for trees.
#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/tree.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include "peer.hpp"

namespace symdyn::bench::peers {

namespace {

KDL::Vector vec(const Eigen::Vector3d& v) {
  return KDL::Vector(v.x(), v.y(), v.z());
}

// KDL turns a segment about (or along) its joint axis through the segment's
// root, then moves by f_tip to its tip, and holds the inertia in the tip frame:
// so link i's segment ends at link i+1's joint (f_tip: link i+1's offset), and
// its centre of mass is given from there. The offset of the first link is a
// fixed segment of its own (none in these models).
// About or along a coordinate axis: KDL's own joint types; another axis through the origin.
KDL::Joint joint(const Link& l) {
  static constexpr KDL::Joint::JointType revolute[] = {KDL::Joint::RotX, KDL::Joint::RotY,
                                                       KDL::Joint::RotZ};
  static constexpr KDL::Joint::JointType prismatic[] = {KDL::Joint::TransX, KDL::Joint::TransY,
                                                        KDL::Joint::TransZ};
  for (int k = 0; k < 3; ++k) {
    if (l.axis == Eigen::Vector3d::Unit(k)) {
      return KDL::Joint(l.name, l.type == JointType::revolute ? revolute[k] : prismatic[k]);
    }
  }
  return KDL::Joint(l.name, KDL::Vector::Zero(), vec(l.axis),
                    l.type == JointType::revolute ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
}

KDL::Chain kdl_chain(const Mechanism& m) {
  KDL::Chain chain;
  if (!m.links.front().p.isZero())
    chain.addSegment(
        KDL::Segment("offset", KDL::Joint(KDL::Joint::None), KDL::Frame(vec(m.links.front().p))));
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const Link& l = m.links[i];
    const Eigen::Vector3d next =
        i + 1 < m.links.size() ? m.links[i + 1].p : Eigen::Vector3d::Zero();
    const KDL::RigidBodyInertia inertia(
        l.mass, vec(l.com - next),
        KDL::RotationalInertia(l.inertia.x(), l.inertia.y(), l.inertia.z()));
    chain.addSegment(KDL::Segment(l.name, joint(l), KDL::Frame(vec(next)), inertia));
  }
  return chain;
}

class KdlPeer final : public Peer {
 public:
  explicit KdlPeer(const Mechanism& mech)
      : chain_(kdl_chain(mech)),
        fd_(chain_, vec(mech.gravity)),
        id_(chain_, vec(mech.gravity)),
        dyn_(chain_, vec(mech.gravity)),
        fk_(chain_),
        nq_(mech.nq()),
        q_(nq_),
        qd_(nq_),
        qdd_(nq_),
        tau_(nq_),
        zero_(nq_),
        H_(nq_),
        f_ext_(static_cast<std::size_t>(nq_), KDL::Wrench::Zero()),
        frames_(chain_.getNrOfSegments()) {
    const std::size_t first =
        chain_.getNrOfSegments() - mech.links.size();  // after the fixed offset, if any
    for (std::size_t i = 0; i < mech.links.size(); ++i) {
      const Eigen::Vector3d next =
          i + 1 < mech.links.size() ? mech.links[i + 1].p : Eigen::Vector3d::Zero();
      if (mech.links[i].mass > 0) bodies_.emplace_back(first + i, vec(mech.links[i].com - next));
    }
  }

  std::string name() const override { return "KDL"; }
  double total_mass() const override {
    double m = 0;
    for (const KDL::Segment& s : chain_.segments) m += s.getInertia().getMass();
    return m;
  }

  void forward_dynamics(const double* q, const double* qd, double* qdd) override {
    set(q, qd);
    fd_.CartToJnt(q_, qd_, zero_, f_ext_, qdd_);
    for (int i = 0; i < nq_; ++i) qdd[i] = qdd_(static_cast<unsigned>(i));
  }
  void mass_matrix(const double* q) override {
    set(q, nullptr);
    dyn_.JntToMass(q_, H_);
  }
  void read_mass_matrix(double* M) const override {
    for (int i = 0; i < nq_; ++i) {
      for (int j = 0; j < nq_; ++j)
        M[i * nq_ + j] = H_(static_cast<unsigned>(i), static_cast<unsigned>(j));
    }
  }
  void inverse_dynamics(const double* q, const double* qd, const double* qdd,
                        double* tau) override {
    set(q, qd);
    for (int i = 0; i < nq_; ++i) qdd_(static_cast<unsigned>(i)) = qdd[i];
    id_.CartToJnt(q_, qd_, qdd_, f_ext_, tau_);
    for (int i = 0; i < nq_; ++i) tau[i] = tau_(static_cast<unsigned>(i));
  }
  // Every segment's frame in one sweep.
  void positions(const double* q) override {
    set(q, nullptr);
    fk_.JntToCart(q_, frames_);
  }
  void read_positions(double* R, double* x) const override {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const KDL::Frame& F = frames_[bodies_[b].first];
      const KDL::Vector c = F * bodies_[b].second;
      for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
          R[9 * b + 3 * i + j] = F.M(static_cast<unsigned>(i), static_cast<unsigned>(j));
        }
        x[3 * b + i] = c[static_cast<int>(i)];
      }
    }
  }

 private:
  void set(const double* q, const double* qd) {
    for (int i = 0; i < nq_; ++i) q_(static_cast<unsigned>(i)) = q[i];
    if (qd != nullptr) {
      for (int i = 0; i < nq_; ++i) qd_(static_cast<unsigned>(i)) = qd[i];
    }
  }

  KDL::Chain chain_;
  KDL::ChainFdSolver_RNE fd_;
  KDL::ChainIdSolver_RNE id_;
  KDL::ChainDynParam dyn_;
  KDL::ChainFkSolverPos_recursive fk_;
  int nq_;
  KDL::JntArray q_, qd_, qdd_, tau_, zero_;
  KDL::JntSpaceInertiaMatrix H_;
  KDL::Wrenches f_ext_;
  std::vector<KDL::Frame> frames_;
  std::vector<std::pair<std::size_t, KDL::Vector>>
      bodies_;  // massive links' segments, centres of mass in the tip frame
};

}  // namespace

// Link i is a segment turning (or sliding) at its origin, inertia at its centre
// of mass in its own frame, hung from a fixed segment that carries its offset.
KDL::Tree kdl_tree(const Mechanism& m) {
  KDL::Tree tree("root");
  for (const Link& l : m.links) {
    std::string hook = l.parent < 0 ? "root" : m.links[static_cast<std::size_t>(l.parent)].name;
    if (!l.p.isZero() || !l.R.isIdentity()) {
      const KDL::Rotation R(l.R(0, 0), l.R(0, 1), l.R(0, 2), l.R(1, 0), l.R(1, 1), l.R(1, 2),
                            l.R(2, 0), l.R(2, 1), l.R(2, 2));
      tree.addSegment(
          KDL::Segment(l.name + "_offset", KDL::Joint(KDL::Joint::None), KDL::Frame(R, vec(l.p))),
          hook);
      hook = l.name + "_offset";
    }
    const KDL::RigidBodyInertia inertia(
        l.mass, vec(l.com), KDL::RotationalInertia(l.inertia.x(), l.inertia.y(), l.inertia.z()));
    tree.addSegment(KDL::Segment(l.name, joint(l), KDL::Frame::Identity(), inertia), hook);
  }
  return tree;
}

class KdlTreePeer final : public Peer {
 public:
  explicit KdlTreePeer(const Mechanism& mech)
      : tree_(kdl_tree(mech)),
        id_(tree_, vec(mech.gravity)),
        fk_(tree_),
        nq_(mech.nq()),
        q_(nq_),
        qd_(nq_),
        qdd_(nq_),
        tau_(nq_) {
    for (const Link& l : mech.links) {
      if (tree_.getSegment(l.name)->second.q_nr != static_cast<unsigned>(l.q)) {
        throw std::runtime_error("KDL: coordinate order");
      }
      if (l.mass > 0) bodies_.push_back({l.name, vec(l.com), KDL::Frame()});
    }
  }

  std::string name() const override { return "KDL"; }
  bool can(Operation op) const override {
    return op == Operation::inverse_dynamics || op == Operation::positions;
  }
  double total_mass() const override {
    double m = 0;
    for (const auto& [name, element] : tree_.getSegments())
      m += element.segment.getInertia().getMass();
    return m;
  }

  void forward_dynamics(const double*, const double*, double*) override {}
  void mass_matrix(const double*) override {}
  void read_mass_matrix(double*) const override {}
  void inverse_dynamics(const double* q, const double* qd, const double* qdd,
                        double* tau) override {
    for (int i = 0; i < nq_; ++i) {
      q_(static_cast<unsigned>(i)) = q[i];
      qd_(static_cast<unsigned>(i)) = qd[i];
      qdd_(static_cast<unsigned>(i)) = qdd[i];
    }
    id_.CartToJnt(q_, qd_, qdd_, f_ext_, tau_);
    for (int i = 0; i < nq_; ++i) tau[i] = tau_(static_cast<unsigned>(i));
  }
  // One call per body: KDL's tree solver gives one segment's frame at a time.
  void positions(const double* q) override {
    for (int i = 0; i < nq_; ++i) q_(static_cast<unsigned>(i)) = q[i];
    for (Body& b : bodies_) fk_.JntToCart(q_, b.frame, b.segment);
  }
  void read_positions(double* R, double* x) const override {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const KDL::Frame& F = bodies_[b].frame;
      const KDL::Vector c = F * bodies_[b].com;
      for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
          R[9 * b + 3 * i + j] = F.M(static_cast<unsigned>(i), static_cast<unsigned>(j));
        }
        x[3 * b + i] = c[static_cast<int>(i)];
      }
    }
  }

 private:
  struct Body {
    std::string segment;
    KDL::Vector com;
    KDL::Frame frame;
  };
  KDL::Tree tree_;
  KDL::TreeIdSolver_RNE id_;
  KDL::TreeFkSolverPos_recursive fk_;
  int nq_;
  KDL::JntArray q_, qd_, qdd_, tau_;
  KDL::WrenchMap f_ext_;
  std::vector<Body> bodies_;
};

std::unique_ptr<Peer> make_kdl(const Mechanism& m, std::string& why) {
  for (int i = 0; i < m.nq(); ++i) {
    if (m.links[static_cast<std::size_t>(i)].parent != i - 1) {
      why =
          "a tree: KDL's forward dynamics and mass matrix (ChainFdSolver_RNE, ChainDynParam) take "
          "chains only";
      return std::make_unique<KdlTreePeer>(m);
    }
  }
  for (const Link& l : m.links) {
    if (!l.R.isIdentity()) {
      why = "a rotated joint frame, which this chain of segments does not write";
      return nullptr;
    }
  }
  return std::make_unique<KdlPeer>(m);
}

}  // namespace symdyn::bench::peers
