#pragma once
// Checks of an emitted struct G (docs/emitted_interface.md), compiled at build
// time by symdyn_add_model, against its model derived afresh in process:
// the DAG evaluated directly, the interpreter over the very programs that were
// printed, and a numerical assembly of the equations of motion. Catch2 checks;
// include from test sources only.

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "support/model_eval.hpp"
#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/kinematics.hpp>

namespace symdyn::testing {

// Largest |a_i - b_i| / max(1, |b_i|).
inline double gap(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]) / std::max(1.0, std::abs(b[i])));
  }
  return worst;
}

// Everything the emitted functions compute at one state.
template <class G>
struct Emitted {
  std::vector<double> R = std::vector<double>(G::nbody * 9), x = std::vector<double>(G::nbody * 3),
                      v = x, w = x, a = x, dw = x;
  std::vector<double> dv = std::vector<double>(G::nbody * G::nq * 3), dwp = dv;
  std::vector<double> M = std::vector<double>(G::nq * G::nq), h = std::vector<double>(G::nq);

  explicit Emitted(const ModelState<double>& s) {
    const double* param = G::param_defaults;
    G::accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), param, R.data(), x.data(),
                     v.data(), w.data(), a.data(), dw.data());
    G::partial_velocities(s.t, s.q.data(), param, dv.data(), dwp.data());
    if constexpr (G::has_equations_of_motion) {
      G::mass_matrix(s.t, s.q.data(), param, M.data());
      G::bias_forces(s.t, s.q.data(), s.qd.data(), param, h.data());
    }
  }
};

// Output arrays for the emitted entry points of G, zeroed when made: kept
// for one entry point and called again at other states, they must give what
// fresh ones give (the structural zeros of a sparse output stay zero, and
// nothing else depends on what a call finds there).
template <class G>
struct EntryBuffers {
  std::vector<double> R = std::vector<double>(G::nbody * 9), x = std::vector<double>(G::nbody * 3),
                      v = x, w = x, a = x, dw = x, joint = x, anchor = x;
  std::vector<double> dv = std::vector<double>(G::nbody * G::nq * 3), dwp = dv, dv_dq = dv,
                      dw_dq = dv;
  std::vector<double> ddv = std::vector<double>(G::nbody * G::nq * G::nq * 3), ddw = ddv;
  std::vector<double> M = std::vector<double>(G::nq * G::nq), h = std::vector<double>(G::nq),
                      dq = M, dqd = M, dqdd = M, pivots = std::vector<double>(2 * G::nq);
  std::vector<double> mass = std::vector<double>(G::nbody),
                      inertia = std::vector<double>(G::nbody * 9),
                      dep = std::vector<double>(G::ndep > 0 ? G::ndep : 1), dep_d = dep,
                      dep_dd = dep;

  // The outputs of the emitted entry point `name`, concatenated in declaration order.
  std::vector<double> call(const std::string& name, const ModelState<double>& s);
};

