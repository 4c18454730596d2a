// The recursive derivatives of the inverse dynamics (dynamics_derivatives.hpp),
// in world axes about the origin.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <optional>
#include <utility>

#include <symdyn/model/detail/dynamics_terms.hpp>
#include <symdyn/model/dynamics_derivatives.hpp>
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/traversal.hpp>

namespace symdyn::model {
namespace {

using detail::Spatial;
using detail::SpatialInertia;
using Step = Transform::Step;
using detail::operator+;
using detail::operator*;
using model::operator+;
using model::operator-;
using model::operator*;

// The spatial cross products: of twists (x×), and of a twist on a wrench (x×*).
Spatial cross_motion(const Spatial& a, const Spatial& b) {
  return {cross(a.angular, b.angular), cross(a.angular, b.linear) + cross(a.linear, b.angular)};
}

Spatial cross_force(const Spatial& v, const Spatial& f) {
  return {cross(v.angular, f.angular) + cross(v.linear, f.linear), cross(v.angular, f.linear)};
}

Spatial operator-(const Spatial& a, const Spatial& b) {
  return a + Expr(-1) * b;
}

Expr component(const Spatial& s, int c) {
  return c < 3 ? s.angular[c] : s.linear[c - 3];
}

// A symmetric 6 x 6 matrix on (angular, linear) 6-vectors.
using Symmetric6 = std::array<Expr, 36>;

Spatial times(const Symmetric6& B, const Spatial& x) {
  Spatial out;
  for (int r = 0; r < 6; ++r) {
    std::vector<Expr> terms;
    for (int c = 0; c < 6; ++c) terms.push_back(B[6 * r + c] * component(x, c));
    (r < 3 ? out.angular[r] : out.linear[r - 3]) = symbolic::add(terms);
  }
  return out;
}

// v ×* I - I·(v ×): the symmetric part of the derivative of f = I·a + v ×* I·v along the twist.
Symmetric6 velocity_variation(const SpatialInertia& I, const Spatial& v) {
  Symmetric6 B;
  for (int c = 0; c < 6; ++c) {
    Spatial e;
    (c < 3 ? e.angular[c] : e.linear[c - 3]) = Expr(1);
    const Spatial column =
        cross_force(v, detail::momentum(I, e)) - detail::momentum(I, cross_motion(v, e));
    for (int r = 0; r <= c; ++r) B[6 * r + c] = B[6 * c + r] = component(column, r);
  }
  return B;
}

// One joint: a coordinate's step, in world axes about the origin.
struct Joint {
  std::size_t coordinate = 0;
  int parent = -1;  // the joint before it on the way from the ground, or -1
  // The steps from the ground before its own, and its own direction.
  std::pair<std::vector<Step>, std::vector<Expr>> screw;
  Spatial S;                 // dtwist/dqd_j
  Spatial v, a, dV, dA;      // after it; ψ × S; α × S + ψ × dV
  SpatialInertia inertia;    // gathered over the bodies after it
  Spatial wrench, momentum;  // likewise
  Symmetric6 variation;      // likewise
  bool has_bodies = false;
};

class Recursion {
 public:
  Recursion(const Model& model, const Kinematics& kinematics)
      : model_(model), kinematics_(kinematics), nq_(model.coordinates().size()) {}

  InverseDynamicsDerivatives derive() {
    InverseDynamicsDerivatives out;
    if (model_.num_implicit() > 0) {
      out.why_not = "the model has implicit dependent parameters";
      return out;
    }
    out.why_not = find_joints();
    if (!out.why_not.empty()) return out;
    for (std::size_t j = 0; j < nq_; ++j) {
      if (!joint_of_[j]) {
        out.why_not =
            fmt::format("coordinate '{}' moves no body", model_.coordinates()[j].q.name());
        return out;
      }
    }
    forward();
    gather();
    pairs(out);
    out.definitions = names_.take_definitions();
    return out;
  }

