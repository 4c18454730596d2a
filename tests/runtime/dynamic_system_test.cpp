// The defaults of DynamicSystem: names, and Jacobians by central differences,
// against hand-derived partials.

#include <catch2/catch.hpp>
#include <cmath>

#include <symdyn/runtime/dynamic_system.hpp>

namespace {

using namespace symdyn::runtime;

// A nonlinear 2-DOF residual with one extra state, and its partials by hand.
class Nonlinear : public DynamicSystem {
 public:
  int num_coordinates() const override { return 2; }
  int num_extra_states() const override { return 1; }
  void accelerations(const State&, Vector&, Vector&) override {}
  void residual(const State& s, const Vector& a, const Vector& yd, Vector& f, Vector& g) override {
    const auto& q = s.q;
    const auto& v = s.qd;
    f.resize(2);
    g.resize(1);
    f[0] = (2 + std::sin(q[1])) * a[0] + 0.3 * a[1] + q[0] * v[1] * v[1] + 5 * std::sin(q[0]) +
           s.y[0] * q[1];
    f[1] = 0.3 * a[0] + (1 + q[0] * q[0]) * a[1] + v[0] * v[1] + std::pow(q[1], 3) - s.t;
    g[0] = yd[0] + s.y[0] - q[0];
  }
  void exact(const State& s, const Vector& a, Matrix& M, Matrix& C, Matrix& K) const {
    const auto& q = s.q;
    const auto& v = s.qd;
    M.resize(2, 2);
    C.resize(2, 2);
    K.resize(2, 2);
    M << 2 + std::sin(q[1]), 0.3, 0.3, 1 + q[0] * q[0];
    C << 0, 2 * q[0] * v[1], v[1], v[0];
    K << v[1] * v[1] + 5 * std::cos(q[0]), std::cos(q[1]) * a[0] + s.y[0], 2 * q[0] * a[1],
        3 * q[1] * q[1];
  }
};

TEST_CASE("default Jacobians match the hand-derived partials", "[dynamic_system]") {
  Nonlinear sys;
  // Points over several magnitudes: the relative step must serve them all.
  const double scales[] = {1e-3, 1.0, 40.0};
  for (double scale : scales) {
    for (int k = 0; k < 20; ++k) {
      State s;
      s.t = 0.1 * k;
      s.q = scale * Vector::Random(2);
      s.qd = scale * Vector::Random(2);
      s.y = Vector::Random(1);
      const Vector a = scale * Vector::Random(2);
      Matrix M, C, K, Me, Ce, Ke;
      sys.jacobians(s, a, M, C, K);
      sys.exact(s, a, Me, Ce, Ke);
      CAPTURE(scale, s.q.transpose(), s.qd.transpose(), a.transpose());
      const auto close = [](const Matrix& A, const Matrix& B) {
        return (A - B).cwiseAbs().maxCoeff() <= 1e-7 * std::max(1.0, B.cwiseAbs().maxCoeff());
      };
      CHECK(close(M, Me));
      CHECK(close(C, Ce));
      CHECK(close(K, Ke));
    }
  }
}

TEST_CASE("default names are q<i> and y<i>", "[dynamic_system]") {
  Nonlinear sys;
  CHECK(sys.coordinate_name(0) == "q0");
  CHECK(sys.coordinate_name(1) == "q1");
  CHECK(sys.extra_state_name(0) == "y0");
}

}  // namespace
