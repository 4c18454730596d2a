// symdyn_bench_derivatives: the derivatives of the forward dynamics,
// dqdd/dq and dqdd/dqd at (q, qd) under gravity, on the mechanisms of
// symdyn_bench_peers, by every means a user has:
//
//   symdyn_exact          MultibodySystem::dynamics_derivatives: the emitted
//                         inverse_dynamics_derivatives (above 20 coordinates
//                         inverse_dynamics_jacobians, M with them), then -M⁻¹·K and -M⁻¹·C
//   symdyn_exact_by_columns  the baseline: the same as dynamics_derivatives did before
//                         its solves took all columns at once (M evaluated and factored
//                         again after qdd, then a solve per column of K and of C)
//   symdyn_differences    the same call after set_exact_jacobians(false): the
//                         runtime's central differences of the residual, then the same solves
//   symdyn_central        central differences of MultibodySystem::accelerations,
//                         4·nq calls (relative step 1e-6, floor 1e-6, as the runtime's)
//   symdyn_emitted_code   the emitted inverse_dynamics_derivatives alone (a floor, not a result)
//   mujoco_qacc_centered  differences of mj_forward's qacc, step 1e-6 (4·nq + 1 evaluations,
//   mujoco_qacc_forward     or 2·nq + 1), each skipping what the perturbation leaves alone
//   mujoco_transition_centered  mjd_transitionFD (step 1e-6, no controls nor sensors): A of
//   mujoco_transition_forward     one Euler step, what MuJoCo offers (4·nq + 1 or 2·nq + 1 steps)
//
//   symdyn_bench_derivatives check [MODEL...]      values at the first kChecked states (TSV)
//   symdyn_bench_derivatives time [--rounds R] [--batch-ms T] [MODEL...]   check, then the CPU
//       time per call of each method: medians over R interleaved rounds (TSV)
//   symdyn_bench_derivatives solves [--rounds R]   the solves -M⁻¹·[K C] alone at each size:
//       the runtime's (its kernels and its plain ones) against its previous ones, Eigen's
//       blocked solves and column by column, then M's factorization: the runtime's, its
//       plain kernel forced, its previous one and Eigen's LLT (TSV rows "solve", "factor")
//   symdyn_bench_derivatives --count METHOD MODEL [CALLS]   one workload, for
//       valgrind --tool=callgrind --toggle-collect='*counted_workload*'
//   symdyn_bench_derivatives --list
// bench/derivatives/run.sh runs them all and writes bench/results/derivatives.md.
#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "peer.hpp"
#include "peers_models.hpp"
#include "states.hpp"
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/spd_solver.hpp>

