// The emitted code of every reference model: against the DAG evaluated
// directly, the interpreter over the printed programs and the equations of
// motion assembled numerically (support/emitted_check.hpp); and the variants
// of a model against each other.
#include <catch2/catch.hpp>
#include <random>

#include "generated.hpp"
#include "support/emitted_check.hpp"
#include "test_plan.hpp"

using namespace symdyn;
using namespace symdyn::testing;
namespace gen = symdyn_generated;

namespace {

template <class G>
void check_against_model() {
  const TestPlan plan = test_plan(G::model);
  INFO(G::model << " " << G::variant);
  EmittedSetup setup{G::model, G::variant, {}};
  // As generated (DERIVATIVES): the program shares them.
  if (G::has_inverse_dynamics_derivatives) setup.options.derivatives = codegen::Derivatives::all;
  setup.trials = std::max(2, plan.states);
  setup.amplitude = plan.amplitude;
  // amru5's generation takes seconds; its printed programs
  // are checked against the interpreter on the smaller models.
  setup.interpreter = std::string_view(G::model) != "amru5";
  check_emitted<G>(setup);
}

// Two variants of one mechanism give the same kinematics, partial velocities
// and equations of motion at random states.
template <class A, class B>
void check_variants_agree() {
  STATIC_REQUIRE(A::nq == B::nq);
  STATIC_REQUIRE(A::nbody == B::nbody);
  const TestPlan plan = test_plan(A::model);
  INFO(A::model << ": " << A::variant << " against " << B::variant);
  std::mt19937 rng(9);
  for (int trial = 0; trial < 10; ++trial) {
    const auto s = random_state_near(rng, A::q_initial, plan.amplitude);
    const Emitted<A> a(s);
    const Emitted<B> b(s);
    CHECK(gap(a.R, b.R) < 1e-10);
    CHECK(gap(a.x, b.x) < 1e-10);
    CHECK(gap(a.v, b.v) < 1e-10);
    CHECK(gap(a.w, b.w) < 1e-10);
    CHECK(gap(a.a, b.a) < 1e-10);
    CHECK(gap(a.dw, b.dw) < 1e-10);
    CHECK(gap(a.dv, b.dv) < 1e-10);
    CHECK(gap(a.dwp, b.dwp) < 1e-10);
    CHECK(gap(a.M, b.M) < 1e-10);
    CHECK(gap(a.h, b.h) < 1e-10);
  }
}

}  // namespace

TEST_CASE("emitted robot3d matches its model", "[models]") {
  check_against_model<gen::robot3d_absolute>();
  check_against_model<gen::robot3d_relative>();
}
TEST_CASE("emitted trike matches its model", "[models]") {
  check_against_model<gen::trike>();
}
TEST_CASE("emitted amru5 (inline) matches its model", "[models]") {
  check_against_model<gen::amru5_inline>();
}
TEST_CASE("emitted amru5 (dependent) matches its model", "[models]") {
  check_against_model<gen::amru5_dependent>();
}
TEST_CASE("emitted hexapod_tree matches its model", "[models]") {
  check_against_model<gen::hexapod_tree>();
}
TEST_CASE("emitted chain_N matches its model", "[models]") {
  check_against_model<gen::chain_2_relative>();
  check_against_model<gen::chain_2_absolute>();
  check_against_model<gen::chain_4_relative>();
  check_against_model<gen::chain_4_absolute>();
  check_against_model<gen::chain_8_relative>();
  check_against_model<gen::chain_8_absolute>();
}
TEST_CASE("emitted chain_16 matches its model", "[models]") {
  check_against_model<gen::chain_16_relative>();
  check_against_model<gen::chain_16_absolute>();
}

TEST_CASE("variants agree: double_pendulum absolute and relative", "[models]") {
  check_variants_agree<gen::double_pendulum_absolute, gen::double_pendulum_relative>();
}
TEST_CASE("variants agree: robot3d absolute and relative", "[models]") {
  check_variants_agree<gen::robot3d_absolute, gen::robot3d_relative>();
}
TEST_CASE("variants agree: slider_crank inline and dependent", "[models]") {
  check_variants_agree<gen::slider_crank_inline, gen::slider_crank_dependent>();
}
TEST_CASE("variants agree: amru5 inline and dependent", "[models]") {
  check_variants_agree<gen::amru5_inline, gen::amru5_dependent>();
}
TEST_CASE("variants agree: chain_N relative and absolute", "[models]") {
  check_variants_agree<gen::chain_2_relative, gen::chain_2_absolute>();
  check_variants_agree<gen::chain_4_relative, gen::chain_4_absolute>();
  check_variants_agree<gen::chain_8_relative, gen::chain_8_absolute>();
  check_variants_agree<gen::chain_16_relative, gen::chain_16_absolute>();
}

// The trike's chassis is free: M_00 = Σ m_i·|R_i's first column|² is its
// total mass, M_01 = Σ m_i·(columns 1 and 2 of R_i) is 0. Expanded and
// reduced modulo sin² + cos² = 1 (symbolic/trig_polynomial.hpp), the emitted
// entries are those constants, not sums that evaluate to them to rounding.
TEST_CASE("emitted trike: M_00 is the total mass, M_01 exactly 0", "[models]") {
  using T = gen::trike;
  double mass[T::nbody], inertia[T::nbody * 9];
  T::inertia(T::param_defaults, mass, inertia);
  double total = 0;
  for (double m : mass) total += m;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 20; ++trial) {
    double q[T::nq], M[T::nq * T::nq];
    for (double& x : q) x = u(rng);
    T::mass_matrix(u(rng), q, T::param_defaults, M);
    CHECK(M[0] == Approx(total).epsilon(1e-15));
    CHECK(M[1] == 0.0);
    CHECK(M[T::nq] == 0.0);
    CHECK(M[T::nq + 1] == Approx(total).epsilon(1e-15));
  }
}
