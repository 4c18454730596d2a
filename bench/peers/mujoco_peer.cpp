// MuJoCo: the mechanism as MJCF, loaded by mj_loadXML; each operation is the
// part of mj_forward (or mj_inverse) it needs, so no time goes to sensors,
// actuators, passive forces or constraints (there are none to compute).
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "peer.hpp"

namespace symdyn::bench::peers {

namespace {

// "j3", "b5": the names given to joints and bodies in the MJCF.
std::string mjcf_name(char kind, std::size_t i) {
  std::string s(1, kind);
  s += std::to_string(i);
  return s;
}

std::string axis_text(const Eigen::Vector3d& axis) {
  std::ostringstream out;
  out.precision(17);
  out << axis.x() << ' ' << axis.y() << ' ' << axis.z();
  return out.str();
}

// Consecutive joints share a MuJoCo body (applied in order, in the moving frame,
// as MuJoCo composes a body's joints) where the links between them are massless
// steps with one child and no offset: MuJoCo's way of writing a multi-DOF joint.
struct Layout {
  std::vector<int> mj_body;  // per link: the link that names its MuJoCo body
};

Layout layout(const Mechanism& m) {
  Layout l;
  std::vector<int> children(m.links.size(), 0);
  for (const Link& k : m.links) {
    if (k.parent >= 0) ++children[static_cast<std::size_t>(k.parent)];
  }
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const Link& k = m.links[i];
    const bool merge = k.parent >= 0 && m.links[static_cast<std::size_t>(k.parent)].mass == 0 &&
                       children[static_cast<std::size_t>(k.parent)] == 1 && k.p.isZero() &&
                       k.R.isIdentity();
    l.mj_body.push_back(merge ? l.mj_body[static_cast<std::size_t>(k.parent)]
                              : static_cast<int>(i));
  }
  return l;
}

void write_body(std::ostream& out, const Mechanism& m, const Layout& l, int head) {
  const Link& h = m.links[static_cast<std::size_t>(head)];
  const Eigen::Quaterniond quat(h.R);
  out << "<body name=\"b" << head << "\" pos=\"" << h.p.x() << ' ' << h.p.y() << ' ' << h.p.z()
      << "\" quat=\"" << quat.w() << ' ' << quat.x() << ' ' << quat.y() << ' ' << quat.z()
      << "\">\n";
  int last = head;
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const Link& k = m.links[i];
    if (l.mj_body[i] != head) continue;
    out << "<joint name=\"j" << i << "\" type=\""
        << (k.type == JointType::revolute ? "hinge" : "slide") << "\" axis=\"" << axis_text(k.axis)
        << "\" pos=\"0 0 0\"/>\n";
    last = static_cast<int>(i);
  }
  const Link& body = m.links[static_cast<std::size_t>(last)];
  if (body.mass > 0) {
    out << "<inertial pos=\"" << body.com.x() << ' ' << body.com.y() << ' ' << body.com.z()
        << "\" mass=\"" << body.mass << "\" diaginertia=\"" << body.inertia.x() << ' '
        << body.inertia.y() << ' ' << body.inertia.z() << "\"/>\n";
  }
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    if (l.mj_body[i] == static_cast<int>(i) && m.links[i].parent >= 0 &&
        l.mj_body[static_cast<std::size_t>(m.links[i].parent)] == head) {
      write_body(out, m, l, static_cast<int>(i));
    }
  }
  out << "</body>\n";
}

std::string mjcf(const Mechanism& m, const Layout& l) {
  std::ostringstream out;
  out.precision(17);
  out << "<mujoco model=\"" << m.name
      << "\">\n<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "<option gravity=\"" << m.gravity.x() << ' ' << m.gravity.y() << ' ' << m.gravity.z()
      << "\">\n"
      << "<flag contact=\"disable\" constraint=\"disable\"/>\n</option>\n<worldbody>\n";
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    if (m.links[i].parent < 0) write_body(out, m, l, static_cast<int>(i));
  }
  out << "</worldbody>\n</mujoco>\n";
  return out.str();
}

class MujocoPeer final : public Peer {
 public:
  explicit MujocoPeer(const Mechanism& mech) : nq_(mech.nq()) {
    const Layout l = layout(mech);
    const std::string path = (std::filesystem::temp_directory_path() /
                              (mech.name + ".symdyn_peers." + std::to_string(getpid()) + ".xml"))
                                 .string();
    std::ofstream(path) << mjcf(mech, l);
    char error[1000] = "";
    m_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    std::filesystem::remove(path);
    if (m_ == nullptr) throw std::runtime_error(std::string("MuJoCo: ") + error);
    d_ = mj_makeData(m_);
    // The coordinates must come in the mechanism's order.
    for (int i = 0; i < nq_; ++i) {
      const int j =
          mj_name2id(m_, mjOBJ_JOINT, mjcf_name('j', static_cast<std::size_t>(i)).c_str());
      if (m_->jnt_qposadr[j] != i || m_->jnt_dofadr[j] != i)
        throw std::runtime_error("MuJoCo: coordinate order");
    }
    for (std::size_t i = 0; i < mech.links.size(); ++i) {
      if (mech.links[i].mass > 0) {
        body_.push_back(mj_name2id(m_, mjOBJ_BODY,
                                   mjcf_name('b', static_cast<std::size_t>(l.mj_body[i])).c_str()));
      }
    }
  }
  ~MujocoPeer() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  MujocoPeer(const MujocoPeer&) = delete;
  MujocoPeer& operator=(const MujocoPeer&) = delete;

