// The reference models against the numbers of docs/models.md, typed here again
// from the page: sizes, masses and inertias, gravity, initial states, and
// positions in simple configurations; amru5's legs close (the thigh and the
// shank meet at the knee) and its dependent parameters follow the page's formulas.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "generated.hpp"
#include "support/model_eval.hpp"

using namespace symdyn::testing;
namespace gen = symdyn_generated;

namespace {

struct Inertia {
  double m, ixx, iyy, izz;
};

// Body name (or leg-part name, before "_k") -> mass and principal inertia.
using InertiaTable = std::map<std::string, Inertia>;

template <class G>
void check_sizes(int nq, int nbody, int ndep) {
  INFO(G::model << " " << G::variant);
  CHECK(G::nq == nq);
  CHECK(G::nbody == nbody);
  CHECK(G::ndep == ndep);
  CHECK(G::nparam == 0);
}

template <class G>
void check_gravity(double gx, double gy, double gz) {
  CHECK(G::gravity[0] == gx);
  CHECK(G::gravity[1] == gy);
  CHECK(G::gravity[2] == gz);
}

// Every body's mass and inertia tensor (diagonal) against the table, by its
// name with any "_<leg>" suffix removed.
template <class G>
void check_inertia(const InertiaTable& table) {
  double mass[G::nbody], inertia[G::nbody * 9];
  G::inertia(G::param_defaults, mass, inertia);
  for (int i = 0; i < G::nbody; ++i) {
    std::string name = G::body_names[i];
    if (!table.count(name)) name = name.substr(0, name.rfind('_'));
    INFO(G::model << " body " << G::body_names[i]);
    REQUIRE(table.count(name) == 1);
    const Inertia& e = table.at(name);
    CHECK(mass[i] == e.m);
    const double diagonal[3] = {e.ixx, e.iyy, e.izz};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) CHECK(inertia[9 * i + 3 * r + c] == (r == c ? diagonal[r] : 0.0));
    }
  }
}

template <class G>
void check_initial(const std::vector<double>& q, const std::vector<double>& qd) {
  INFO(G::model << " " << G::variant);
  REQUIRE(q.size() == std::size_t(G::nq));
  for (int i = 0; i < G::nq; ++i) {
    CHECK(G::q_initial[i] == q[i]);
    CHECK(G::qd_initial[i] == qd[i]);
  }
}

// Centre of gravity of every body at configuration q.
template <class G>
std::vector<Eigen::Vector3d> centres(const std::vector<double>& q) {
  double R[G::nbody * 9], x[G::nbody * 3];
  G::positions(0.0, q.data(), G::param_defaults, R, x);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < G::nbody; ++i) out.emplace_back(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  return out;
}

template <class G>
int body(std::string_view name) {
  for (int i = 0; i < G::nbody; ++i) {
    if (G::body_names[i] == name) return i;
  }
  FAIL("no body " << name << " in " << G::model);
  return -1;
}

bool near(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() < 1e-14;
}

}  // namespace

TEST_CASE("robot3d matches docs/models.md", "[models]") {
  const InertiaTable table = {{"turret", {10.0, 0.3, 0.3, 0.1}},
                              {"arm", {5.0, 0.01, 0.41666666666666667, 0.41666666666666667}},
                              {"gripper", {2.0, 0.01, 0.02, 0.02}}};
  const std::vector<double> q0 = {0, 0.3, 0.6, 0, 0}, qd0 = {1.0, 0, 0, 2.0, 0};
  // Arm extended by 0.6 along x at rest: H = 0.5, L = 1.0, C = 0.2.
  const std::vector<double> extended = {0, 0, 0.6, 0, 0};
  auto check = [&]<class G>() {
    check_sizes<G>(5, 3, 0);
    check_gravity<G>(0, 0, -9.81);
    check_inertia<G>(table);
    check_initial<G>(q0, qd0);
    const auto x = centres<G>(extended);
    CHECK(near(x[body<G>("turret")], {0, 0, 0.25}));
    CHECK(near(x[body<G>("arm")], {0.6, 0, 0.5}));
    CHECK(near(x[body<G>("gripper")], {0.6 + 0.5 + 0.2, 0, 0.5}));
  };
  check.operator()<gen::robot3d_absolute>();
  check.operator()<gen::robot3d_relative>();
}

