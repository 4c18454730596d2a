// Differentiation, total time derivative and substitution, checked against
// numbers computed independently of the engine's calculus: complex step and
// central differences on the evaluated DAG, closed forms written by hand, and
// a numerical 4x4 product for the chain model.
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <random>

#include "support/chain_model.hpp"
#include "support/dag_size.hpp"
#include "support/random_expr.hpp"
#include <symdyn/symbolic/diff.hpp>
#include <symdyn/symbolic/eval.hpp>

using namespace symdyn::symbolic;
using symdyn::testing::RandomExpr;
using Complex = std::complex<double>;

namespace {

constexpr int kCases = 3000;
constexpr int kDepth = 5;

// |a - b| within `rel` of the larger magnitude, with an absolute floor of `rel`
// (MuJoCo's RelativeError: values near zero are compared absolutely).
bool close(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::max({1.0, std::abs(a), std::abs(b)});
}

template <class S>
Bindings<S> bind_values(std::span<const Expr> symbols, std::span<const S> values) {
  Bindings<S> b;
  for (std::size_t i = 0; i < symbols.size(); ++i) b.emplace(symbols[i], values[i]);
  return b;
}

// d e/d symbols[k] at `point` by the complex step: Im f(x + ih)/h, exact to
// rounding since there is no subtraction.
double complex_step(Expr e, std::span<const Expr> symbols, std::span<const double> point,
                    std::size_t k) {
  constexpr double h = 1e-30;
  std::vector<Complex> z(point.begin(), point.end());
  z[k] += Complex(0.0, h);
  return evaluate(e, bind_values<Complex>(symbols, z)).imag() / h;
}

// d e/d symbols[k] at `point` by central differences with a relative step.
double central_difference(Expr e, std::span<const Expr> symbols, std::span<const double> point,
                          std::size_t k) {
  const double h = 1e-5 * std::max(1.0, std::abs(point[k]));
  std::vector<double> plus(point.begin(), point.end());
  std::vector<double> minus(point.begin(), point.end());
  plus[k] += h;
  minus[k] -= h;
  return (evaluate(e, bind_values<double>(symbols, plus)) -
          evaluate(e, bind_values<double>(symbols, minus))) /
         (2 * h);
}

double value_at(Expr e, Bindings<double> at) {
  return evaluate(e, at);
}

}  // namespace

// ---------------------------------------------------------------------------
// Properties over random expressions

TEST_CASE("diff matches the complex step and central differences", "[diff][property]") {
  for (unsigned seed = 0; seed < kCases; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    const std::vector<Expr> xs{symbol("x"), symbol("y"), symbol("z")};
    RandomExpr gen(seed, xs);
    const Expr e = gen(kDepth);
    const std::size_t k = gen.pick(xs.size());
    const Expr d = diff(e, xs[k]);
    const auto p = gen.point();
    const double value = evaluate(d, bind_values<double>(xs, p));
    const double cs = complex_step(e, xs, p, k);
    INFO("seed " << seed << "\ne = " << e << "\nd/d" << xs[k] << " = " << d << "\nvalue " << value
                 << ", complex step " << cs);
    REQUIRE(std::isfinite(cs));
    CHECK(close(value, cs, 1e-9));
    // Central differences: truncation and cancellation errors, a loose tolerance.
    const double fd = central_difference(e, xs, p, k);
    CHECK(close(value, fd, 1e-4));
  }
}

TEST_CASE("d/dx of an expression without x is exactly zero", "[diff][property]") {
  for (unsigned seed = 0; seed < kCases; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    const Expr x = symbol("x");
    RandomExpr gen(seed, {symbol("y"), symbol("z")});
    const Expr e = gen(kDepth);
    INFO("seed " << seed << ": " << e);
    CHECK(diff(e, x) == Expr(0));
  }
}