namespace {

using namespace symdyn::bench::peers;
namespace rt = symdyn::runtime;

// The values are checked at the first kChecked of the kStates states.
constexpr int kChecked = 8;
// MuJoCo's step (absolute, as mjd_transitionFD takes it).
constexpr double kEps = 1e-6;

// dqdd/dq and dqdd/dqd (nq x nq), column-major.
struct Derivatives {
  rt::Matrix dq, dqd;
};

// Per state k; the result of the last call stays in the workload's storage.
using Workload = std::function<void(int k)>;
// Per state k, the derivatives (check only).
using Evaluation = std::function<Derivatives(int k)>;

struct Method {
  std::string id;
  Workload work;
  Evaluation evaluate;  // empty: not checked (the emitted code alone)
};

// symdyn's side of a model.
struct SymdynModel {
  std::string target;
  std::function<rt::Model()> make;
  std::function<Mechanism()> mechanism;
  // The emitted inverse_dynamics_derivatives alone; empty where not emitted.
  std::function<Workload(const States&)> emitted_code;
};

template <class G>
SymdynModel symdyn_model(std::string target) {
  SymdynModel s;
  s.target = std::move(target);
  s.make = [] { return rt::Model::from<G>(); };
  s.mechanism = [] { return mechanism_of(G::model); };
  if constexpr (rt::detail::has_inverse_dynamics_derivatives<G>) {
    s.emitted_code = [](const States& st) -> Workload {
      auto out = std::make_shared<std::vector<double>>(2 * G::nq * G::nq);
      return [out, &st](int k) {
        G::inverse_dynamics_derivatives(0.0, st.q[k].data(), st.qd[k].data(), st.qdd[k].data(),
                                        G::param_defaults, out->data(),
                                        out->data() + G::nq * G::nq);
      };
    };
  }
  return s;
}

const std::vector<SymdynModel>& symdyn_models() {
  static const std::vector<SymdynModel> all = [] {
    std::vector<SymdynModel> v;
#define SYMDYN_PEERS_MODEL(target) v.push_back(symdyn_model<symdyn_generated::target>(#target));
    SYMDYN_PEERS_MODELS(SYMDYN_PEERS_MODEL)
#undef SYMDYN_PEERS_MODEL
    return v;
  }();
  return all;
}

// The system and state a symdyn method works on, shared by its workload and check.
struct SystemAt {
  std::shared_ptr<rt::MultibodySystem> system;
  std::shared_ptr<rt::State> state;
  void set(const States& st, int k) const {
    state->q = st.q[k];
    state->qd = st.qd[k];
  }
};

SystemAt system_at(const SymdynModel& s, bool exact) {
  auto system = std::make_shared<rt::MultibodySystem>(s.make(), rt::EquationsSource::emitted);
  system->set_exact_jacobians(exact);
  return {system, std::make_shared<rt::State>(system->initial_state())};
}

Method dynamics_derivatives(const SymdynModel& s, const States& st, bool exact) {
  const SystemAt at = system_at(s, exact);
  auto d = std::make_shared<rt::DynamicsDerivatives>();
  Method m{exact ? "symdyn_exact" : "symdyn_differences", {}, {}};
  m.work = [at, d, &st](int k) {
    at.set(st, k);
    at.system->dynamics_derivatives(*at.state, *d);
  };
  m.evaluate = [at, d, &st](int k) {
    at.set(st, k);
    at.system->dynamics_derivatives(*at.state, *d);
    return Derivatives{d->dqdd_dq, d->dqdd_dqd};
  };
  return m;
}

// The baseline: the runtime's dynamics_derivatives as it was before its solves
// took all columns at once (accelerations, jacobians with M, its Cholesky, then
// a solve per column of K and of C), from public calls and the same SpdSolver.
struct ByColumns {
  SystemAt at;
  rt::Vector qdd, yd, column, solved;
  rt::Matrix M;
  rt::SpdSolver solver;
  Derivatives out;
  void operator()(const States& st, int k) {
    at.set(st, k);
    at.system->accelerations(*at.state, qdd, yd);
    at.system->jacobians(*at.state, qdd, M, out.dqd, out.dq);
    if (!solver.factor(M)) throw rt::NumericError("singular mass matrix");
    solved.resize(qdd.size());
    for (int j = 0; j < qdd.size(); ++j) {
      column = out.dq.col(j);
      solver.solve_negated(column, solved);
      out.dq.col(j) = solved;
      column = out.dqd.col(j);
      solver.solve_negated(column, solved);
      out.dqd.col(j) = solved;
    }
  }
};

Method by_columns(const SymdynModel& s, const States& st) {
  auto b = std::make_shared<ByColumns>();
  b->at = system_at(s, true);
  b->solver = rt::SpdSolver(b->at.system->model().nq());
  return {"symdyn_exact_by_columns", [b, &st](int k) { (*b)(st, k); },
          [b, &st](int k) {
            (*b)(st, k);
            return b->out;
          }};
}

// What a user without derivatives writes: each column by two calls of accelerations.
struct CentralDifferences {
  SystemAt at;
  rt::State p;
  rt::Vector plus, minus, yd;
  Derivatives out;
  void operator()(const States& st, int k) {
    at.set(st, k);
    const rt::State& s = *at.state;
    const int n = static_cast<int>(s.q.size());
    p = s;
    out.dq.resize(n, n);
    out.dqd.resize(n, n);
    const auto column = [&](rt::Vector& x, const rt::Vector& x0, rt::Matrix& J, int j) {
      const double h = 1e-6 * std::max(1.0, std::abs(x0(j)));
      x(j) = x0(j) + h;
      at.system->accelerations(p, plus, yd);
      x(j) = x0(j) - h;
      at.system->accelerations(p, minus, yd);
      x(j) = x0(j);
      J.col(j) = (plus - minus) / (2.0 * h);
    };
    for (int j = 0; j < n; ++j) {
      column(p.q, s.q, out.dq, j);
      column(p.qd, s.qd, out.dqd, j);
    }
  }
};

Method central_differences(const SymdynModel& s, const States& st) {
  auto cd = std::make_shared<CentralDifferences>();
  cd->at = system_at(s, true);
  return {"symdyn_central", [cd, &st](int k) { (*cd)(st, k); },
          [cd, &st](int k) {
            (*cd)(st, k);
            return cd->out;
          }};
}

Derivatives from_rows(const std::vector<double>& dq, const std::vector<double>& dqd, int n) {
  return {Eigen::Map<const RowMatrix>(dq.data(), n, n),
          Eigen::Map<const RowMatrix>(dqd.data(), n, n)};
}

Method peer_acceleration_differences(Peer& p, const States& st, Differences how) {
  const int n = static_cast<int>(st.q[0].size());
  auto dq = std::make_shared<std::vector<double>>(static_cast<std::size_t>(n * n));
  auto dqd = std::make_shared<std::vector<double>>(static_cast<std::size_t>(n * n));
  Workload w = [=, &p, &st](int k) {
    p.acceleration_differences(st.q[k].data(), st.qd[k].data(), how, kEps, dq->data(), dqd->data());
  };
  return {how == Differences::centered ? "qacc_centered" : "qacc_forward", w, [=](int k) {
            w(k);
            return from_rows(*dq, *dqd, n);
          }};
}

// A's lower blocks are h·dqdd/dq and 1 + h·dqdd/dqd (Peer::time_step).
Method peer_transition(Peer& p, const States& st, Differences how) {
  const int n = static_cast<int>(st.q[0].size());
  auto A = std::make_shared<RowMatrix>(2 * n, 2 * n);
  Workload w = [=, &p, &st](int k) {
    p.transition_differences(st.q[k].data(), st.qd[k].data(), how, kEps, A->data());
  };
  return {how == Differences::centered ? "transition_centered" : "transition_forward", w,
          [=, &p](int k) {
            w(k);
            const double h = p.time_step();
            return Derivatives{A->block(n, 0, n, n) / h,
                               (A->block(n, n, n, n) - rt::Matrix::Identity(n, n)) / h};
          }};
}

struct PeerFactory {
  const char* id;
  std::unique_ptr<Peer> (*make)(const Mechanism&, std::string&);
};

const std::vector<PeerFactory>& peer_factories() {
  static const std::vector<PeerFactory> all = {
#ifdef SYMDYN_HAVE_MUJOCO
      {"mujoco", make_mujoco},
#endif
  };
  return all;
}

// Every method on one model; the peers that cannot build it, or cannot
// differentiate, are reported and left out.
struct Methods {
  std::vector<Method> list;
  std::vector<std::unique_ptr<Peer>> peers;  // owned here, referenced by the methods
};

Methods methods(const SymdynModel& s, const States& st, bool report) {
  Methods m;
  if (!s.emitted_code) {
    throw std::runtime_error(s.target + " was generated without its derivatives (DERIVATIVES)");
  }
  m.list.push_back(dynamics_derivatives(s, st, true));
  m.list.push_back(by_columns(s, st));
  m.list.push_back(dynamics_derivatives(s, st, false));
  m.list.push_back(central_differences(s, st));
  m.list.push_back({"symdyn_emitted_code", s.emitted_code(st), {}});
  for (const PeerFactory& f : peer_factories()) {
    std::string why;
    std::unique_ptr<Peer> p = f.make(s.mechanism(), why);
    if (!p || !p->can_differentiate()) {
      if (report) fmt::print("skip\t{}\t{}\t{}\n", s.target, f.id, p ? "no derivatives" : why);
      continue;
    }
    for (auto method : {peer_acceleration_differences, peer_transition}) {
      for (Differences how : {Differences::centered, Differences::forward}) {
        Method x = method(*p, st, how);
        x.id = std::string(f.id) + "_" + x.id;
        m.list.push_back(std::move(x));
      }
    }
    m.peers.push_back(std::move(p));
  }
  return m;
}

double max_abs(const rt::Matrix& a) {
  return a.cwiseAbs().maxCoeff();
}

// Each method's derivatives against the exact ones at the first kChecked
// states: max |X - exact| / max |exact|, dq and dqd apart, the largest over the
// states. Beside them the rounding of the forward dynamics, delta: the largest
// |qdd_peer - qdd_symdyn| (absolute) at those states, which a difference with step
// h turns into an error up to delta / h.
void check(const SymdynModel& s, const States& st, Methods& m) {
  const int n = static_cast<int>(st.q[0].size());
  const Method& exact = m.list.front();
  std::vector<Derivatives> reference;
  double scale_dq = 0, scale_dqd = 0;
  for (int k = 0; k < kChecked; ++k) {
    reference.push_back(exact.evaluate(k));
    scale_dq = std::max(scale_dq, max_abs(reference.back().dq));
    scale_dqd = std::max(scale_dqd, max_abs(reference.back().dqd));
  }
  fmt::print("scale\t{}\t{}\t{:.6g}\t{:.6g}\n", s.target, n, scale_dq, scale_dqd);
  for (const auto& p : m.peers)
    fmt::print("steps\t{}\t{}\t{:g}\t{:g}\n", s.target, p->name(), kEps, p->time_step());
  // The forward dynamics' rounding: symdyn's accelerations against each peer's.
  const SystemAt at = system_at(s, true);
  rt::Vector qdd, yd;
  std::vector<double> peer_qdd(static_cast<std::size_t>(n));
  for (const auto& p : m.peers) {
    double delta = 0, size = 0;
    for (int k = 0; k < kChecked; ++k) {
      at.set(st, k);
      at.system->accelerations(*at.state, qdd, yd);
      p->forward_dynamics(st.q[k].data(), st.qd[k].data(), peer_qdd.data());
      for (int i = 0; i < n; ++i) {
        delta = std::max(delta, std::abs(peer_qdd[static_cast<std::size_t>(i)] - qdd(i)));
        size = std::max(size, std::abs(qdd(i)));
      }
    }
    fmt::print("rounding\t{}\t{}\t{:.3g}\t{:.3g}\n", s.target, p->name(), delta, size);
  }
  for (const Method& x : m.list) {
    if (!x.evaluate || &x == &exact) continue;
    double e_dq = 0, e_dqd = 0;
    for (int k = 0; k < kChecked; ++k) {
      const Derivatives d = x.evaluate(k);
      e_dq = std::max(e_dq, max_abs(d.dq - reference[static_cast<std::size_t>(k)].dq) / scale_dq);
      e_dqd =
          std::max(e_dqd, max_abs(d.dqd - reference[static_cast<std::size_t>(k)].dqd) / scale_dqd);
    }
    fmt::print("check\t{}\t{}\t{:.3g}\t{:.3g}\n", s.target, x.id, e_dq, e_dqd);
  }
  std::fflush(stdout);
}

// The timed region: `calls` calls, cycling through the states from `first`.
[[gnu::noinline]] double timed_batch(const Workload& w, int calls, int first) {
  const double start = cpu_seconds();
  for (int c = 0; c < calls; ++c) w((first + c) % kStates);
  return (cpu_seconds() - start) / calls;
}

void time_model(const SymdynModel& s, int rounds, double batch_ms) {
  const States st = random_states(s.make());
  Methods m = methods(s, st, true);
  check(s, st, m);
  // Calls per batch: a batch lasts about batch_ms, found after warm-up calls
  // (the first calls of chain_64's derivatives fault its 8.6 MB of code in).
  std::vector<int> calls;
  for (const Method& x : m.list) {
    timed_batch(x.work, 3, 0);
    const double per_call = timed_batch(x.work, 3, 3);
    calls.push_back(std::max(1, static_cast<int>(batch_ms * 1e-3 / per_call)));
  }
  std::vector<std::vector<double>> ns(m.list.size());
  for (int r = 0; r < rounds; ++r) {
    for (std::size_t i = 0; i < m.list.size(); ++i) {
      ns[i].push_back(1e9 * timed_batch(m.list[i].work, calls[i], r * calls[i]));
    }
  }
  for (std::size_t i = 0; i < m.list.size(); ++i) {
    std::vector<double>& v = ns[i];
    std::sort(v.begin(), v.end());
    const auto at = [&](double f) {
      return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1))];
    };
    fmt::print("time\t{}\t{}\t{:.1f}\t{:.1f}\t{:.1f}\t{}\t{}\n", s.target, m.list[i].id, at(0.5),
               at(0.25), at(0.75), rounds, calls[i]);
  }
  std::fflush(stdout);
}