 private:
  // The joints, parents first, and the last joint on each body's way; or why not.
  std::string find_joints() {
    const std::vector<int> refs = model_.reference_indices();
    joint_of_.assign(nq_, std::nullopt);
    last_.assign(model_.bodies().size(), -1);
    std::vector<std::vector<Step>> paths(model_.bodies().size());
    for (int b : model_.topological_order()) {
      const int ref = refs[b];
      Mat3 R = ref < 0 ? identity3() : kinematics_.bodies[ref].R;
      Vec3 p = ref < 0 ? zero3() : kinematics_.bodies[ref].x;
      int last = ref < 0 ? -1 : last_[ref];
      std::vector<Step> path = ref < 0 ? std::vector<Step>{} : paths[ref];
      const std::string& body = model_.bodies()[b].name();
      for (const Step& step : model_.bodies()[b].motion().steps()) {
        std::vector<Expr> values;
        if (step.is_rotation) {
          values.push_back(step.angle);
        } else {
          values.assign(step.displacement.begin(), step.displacement.end());
        }
        // The coordinates it moves with, each a joint: the screws of one step
        // commute (parallel rotations about one axis, or translations).
        std::vector<std::size_t> moving;
        for (Expr x : symbolic::free_symbols(values)) {
          if (x.symbol_kind() == symbolic::SymbolKind::Parameter) continue;
          if (x.symbol_kind() != symbolic::SymbolKind::Variable)
            return fmt::format("a step of body '{}' moves with '{}', not a coordinate", body,
                               x.name());
          moving.push_back(coordinate_index(x));
        }
        std::sort(moving.begin(), moving.end());
        for (std::size_t j : moving) {
          const Expr q = model_.coordinates()[j].q;
          std::vector<Expr> rates;
          for (Expr x : values) rates.push_back(symbolic::diff(x, q));
          for (Expr r : rates) {
            if (!r.is_number())
              return fmt::format("a step of body '{}' is not linear in '{}'", body, q.name());
          }
          // Its screw: the steps before it and its direction (not the step's
          // constant part); and the joint before it, the same wherever it moves.
          const std::pair<std::vector<Step>, std::vector<Expr>> screw{
              path, step.is_rotation
                        ? std::vector<Expr>{rates[0], step.axis[0], step.axis[1], step.axis[2]}
                        : rates};
          if (joint_of_[j]) {
            const Joint& seen = joints_[*joint_of_[j]];
            if (seen.screw != screw || seen.parent != last)
              return fmt::format("coordinate '{}' moves body '{}' through other steps than before",
                                 q.name(), body);
          } else {
            joint_of_[j] = joints_.size();
            Joint joint;
            joint.coordinate = j;
            joint.parent = last;
            joint.screw = screw;
            if (step.is_rotation) {
              const Vec3 u = rates[0] * (R * step.axis);
              joint.S = {u, cross(p, u)};
            } else {
              joint.S = {zero3(), R * Vec3{rates[0], rates[1], rates[2]}};
            }
            name(joint.S, prefix(j) + "S");
            joints_.push_back(std::move(joint));
          }
          last = static_cast<int>(*joint_of_[j]);
        }
        path.push_back(step);
        if (step.is_rotation) {
          R = R * Transform::rotation_matrix(step.axis, step.angle);
          names_.name_all(R, fmt::format("{}.dtau_R{}_", body, path.size()));
        } else {
          p = p + R * step.displacement;
          names_.name_all(p, fmt::format("{}.dtau_x{}_", body, path.size()));
        }
      }
      paths[b] = std::move(path);
      last_[b] = last;
    }
    return {};
  }

  std::size_t coordinate_index(Expr q) const {
    for (std::size_t j = 0; j < nq_; ++j) {
      if (model_.coordinates()[j].q == q) return j;
    }
    return nq_;  // not reached: a Variable symbol is a coordinate
  }

  // Parents first: the twists and accelerations, and their turning terms.
  void forward() {
    for (Joint& J : joints_) {
      const Coordinate& c = model_.coordinates()[J.coordinate];
      const Spatial psi = J.parent < 0 ? Spatial{} : joints_[J.parent].v;
      const Spatial alpha =
          J.parent < 0 ? Spatial{zero3(), Expr(-1) * model_.gravity()} : joints_[J.parent].a;
      const std::string n = prefix(J.coordinate);
      J.dV = cross_motion(psi, J.S);
      name(J.dV, n + "dV");
      J.v = psi + c.qd * J.S;
      name(J.v, n + "v");
      J.a = alpha + c.qdd * J.S + c.qd * J.dV;
      name(J.a, n + "a");
      J.dA = cross_motion(alpha, J.S) + cross_motion(psi, J.dV);
      name(J.dA, n + "dA");
    }
  }