  std::string name() const override { return "MuJoCo"; }
  double total_mass() const override {
    double sum = 0;
    for (int b = 0; b < m_->nbody; ++b) sum += m_->body_mass[b];
    return sum;
  }

  // mj_fwdPosition's and mj_fwdVelocity's smooth parts, then qacc = -M^-1·qfrc_bias.
  void forward_dynamics(const double* q, const double* qd, double* qdd) override {
    set(q, qd);
    mj_kinematics(m_, d_);
    mj_comPos(m_, d_);
    mj_crb(m_, d_);
    mj_factorM(m_, d_);
    mj_comVel(m_, d_);
    mj_rne(m_, d_, 0, d_->qfrc_bias);
    for (int i = 0; i < nq_; ++i) qdd[i] = -d_->qfrc_bias[i];
    mj_solveM(m_, d_, qdd, qdd, 1);
  }
  // M in MuJoCo's sparse storage (qM); read_mass_matrix expands it.
  void mass_matrix(const double* q) override {
    set(q, nullptr);
    mj_kinematics(m_, d_);
    mj_comPos(m_, d_);
    mj_crb(m_, d_);
  }
  void read_mass_matrix(double* M) const override { mj_fullM(m_, M, d_->qM); }
  // mj_inverse's smooth part: recursive Newton-Euler with qacc.
  void inverse_dynamics(const double* q, const double* qd, const double* qdd,
                        double* tau) override {
    set(q, qd);
    for (int i = 0; i < nq_; ++i) d_->qacc[i] = qdd[i];
    mj_kinematics(m_, d_);
    mj_comPos(m_, d_);
    mj_comVel(m_, d_);
    mj_rne(m_, d_, 1, tau);
  }
  void positions(const double* q) override {
    set(q, nullptr);
    mj_kinematics(m_, d_);
  }
  // xipos, ximat: the inertial frame of each body, our body frame.
  void read_positions(double* R, double* x) const override {
    for (std::size_t i = 0; i < body_.size(); ++i) {
      for (int k = 0; k < 9; ++k) R[9 * i + k] = d_->ximat[9 * body_[i] + k];
      for (int k = 0; k < 3; ++k) x[3 * i + k] = d_->xipos[3 * body_[i] + k];
    }
  }

  bool can_differentiate() const override { return true; }
  // Differences of mj_forward's qacc, as mjd_stepFD differences mj_step: the
  // velocities first, each perturbed evaluation skipping the position stage
  // (mj_forwardSkip(mjSTAGE_POS)), then the positions, recomputing everything.
  // Hinge and slide joints only: qpos and qvel share their indices.
  void acceleration_differences(const double* q, const double* qd, Differences how, double eps,
                                double* dqdd_dq, double* dqdd_dqd) override {
    const bool centered = how == Differences::centered;
    set(q, qd);
    mj_forward(m_, d_);
    for (int i = 0; i < nq_; ++i) qacc0_[i] = d_->qacc[i];
    const auto column = [&](double* x, int j, int skip, double* J) {
      const double saved = x[j];
      x[j] = saved + eps;
      mj_forwardSkip(m_, d_, skip, 1);
      for (int i = 0; i < nq_; ++i) plus_[i] = d_->qacc[i];
      if (centered) {
        x[j] = saved - eps;
        mj_forwardSkip(m_, d_, skip, 1);
      }
      x[j] = saved;
      const double* minus = centered ? d_->qacc : qacc0_.data();
      const double scale = centered ? 0.5 / eps : 1.0 / eps;
      for (int i = 0; i < nq_; ++i) J[i * nq_ + j] = (plus_[i] - minus[i]) * scale;
    };
    for (int j = 0; j < nq_; ++j) column(d_->qvel, j, mjSTAGE_POS, dqdd_dqd);
    for (int j = 0; j < nq_; ++j) column(d_->qpos, j, mjSTAGE_NONE, dqdd_dq);
  }
  void transition_differences(const double* q, const double* qd, Differences how, double eps,
                              double* A) override {
    set(q, qd);
    mjd_transitionFD(m_, d_, eps, how == Differences::centered ? 1 : 0, A, nullptr, nullptr,
                     nullptr);
  }
  double time_step() const override { return m_->opt.timestep; }

 private:
  void set(const double* q, const double* qd) {
    for (int i = 0; i < nq_; ++i) d_->qpos[i] = q[i];
    if (qd != nullptr) {
      for (int i = 0; i < nq_; ++i) d_->qvel[i] = qd[i];
    }
  }

  int nq_;
  std::vector<double> qacc0_ = std::vector<double>(static_cast<std::size_t>(nq_)),
                      plus_ = std::vector<double>(static_cast<std::size_t>(nq_));
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<int> body_;  // the MuJoCo body of each massive link
};

}  // namespace

std::unique_ptr<Peer> make_mujoco(const Mechanism& m, std::string&) {
  return std::make_unique<MujocoPeer>(m);
}

}  // namespace symdyn::bench::peers