// The previous runtime's -M⁻¹·B, the baseline: up to 8 coordinates a row loop
// on B in place (column-major, so each row strided by n), above them Eigen's
// blocked triangular solves. L: the Cholesky factor of M (n x n, lower).
void previous_solve_negated(const rt::Matrix& L, rt::Matrix& B) {
  const Eigen::Index n = L.rows(), m = B.cols();
  if (n > 8) {
    const auto Lv = L.triangularView<Eigen::Lower>();
    Lv.solveInPlace(B);
    Lv.adjoint().solveInPlace(B);
    B = -B;
    return;
  }
  const double* l = L.data();
  double* b = B.data();
  const auto axpy = [&](Eigen::Index i, Eigen::Index k, double c) {
    for (Eigen::Index j = 0; j < m; ++j) b[i + j * n] -= c * b[k + j * n];
  };
  const auto scale = [&](Eigen::Index i, double c) {
    for (Eigen::Index j = 0; j < m; ++j) b[i + j * n] *= c;
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    scale(i, -1.0);
    for (Eigen::Index k = 0; k < i; ++k) axpy(i, k, l[i + k * n]);
    scale(i, 1.0 / l[i + i * n]);
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    for (Eigen::Index k = i + 1; k < n; ++k) axpy(i, k, l[k + i * n]);
    scale(i, 1.0 / l[i + i * n]);
  }
}

