// The emitted C++, compiled at build time by symdyn_add_model (models/CMakeLists.txt),
// against the interpreter over the very programs it prints, against the DAG
// evaluated directly, and against a numerical assembly of the equations of motion.
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include "codegen/generate.hpp"
#include "double_pendulum_absolute.hpp"
#include "double_pendulum_absolute_case1.hpp"
#include "double_pendulum_relative.hpp"
#include "model/kinematics.hpp"
#include "slider_crank_dependent.hpp"
#include "slider_crank_inline.hpp"
#include "slider_crank_inline_case1.hpp"
#include "support/model_eval.hpp"

using namespace symdyn;
using namespace symdyn::testing;
using Catch::Matchers::Contains;

namespace {

double gap(const std::vector<double>& a, const std::vector<double>& b) {
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
    G::accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), param, R.data(), x.data(), v.data(), w.data(),
                     a.data(), dw.data());
    G::partial_velocities(s.t, s.q.data(), param, dv.data(), dwp.data());
    if constexpr (G::has_equations_of_motion) {
      G::mass_matrix(s.t, s.q.data(), param, M.data());
      G::bias_forces(s.t, s.q.data(), s.qd.data(), param, h.data());
    }
  }
};

// The outputs of the emitted entry point `name`, concatenated in declaration order.
template <class G>
std::vector<double> call_entry(const std::string& name, const ModelState<double>& s) {
  const double* p = G::param_defaults;
  std::vector<double> out;
  auto take = [&out](std::initializer_list<const std::vector<double>*> arrays) {
    for (const auto* a : arrays) out.insert(out.end(), a->begin(), a->end());
  };
  std::vector<double> R(G::nbody * 9), x(G::nbody * 3), v(x), w(x), a(x), dw(x);
  std::vector<double> dv(G::nbody * G::nq * 3), dwp(dv), M(G::nq * G::nq), h(G::nq);
  std::vector<double> mass(G::nbody), inertia(G::nbody * 9), dep(G::ndep > 0 ? G::ndep : 1), dep_d(dep), dep_dd(dep);
  if (name == "inertia") G::inertia(p, mass.data(), inertia.data()), take({&mass, &inertia});
  if (name == "positions") G::positions(s.t, s.q.data(), p, R.data(), x.data()), take({&R, &x});
  if (name == "velocities") {
    G::velocities(s.t, s.q.data(), s.qd.data(), p, R.data(), x.data(), v.data(), w.data());
    take({&R, &x, &v, &w});
  }
  if (name == "accelerations") {
    G::accelerations(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, R.data(), x.data(), v.data(), w.data(), a.data(),
                     dw.data());
    take({&R, &x, &v, &w, &a, &dw});
  }
  if (name == "partial_velocities") G::partial_velocities(s.t, s.q.data(), p, dv.data(), dwp.data()), take({&dv, &dwp});
  if (name == "dependent_parameters") {
    G::dependent_parameters(s.t, s.q.data(), s.qd.data(), s.qdd.data(), p, dep.data(), dep_d.data(), dep_dd.data());
    for (auto* d : {&dep, &dep_d, &dep_dd}) d->resize(G::ndep);
    take({&dep, &dep_d, &dep_dd});
  }
  if constexpr (G::has_equations_of_motion) {
    if (name == "mass_matrix") G::mass_matrix(s.t, s.q.data(), p, M.data()), take({&M});
    if (name == "bias_forces") G::bias_forces(s.t, s.q.data(), s.qd.data(), p, h.data()), take({&h});
  }
  return out;
}

struct Setup {
  std::string name, variant;
  codegen::Options options;
};