TEST_CASE("trike matches docs/models.md", "[models]") {
  using G = gen::trike;
  check_sizes<G>(13, 5, 0);
  check_gravity<G>(0, 0, -9.81);
  check_inertia<G>({{"chassis", {150, 15, 40, 45}},
                    {"rear_axle", {20, 2, 0.2, 2}},
                    {"left_rear_wheel", {5, 0.2, 0.4, 0.2}},
                    {"right_rear_wheel", {5, 0.2, 0.4, 0.2}},
                    {"front_wheel", {6, 0.2, 0.4, 0.2}}});
  std::vector<double> q0(13, 0.0), qd0(13, 0.0);
  q0[2] = 0.5;
  qd0[0] = 5;
  qd0[8] = qd0[9] = qd0[12] = 5 / 0.3;
  check_initial<G>(q0, qd0);
  // Suspensions travelled by s: the rear axle along the 45° strut, the front wheel down.
  const double s = 0.1;
  std::vector<double> q(13, 0.0);
  q[6] = s;
  q[11] = s;
  const auto x = centres<G>(q);
  const double r = s / std::sqrt(2.0);
  CHECK(near(x[body<G>("chassis")], {0, 0, 0}));
  CHECK(near(x[body<G>("rear_axle")], {-0.9 - r, 0, -0.2 + r}));
  CHECK(near(x[body<G>("left_rear_wheel")], {-0.9 - r, 0.55, -0.2 + r}));
  CHECK(near(x[body<G>("right_rear_wheel")], {-0.9 - r, -0.55, -0.2 + r}));
  CHECK(near(x[body<G>("front_wheel")], {1.2, 0, -0.2 - s}));
}

namespace {

const InertiaTable hexapod_main_body = {{"body", {60, 2.0, 7.4, 9.0}}};

// Hips and their mounting yaw (docs/models.md 5).
struct HipSpec {
  double x, y, psi;
};
const HipSpec hip_spec[6] = {
    {0.5, 0.3, std::numbers::pi / 2},  {0.5, -0.3, -std::numbers::pi / 2},
    {0, 0.3, std::numbers::pi / 2},    {0, -0.3, -std::numbers::pi / 2},
    {-0.5, 0.3, std::numbers::pi / 2}, {-0.5, -0.3, -std::numbers::pi / 2}};

}  // namespace

TEST_CASE("amru5 matches docs/models.md", "[models]") {
  InertiaTable table = hexapod_main_body;
  table.insert({{"coxa", {1.0, 0.002, 0.002, 0.002}},
                {"vertical_slider", {0.5, 0.001, 0.001, 0.001}},
                {"horizontal_slider", {0.5, 0.001, 0.001, 0.001}},
                {"thigh", {1.0, 0.001, 0.0075, 0.0075}},
                {"shank", {0.8, 0.001, 0.0041666666666666667, 0.0041666666666666667}},
                {"link6", {0.4, 0.0005, 0.0020833333333333333, 0.0020833333333333333}},
                {"link7", {0.6, 0.0005, 0.006125, 0.006125}},
                {"foot", {0.2, 1e-4, 1e-4, 1e-4}}});
  std::vector<double> q0(24, 0.0), qd0(24, 0.0);
  q0[2] = 0.62;
  for (int k = 0; k < 6; ++k) q0[8 + 3 * k] = 0.35;
  auto check = [&]<class G>(int ndep) {
    check_sizes<G>(24, 49, ndep);
    check_gravity<G>(0, 0, -9.81);
    check_inertia<G>(table);
    check_initial<G>(q0, qd0);
  };
  check.operator()<gen::amru5_inline>(0);
  check.operator()<gen::amru5_dependent>(12);
}

TEST_CASE(
    "amru5's legs close: thigh and shank meet at the knee, the foot keeps the coxa's attitude",
    "[models]") {
  const double a = 0.3, b = 0.25;
  auto check = [&]<class G>() {
    std::mt19937 rng(4);
    for (int trial = 0; trial < 20; ++trial) {
      const auto s = random_state_near(rng, G::q_initial, 0.1);
      double R[G::nbody * 9], x[G::nbody * 3];
      G::positions(0.0, s.q.data(), G::param_defaults, R, x);
      auto frame = [&](std::string_view name) {
        const int i = body<G>(name);
        return std::pair{Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&R[9 * i]),
                         Eigen::Vector3d(&x[3 * i])};
      };
      for (int k = 0; k < 6; ++k) {
        INFO(G::variant << " leg " << k);
        auto part = [k](std::string_view name) { return fmt::format("{}_{}", name, k); };
        const auto [R_thigh, x_thigh] = frame(part("thigh"));
        const auto [R_shank, x_shank] = frame(part("shank"));
        const Eigen::Vector3d knee_from_thigh = x_thigh + R_thigh * Eigen::Vector3d(a / 2, 0, 0);
        const Eigen::Vector3d knee_from_shank = x_shank + R_shank * Eigen::Vector3d(b / 2, 0, 0);
        CHECK((knee_from_thigh - knee_from_shank).norm() < 1e-14);
        CHECK((frame(part("foot")).first - frame(part("coxa")).first).cwiseAbs().maxCoeff() <
              1e-14);
      }
    }
  };
  check.operator()<gen::amru5_inline>();
  check.operator()<gen::amru5_dependent>();
}

