#pragma once
// One library's model of a mechanism, behind the four operations the bench
// compares. Each call does what the library's users do for that result, on
// the library's recommended fast path; the read_* functions only copy the
// last result out (verification, never timed).
//
// Arrays: q, qd, qdd, tau (nq) in the mechanism's coordinate order (a peer
// that orders them otherwise permutes); M (nq x nq) row-major; R (nbody x 3 x 3)
// row-major and x (nbody x 3): each massive link's axes and centre of mass in
// the global frame, in symdyn's body order.
#include <memory>
#include <string>

#include "mechanism.hpp"

namespace symdyn::bench::peers {

enum class Operation { forward_dynamics, mass_matrix, inverse_dynamics, positions };

// Finite differences with step eps: (f(x + eps) - f(x - eps)) / 2·eps, or
// (f(x + eps) - f(x)) / eps.
enum class Differences { centered, forward };

class Peer {
 public:
  virtual ~Peer() = default;
  virtual std::string name() const = 0;
  // Whether the library computes op on this model (its make_ function says why not).
  virtual bool can(Operation) const { return true; }
  // The total mass the library's model holds (an independent check of the model).
  virtual double total_mass() const = 0;

  // qdd from q, qd under gravity, no other force.
  virtual void forward_dynamics(const double* q, const double* qd, double* qdd) = 0;
  // The mass matrix at q, in the library's own storage.
  virtual void mass_matrix(const double* q) = 0;
  virtual void read_mass_matrix(double* M) const = 0;
  // tau = M(q)·qdd + h(q, qd), h with gravity.
  virtual void inverse_dynamics(const double* q, const double* qd, const double* qdd,
                                double* tau) = 0;
  // Every body's pose at q, in the library's own storage.
  virtual void positions(const double* q) = 0;
  virtual void read_positions(double* R, double* x) const = 0;

  // Derivatives of the forward dynamics, by the library's own means, where it
  // has them (symdyn_bench_derivatives). dqdd_dq, dqdd_dqd (nq x nq) row-major.
  virtual bool can_differentiate() const { return false; }
  // dqdd/dq and dqdd/dqd at (q, qd) by finite differences of the forward
  // dynamics users call (each perturbed evaluation recomputing only what the
  // perturbation changes, as the library's own differences do), step eps.
  virtual void acceleration_differences(const double* /*q*/, const double* /*qd*/, Differences,
                                        double /*eps*/, double* /*dqdd_dq*/, double* /*dqdd_dqd*/) {
  }
  // The library's transition matrix A (2nq x 2nq, row-major) of one step of its
  // integrator from (q, qd), d(q, qd)_next = A·d(q, qd), by its own routine, step eps.
  virtual void transition_differences(const double* /*q*/, const double* /*qd*/, Differences,
                                      double /*eps*/, double* /*A*/) {}
  // The step h of that integrator, whose velocity update must be qd + h·qdd
  // (MuJoCo's Euler without joint damping): A's lower blocks are then
  // h·dqdd/dq and 1 + h·dqdd/dqd.
  virtual double time_step() const { return 0.0; }
};

// Each returns nullptr when the library cannot express the mechanism, and sets
// why (a sentence for the results); or a peer that cannot do some operations,
// with why saying which and why.
std::unique_ptr<Peer> make_mujoco(const Mechanism& m, std::string& why);
std::unique_ptr<Peer> make_simbody(const Mechanism& m, std::string& why);
std::unique_ptr<Peer> make_kdl(const Mechanism& m, std::string& why);
std::unique_ptr<Peer> make_dart(const Mechanism& m, std::string& why);

}  // namespace symdyn::bench::peers
