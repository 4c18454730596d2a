// Calls one entry point of an emitted model (the header gen.hpp, struct gen)
// CALLS times at a fixed state, inside counted_workload, for callgrind:
//
//   valgrind --tool=callgrind --toggle-collect='*counted_workload*' driver ENTRY CALLS
//
// ENTRY: dynamics, inverse_dynamics or forward_dynamics. Prints a checksum
// of the outputs, so that no call is optimized away and two builds of the
// same model can be compared.
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "gen.hpp"

namespace {

using Model = symdyn_generated::gen;
constexpr int nq = Model::nq;

struct State {
  std::vector<double> q, qd, qdd, tau, param, out;
  State()
      : q(nq),
        qd(nq),
        qdd(nq),
        tau(nq),
        param(Model::param_defaults, Model::param_defaults + Model::nparam) {
    for (int i = 0; i < nq; ++i) {
      q[i] = Model::q_initial[i] + 0.01 * (i % 7);
      qd[i] = 0.3 - 0.05 * (i % 5);
      qdd[i] = 0.2 * (i % 3) - 0.1;
      tau[i] = 0.5 - 0.1 * (i % 4);
    }
    out.assign(static_cast<std::size_t>(nq) * (nq + 1), 0.0);
  }
};

// A template, so that forward_dynamics is only named where it is emitted.
template <class M>
[[gnu::noinline]] void counted_workload(std::string_view entry, int calls, State& s) {
  double* out = s.out.data();
  for (int c = 0; c < calls; ++c) {
    if (entry == "dynamics") {
      M::dynamics(0.0, s.q.data(), s.qd.data(), s.param.data(), out, out + nq * nq);
    } else if (entry == "inverse_dynamics") {
      M::inverse_dynamics(0.0, s.q.data(), s.qd.data(), s.qdd.data(), s.param.data(), out);
    } else {
      if constexpr (M::has_forward_dynamics)
        M::forward_dynamics(0.0, s.q.data(), s.qd.data(), s.tau.data(), s.param.data(), out);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s dynamics|inverse_dynamics|forward_dynamics CALLS\n", argv[0]);
    return 2;
  }
  const std::string_view entry = argv[1];
  if (entry == "forward_dynamics" && !Model::has_forward_dynamics) {
    std::fprintf(stderr, "%s: no forward_dynamics emitted\n", argv[0]);
    return 3;
  }
  State s;
  counted_workload<Model>(entry, std::atoi(argv[2]), s);
  double sum = 0;
  for (double v : s.out) sum += v;
  std::printf("%.17g\n", sum);
  return 0;
}
