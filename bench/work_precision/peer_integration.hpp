#pragma once
// A peer library's own time integration of a mechanism (bench/peers/mechanism.hpp),
// the way its users run it: MuJoCo's mj_step at a fixed time step with one of
// its integrators, Simbody's TimeStepper with one of its error-controlled
// integrators at an accuracy. Used by work_precision.cpp on the double pendulum.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "../peers/mechanism.hpp"

namespace symdyn::bench::work_precision {

class PeerIntegration {
 public:
  virtual ~PeerIntegration() = default;
  // "MuJoCo RK4", "Simbody CPodes": the library and its integrator.
  virtual std::string name() const = 0;
  // From (q0, qd0) (nq each) at t = 0 to t_end; the final state in q(), qd().
  virtual void run(const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0, double t_end) = 0;
  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& qd() const { return qd_; }
  long steps() const { return steps_; }

 protected:
  Eigen::VectorXd q_, qd_;
  long steps_ = 0;
};

// MuJoCo's names: "Euler" (semi-implicit), "RK4", "implicit" (in velocity);
// `step` the fixed time step. Built only when MuJoCo is found (SYMDYN_HAVE_MUJOCO).
std::unique_ptr<PeerIntegration> make_mujoco_integration(const peers::Mechanism& m,
                                                         const std::string& integrator,
                                                         double step);
std::vector<std::string> mujoco_integrators();

// Simbody's names: "RungeKuttaMerson", "CPodes" (BDF with Newton, its default);
// `accuracy` Simbody's setAccuracy. Built only when Simbody is found (SYMDYN_HAVE_SIMBODY).
std::unique_ptr<PeerIntegration> make_simbody_integration(const peers::Mechanism& m,
                                                          const std::string& integrator,
                                                          double accuracy);
std::vector<std::string> simbody_integrators();

}  // namespace symdyn::bench::work_precision