// Checks one generated struct G against its model, derived afresh without simplification.
template <class G>
void check_emitted(const Setup& setup) {
  const model::Model m = model::find_definition(setup.name).make(setup.variant);
  model::DeriveOptions derive;
  derive.symbolic_partials = true;
  const model::Kinematics k = model::derive_kinematics(m, derive);
  const codegen::GeneratedCode code = codegen::generate(m, setup.variant, "x", setup.options);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const auto s = random_state(rng, G::nq);
    const Emitted<G> e(s);
    const auto b = bind_state(m, k, s);
    // Against the DAG evaluated directly.
    std::vector<double> R, x, v, w, a, dw, dv, dwp;
    for (const auto& body : k.bodies) {
      for (auto r : body.R) R.push_back(symbolic::evaluate(r, b));
      auto push = [&](std::vector<double>& out, const model::Vec3& vec) {
        for (auto c : vec) out.push_back(symbolic::evaluate(c, b));
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
    // Against the interpreter over the printed program, entry point by entry point.
    for (const auto& f : code.functions) {
      if (!f.program) continue;
      INFO("entry point " << f.name);
      std::vector<double> in;
      for (const std::string& arr : f.inputs) {
        if (arr == "t") in.push_back(s.t);
        if (arr == "q") in.insert(in.end(), s.q.begin(), s.q.end());
        if (arr == "qd") in.insert(in.end(), s.qd.begin(), s.qd.end());
        if (arr == "qdd") in.insert(in.end(), s.qdd.begin(), s.qdd.end());
        if (arr == "param") in.insert(in.end(), G::param_defaults, G::param_defaults + G::nparam);
      }
      CHECK(gap(call_entry<G>(f.name, s), f.program->evaluate<double>(in)) < 1e-14);
    }
    if constexpr (G::has_equations_of_motion) {
      // M·qdd + h against the residual assembled numerically in the global frame:
      // f_j = Σ (m a - m g)·dv_ij + (J dw + w × J w)·dw_ij, J = R I Rᵀ.
      std::vector<double> mass(G::nbody), inertia(G::nbody * 9);
      G::inertia(G::param_defaults, mass.data(), inertia.data());
      Eigen::VectorXd f = Eigen::VectorXd::Zero(G::nq);
      for (int i = 0; i < G::nbody; ++i) {
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Ri(&e.R[9 * i]), Ii(&inertia[9 * i]);
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

codegen::Options case1() {
  codegen::Options o;
  o.simplify = false;
  o.symbolic_partials = false;
  o.equations_of_motion = false;
  return o;
}

}  // namespace

TEST_CASE("emitted double pendulum (absolute) matches the DAG, the interpreter and the assembled residual", "[codegen]") {
  check_emitted<symdyn_generated::double_pendulum_absolute>({"double_pendulum", "absolute", {}});
}
TEST_CASE("emitted double pendulum (relative) matches", "[codegen]") {
  check_emitted<symdyn_generated::double_pendulum_relative>({"double_pendulum", "relative", {}});
}
TEST_CASE("emitted slider-crank (inline) matches", "[codegen]") {
  check_emitted<symdyn_generated::slider_crank_inline>({"slider_crank", "inline", {}});
}
TEST_CASE("emitted slider-crank (dependent) matches", "[codegen]") {
  check_emitted<symdyn_generated::slider_crank_dependent>({"slider_crank", "dependent", {}});
}
TEST_CASE("emitted case 1 (numeric partial velocities, no simplification) matches", "[codegen]") {
  check_emitted<symdyn_generated::double_pendulum_absolute_case1>({"double_pendulum", "absolute", case1()});
  check_emitted<symdyn_generated::slider_crank_inline_case1>({"slider_crank", "inline", case1()});
}

TEST_CASE("emitted dependent parameters are the slider-crank's alpha and x", "[codegen]") {
  using G = symdyn_generated::slider_crank_dependent;
  STATIC_REQUIRE(G::ndep == 2);
  const double q = 0.7, qd = 1.3, qdd = -0.4;
  double p[2], pd[2], pdd[2];
  G::dependent_parameters(0.0, &q, &qd, &qdd, G::param_defaults, p, pd, pdd);
  const double alpha = std::asin(0.1 * std::sin(q) / 0.3);
  CHECK(p[0] == Approx(alpha).epsilon(1e-14));
  CHECK(p[1] == Approx(0.1 * std::cos(q) + 0.3 * std::cos(alpha)).epsilon(1e-14));
  // d alpha/dt = l1 cos(q) qd / (l2 cos(alpha))
  CHECK(pd[0] == Approx(0.1 * std::cos(q) * qd / (0.3 * std::cos(alpha))).epsilon(1e-13));
}

TEST_CASE("generation is deterministic", "[codegen]") {
  for (const auto& d : model::registry()) {
    for (const auto& variant : d.variants) {
      std::string first;
      for (int run = 0; run < 2; ++run) {
        symbolic::Context context;  // fresh nodes, fresh addresses
        symbolic::Context::Scope scope(context);
        const model::Model m = d.make(variant);
        const auto code = codegen::generate(m, variant, "x");
        if (run == 0) first = code.header + code.source;
        INFO(d.name << " " << variant);
        CHECK(code.header + code.source == first);
      }
    }
  }
}

TEST_CASE("each entry point computes only what it needs", "[codegen]") {
  const model::Model m = model::find_definition("slider_crank").make("dependent");
  const auto code = codegen::generate(m, "dependent", "x");
  for (const auto& f : code.functions) {
    if (f.name == "positions") {
      const auto& positions = f.operations;
      for (const auto& g : code.functions) {
        if (g.name == "velocities") CHECK(positions.total() < g.operations.total());
      }
    }
  }
  // positions() takes no rate: its signature has no qd.
  CHECK_THAT(code.header, Contains("static void positions(double t, const double* q, const double* param, double* R, double* x);"));
}

TEST_CASE("run-time parameters are inputs of the emitted programs", "[codegen]") {
  model::Model m("swing");
  const model::Expr q0 = m.coordinate("q0");
  const model::Expr length = m.parameter("length", 1.0, true);
  m.body("bob").mass(2.0).inertia(0.01, 0.01, 0.01).motion(model::Trotz(q0) * model::Tdisp(length, 0, 0));
  const auto code = codegen::generate(m, "default", "swing");
  CHECK_THAT(code.header, Contains("static constexpr const char* param_names[1] = {\"length\"};"));
  for (const auto& f : code.functions) {
    if (f.name != "positions") continue;
    // inputs: t, q0, length; outputs: R (9), x (3)
    const std::vector<double> out = f.program->evaluate<double>(std::vector<double>{0.0, 0.4, 2.5});
    CHECK(out[9] == Approx(2.5 * std::cos(0.4)).epsilon(1e-15));
    CHECK(out[10] == Approx(2.5 * std::sin(0.4)).epsilon(1e-15));
  }
}