// Symbols q_i (Variable) and qd_i (Rate) move along
//   q(t) = q0 + qd0·t + qdd0·t²/2,  qd(t) = qd0 + qdd0·t,  qdd constant;
// t (Time) is itself; p (Parameter) and c (Free) are constant.
struct Path {
  std::vector<Expr> q, qd, qdd;
  Expr t, p, c;
  std::vector<double> q0, qd0, qdd0;
  double t0 = 0, p0 = 0, c0 = 0;

  std::vector<Expr> symbols() const {
    std::vector<Expr> s = q;
    s.insert(s.end(), qd.begin(), qd.end());
    s.push_back(t);
    s.push_back(p);
    s.push_back(c);
    return s;
  }
  RateMap rates() const {
    RateMap r;
    for (std::size_t i = 0; i < q.size(); ++i) {
      r.emplace(q[i], qd[i]);
      r.emplace(qd[i], qdd[i]);
      r.emplace(qdd[i], Expr(0));
    }
    return r;
  }
  // Every symbol bound to its value at time t0 + dt (dt may be complex).
  template <class S>
  Bindings<S> at(S dt) const {
    Bindings<S> b;
    for (std::size_t i = 0; i < q.size(); ++i) {
      b.emplace(q[i], S(q0[i]) + S(qd0[i]) * dt + S(qdd0[i]) * dt * dt / S(2));
      b.emplace(qd[i], S(qd0[i]) + S(qdd0[i]) * dt);
      b.emplace(qdd[i], S(qdd0[i]));
    }
    b.emplace(t, S(t0) + dt);
    b.emplace(p, S(p0));
    b.emplace(c, S(c0));
    return b;
  }
};

Path random_path(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Path path;
  for (int i = 0; i < 2; ++i) {
    path.q.push_back(symbol(fmt::format("q{}", i), SymbolKind::Variable));
    path.qd.push_back(symbol(fmt::format("qd{}", i), SymbolKind::Rate));
    path.qdd.push_back(symbol(fmt::format("qdd{}", i), SymbolKind::Acceleration));
    path.q0.push_back(u(rng));
    path.qd0.push_back(u(rng));
    path.qdd0.push_back(u(rng));
  }
  path.t = symbol("t", SymbolKind::Time);
  path.p = symbol("p", SymbolKind::Parameter);
  path.c = symbol("c", SymbolKind::Free);
  path.t0 = u(rng);
  path.p0 = u(rng);
  path.c0 = u(rng);
  return path;
}

// d/dt of e along the path at t0, by the complex step and by central differences.
std::pair<double, double> path_derivative(const Path& path, Expr e) {
  constexpr double h_cs = 1e-30;
  constexpr double h_fd = 1e-5;
  const double cs = evaluate(e, path.at<Complex>(Complex(0, h_cs))).imag() / h_cs;
  const double fd =
      (evaluate(e, path.at<double>(h_fd)) - evaluate(e, path.at<double>(-h_fd))) / (2 * h_fd);
  return {cs, fd};
}

TEST_CASE("the total time derivative matches differences along a path, twice",
          "[time_derivative][property]") {
  int badly_scaled = 0;
  for (unsigned seed = 0; seed < kCases; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    std::mt19937 rng(seed);
    const Path path = random_path(rng);
    RandomExpr gen(seed, path.symbols());
    const Expr e = gen(kDepth);
    TimeDerivative dt(path.rates());
    const Expr e1 = dt(e);
    const Expr e2 = dt(e1);
    // Powers up to 60 make values of 1e-150, whose derivatives through |u|
    // (u·u'/|u|, then u²u'²/|u|³) underflow: such cases are counted, not checked.
    const double v0 = evaluate(e, path.at<double>(0.0));
    if (v0 != 0.0 && (std::abs(v0) < 1e-60 || std::abs(v0) > 1e60)) {
      ++badly_scaled;
      continue;
    }
    const double v1 = evaluate(e1, path.at<double>(0.0));
    const double v2 = evaluate(e2, path.at<double>(0.0));
    const auto [cs1, fd1] = path_derivative(path, e);
    const auto [cs2, fd2] = path_derivative(path, e1);
    INFO("seed " << seed << "\ne = " << e << "\nde/dt = " << e1 << "\nd2e/dt2 = " << e2);
    INFO("first: " << v1 << " cs " << cs1 << " fd " << fd1 << "; second: " << v2 << " cs " << cs2
                   << " fd " << fd2);
    CHECK(close(v1, cs1, 1e-9));
    CHECK(close(v2, cs2, 1e-9));
    CHECK(close(v1, fd1, 1e-4));
    CHECK(close(v2, fd2, 1e-4));
  }
  CHECK(badly_scaled < kCases / 100);
}

