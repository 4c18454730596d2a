#pragma once
// What symdyn_bench_peers and symdyn_bench_derivatives share: the random
// states every library sees, each model's mechanism, and the clock.
#include <Eigen/Core>
#include <cmath>
#include <ctime>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mechanism.hpp"
#include <symdyn/runtime/model.hpp>

namespace symdyn::bench::peers {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr int kStates = 64;

// The states every library sees: q within 1 of the model's initial configuration
// (radians or metres), qd and qdd (for inverse dynamics) in [-1, 1]; seeded.
struct States {
  std::vector<Eigen::VectorXd> q, qd, qdd;
};

inline States random_states(const runtime::Model& model) {
  std::mt19937 rng(2013);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  States s;
  const runtime::State s0 = model.initial_state();
  for (int k = 0; k < kStates; ++k) {
    Eigen::VectorXd q = s0.q, qd(model.nq()), qdd(model.nq());
    for (int j = 0; j < model.nq(); ++j) {
      q(j) += u(rng);
      qd(j) = u(rng);
      qdd(j) = u(rng);
    }
    s.q.push_back(q);
    s.qd.push_back(qd);
    s.qdd.push_back(qdd);
  }
  return s;
}

// The mechanism of a generated model, by the model's name.
inline Mechanism mechanism_of(const std::string& model) {
  if (model == "double_pendulum") return double_pendulum();
  if (model == "robot3d") return robot3d();
  if (model == "hexapod_tree") return hexapod_tree();
  if (model == "trike") return trike();
  if (model.rfind("chain_", 0) == 0) return chain(std::stoi(model.substr(6)));
  throw std::invalid_argument("no mechanism for " + model);
}

// CPU time of the calling thread, in seconds.
inline double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// max |a - b| / max |b| over n entries: the error relative to the size of the reference b.
inline double relative_error(const double* a, const double* b, std::size_t n) {
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < n; ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return diff / std::max(scale, 1e-300);
}

}  // namespace symdyn::bench::peers
