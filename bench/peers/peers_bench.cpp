// symdyn_bench_peers: symdyn's emitted code and runtime against MuJoCo,
// Simbody, KDL and DART on the same mechanisms (mechanism.hpp), per model:
// forward dynamics, mass matrix, inverse dynamics, positions of all bodies.
//
//   symdyn_bench_peers verify [MODEL...]   each peer against symdyn at 64 random
//       states and q = 0 (masses, M, qdd, tau, poses); TSV on stdout
//   symdyn_bench_peers time [--rounds R] [--batch-ms T] [MODEL...]   verify, then
//       CPU time per call of every library that agreed: medians over R rounds, each
//       round timing one batch of each library in turn (interleaved); TSV on stdout
//   symdyn_bench_peers --count LIBRARY OP MODEL [CALLS]   one workload, for
//       valgrind --tool=callgrind --toggle-collect='*counted_workload*'
//   symdyn_bench_peers --list                 models, libraries, operations
// bench/peers/run.sh runs them all and writes bench/results/peers.md.
#include <fmt/format.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mechanism.hpp"
#include "peer.hpp"
#include "peers_models.hpp"
#include "states.hpp"
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/spd_solver.hpp>

namespace {

using namespace symdyn::bench::peers;
namespace rt = symdyn::runtime;

// Agreement required of every peer, relative to the largest entry of symdyn's
// result: rounding in different algorithms leaves ~1e-15 on M, tau and poses,
// and qdd = M^-1·(-h) loses up to cond(M)·eps: 4e-10 seen at chain_64, whose M
// reaches cond 1.6e8 at these states. 1e-9 admits that and nothing wrong (a
// misplaced centre of mass or axis shows as 1e-1 or worse).
constexpr double kTolerance = 1e-9;

// Per state k; the output of the last call stays in the workload's storage.
using Workload = std::function<void(int k)>;

using Op = Operation;
const char* op_name(Op op) {
  static constexpr const char* names[] = {"forward_dynamics", "mass_matrix", "inverse_dynamics",
                                          "positions"};
  return names[static_cast<int>(op)];
}
constexpr Op kOps[] = {Op::forward_dynamics, Op::mass_matrix, Op::inverse_dynamics, Op::positions};

// symdyn's side of a model: the emitted code, and the runtime on it.
struct SymdynModel {
  std::string target;
  std::function<rt::Model()> make;
  std::function<Mechanism()> mechanism;
  // Outputs at state (q, qd, qdd): M (row-major), qdd = M^-1·(-h), tau = M·qdd + h, R, x.
  std::function<void(const double* q, const double* qd, const double* qdd, double* M,
                     double* qdd_out, double* tau, double* R, double* x)>
      evaluate;
  std::function<Workload(Op, const States&)> workload;
};

template <class G>
SymdynModel symdyn_model(std::string target) {
  SymdynModel s;
  s.target = std::move(target);
  s.make = [] { return rt::Model::from<G>(); };
  s.mechanism = [] { return mechanism_of(G::model); };
  s.evaluate = [](const double* q, const double* qd, const double* qdd, double* M, double* qdd_out,
                  double* tau, double* R, double* x) {
    const int n = G::nq;
    rt::Matrix Mc(n, n);
    rt::Vector h(n);
    G::dynamics(0.0, q, qd, G::param_defaults, Mc.data(), h.data());
    Eigen::Map<RowMatrix>(M, n, n) = Mc;  // symmetric: either order
    rt::SpdSolver solver(n);
    if (!solver.factor(Mc)) throw rt::NumericError("singular mass matrix");
    rt::Vector a = -h;
    solver.solve_in_place(a);
    Eigen::Map<Eigen::VectorXd>(qdd_out, n) = a;
    Eigen::Map<Eigen::VectorXd>(tau, n) = Mc * Eigen::Map<const Eigen::VectorXd>(qdd, n) + h;
    G::positions(0.0, q, G::param_defaults, R, x);
  };
  s.workload = [](Op op, const States& st) -> Workload {
    constexpr int n = G::nq;
    auto M = std::make_shared<rt::Matrix>(n, n);
    auto h = std::make_shared<rt::Vector>(n);
    auto out = std::make_shared<rt::Vector>(n);
    switch (op) {
      case Op::forward_dynamics: {
        if constexpr (requires { G::has_forward_dynamics; }) {
          if constexpr (G::has_forward_dynamics) {
            // The articulated-body algorithm, where the generator chose it.
            auto tau = std::make_shared<rt::Vector>(rt::Vector::Zero(n));
            return [=, &st](int k) {
              if (G::forward_dynamics(0.0, st.q[k].data(), st.qd[k].data(), tau->data(),
                                      G::param_defaults, out->data()) >= 0) {
                throw rt::NumericError("singular articulated inertia");
              }
            };
          }
        }
        auto solver = std::make_shared<rt::SpdSolver>(n);
        return [=, &st](int k) {
          G::dynamics(0.0, st.q[k].data(), st.qd[k].data(), G::param_defaults, M->data(),
                      h->data());
          if (!solver->factor(*M)) throw rt::NumericError("singular mass matrix");
          *out = -*h;
          solver->solve_in_place(*out);
        };
      }
      case Op::mass_matrix:
        return
            [=, &st](int k) { G::mass_matrix(0.0, st.q[k].data(), G::param_defaults, M->data()); };
      case Op::inverse_dynamics:
        if constexpr (requires { G::has_inverse_dynamics; }) {
          return [=, &st](int k) {
            G::inverse_dynamics(0.0, st.q[k].data(), st.qd[k].data(), st.qdd[k].data(),
                                G::param_defaults, out->data());
          };
        }
        return [=, &st](int k) {
          G::dynamics(0.0, st.q[k].data(), st.qd[k].data(), G::param_defaults, M->data(),
                      h->data());
          out->noalias() = *M * st.qdd[k];
          *out += *h;
        };
      case Op::positions: {
        auto R = std::make_shared<std::vector<double>>(9 * G::nbody);
        auto x = std::make_shared<std::vector<double>>(3 * G::nbody);
        return [=, &st](int k) {
          G::positions(0.0, st.q[k].data(), G::param_defaults, R->data(), x->data());
        };
      }
    }
    return {};
  };
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

// What users call: MultibodySystem::accelerations under gravity, and for M and
// tau the system's mass_matrix and residual (f = inverse_dynamics(qdd), or M·qdd + h, no force
// element). The runtime has no call for positions alone: users call the emitted positions().
struct SystemWorkload {
  std::shared_ptr<rt::MultibodySystem> system;
  std::shared_ptr<rt::State> state;
  std::shared_ptr<rt::Vector> out, yd, g;
  std::shared_ptr<rt::Matrix> M;
};

Workload system_workload(const SymdynModel& s, const States& st, Op op = Op::forward_dynamics) {
  SystemWorkload w{std::make_shared<rt::MultibodySystem>(s.make(), rt::EquationsSource::emitted),
                   nullptr,
                   std::make_shared<rt::Vector>(),
                   std::make_shared<rt::Vector>(),
                   std::make_shared<rt::Vector>(),
                   std::make_shared<rt::Matrix>()};
  w.state = std::make_shared<rt::State>(w.system->initial_state());
  switch (op) {
    case Op::forward_dynamics:
      return [w, &st](int k) {
        w.state->q = st.q[k];
        w.state->qd = st.qd[k];
        w.system->accelerations(*w.state, *w.out, *w.yd);
      };
    case Op::mass_matrix:
      return [w, &st](int k) {
        w.state->q = st.q[k];
        w.system->mass_matrix(*w.state, *w.M);
      };
    case Op::inverse_dynamics:
      return [w, &st](int k) {
        w.state->q = st.q[k];
        w.state->qd = st.qd[k];
        w.system->residual(*w.state, st.qdd[k], *w.yd, *w.out, *w.g);
      };
    case Op::positions:
      return {};
  }
  return {};
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
#ifdef SYMDYN_HAVE_SIMBODY
      {"simbody", make_simbody},
#endif
#ifdef SYMDYN_HAVE_KDL
      {"kdl", make_kdl},
#endif
#ifdef SYMDYN_HAVE_DART
      {"dart", make_dart},
#endif
  };
  return all;
}

Workload peer_workload(Peer& p, Op op, const States& st) {
  const std::size_t n = static_cast<std::size_t>(st.q[0].size());
  auto out = std::make_shared<std::vector<double>>(n);
  switch (op) {
    case Op::forward_dynamics:
      return
          [=, &p, &st](int k) { p.forward_dynamics(st.q[k].data(), st.qd[k].data(), out->data()); };
    case Op::mass_matrix:
      return [&p, &st](int k) { p.mass_matrix(st.q[k].data()); };
    case Op::inverse_dynamics:
      return [=, &p, &st](int k) {
        p.inverse_dynamics(st.q[k].data(), st.qd[k].data(), st.qdd[k].data(), out->data());
      };
    case Op::positions:
      return [&p, &st](int k) { p.positions(st.q[k].data()); };
  }
  return {};
}

double relative_error(const std::vector<double>& a, const std::vector<double>& b) {
  return symdyn::bench::peers::relative_error(a.data(), b.data(), a.size());
}

struct Outputs {
  std::vector<double> M, qdd, tau, R, x;
  Outputs(int nq, int nbody)
      : M(static_cast<std::size_t>(nq * nq)),
        qdd(static_cast<std::size_t>(nq)),
        tau(static_cast<std::size_t>(nq)),
        R(static_cast<std::size_t>(9 * nbody)),
        x(static_cast<std::size_t>(3 * nbody)) {}
};

// A model's peers, each verified against symdyn; those that disagree are dropped.
struct Contenders {
  std::vector<std::pair<std::string, std::unique_ptr<Peer>>> peers;  // (id, peer), verified
};

Contenders verify(const SymdynModel& s, const States& st) {
  const rt::Model model = s.make();
  const Mechanism mech = s.mechanism();
  const int nq = model.nq(), nbody = model.nbody();
  double symdyn_mass = 0;
  for (int b = 0; b < nbody; ++b) symdyn_mass += model.mass(b);
  fmt::print("mass\t{}\tmechanism\t{:.17g}\t{:.17g}\n", s.target, mech.total_mass(), symdyn_mass);
  if (mech.nq() != nq || mech.nbody() != nbody ||
      std::abs(mech.total_mass() - symdyn_mass) > 1e-12 * symdyn_mass) {
    throw std::logic_error(
        fmt::format("{}: mechanism differs from the model in size or mass", s.target));
  }

  // symdyn's own two paths agree first: the runtime against the emitted code.
  std::vector<Outputs> ref;
  double max_cond = 0;
  std::map<std::string, double> system_err;
  rt::Matrix M_sys;
  rt::Vector tau_sys, g;
  auto system = rt::MultibodySystem(s.make(), rt::EquationsSource::emitted);
  rt::State state = system.initial_state();
  rt::Vector qdd_sys, yd;
  for (int k = 0; k <= kStates; ++k) {
    // k == kStates: q = 0, qd = 0, the first state checked for each peer.
    const Eigen::VectorXd q = k < kStates ? st.q[k] : Eigen::VectorXd::Zero(nq);
    const Eigen::VectorXd qd = k < kStates ? st.qd[k] : Eigen::VectorXd::Zero(nq);
    const Eigen::VectorXd qdd = k < kStates ? st.qdd[k] : Eigen::VectorXd::Zero(nq);
    Outputs o(nq, nbody);
    s.evaluate(q.data(), qd.data(), qdd.data(), o.M.data(), o.qdd.data(), o.tau.data(), o.R.data(),
               o.x.data());
    const Eigen::Map<const RowMatrix> M(o.M.data(), nq, nq);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
    max_cond = std::max(max_cond, eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff());
    state.q = q;
    state.qd = qd;
    system.accelerations(state, qdd_sys, yd);
    system_err["qdd"] =
        std::max(system_err["qdd"], relative_error({qdd_sys.data(), qdd_sys.data() + nq}, o.qdd));
    system.mass_matrix(state, M_sys);
    const RowMatrix M_rows = M_sys;
    system_err["M"] =
        std::max(system_err["M"], relative_error({M_rows.data(), M_rows.data() + nq * nq}, o.M));
    system.residual(state, qdd, yd, tau_sys, g);
    system_err["tau"] =
        std::max(system_err["tau"], relative_error({tau_sys.data(), tau_sys.data() + nq}, o.tau));
    ref.push_back(std::move(o));
  }
  fmt::print("cond\t{}\t{:.3g}\n", s.target, max_cond);
  fmt::print("dynamics\t{}\t{}\n", s.target,
             model.has_forward_dynamics() ? "recursive" : "mass_matrix");
  for (const auto& [quantity, e] : system_err) {
    fmt::print("verify\t{}\tsymdyn_system\t{}\t{:.3g}\t{:.0e}\t{}\n", s.target, quantity, e,
               kTolerance, e <= kTolerance ? "ok" : "DISAGREES");
  }

  Contenders c;
  for (const PeerFactory& f : peer_factories()) {
    std::string why;
    std::unique_ptr<Peer> p;
    try {
      p = f.make(mech, why);
    } catch (const std::exception& e) {
      why = std::string("cannot build the model: ") + e.what();
    }
    if (!p) {
      fmt::print("skip\t{}\t{}\t{}\n", s.target, f.id, why);
      continue;
    }
    std::map<std::string, double> err;
    err["mass"] = std::abs(p->total_mass() - symdyn_mass) / symdyn_mass;
    for (int k = kStates; k >= 0; --k) {
      const Eigen::VectorXd q = k < kStates ? st.q[k] : Eigen::VectorXd::Zero(nq);
      const Eigen::VectorXd qd = k < kStates ? st.qd[k] : Eigen::VectorXd::Zero(nq);
      const Eigen::VectorXd qdd = k < kStates ? st.qdd[k] : Eigen::VectorXd::Zero(nq);
      const Outputs& r = ref[static_cast<std::size_t>(k)];
      Outputs o(nq, nbody);
      if (p->can(Op::mass_matrix)) {
        p->mass_matrix(q.data());
        p->read_mass_matrix(o.M.data());
      }
      if (p->can(Op::forward_dynamics)) p->forward_dynamics(q.data(), qd.data(), o.qdd.data());
      if (p->can(Op::inverse_dynamics))
        p->inverse_dynamics(q.data(), qd.data(), qdd.data(), o.tau.data());
      if (p->can(Op::positions)) {
        p->positions(q.data());
        p->read_positions(o.R.data(), o.x.data());
      }
      const std::string at = k == kStates ? "_at_q0" : "";
      for (auto [op, name, a, b] : {std::tuple{Op::mass_matrix, "M", &o.M, &r.M},
                                    std::tuple{Op::forward_dynamics, "qdd", &o.qdd, &r.qdd},
                                    std::tuple{Op::inverse_dynamics, "tau", &o.tau, &r.tau},
                                    std::tuple{Op::positions, "R", &o.R, &r.R},
                                    std::tuple{Op::positions, "x", &o.x, &r.x}}) {
        if (!p->can(op)) continue;
        double& e = err[name + at];
        e = std::max(e, relative_error(*a, *b));
      }
    }
    bool ok = true;
    for (const auto& [quantity, e] : err) {
      const bool pass = e <= kTolerance;
      ok = ok && pass;
      fmt::print("verify\t{}\t{}\t{}\t{:.3g}\t{:.0e}\t{}\n", s.target, f.id, quantity, e,
                 kTolerance, pass ? "ok" : "DISAGREES");
    }
    for (Op op : kOps) {
      if (!p->can(op)) fmt::print("skipop\t{}\t{}\t{}\t{}\n", s.target, f.id, op_name(op), why);
    }
    if (ok) c.peers.emplace_back(f.id, std::move(p));
  }
  return c;
}

// The timed region: every state once per pass.
[[gnu::noinline]] double timed_batch(const Workload& w, int passes) {
  const double start = cpu_seconds();
  for (int p = 0; p < passes; ++p) {
    for (int k = 0; k < kStates; ++k) w(k);
  }
  return (cpu_seconds() - start) / (passes * kStates);
}

void time_model(const SymdynModel& s, int rounds, double batch_ms) {
  const States st = random_states(s.make());
  Contenders c = verify(s, st);
  for (Op op : kOps) {
    std::vector<std::pair<std::string, Workload>> w;
    w.emplace_back("symdyn_emitted", s.workload(op, st));
    if (op != Op::positions) w.emplace_back("symdyn_system", system_workload(s, st, op));
    for (auto& [id, p] : c.peers) {
      if (p->can(op)) w.emplace_back(id, peer_workload(*p, op, st));
    }
    // Passes per batch: a batch lasts about batch_ms, found on a warm-up batch.
    std::vector<int> passes;
    for (auto& [id, work] : w) {
      timed_batch(work, 1);
      const double per_call = timed_batch(work, 2);
      passes.push_back(std::max(1, static_cast<int>(batch_ms * 1e-3 / (per_call * kStates))));
    }
    std::vector<std::vector<double>> ns(w.size());
    for (int r = 0; r < rounds; ++r) {
      for (std::size_t i = 0; i < w.size(); ++i)
        ns[i].push_back(1e9 * timed_batch(w[i].second, passes[i]));
    }
    for (std::size_t i = 0; i < w.size(); ++i) {
      std::vector<double>& v = ns[i];
      std::sort(v.begin(), v.end());
      const auto at = [&](double f) {
        return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1))];
      };
      fmt::print("time\t{}\t{}\t{}\t{:.1f}\t{:.1f}\t{:.1f}\t{}\n", s.target, op_name(op),
                 w[i].first, at(0.5), at(0.25), at(0.75), rounds);
    }
    std::fflush(stdout);
  }
}