// The previous runtime's factorization up to 40 coordinates, as it was: M = L·Lᵀ
// by the scalar column loop, L_ij = (M_ij - Σ_k<j L_ik·L_jk) / L_jj, with its
// pivot checks and smallest ratio.
[[gnu::noinline]] bool previous_factor(const rt::Matrix& M, rt::Matrix& L, double& ratio) {
  const Eigen::Index n = L.rows();
  const double* m = M.data();
  double* l = L.data();
  double smallest = 1.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    double d = m[j + j * n];
    for (Eigen::Index k = 0; k < j; ++k) d -= l[j + k * n] * l[j + k * n];
    if (!(d > 0.0)) {
      ratio = d < 0.0 && m[j + j * n] > 0.0 ? d / m[j + j * n] : 0.0;
      return false;
    }
    smallest = std::min(smallest, d / m[j + j * n]);
    const double Ljj = std::sqrt(d);
    l[j + j * n] = Ljj;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double sum = m[i + j * n];
      for (Eigen::Index k = 0; k < j; ++k) sum -= l[i + k * n] * l[j + k * n];
      l[i + j * n] = sum / Ljj;
    }
  }
  ratio = smallest;
  return true;
}

// Median ns of each way over interleaved rounds, as "label\tn\tway\tns".
template <std::size_t N>
void time_ways(const char* label, int n, const std::pair<const char*, Workload> (&ways)[N],
               int rounds) {
  std::vector<int> calls;
  for (const auto& [name, w] : ways)
    calls.push_back(std::max(1, static_cast<int>(2e-3 / timed_batch(w, 8, 0))));
  std::vector<std::vector<double>> ns(N);
  for (int r = 0; r < rounds; ++r) {
    for (std::size_t i = 0; i < N; ++i)
      ns[i].push_back(1e9 * timed_batch(ways[i].second, calls[i], 0));
  }
  for (std::size_t i = 0; i < N; ++i) {
    std::sort(ns[i].begin(), ns[i].end());
    fmt::print("{}\t{}\t{}\t{:.1f}\n", label, n, ways[i].first, ns[i][ns[i].size() / 2]);
  }
  std::fflush(stdout);
}

