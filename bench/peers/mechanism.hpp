#pragma once
// The reference models of docs/models.md that a joint-tree library
// can express, written once as trees of one-DOF joints; every peer builds its own
// model from this description, so all of them see the same mechanism.
//
// A link's frame is its parent's link frame (the ground for parent -1) moved by
// the fixed offset (R, p) and then by the joint: Tdisp(p)·R·Trot(axis, q) for a
// revolute joint, Tdisp(p)·R·Tdisp(q·axis) for a prismatic one. The link's centre
// of mass is at `com` in its frame and its inertia diag(I) is about the centre of
// mass, in the link's axes. That is the form of every model below: each symdyn
// body's motion is a product of such steps ending with a translation, so a link
// frame has the axes of the symdyn body frame. A link without mass stands for an
// intermediate step of a multi-DOF motion (robot3d's wrist, the floating base).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace symdyn::bench::peers {

enum class JointType { revolute, prismatic };

struct Link {
  std::string name;
  int parent = -1;                                  // link index, -1 for the ground
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // fixed rotation of the offset
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      // fixed translation, in the parent's axes
  JointType type = JointType::revolute;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();    // unit, in the link's axes
  int q = 0;                                          // index of the joint's coordinate
  double mass = 0.0;                                  // 0: an intermediate frame
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // centre of mass in the link frame
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();  // diag(Ixx, Iyy, Izz) at the centre of mass
  int body = -1;                                      // the symdyn body it is, -1 for none
};

struct Mechanism {
  std::string name;
  std::vector<Link> links;  // parents before children; coordinate i is link i's joint
  Eigen::Vector3d gravity;
  int nq() const { return static_cast<int>(links.size()); }
  int nbody() const;  // links with mass
  double total_mass() const;
};

Mechanism double_pendulum();
Mechanism robot3d();
Mechanism chain(int n);
Mechanism hexapod_tree();
Mechanism trike();

}  // namespace symdyn::bench::peers