  // Each body's inertia, wrench, momentum and velocity variation, gathered
  // into its last joint, then children into parents.
  void gather() {
    for (std::size_t b = 0; b < model_.bodies().size(); ++b) {
      if (last_[b] < 0) continue;
      Joint& J = joints_[last_[b]];
      const Body& body = model_.bodies()[b];
      const std::string n = body.name() + ".dtau_";
      SpatialInertia I = detail::to_reference(SpatialInertia{body.mass(), zero3(), body.inertia()},
                                              kinematics_.bodies[b].R, kinematics_.bodies[b].x);
      names_.name_all(I.moment, n + "h");
      names_.name_all(I.rotational, n + "K");
      Spatial h = detail::momentum(I, J.v);
      name(h, n + "p");
      Spatial f = detail::momentum(I, J.a) + cross_force(J.v, h);
      name(f, n + "f");
      Symmetric6 B = velocity_variation(I, J.v);
      names_.name_all(B, n + "V");
      add(J, I, f, h, B);
    }
    for (std::size_t k = joints_.size(); k-- > 0;) {
      Joint& J = joints_[k];
      const std::string n = prefix(J.coordinate);
      names_.name_all(J.inertia.moment, n + "Ih");
      names_.name_all(J.inertia.rotational, n + "IK");
      J.inertia.mass = names_(J.inertia.mass, n + "Im");
      name(J.wrench, n + "F");
      name(J.momentum, n + "H");
      names_.name_all(J.variation, n + "B");
      if (J.parent >= 0) add(joints_[J.parent], J.inertia, J.wrench, J.momentum, J.variation);
    }
  }

  static void add(Joint& J, const SpatialInertia& I, const Spatial& f, const Spatial& h,
                  const Symmetric6& B) {
    if (!J.has_bodies) {
      J.inertia = I, J.wrench = f, J.momentum = h, J.variation = B, J.has_bodies = true;
      return;
    }
    J.inertia = J.inertia + I;
    J.wrench = J.wrench + f;
    J.momentum = J.momentum + h;
    for (int e = 0; e < 36; ++e) J.variation[e] = J.variation[e] + B[e];
  }

  // The pairs (k, i), k = i or an ancestor of i.
  void pairs(InverseDynamicsDerivatives& out) {
    out.dtau_dq.assign(nq_ * nq_, Expr(0));
    out.dtau_dqd.assign(nq_ * nq_, Expr(0));
    out.mass_matrix.assign(nq_ * nq_, Expr(0));
    for (Joint& J : joints_) {
      if (!J.has_bodies) continue;  // nothing after it: its row and column are zero
      const std::string n = prefix(J.coordinate);
      Spatial P = detail::momentum(J.inertia, J.S);
      name(P, n + "P");
      Spatial BS = times(J.variation, J.S), SH = cross_force(J.S, J.momentum);
      name(BS, n + "BS");
      name(SH, n + "SH");
      Spatial Q = BS - SH;
      name(Q, n + "Q");
      Spatial dF = cross_force(J.S, J.wrench) + detail::momentum(J.inertia, J.dA) +
                   times(J.variation, J.dV) + cross_force(J.dV, J.momentum);
      name(dF, n + "dF");
      Spatial dFv = detail::momentum(J.inertia, Expr(2) * J.dV) + BS + SH;
      name(dFv, n + "dFv");
      const std::size_t i = J.coordinate;
      for (int k = static_cast<int>(*joint_of_[i]); k >= 0; k = joints_[k].parent) {
        const Joint& K = joints_[k];
        const std::size_t c = K.coordinate;
        out.dtau_dq[i * nq_ + c] = detail::dot(P, K.dA) + detail::dot(Q, K.dV);
        out.dtau_dqd[i * nq_ + c] = Expr(2) * detail::dot(P, K.dV) + detail::dot(Q, K.S);
        out.mass_matrix[i * nq_ + c] = out.mass_matrix[c * nq_ + i] = detail::dot(K.S, P);
        if (c == i) continue;
        out.dtau_dq[c * nq_ + i] = detail::dot(K.S, dF);
        out.dtau_dqd[c * nq_ + i] = detail::dot(K.S, dFv);
      }
    }
  }

  std::string prefix(std::size_t j) const { return model_.coordinates()[j].q.name() + ".dtau_"; }

  void name(Spatial& s, const std::string& prefix) {
    names_.name_all(s.angular, prefix + "w");
    names_.name_all(s.linear, prefix + "v");
  }

  const Model& model_;
  const Kinematics& kinematics_;
  const std::size_t nq_;
  IntermediateNames names_;
  std::vector<Joint> joints_;                         // parents first
  std::vector<std::optional<std::size_t>> joint_of_;  // (nq)
  std::vector<int> last_;                             // (nbody) its last joint, or -1
};

}  // namespace

InverseDynamicsDerivatives derive_inverse_dynamics_derivatives(const Model& model,
                                                               const Kinematics& kinematics) {
  return Recursion(model, kinematics).derive();
}

}  // namespace symdyn::model
