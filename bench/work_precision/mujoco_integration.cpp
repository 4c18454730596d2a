// MuJoCo integrating a serial chain of revolute links: the MJCF written from the
// mechanism (nested bodies, hinge joints), contacts and constraints disabled as
// in bench/peers, every other option MuJoCo's default; then mj_step repeatedly.
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "peer_integration.hpp"

namespace symdyn::bench::work_precision {

namespace {

using peers::JointType;
using peers::Mechanism;

void write_vector(std::ostream& out, const Eigen::Vector3d& v) {
  out << v.x() << ' ' << v.y() << ' ' << v.z();
}

// Only what the double pendulum needs: each link the child of the previous, revolute,
// no fixed rotation.
std::string serial_chain_mjcf(const Mechanism& m) {
  std::ostringstream out;
  out.precision(17);
  out << "<mujoco model=\"" << m.name
      << "\">\n<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "<option gravity=\"";
  write_vector(out, m.gravity);
  out << "\">\n<flag contact=\"disable\" constraint=\"disable\"/>\n</option>\n<worldbody>\n";
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const peers::Link& l = m.links[i];
    if (l.parent != static_cast<int>(i) - 1 || l.type != JointType::revolute || !l.R.isIdentity() ||
        l.mass <= 0)
      throw std::invalid_argument("MuJoCo integration: " + m.name +
                                  " is not a serial chain of revolute links");
    out << "<body name=\"b" << i << "\" pos=\"";
    write_vector(out, l.p);
    out << "\">\n<joint name=\"j" << i << "\" type=\"hinge\" axis=\"";
    write_vector(out, l.axis);
    out << "\"/>\n<inertial pos=\"";
    write_vector(out, l.com);
    out << "\" mass=\"" << l.mass << "\" diaginertia=\"";
    write_vector(out, l.inertia);
    out << "\"/>\n";
  }
  for (std::size_t i = 0; i < m.links.size(); ++i) out << "</body>\n";
  out << "</worldbody>\n</mujoco>\n";
  return out.str();
}

struct Integrator {
  const char* name;
  int value;
};
constexpr Integrator integrators[] = {
    {"Euler", mjINT_EULER}, {"RK4", mjINT_RK4}, {"implicit", mjINT_IMPLICIT}};

class MujocoIntegration final : public PeerIntegration {
 public:
  MujocoIntegration(const Mechanism& mech, const Integrator& integrator, double step)
      : integrator_(integrator.name), step_(step) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              (mech.name + ".symdyn_wp." + std::to_string(getpid()) + ".xml"))
                                 .string();
    std::ofstream(path) << serial_chain_mjcf(mech);
    char error[1000] = "";
    m_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    std::filesystem::remove(path);
    if (m_ == nullptr) throw std::runtime_error(std::string("MuJoCo: ") + error);
    if (m_->nq != mech.nq() || m_->nv != mech.nq())
      throw std::runtime_error("MuJoCo: coordinate count");
    m_->opt.integrator = integrator.value;
    m_->opt.timestep = step;
    d_ = mj_makeData(m_);
  }
  ~MujocoIntegration() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  MujocoIntegration(const MujocoIntegration&) = delete;
  MujocoIntegration& operator=(const MujocoIntegration&) = delete;

  std::string name() const override { return "MuJoCo " + integrator_; }

  // t_end must be a whole number of steps (fixed-step integrators end on a step).
  void run(const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0, double t_end) override {
    const long n = std::lround(t_end / step_);
    if (std::abs(static_cast<double>(n) * step_ - t_end) > 1e-9 * t_end)
      throw std::invalid_argument("MuJoCo integration: t_end is not a multiple of the step");
    mj_resetData(m_, d_);
    for (int i = 0; i < m_->nq; ++i) {
      d_->qpos[i] = q0[i];
      d_->qvel[i] = qd0[i];
    }
    for (long k = 0; k < n; ++k) mj_step(m_, d_);
    q_ = Eigen::Map<const Eigen::VectorXd>(d_->qpos, m_->nq);
    qd_ = Eigen::Map<const Eigen::VectorXd>(d_->qvel, m_->nv);
    steps_ = n;
  }

 private:
  std::string integrator_;
  double step_;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
};

}  // namespace

std::unique_ptr<PeerIntegration> make_mujoco_integration(const Mechanism& m,
                                                         const std::string& integrator,
                                                         double step) {
  for (const Integrator& i : integrators) {
    if (integrator == i.name) return std::make_unique<MujocoIntegration>(m, i, step);
  }
  throw std::invalid_argument("MuJoCo integration: unknown integrator " + integrator);
}

std::vector<std::string> mujoco_integrators() {
  std::vector<std::string> names;
  for (const Integrator& i : integrators) names.emplace_back(i.name);
  return names;
}

}  // namespace symdyn::bench::work_precision
