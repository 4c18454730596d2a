#pragma once
// Linearization of a system about a state, and its modes.
//
// About (q, qd, qdd) the residual f(q, qd, qdd, u) = 0 linearizes into
//   M dqdd + C dqd + K dq = B du,
// M = df/dqdd, C = df/dqd, K = df/dq (from DynamicSystem::jacobians: exact M
// for a MultibodySystem, C and K by central differences unless the system
// overrides them) and B = -df/du (central differences on declared inputs).
// Locked coordinates are removed (their rows and columns dropped). Extra
// states are held at their values (not part of the linear model).
//
// State matrix (x = (dq, dqd), 2n): A = [0 I; -M^-1 K  -M^-1 C],
// input matrix [0; M^-1 B]. Modes are the eigenpairs of A: for each pole
// lambda = sigma + i omega (conjugate pairs listed once, omega >= 0; real
// poles all listed), sorted by |lambda|:
//   natural frequency |lambda| / 2 pi (Hz), damped frequency omega / 2 pi,
//   damping ratio -sigma / |lambda| (0 for lambda = 0),
//   shape psi: the dq part of the eigenvector, scaled so that its largest
//   component is 1 (real), modal mass |psi^T M psi|.

#include <complex>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime {

// An input u of the system: how to read and set its value (e.g. a variable a
// force element reads).
struct Input {
  std::string name;
  std::function<double()> get;
  std::function<void(double)> set;
};

struct LinearizationOptions {
  std::vector<int> locked;    // coordinates removed
  std::vector<Input> inputs;  // columns of B
  std::optional<Vector> qdd;  // default: the accelerations at the state
  double input_step = 1e-6;   // relative, floor 1e-6
};

struct Linearization {
  std::vector<std::string> coordinates;  // names of the kept coordinates (n)
  std::vector<int> kept;                 // their indices in the system
  std::vector<std::string> inputs;       // (nu)
  Matrix M, C, K;                        // (n x n)
  Matrix B;                              // (n x nu)
  Matrix A;                              // (2n x 2n) state matrix
  Matrix Bx;                             // (2n x nu) state input matrix
};

Linearization linearize(DynamicSystem& system, const State& s,
                        const LinearizationOptions& options = {});

struct Mode {
  std::complex<double> pole;
  double natural_frequency_hz = 0.0;
  double damped_frequency_hz = 0.0;
  double damping_ratio = 0.0;
  double modal_mass = 0.0;
  Eigen::VectorXcd shape;  // (n)
};

// Throws NumericError when M is singular.
std::vector<Mode> modes(const Linearization& lin);

// CSV exports: the matrices M, C, K, B as blocks "matrix,row,<columns...>"
// with a header naming the columns; the modes one line each (pole, frequencies,
// damping, modal mass, then the real and imaginary part of each shape entry).
void write_matrices_csv(std::ostream& out, const Linearization& lin);
void write_modes_csv(std::ostream& out, const Linearization& lin, const std::vector<Mode>& modes);

}  // namespace symdyn::runtime