TEST_CASE("substitution equals evaluation with the substituted values", "[substitute][property]") {
  for (unsigned seed = 0; seed < kCases; ++seed) {
    Context ctx;
    Context::Scope scope(ctx);
    const Expr x = symbol("x"), y = symbol("y"), z = symbol("z"), w = symbol("w");
    RandomExpr gen(seed, {x, y, z});
    const Expr e = gen(kDepth);
    RandomExpr values(seed + 1000003u, {y, z, w});
    // x -> an expression of the others (y, z, w); y <-> z swapped simultaneously.
    const Expr x_value = values(2);
    const Expr s = substitute(e, {{x, x_value}, {y, z}, {z, y}});
    const auto p = values.point();  // y, z, w
    const Bindings<double> at{{y, p[0]}, {z, p[1]}, {w, p[2]}};
    const double x_num = evaluate(x_value, at);
    const Bindings<double> original{{x, x_num}, {y, p[1]}, {z, p[0]}};
    const double expected = evaluate(e, original);
    const double got = evaluate(s, at);
    INFO("seed " << seed << "\ne = " << e << "\nx -> " << x_value << "\nresult " << s);
    INFO("got " << got << ", expected " << expected);
    REQUIRE(std::isfinite(expected));
    CHECK(close(got, expected, 1e-9));
  }
}

// ---------------------------------------------------------------------------
// Closed forms, kind by kind