// The counted region: callgrind --toggle-collect='*counted_workload*'.
[[gnu::noinline]] void counted_workload(const Workload& w, int calls) {
  for (int c = 0; c < calls; ++c) w(c % kStates);
}

int count(const std::string& library, const std::string& op_text, const std::string& target,
          int calls) {
  for (const SymdynModel& s : symdyn_models()) {
    if (s.target != target) continue;
    const States st = random_states(s.make());
    Op op = Op::forward_dynamics;
    for (Op o : kOps) {
      if (op_text == op_name(o)) op = o;
    }
    Workload w;
    std::unique_ptr<Peer> peer;
    if (library == "symdyn_emitted") w = s.workload(op, st);
    if (library == "symdyn_system") w = system_workload(s, st, op);
    for (const PeerFactory& f : peer_factories()) {
      if (library != f.id) continue;
      std::string why;
      peer = f.make(s.mechanism(), why);
      if (!peer) {
        fmt::print("{} cannot express {}: {}\n", library, target, why);
        return 3;
      }
      if (!peer->can(op)) {
        fmt::print("{} cannot compute {} of {}: {}\n", library, op_name(op), target, why);
        return 3;
      }
      w = peer_workload(*peer, op, st);
    }
    if (!w) break;
    // Warm outside counted_workload: callgrind collects every call of it.
    for (int k = 0; k < kStates; ++k) w(k);
    counted_workload(w, calls);
    fmt::print("{} {} {} calls {}\n", library, op_name(op), target, calls);
    return 0;
  }
  fmt::print(stderr, "unknown library or model '{}' '{}' (--list)\n", library, target);
  return 2;
}

