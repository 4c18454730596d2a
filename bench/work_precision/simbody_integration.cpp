// Simbody integrating a serial chain of revolute z-axis links: Pin mobilizers,
// Force::UniformGravity, then a TimeStepper with the chosen integrator at
// setAccuracy(accuracy), every other setting Simbody's default.
#include <Simbody.h>

#include <stdexcept>

#include "peer_integration.hpp"

namespace symdyn::bench::work_precision {

namespace {

using peers::Mechanism;

class SimbodyIntegration final : public PeerIntegration {
 public:
  SimbodyIntegration(const Mechanism& mech, const std::string& integrator, double accuracy)
      : matter_(system_),
        forces_(system_),
        gravity_(forces_, matter_,
                 SimTK::Vec3(mech.gravity.x(), mech.gravity.y(), mech.gravity.z())),
        integrator_name_(integrator) {
    build(mech);
    system_.realizeTopology();
    if (integrator == "RungeKuttaMerson") {
      integrator_ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system_);
    } else if (integrator == "CPodes") {
      integrator_ = std::make_unique<SimTK::CPodesIntegrator>(system_);
    } else {
      throw std::invalid_argument("Simbody integration: unknown integrator " + integrator);
    }
    integrator_->setAccuracy(accuracy);
  }

  std::string name() const override { return "Simbody " + integrator_name_; }

  void run(const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0, double t_end) override {
    SimTK::State state = system_.getDefaultState();
    for (int i = 0; i < q0.size(); ++i) {
      state.updQ()[i] = q0[i];
      state.updU()[i] = qd0[i];
    }
    SimTK::TimeStepper stepper(system_, *integrator_);
    stepper.initialize(state);
    stepper.stepTo(t_end);
    const SimTK::State& end = integrator_->getState();
    if (end.getTime() != t_end)
      throw std::runtime_error("Simbody integration stopped before t_end");
    q_.resize(q0.size());
    qd_.resize(q0.size());
    for (int i = 0; i < q0.size(); ++i) {
      q_[i] = end.getQ()[i];
      qd_[i] = end.getU()[i];
    }
    steps_ = integrator_->getNumStepsTaken();
  }

 private:
  void build(const Mechanism& mech) {
    for (const peers::Link& l : mech.links) {
      if (l.type != peers::JointType::revolute || l.axis != Eigen::Vector3d::UnitZ() ||
          !l.R.isIdentity())
        throw std::invalid_argument("Simbody integration: " + mech.name +
                                    " has a joint other than a z-axis pin");
      const SimTK::Vec3 com(l.com.x(), l.com.y(), l.com.z());
      const SimTK::Body::Rigid body(SimTK::MassProperties(
          l.mass, com,
          SimTK::Inertia(SimTK::Vec3(l.inertia.x(), l.inertia.y(), l.inertia.z()))
              .shiftFromMassCenter(com, l.mass)));
      SimTK::MobilizedBody& parent =
          l.parent < 0 ? matter_.updGround() : links_[static_cast<std::size_t>(l.parent)];
      links_.push_back(SimTK::MobilizedBody::Pin(
          parent, SimTK::Transform(SimTK::Vec3(l.p.x(), l.p.y(), l.p.z())), body,
          SimTK::Transform()));
    }
  }

  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  SimTK::Force::UniformGravity gravity_;
  std::string integrator_name_;
  std::vector<SimTK::MobilizedBody> links_;
  std::unique_ptr<SimTK::Integrator> integrator_;
};

}  // namespace

std::unique_ptr<PeerIntegration> make_simbody_integration(const Mechanism& m,
                                                          const std::string& integrator,
                                                          double accuracy) {
  return std::make_unique<SimbodyIntegration>(m, integrator, accuracy);
}

std::vector<std::string> simbody_integrators() {
  return {"RungeKuttaMerson", "CPodes"};
}

}  // namespace symdyn::bench::work_precision