TEST_CASE("each kind's derivative is its closed form", "[diff]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y"), z = symbol("z");

  SECTION("structure") {
    CHECK(diff(x + 3 * y + sin(x), x) == 1 + cos(x));
    CHECK(diff(x * y * z, y) == x * z);
    CHECK(diff(pow(x, 5), x) == 5 * pow(x, 4));
    CHECK(diff(sqrt(x), x) == 1 / (2 * sqrt(x)));
    CHECK(diff(sin(x), x) == cos(x));
    CHECK(diff(cos(x), x) == -sin(x));
    CHECK(diff(tan(x), x) == 1 + pow(tan(x), 2));
    CHECK(diff(asin(x), x) == 1 / sqrt(1 - x * x));
    CHECK(diff(acos(x), x) == -1 / sqrt(1 - x * x));
    CHECK(diff(atan(x), x) == 1 / (1 + x * x));
    CHECK(diff(atan2(y, x), y) == x / (x * x + y * y));
    CHECK(diff(atan2(y, x), x) == -y / (x * x + y * y));
    CHECK(diff(exp(x), x) == exp(x));
    CHECK(diff(log(x), x) == 1 / x);
    CHECK(diff(abs(x), x) == x / abs(x));
    CHECK(diff(sin(y * z), x) == Expr(0));
    CHECK(diff(x, x) == Expr(1));
    CHECK(diff(Expr(3), x) == Expr(0));
  }

  SECTION("values against hand-written formulas") {
    const double a = 0.3, b = -0.7;
    const Bindings<double> at{{x, a}, {y, b}, {z, 1.9}};
    auto d = [&](Expr e, Expr v) { return value_at(diff(e, v), at); };
    CHECK(d(pow(x, 5), x) == Approx(5 * std::pow(a, 4)));
    CHECK(d(pow(x, Expr(2.5)), x) == Approx(2.5 * std::pow(a, 1.5)));
    CHECK(d(pow(x, -3), x) == Approx(-3 / std::pow(a, 4)));
    CHECK(d(sqrt(x), x) == Approx(0.5 / std::sqrt(a)));
    CHECK(d(sin(x), x) == Approx(std::cos(a)));
    CHECK(d(cos(x), x) == Approx(-std::sin(a)));
    CHECK(d(tan(x), x) == Approx(1 / (std::cos(a) * std::cos(a))));
    CHECK(d(asin(x), x) == Approx(1 / std::sqrt(1 - a * a)));
    CHECK(d(acos(x), x) == Approx(-1 / std::sqrt(1 - a * a)));
    CHECK(d(atan(x), x) == Approx(1 / (1 + a * a)));
    CHECK(d(atan2(y, x), y) == Approx(a / (a * a + b * b)));
    CHECK(d(atan2(y, x), x) == Approx(-b / (a * a + b * b)));
    CHECK(d(exp(x), x) == Approx(std::exp(a)));
    CHECK(d(log(x), x) == Approx(1 / a));
    CHECK(d(abs(x), x) == Approx(1.0));
    CHECK(d(abs(y), y) == Approx(-1.0));
    CHECK(d(x * y * z * sin(x), x) == Approx(b * 1.9 * (std::sin(a) + a * std::cos(a))));
  }

  SECTION("the product rule never divides by a factor") {
    // At x = 0 a rule e·sum(f'/f) would give 0/0; the product rule gives the value.
    const Bindings<double> at{{x, 0.0}, {y, 2.0}, {z, 3.0}};
    CHECK(value_at(diff(x * y * z * sin(x), x), at) == 0.0);
    CHECK(value_at(diff(x * y * z, x), at) == 6.0);
    CHECK(value_at(diff(x * pow(y, 3) * z, y), at) == 0.0);
  }

  SECTION("partial() is the table the sweeps use") {
    CHECK(partial(atan2(y, x), 1) == -y / (x * x + y * y));
    CHECK(partial(x * y * z, 1) == x * z);
    CHECK(partial(sin(x) + y, 0) == Expr(1));
  }
}

TEST_CASE("time derivatives of symbols by their kind", "[time_derivative]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q = symbol("q0", SymbolKind::Variable), qd = symbol("qd0", SymbolKind::Rate);
  const Expr t = symbol("t", SymbolKind::Time), m = symbol("m", SymbolKind::Parameter),
             c = symbol("c");
  TimeDerivative dt(RateMap{{q, qd}});
  CHECK(dt(t) == Expr(1));
  CHECK(dt(m * c) == Expr(0));
  CHECK(dt(m * sin(q) + t * t) == m * cos(q) * qd + 2 * t);
  // A rate given for Time overrides the default 1 (time scaling).
  CHECK(time_derivative(t, {{t, Expr(2)}}) == Expr(2));
}

// ---------------------------------------------------------------------------
// Memoization: each node once, on DAGs far larger as trees