std::vector<const SymdynModel*> selected(const std::vector<std::string>& names) {
  std::vector<const SymdynModel*> v;
  for (const SymdynModel& s : symdyn_models()) {
    if (names.empty() || std::find(names.begin(), names.end(), s.target) != names.end())
      v.push_back(&s);
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (!args.empty() && args[0] == "--list") {
      for (const SymdynModel& s : symdyn_models())
        fmt::print("model {} {}\n", s.target, s.make().nq());
      fmt::print("library symdyn_emitted\nlibrary symdyn_system\n");
      for (const PeerFactory& f : peer_factories()) fmt::print("library {}\n", f.id);
      for (Op op : kOps) fmt::print("op {}\n", op_name(op));
      return 0;
    }
    if (!args.empty() && args[0] == "--count") {
      if (args.size() < 4) {
        fmt::print(stderr, "usage: symdyn_bench_peers --count LIBRARY OP MODEL [CALLS]\n");
        return 2;
      }
      return count(args[1], args[2], args[3], args.size() > 4 ? std::stoi(args[4]) : 256);
    }
    if (!args.empty() && (args[0] == "verify" || args[0] == "time")) {
      const bool timing = args[0] == "time";
      int rounds = 21;
      double batch_ms = 2.0;
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
      for (const SymdynModel* s : selected(names)) {
        if (timing) {
          time_model(*s, rounds, batch_ms);
        } else {
          verify(*s, random_states(s->make()));
        }
        std::fflush(stdout);
      }
      return 0;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "symdyn_bench_peers: {}\n", e.what());
    return 1;
  }
  fmt::print(
      stderr,
      "usage: symdyn_bench_peers verify|time [--rounds R] [--batch-ms T] [MODEL...] | --count "
      "LIBRARY OP MODEL [CALLS] | --list\n");
  return 2;
}
