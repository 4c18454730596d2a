// The generator on random multibody systems (support/random_model.hpp,
// rapidcheck), with and without simplification: the interpreter over every
// program it would print computes what the references give. Positions against
// the 4x4 products, the equations of motion against the direct sums over
// bodies, every other output against the derivation without simplification
// (itself checked against the complex step and differences in qd:
// tests/model/random_models_test.cpp), relative motions relative to the
// references the generator chose (Model::with_shared_motions_relative).
#include <rapidcheck/catch.h>

#include <array>

#include "support/emitted_check.hpp"
#include "support/equations_checks.hpp"
#include "support/random_model.hpp"
#include <symdyn/codegen/generate.hpp>
#include <symdyn/symbolic/traversal.hpp>

using namespace symdyn;
using namespace symdyn::testing;

namespace {

// Everything an entry point may output, for one state, by array name.
class References {
 public:
  References(const model::Model& m, const model::Kinematics& k, const ModelState<double>& s)
      : m_(m), k_(k), bindings_(bind_state(m, k, s)), eval_(bindings_) {
    for (const auto& T : direct_transforms(m, bindings_)) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) R_4x4_.push_back(T(r, c));
      }
      for (int r = 0; r < 3; ++r) x_4x4_.push_back(T(r, 3));
    }
    const Equations e = equations_by_direct_sums(m, k, s);
    for (Eigen::Index j = 0; j < e.M.rows(); ++j) {
      for (Eigen::Index l = 0; l < e.M.cols(); ++l) M_.push_back(e.M(j, l));
      h_.push_back(e.h(j));
    }
    // tau = M·qdd + h; the forward dynamics' tau is the state's qdd (program_inputs).
    const Eigen::VectorXd qdd =
        Eigen::Map<const Eigen::VectorXd>(s.qdd.data(), Eigen::Index(s.qdd.size()));
    const Eigen::VectorXd tau = e.M * qdd + e.h, solved = e.M.ldlt().solve(qdd - e.h);
    tau_.assign(tau.data(), tau.data() + tau.size());
    // Only a well-conditioned M has a solution to compare to 1e-10 (random
    // models may turn two coordinates about one axis: M singular).
    const Eigen::VectorXd eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(e.M).eigenvalues();
    if (eigenvalues.size() > 0 && eigenvalues.minCoeff() > 1e-4 * eigenvalues.maxCoeff()) {
      solved_.assign(solved.data(), solved.data() + solved.size());
    }
  }

  // The forward dynamics has a solution to compare with.
  bool solvable() const { return !solved_.empty() || tau_.empty(); }

  // The outputs of entry point `f`, concatenated in its order.
  std::vector<double> outputs(const codegen::EmittedFunction& f) {
    std::vector<double> out;
    for (const auto& [array, size] : f.outputs) {
      const std::vector<double> values = named(f.name, array);
      out.insert(out.end(), values.begin(), values.end());
    }
    return out;
  }

 private:
  std::vector<double> named(const std::string& entry, const std::string& array) {
    if (array == "M") return M_;
    if (array == "h") return h_;
    if (array == "tau") return tau_;
    if (array == "qdd_solved") return solved_;
    if (array == "pivots") return {};  // checked by the emitted forward_dynamics (tests/models)
    if (entry == "positions") return array == "R" ? R_4x4_ : x_4x4_;
    if (entry == "joint_points") return joint_points(array == "anchor");
    std::vector<double> out;
    auto push = [&](const auto& expressions) {
      for (model::Expr e : expressions) out.push_back(eval_(e));
    };
    if (array == "p" || array == "pd" || array == "pdd") {
      for (const auto& p : k_.dependents)
        push(std::array{array == "p" ? p.value : array == "pd" ? p.rate : p.acceleration});
      return out;
    }
    const bool relative = entry.rfind("relative_", 0) == 0;
    // dynamics_positions and dynamics_velocities carry the partial velocities as dv, dw;
    // accelerations_partials and its relative form as dv_dqd, dw_dqd.
    const bool partials = entry.find("partial_velocities") != std::string::npos ||
                          (entry.rfind("dynamics_", 0) == 0 && (array == "dv" || array == "dw")) ||
                          array == "dv_dqd" || array == "dw_dqd";
    for (std::size_t i = 0; i < k_.bodies.size(); ++i) {
      const model::Motion& motion = relative ? k_.bodies[i].relative : k_.bodies[i];
      if (partials) {
        for (const model::Vec3& v : array.rfind("dv", 0) == 0 ? motion.dv_dqd : motion.dw_dqd)
          push(v);
      } else if (array == "mass") {
        push(std::array{m_.bodies()[i].mass()});
      } else if (array == "inertia") {
        push(m_.bodies()[i].inertia());
      } else if (array == "R") {
        push(motion.R);
      } else {
        push(array == "x"   ? motion.x
             : array == "v" ? motion.v
             : array == "w" ? motion.w
             : array == "a" ? motion.a
                            : motion.dw);
      }
    }
    return out;
  }

  const model::Model& m_;
  const model::Kinematics& k_;
  // Each step of a motion as a 4x4 matrix (Eigen's angle-axis rotation).
  Eigen::Matrix4d step_matrix(const model::Transform::Step& step) {
    Eigen::Matrix4d E = Eigen::Matrix4d::Identity();
    if (step.is_rotation) {
      const Eigen::Vector3d axis(step.axis[0].number().to_double(),
                                 step.axis[1].number().to_double(),
                                 step.axis[2].number().to_double());
      E.topLeftCorner<3, 3>() = Eigen::AngleAxisd(eval_(step.angle), axis).toRotationMatrix();
    } else {
      for (int k = 0; k < 3; ++k) E(k, 3) = eval_(step.displacement[k]);
    }
    return E;
  }

  // joint_points' joint (J from G, G's axes) or anchor (the frame before the
  // first step that moves, in the reference's) by products of the steps'
  // matrices: a step moves when it depends on a symbol other than a run-time
  // parameter; without one, both are the start of the motion.
  std::vector<double> joint_points(bool anchor) {
    std::vector<double> out;
    for (const model::Body& b : m_.bodies()) {
      const auto& steps = b.motion().steps();
      std::size_t first = steps.size(), last = 0;
      for (std::size_t k = 0; k < steps.size(); ++k) {
        const auto& st = steps[k];
        const std::vector<model::Expr> values =
            st.is_rotation
                ? std::vector<model::Expr>{st.angle}
                : std::vector<model::Expr>(st.displacement.begin(), st.displacement.end());
        for (const model::Expr x : symbolic::free_symbols(values)) {
          if (x.symbol_kind() == symbolic::SymbolKind::Parameter) continue;
          first = std::min(first, k);
          last = k + 1;
        }
      }
      if (last == 0) first = 0;
      Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
      for (std::size_t k = anchor ? 0 : last; k < (anchor ? first : steps.size()); ++k)
        T = T * step_matrix(steps[k]);
      const Eigen::Vector3d point = anchor ? Eigen::Vector3d(T.topRightCorner<3, 1>())
                                           : Eigen::Vector3d(T.inverse().topRightCorner<3, 1>());
      out.insert(out.end(), point.data(), point.data() + 3);
    }
    return out;
  }

  symbolic::Bindings<double> bindings_;
  symbolic::Evaluator<double> eval_;
  std::vector<double> R_4x4_, x_4x4_, M_, h_, tau_, solved_;
};