TEST_CASE("sweeps visit each node once", "[diff][dag]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y");
  // e_{k+1} = sin(e_k)·e_k + y: a tree of 2^200 nodes, a DAG of ~800.
  Expr e = x;
  for (int k = 0; k < 200; ++k) e = sin(e) * e + y;
  const std::size_t before = symdyn::testing::count_dag_nodes(std::array{e});
  const Expr d = diff(e, x);
  const Expr s = substitute(e, {{y, x}});
  const std::size_t d_nodes = symdyn::testing::count_dag_nodes(std::array{d});
  INFO("e: " << before << " nodes, de/dx: " << d_nodes);
  CHECK(d_nodes < 6 * before);
  CHECK(symdyn::testing::count_dag_nodes(std::array{s}) <= before);

  // The rule of a DagMap runs once per distinct node, across calls too.
  std::size_t calls = 0;
  DagMap count([&](Expr node, std::span<const Expr>) {
    ++calls;
    return node;
  });
  count(e);
  CHECK(calls == before);
  count(sin(e));
  CHECK(calls == before + 1);

  // Deep DAGs do not overflow the stack: the sweep is iterative. (A sum keeps
  // each derivative small: sin(sin(...)) would flatten its chain of cosines
  // into products of every length, quadratic in the depth.)
  Expr deep = x;
  for (int k = 0; k < 100000; ++k) deep = sin(deep) + x;
  const Expr d_deep = diff(deep, x);
  CHECK(symdyn::testing::count_dag_nodes(std::array{d_deep}) > 100000);
}

// ---------------------------------------------------------------------------
// Errors name the culprit

TEST_CASE("differentiating with respect to a non-symbol is an error", "[diff][error]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x");
  CHECK_THROWS_WITH(diff(sin(x), x + 1), "diff: the variable '1 + x' is not a symbol");
  CHECK_THROWS_AS(Differentiator(Expr(2)), UsageError);
}

TEST_CASE("a varying symbol without a rate is an error", "[time_derivative][error]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr q = symbol("q0", SymbolKind::Variable), qd = symbol("qd0", SymbolKind::Rate);
  CHECK_THROWS_WITH(time_derivative(sin(q), {}),
                    "time derivative: symbol 'q0' (variable) has no rate given");
  CHECK_THROWS_WITH(time_derivative(q * qd, {{q, qd}}),
                    "time derivative: symbol 'qd0' (rate) has no rate given");
  const Expr p = symbol("p0", SymbolKind::Dependent);
  CHECK_THROWS_WITH(time_derivative(p, {}),
                    "time derivative: symbol 'p0' (dependent) has no rate given");
  CHECK_THROWS_WITH(TimeDerivative(RateMap{{2 * q, qd}}),
                    "time derivative: rate map: key '2*q0' is not a symbol");
}

TEST_CASE("substitution keys must be symbols; partial() of a leaf is an error",
          "[substitute][error]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), y = symbol("y");
  CHECK_THROWS_WITH(substitute(x, {{sin(x), y}}), "substitute: key 'sin(x)' is not a symbol");
  CHECK_THROWS_WITH(partial(x, 0), "partial: 'x' is a leaf, it has no arguments");
  CHECK_THROWS_WITH(partial(sin(x), 1), "partial: 'sin(x)' has no argument 1");
  CHECK_THROWS_WITH(partial(pow(x, 3), 1), "partial: the exponent of 'x^3' is a constant");
  CHECK_THROWS_AS(substitute(log(x), {{x, Expr(0)}}), DomainError);
}

TEST_CASE("a substitution grows along a chain of definitions, never behind what it met",
          "[substitute]") {
  Context ctx;
  Context::Scope scope(ctx);
  const Expr x = symbol("x"), a = symbol("a", SymbolKind::Intermediate),
             b = symbol("b", SymbolKind::Intermediate);
  Substitution s(std::unordered_map<Expr, Expr>{{x, Expr(0)}});
  const Expr a0 = symbol("a0", SymbolKind::Intermediate);
  CHECK(s(sin(x) + 3) == Expr(3));
  s.add(a, a0);  // a = x + 1 at x = 0: the value of a is a0
  CHECK(s(a * cos(x) + b) == a0 + b);
  CHECK_THROWS_WITH(s.add(b, Expr(2)), "substitute: 'b' is already met or replaced");
  CHECK_THROWS_WITH(s.add(a, Expr(2)), "substitute: 'a' is already met or replaced");
  CHECK_THROWS_WITH(s.add(sin(x), Expr(2)), "substitute: key 'sin(x)' is not a symbol");
}