// The solves -M⁻¹·B of dynamics_derivatives (B: nq x 2·nq, K and C side by
// side) at each size: the runtime's SpdSolver::solve_negated_in_place with the
// kernels it picks (wide where the processor runs AVX2 with FMA) and with its
// plain ones forced, the previous runtime's solve, Eigen's blocked solves and
// SpdSolver's vector solve column by column, on a random SPD M (seeded),
// medians over interleaved rounds.
void time_solves(int rounds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {2, 3, 4, 5, 6, 8, 10, 13, 16, 24, 32, 48, 64, 96, 128}) {
    rt::Matrix A(n, n), B0(n, 2 * n);
    for (double& x : A.reshaped()) x = u(rng);
    for (double& x : B0.reshaped()) x = u(rng);
    const rt::Matrix M = A * A.transpose() + n * rt::Matrix::Identity(n, n);
    rt::SpdSolver solver(n), plain(n, rt::SpdSolver::Kernels::plain);
    if (!solver.factor(M) || !plain.factor(M)) throw std::logic_error("random SPD matrix refused");
    const rt::Matrix L = M.llt().matrixL();
    rt::Matrix B = B0;
    rt::Vector column, solved(n);
    const std::pair<const char*, Workload> ways[] = {
        {"runtime", [&](int) { B = B0, solver.solve_negated_in_place(B); }},
        {"plain", [&](int) { B = B0, plain.solve_negated_in_place(B); }},
        {"previous", [&](int) { B = B0, previous_solve_negated(L, B); }},
        {"eigen_blocked",
         [&](int) {
           B = B0;
           const auto Lv = L.triangularView<Eigen::Lower>();
           Lv.solveInPlace(B);
           Lv.adjoint().solveInPlace(B);
           B = -B;
         }},
        {"by_columns",
         [&](int) {
           B = B0;
           for (int j = 0; j < 2 * n; ++j) {
             column = B.col(j);
             solver.solve_negated(column, solved);
             B.col(j) = solved;
           }
         }},
    };
    time_ways("solve", n, ways, rounds);
    // The factorization of M: the runtime's (its kernels, the same to the bit in
    // each), the plain kernels forced, the previous runtime's (the scalar column
    // loop up to 40 coordinates, Eigen's LLT above) and Eigen's LLT.
    rt::SpdSolver factored(n), factored_plain(n, rt::SpdSolver::Kernels::plain);
    Eigen::LLT<rt::Matrix> llt(n);
    rt::Matrix previous_L(n, n);
    double previous_ratio = 0.0;
    const std::pair<const char*, Workload> factorizations[] = {
        {"runtime", [&](int) { factored.factor(M); }},
        {"plain", [&](int) { factored_plain.factor(M); }},
        {"previous",
         [&](int) {
           if (n > 40) {
             llt.compute(M);
           } else {
             previous_factor(M, previous_L, previous_ratio);
           }
         }},
        {"eigen_llt", [&](int) { llt.compute(M); }},
    };
    time_ways("factor", n, factorizations, rounds);
  }
}