template <class G>
std::vector<double> EntryBuffers<G>::call(const std::string& name, const ModelState<double>& s) {
  const double* p = G::param_defaults;
  std::vector<double> out;
  auto take = [&out](std::initializer_list<const std::vector<double>*> arrays) {
    for (const auto* a : arrays) out.insert(out.end(), a->begin(), a->end());
  };
  if (name == "inertia") G::inertia(p, mass.data(), inertia.data()), take({&mass, &inertia});
  if (name == "joint_points") {
    G::joint_points(p, joint.data(), anchor.data()), take({&joint, &anchor});
  }
  if (name == "positions") G::positions(s.t, s.q.data(), p, R.data(), x.data()), take({&R, &x});
  if (name == "velocities") {
    G::velocities(s.t, s.q.data(), s.qd.data(), p, R.data(), x.data(), v.data(), w.data());
    take({&R, &x, &v, &w});
  }
  if (name == "accelerations") {
    G::accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, R.data(), x.data(), v.data(),
                     w.data(), a.data(), dw.data());
    take({&R, &x, &v, &w, &a, &dw});
  }
  if (name == "relative_accelerations") {
    G::relative_accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, R.data(), x.data(),
                              v.data(), w.data(), a.data(), dw.data());
    take({&R, &x, &v, &w, &a, &dw});
  }
  if (name == "partial_velocities")
    G::partial_velocities(s.t, s.q.data(), p, dv.data(), dwp.data()), take({&dv, &dwp});
  if constexpr (requires { G::relative_partial_velocities; }) {
    if (name == "relative_partial_velocities") {
      G::relative_partial_velocities(s.t, s.q.data(), p, dv.data(), dwp.data());
      take({&dv, &dwp});
    }
  }
  if constexpr (requires { G::accelerations_partials; }) {
    if (name == "accelerations_partials") {
      G::accelerations_partials(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, R.data(), x.data(),
                                v.data(), w.data(), a.data(), dw.data(), dv.data(), dwp.data());
      take({&R, &x, &v, &w, &a, &dw, &dv, &dwp});
    }
    if (name == "relative_accelerations_partials") {
      G::relative_accelerations_partials(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, R.data(),
                                         x.data(), v.data(), w.data(), a.data(), dw.data(),
                                         dv.data(), dwp.data());
      take({&R, &x, &v, &w, &a, &dw, &dv, &dwp});
    }
  }
  if (name == "dependent_parameters") {
    G::dependent_parameters(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, dep.data(), dep_d.data(),
                            dep_dd.data());
    out.insert(out.end(), dep.begin(), dep.begin() + G::ndep);
    out.insert(out.end(), dep_d.begin(), dep_d.begin() + G::ndep);
    out.insert(out.end(), dep_dd.begin(), dep_dd.begin() + G::ndep);
  }
  if constexpr (G::has_equations_of_motion) {
    if (name == "mass_matrix") G::mass_matrix(s.t, s.q.data(), p, M.data()), take({&M});
    if (name == "bias_forces")
      G::bias_forces(s.t, s.q.data(), s.qd.data(), p, h.data()), take({&h});
    if (name == "dynamics")
      G::dynamics(s.t, s.q.data(), s.qd.data(), p, M.data(), h.data()), take({&M, &h});
    if constexpr (requires { G::inverse_dynamics; }) {
      if (name == "inverse_dynamics")
        G::inverse_dynamics(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, h.data()), take({&h});
    }
    if constexpr (requires { G::inverse_dynamics_derivatives; }) {
      if (name == "inverse_dynamics_derivatives") {
        G::inverse_dynamics_derivatives(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, dq.data(),
                                        dqd.data());
        take({&dq, &dqd});
      }
    }
    if constexpr (requires { G::inverse_dynamics_jacobians; }) {
      if (name == "inverse_dynamics_jacobians") {
        G::inverse_dynamics_jacobians(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, dq.data(),
                                      dqd.data(), dqdd.data());
        take({&dq, &dqd, &dqdd});
      }
    }
    if constexpr (requires { G::kinematics_derivatives; }) {
      if (name == "kinematics_derivatives") {
        G::kinematics_derivatives(s.t, s.q.data(), s.qd.data(), p, dv_dq.data(), dw_dq.data(),
                                  ddv.data(), ddw.data());
        take({&dv_dq, &dw_dq, &ddv, &ddw});
      }
    }
    // The generalized forces tau of a state are its qdd (program_inputs).
    if constexpr (requires { G::forward_dynamics_pivots; }) {
      if (name == "forward_dynamics_pivots") {
        G::forward_dynamics_pivots(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, h.data(),
                                   pivots.data());
        take({&h, &pivots});
      }
    }
    if constexpr (requires { G::dynamics_velocities; }) {
      if (name == "dynamics_positions") {
        G::dynamics_positions(s.t, s.q.data(), s.qd.data(), p, M.data(), h.data(), R.data(),
                              x.data(), dv.data(), dwp.data());
        take({&M, &h, &R, &x, &dv, &dwp});
      }
      if (name == "dynamics_velocities") {
        G::dynamics_velocities(s.t, s.q.data(), s.qd.data(), p, M.data(), h.data(), R.data(),
                               x.data(), v.data(), w.data(), dv.data(), dwp.data());
        take({&M, &h, &R, &x, &v, &w, &dv, &dwp});
      }
    }
  }
  return out;
}

// The outputs of the emitted entry point `name` into fresh (zeroed) arrays.
template <class G>
std::vector<double> call_entry(const std::string& name, const ModelState<double>& s) {
  return EntryBuffers<G>().call(name, s);
}

// The inputs of an emitted function's program at a state, in its order.
inline std::vector<double> program_inputs(const codegen::EmittedFunction& f,
                                          const ModelState<double>& s,
                                          std::span<const double> param) {
  std::vector<double> in;
  for (const std::string& array : f.inputs) {
    if (array == "t") in.push_back(s.t);
    if (array == "q") in.insert(in.end(), s.q.begin(), s.q.end());
    if (array == "qd") in.insert(in.end(), s.qd.begin(), s.qd.end());
    if (array == "qdd" || array == "tau") in.insert(in.end(), s.qdd.begin(), s.qdd.end());
    if (array == "param") in.insert(in.end(), param.begin(), param.end());
  }
  return in;
}