// ---------------------------------------------------------------------------
// Sizes on the chain model: positions, velocities, accelerations stay small

TEST_CASE("chain_16 absolute: kinematics by the time derivative stay a small DAG",
          "[time_derivative][chain]") {
  using namespace symdyn::testing;
  constexpr int n = 16;
  Context ctx;
  Context::Scope scope(ctx);
  std::vector<Expr> q, qd, qdd;
  RateMap rates;
  for (int i = 0; i < n; ++i) {
    q.push_back(symbol(fmt::format("q{}", i), SymbolKind::Variable));
    qd.push_back(symbol(fmt::format("qd{}", i), SymbolKind::Rate));
    qdd.push_back(symbol(fmt::format("qdd{}", i), SymbolKind::Acceleration));
    rates.emplace(q[i], qd[i]);
    rates.emplace(qd[i], qdd[i]);
  }
  const auto poses = chain_absolute<Expr>(q, rational(1, 4));
  std::vector<Expr> positions, velocities, accelerations;
  for (const auto& pose : poses) append_pose_entries(pose, positions);
  TimeDerivative dt(rates);
  for (Expr e : positions) velocities.push_back(dt(e));
  for (Expr e : velocities) accelerations.push_back(dt(e));

  std::vector<Expr> all = positions;
  all.insert(all.end(), velocities.begin(), velocities.end());
  all.insert(all.end(), accelerations.begin(), accelerations.end());
  const std::size_t pos_nodes = count_dag_nodes(positions);
  const std::size_t all_nodes = count_dag_nodes(all);
  INFO("DAG nodes: positions " << pos_nodes << ", with velocities and accelerations " << all_nodes
                               << "; context " << ctx.size());
  // Measured: positions 466, with velocities and accelerations 2616 (context:
  // 4564 nodes). Bounds with ~25% margin: a quadratic blow-up would fail them.
  CHECK(pos_nodes <= 600);
  CHECK(all_nodes <= 3300);

  // Values at a random state against a numerical 4x4 product, and the
  // velocities and accelerations against central differences in time along
  // q(t) = q0 + qd0·t + qdd0·t²/2.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<double> q0(n), qd0(n), qdd0(n);
  for (int i = 0; i < n; ++i) {
    q0[i] = u(rng);
    qd0[i] = u(rng);
    qdd0[i] = u(rng);
  }
  auto bindings = [&](double t) {
    Bindings<double> b;
    for (int i = 0; i < n; ++i) {
      b.emplace(q[i], q0[i] + qd0[i] * t + qdd0[i] * t * t / 2);
      b.emplace(qd[i], qd0[i] + qdd0[i] * t);
      b.emplace(qdd[i], qdd0[i]);
    }
    return b;
  };
  auto numeric_positions = [&](double t) {
    std::vector<double> qt(n);
    for (int i = 0; i < n; ++i) qt[i] = q0[i] + qd0[i] * t + qdd0[i] * t * t / 2;
    std::vector<double> out;
    for (const auto& pose : chain_absolute<double>(qt, 0.25)) append_pose_entries(pose, out);
    return out;
  };
  const auto at0 = bindings(0.0);
  const auto at_plus = bindings(1e-5);
  const auto at_minus = bindings(-1e-5);
  const auto expected = numeric_positions(0.0);
  const auto plus = numeric_positions(1e-5);
  const auto minus = numeric_positions(-1e-5);
  Evaluator<double> eval0(at0), eval_plus(at_plus), eval_minus(at_minus);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    INFO("entry " << i % 12 << " of body " << i / 12);
    CHECK(close(eval0(positions[i]), expected[i], 1e-12));
    CHECK(close(eval0(velocities[i]), (plus[i] - minus[i]) / 2e-5, 1e-6));
    CHECK(close(eval0(accelerations[i]),
                (eval_plus(velocities[i]) - eval_minus(velocities[i])) / 2e-5, 1e-6));
  }
}