// The counted region: callgrind --toggle-collect='*counted_workload*'.
[[gnu::noinline]] void counted_workload(const Workload& w, int calls) {
  for (int c = 0; c < calls; ++c) w(c % kStates);
}

int count(const std::string& method, const std::string& target, int calls) {
  for (const SymdynModel& s : symdyn_models()) {
    if (s.target != target) continue;
    const States st = random_states(s.make());
    Methods m = methods(s, st, false);
    for (const Method& x : m.list) {
      if (x.id != method) continue;
      // Warm outside counted_workload: callgrind collects every call of it.
      for (int k = 0; k < 2; ++k) x.work(k);
      counted_workload(x.work, calls);
      fmt::print("{} {} calls {}\n", method, target, calls);
      return 0;
    }
    fmt::print(stderr, "no method '{}' on {} (--list)\n", method, target);
    return 3;
  }
  fmt::print(stderr, "unknown model '{}' (--list)\n", target);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (!args.empty() && args[0] == "--list") {
      for (const SymdynModel& s : symdyn_models())
        fmt::print("model {} {}\n", s.target, s.make().nq());
      const SymdynModel& first = symdyn_models().front();
      const States st = random_states(first.make());
      for (const Method& x : methods(first, st, false).list) fmt::print("method {}\n", x.id);
      return 0;
    }
    if (!args.empty() && args[0] == "solves") {
      time_solves(args.size() > 2 && args[1] == "--rounds" ? std::stoi(args[2]) : 21);
      return 0;
    }
    if (!args.empty() && args[0] == "--count") {
      if (args.size() < 3) {
        fmt::print(stderr, "usage: symdyn_bench_derivatives --count METHOD MODEL [CALLS]\n");
        return 2;
      }
      return count(args[1], args[2], args.size() > 3 ? std::stoi(args[3]) : 16);
    }
    if (!args.empty() && (args[0] == "check" || args[0] == "time")) {
      int rounds = 21;
      double batch_ms = 10.0;
      std::vector<std::string> names;
      for (std::size_t i = 1; i < args.size(); ++i) {
        if (args[i] == "--rounds" && i + 1 < args.size()) {
          rounds = std::stoi(args[++i]);
        } else if (args[i] == "--batch-ms" && i + 1 < args.size()) {
          batch_ms = std::stod(args[++i]);
        } else {
          names.push_back(args[i]);
        }
      }
      for (const SymdynModel& s : symdyn_models()) {
        if (!names.empty() && std::find(names.begin(), names.end(), s.target) == names.end())
          continue;
        if (args[0] == "time") {
          time_model(s, rounds, batch_ms);
        } else {
          const States st = random_states(s.make());
          Methods m = methods(s, st, true);
          check(s, st, m);
        }
      }
      return 0;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "symdyn_bench_derivatives: {}\n", e.what());
    return 1;
  }
  fmt::print(stderr,
             "usage: symdyn_bench_derivatives check|time [--rounds R] [--batch-ms T] [MODEL...] | "
             "solves [--rounds R] "
             "| --count METHOD MODEL [CALLS] | --list\n");
  return 2;
}