struct EmittedSetup {
  std::string name, variant;
  codegen::Options options;  // those G was generated with
  int trials = 20;           // random states
  double amplitude = 1.0;    // of q around the initial configuration (random_state_near)
  // Also run the interpreter over the printed programs: this generates the
  // model again in process, which costs the model's generation time.
  bool interpreter = true;
};

// Checks one generated struct G against its model, derived afresh without
// simplification, with the references the generator gives bodies that share
// a motion (Model::with_shared_motions_relative): the emitted relative motions
// are relative to G::reference_body.
template <class G>
void check_emitted(const EmittedSetup& setup) {
  const model::Model m =
      model::find_definition(setup.name).make(setup.variant).with_shared_motions_relative();
  const std::vector<int> references = m.reference_indices();
  CHECK(std::equal(references.begin(), references.end(), G::reference_body));
  model::DeriveOptions derive;
  derive.symbolic_partials = true;
  const model::Kinematics k = model::derive_kinematics(m, derive);
  std::optional<codegen::GeneratedCode> code;
  if (setup.interpreter) code = codegen::generate(m, setup.variant, "x", setup.options);
  const std::vector<codegen::EmittedFunction> none;
  const std::vector<codegen::EmittedFunction>& functions = code ? code->functions : none;
  std::mt19937 rng(5);
  // Every entry point's arrays, kept from trial to trial.
  std::map<std::string_view, EntryBuffers<G>> kept;
  for (int trial = 0; trial < setup.trials; ++trial) {
    const auto s = random_state_near(rng, m, setup.amplitude);
    // Called again on the arrays of the previous states, each entry point gives what it gives
    // on fresh ones: nothing stale survives (docs/emitted_interface.md, sparse outputs).
    for (const std::string_view name : codegen::detail::entry_point_names()) {
      INFO("entry point " << name << " on kept arrays");
      CHECK(kept[name].call(std::string(name), s) == call_entry<G>(std::string(name), s));
    }
    const Emitted<G> e(s);
    const auto b = bind_state(m, k, s);
    symbolic::Evaluator<double> eval(b);
    // Against the DAG evaluated directly.
    std::vector<double> R, x, v, w, a, dw, dv, dwp;
    for (const auto& body : k.bodies) {
      for (auto r : body.R) R.push_back(eval(r));
      auto push = [&](std::vector<double>& out, const model::Vec3& vec) {
        for (auto c : vec) out.push_back(eval(c));
      };
      push(x, body.x), push(v, body.v), push(w, body.w), push(a, body.a), push(dw, body.dw);
      for (std::size_t j = 0; j < G::nq; ++j) push(dv, body.dv_dqd[j]), push(dwp, body.dw_dqd[j]);
    }
    CHECK(gap(e.R, R) < 1e-12);
    CHECK(gap(e.x, x) < 1e-12);
    CHECK(gap(e.v, v) < 1e-12);
    CHECK(gap(e.w, w) < 1e-12);
    CHECK(gap(e.a, a) < 1e-12);
    CHECK(gap(e.dw, dw) < 1e-12);
    CHECK(gap(e.dv, dv) < 1e-12);
    CHECK(gap(e.dwp, dwp) < 1e-12);
    // The relative motions likewise.
    std::vector<double> relative;
    for (const auto& body : k.bodies) {
      const model::Motion& r = body.relative;
      for (auto c : r.R) relative.push_back(eval(c));
    }
    for (auto field : {&model::Motion::x, &model::Motion::v, &model::Motion::w, &model::Motion::a,
                       &model::Motion::dw}) {
      for (const auto& body : k.bodies) {
        for (auto c : body.relative.*field) relative.push_back(eval(c));
      }
    }
    CHECK(gap(call_entry<G>("relative_accelerations", s), relative) < 1e-12);
    // The fused entry points give exactly what the separate ones give.
    const auto separate = [&](std::initializer_list<const char*> entries) {
      std::vector<double> out;
      for (const char* e : entries) {
        const std::vector<double> part = call_entry<G>(e, s);
        out.insert(out.end(), part.begin(), part.end());
      }
      return out;
    };
    if constexpr (requires { G::accelerations_partials; }) {
      CHECK(gap(call_entry<G>("accelerations_partials", s),
                separate({"accelerations", "partial_velocities"})) < 1e-14);
      CHECK(gap(call_entry<G>("relative_accelerations_partials", s),
                separate({"relative_accelerations", "relative_partial_velocities"})) < 1e-14);
    }
    if constexpr (requires { G::inverse_dynamics_jacobians; }) {
      // Its dtau_dq and dtau_dqd are inverse_dynamics_derivatives', its M mass_matrix's: the
      // recursive derivatives' S_k·P_i against the mass matrix's own expressions.
      CHECK(gap(call_entry<G>("inverse_dynamics_jacobians", s),
                separate({"inverse_dynamics_derivatives", "mass_matrix"})) < 1e-12);
    }
    if constexpr (G::has_equations_of_motion) {
      CHECK(gap(call_entry<G>("dynamics", s), separate({"mass_matrix", "bias_forces"})) < 1e-14);
      if constexpr (requires { G::dynamics_velocities; }) {
        std::vector<double> velocities = call_entry<G>("velocities", s);
        const std::vector<double> partials = call_entry<G>("partial_velocities", s);
        velocities.insert(velocities.end(), partials.begin(), partials.end());
        const std::vector<double> mh = separate({"mass_matrix", "bias_forces"});
        std::vector<double> expected = mh;
        expected.insert(expected.end(), velocities.begin(), velocities.end());
        CHECK(gap(call_entry<G>("dynamics_velocities", s), expected) < 1e-14);
        // R and x are the first 12 nbody entries of velocities' R, x, v, w.
        expected = mh;
        expected.insert(expected.end(), velocities.begin(), velocities.begin() + 12 * G::nbody);
        expected.insert(expected.end(), partials.begin(), partials.end());
        CHECK(gap(call_entry<G>("dynamics_positions", s), expected) < 1e-14);
      }
    }
    // Against the interpreter over the printed program, entry point by entry point.
    for (const auto& f : functions) {
      if (!f.program) continue;
      INFO("entry point " << f.name);
      const std::vector<double> in =
          program_inputs(f, s, {G::param_defaults, G::param_defaults + G::nparam});
      const double worst = gap(call_entry<G>(f.name, s), f.program->evaluate<double>(in));
      INFO("gap " << worst);
      // The derivatives' long sums of products, printed as shared parts, differ from the
      // interpreter's by tens of ulps (chain_8: 1.2e-14).
      const bool derivatives =
          f.name.ends_with("_derivatives") || f.name == "inverse_dynamics_jacobians";
      CHECK(worst < (derivatives ? 1e-13 : 1e-14));
    }
    if constexpr (G::has_equations_of_motion) {
      // M·qdd + h against the residual assembled numerically in the global frame:
      // f_j = Σ (m a - m g)·dv_ij + (J dw + w × J w)·dw_ij, J = R I Rᵀ.
      std::vector<double> mass(G::nbody), inertia(G::nbody * 9);
      G::inertia(G::param_defaults, mass.data(), inertia.data());
      Eigen::VectorXd f = Eigen::VectorXd::Zero(G::nq);
      for (int i = 0; i < G::nbody; ++i) {
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Ri(&e.R[9 * i]),
            Ii(&inertia[9 * i]);
        const Eigen::Matrix3d J = Ri * Ii * Ri.transpose();
        const Eigen::Vector3d ai(&e.a[3 * i]), wi(&e.w[3 * i]), dwi(&e.dw[3 * i]), g(G::gravity);
        const Eigen::Vector3d force = mass[i] * (ai - g);
        const Eigen::Vector3d moment = J * dwi + wi.cross(J * wi);
        for (int j = 0; j < G::nq; ++j) {
          f[j] += force.dot(Eigen::Vector3d(&e.dv[3 * (i * G::nq + j)])) +
                  moment.dot(Eigen::Vector3d(&e.dwp[3 * (i * G::nq + j)]));
        }
      }
      const Eigen::Map<const Eigen::Matrix<double, G::nq, G::nq, Eigen::RowMajor>> M(e.M.data());
      const Eigen::Map<const Eigen::Matrix<double, G::nq, 1>> qdd(s.qdd.data()), h(e.h.data());
      const Eigen::VectorXd lhs = M * qdd + h;
      CHECK((lhs - f).cwiseAbs().maxCoeff() < 1e-10 * std::max(1.0, f.cwiseAbs().maxCoeff()));
      CHECK((M - M.transpose()).cwiseAbs().maxCoeff() == 0.0);
      CHECK(Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd(M)).info() == Eigen::Success);
    }
  }
}

}  // namespace symdyn::testing