double largest_gap(const std::vector<double>& got, const std::vector<double>& want) {
  if (got.size() != want.size()) return INFINITY;
  double worst = 0.0, scale = 1.0;
  for (double w : want) scale = std::max(scale, std::abs(w));
  for (std::size_t i = 0; i < got.size(); ++i) {
    const double gap = std::abs(got[i] - want[i]);
    worst = std::isnan(gap) ? INFINITY : std::max(worst, gap);
  }
  return worst / scale;
}

}  // namespace

TEST_CASE("programs generated for random models compute the references", "[codegen][random]") {
  rc::prop("every entry point", [] {
    RandomModel random;
    const model::Model m = random.build();
    codegen::Options options;
    options.simplify = *rc::gen::arbitrary<bool>();
    options.dynamics = codegen::DynamicsMethod::recursive;  // forward_dynamics wherever it applies
    RC_LOG() << random.description() << "simplify=" << options.simplify << "\n";
    const codegen::GeneratedCode code = codegen::generate(m, "default", "random", options);
    const model::Model shared = m.with_shared_motions_relative();
    const model::Kinematics k = derive_for_test(shared, false, true);
    for (const auto& s : random_states(m, *rc::gen::arbitrary<unsigned>())) {
      References references(shared, k, s);
      for (const auto& f : code.functions) {
        if (f.name == "forward_dynamics")
          continue;  // forward_dynamics_pivots' program and a check of its pivots
        RC_ASSERT(f.program.has_value());
        std::vector<double> got = f.program->evaluate<double>(program_inputs(f, s, {}));
        if (f.name == "forward_dynamics_pivots")
          got.resize(references.solvable() ? m.coordinates().size()
                                           : 0);  // qdd, without the pivots
        Gap gap;
        gap.add(largest_gap(got, references.outputs(f)), f.name);
        assert_gap(gap, 1e-10, "entry point");
      }
    }
  });
}