TEST_CASE("amru5's dependent parameters are docs/models.md's alpha_k and beta_k", "[models]") {
  using G = gen::amru5_dependent;
  const double a = 0.3, b = 0.25;
  std::mt19937 rng(8);
  for (int trial = 0; trial < 10; ++trial) {
    const auto s = random_state_near(rng, G::q_initial, 0.1);
    double p[G::ndep], pd[G::ndep], pdd[G::ndep];
    G::dependent_parameters(s.t, s.q.data(), s.qd.data(), s.qdd.data(), G::param_defaults, p, pd,
                            pdd);
    for (int k = 0; k < 6; ++k) {
      const double v = s.q[7 + 3 * k], h = s.q[8 + 3 * k];
      const double Dx = h - 0.1, Dz = -0.1 - v, r = std::hypot(Dx, Dz);
      const double alpha = std::atan2(-Dz, Dx) + std::acos((a * a + r * r - b * b) / (2 * a * r));
      const double beta = std::atan2(Dz + a * std::sin(alpha), a * std::cos(alpha) - Dx);
      INFO("leg " << k);
      CHECK(p[2 * k] == Approx(alpha).epsilon(1e-13));
      CHECK(p[2 * k + 1] == Approx(beta).epsilon(1e-13));
    }
  }
}

TEST_CASE("hexapod_tree matches docs/models.md", "[models]") {
  using G = gen::hexapod_tree;
  InertiaTable table = hexapod_main_body;
  table.insert({{"coxa", {1.0, 0.002, 0.002, 0.002}},
                {"femur", {2.0, 0.002, 0.015, 0.015}},
                {"tibia", {2.0, 0.002, 0.03, 0.03}}});
  check_sizes<G>(24, 19, 0);
  check_gravity<G>(0, 0, -9.81);
  check_inertia<G>(table);
  std::vector<double> q0(24, 0.0), qd0(24, 0.0);
  q0[2] = 0.5;
  for (int k = 0; k < 6; ++k) q0[7 + 3 * k] = 0.3, q0[8 + 3 * k] = 1.2;
  check_initial<G>(q0, qd0);
  // Legs stretched out: centres along the leg's direction psi_k from the hip.
  const auto x = centres<G>(std::vector<double>(24, 0.0));
  for (int k = 0; k < 6; ++k) {
    const auto& hip = hip_spec[k];
    const Eigen::Vector3d hip_x(hip.x, hip.y, 0), out(std::cos(hip.psi), std::sin(hip.psi), 0);
    INFO("leg " << k);
    CHECK(near(x[body<G>("coxa_" + std::to_string(k))], hip_x + 0.05 * out));
    CHECK(near(x[body<G>("femur_" + std::to_string(k))], hip_x + 0.25 * out));
    CHECK(near(x[body<G>("tibia_" + std::to_string(k))], hip_x + 0.6 * out));
  }
}

TEST_CASE("chain_N matches docs/models.md", "[models]") {
  auto check = [&]<class G>(int n) {
    check_sizes<G>(n, n, 0);
    check_gravity<G>(0, 0, -9.81);
    InertiaTable table;
    for (int k = 0; k < n; ++k)
      table["link" + std::to_string(k)] = {1.0, 0.001, 0.020833333333333333, 0.020833333333333333};
    check_inertia<G>(table);
    check_initial<G>(std::vector<double>(n, 0.1), std::vector<double>(n, 0.0));
    // Straight along x at q = 0, links of length L = 0.5.
    const auto x = centres<G>(std::vector<double>(n, 0.0));
    for (int k = 0; k < n; ++k) CHECK(near(x[k], {0.25 + 0.5 * k, 0, 0}));
  };
  check.operator()<gen::chain_2_relative>(2);
  check.operator()<gen::chain_2_absolute>(2);
  check.operator()<gen::chain_4_relative>(4);
  check.operator()<gen::chain_4_absolute>(4);
  check.operator()<gen::chain_8_relative>(8);
  check.operator()<gen::chain_8_absolute>(8);
  check.operator()<gen::chain_16_relative>(16);
  check.operator()<gen::chain_16_absolute>(16);
}
