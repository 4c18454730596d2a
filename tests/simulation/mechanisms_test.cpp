// The reference mechanisms with closed loops (docs/models.md): the
// double-wishbone quarter car against a planar construction of its geometry
// done here (circle intersection) and a virtual-work balance of its spring,
// and the Stewart platform against its inverse kinematics and the statics of
// its platform through the legs' unit vectors; both for loop closure and
// energy over free runs.

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "quarter_car.hpp"
#include "stewart.hpp"
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>
#include <symdyn/runtime/statics.hpp>

namespace {

using namespace symdyn::runtime;
namespace gen = symdyn_generated;
constexpr double pi = std::numbers::pi;
constexpr double g = 9.81;

double max_abs(const Vector& a) {
  return a.size() ? a.cwiseAbs().maxCoeff() : 0.0;
}

// The largest loop gap |g| and velocity gap |g_q·qd + g_p·pd + g_t| at s (in q).
struct Gaps {
  double position, velocity;
};
Gaps loop_gaps(MultibodySystem& system, const State& s) {
  const Model& model = system.model();
  const State x = system.extended_state(s);
  const int n = model.nindependent(), m = model.ncon();
  Vector gap(m), g_t(m);
  Matrix g_q(n, m), g_p(m, m);  // row-major arrays, transposed
  model.constraints(s.t, x.q.data(), gap.data(), g_q.data(), g_p.data(), g_t.data());
  const Vector rate = g_q.transpose() * x.qd.head(n) + g_p.transpose() * x.qd.tail(m) + g_t;
  return {max_abs(gap), max_abs(rate)};
}

// ---- Quarter car ------------------------------------------------------------

// The design points of models/quarter_car.cpp in the y-z plane (y out of the
// car, z up), chassis G at z = 0.6.
using P2 = Eigen::Vector2d;
const P2 lower_inner(0.20, 0.18), lower_outer(0.60, 0.15), upper_inner(0.30, 0.48),
    upper_outer(0.57, 0.50), upright_g(0.61, 0.30), wheel_centre(0.72, 0.30);
constexpr double design_height = 0.6, wheel_radius = 0.3;
// The spring: on the lower wishbone 0.25 m from its hinge, and at (0.42, 0.75) on the chassis.
constexpr double spring_on_arm = 0.25, spring_rate = 60e3, spring_free_length = 0.69;
const P2 spring_top(0.42, 0.75);
// Masses: chassis, lower wishbone, upper wishbone, upright, wheel.
constexpr double masses[] = {350, 4.0, 2.5, 6.0, 18.0};

double cross(const P2& a, const P2& b) {
  return a.x() * b.y() - a.y() * b.x();
}
P2 rotated(const P2& v, double a) {
  return Eigen::Rotation2Dd(a) * v;
}
double angle_of(const P2& v) {
  return std::atan2(v.y(), v.x());
}

// The geometry at chassis height zc and lower wishbone angle q, by the
// intersection of the circles about the upper hinge (radius: the upper
// wishbone) and the lower ball joint (radius: the upright's ball joints'
// distance), on the design's side.
struct QuarterCarPose {
  double upper, upright;  // the upper wishbone's angle, the upright's rotation (-camber)
  P2 g[5];                // the bodies' G (chassis first)
  P2 contact;             // the tyre's lowest point
  double spring_length;
};
QuarterCarPose quarter_car_geometry(double zc, double q) {
  const P2 lift(0, zc - design_height);
  const P2 li = lower_inner + lift, ui = upper_inner + lift;
  const double lower = (lower_outer - lower_inner).norm(),
               upper = (upper_outer - upper_inner).norm();
  const double kingpin = (upper_outer - lower_outer).norm();
  const P2 lo = li + rotated(P2(lower, 0), q);
  const double e = (lo - ui).norm();
  const double a = (upper * upper - kingpin * kingpin + e * e) / (2 * e);
  const double h = std::sqrt(upper * upper - a * a);
  const P2 u = (lo - ui) / e, normal(-u.y(), u.x());
  const double side = cross(lower_outer - upper_inner, upper_outer - upper_inner) > 0 ? 1 : -1;
  const P2 uo = ui + a * u + side * h * normal;
  QuarterCarPose pose;
  pose.upper = angle_of(uo - ui);
  pose.upright = angle_of(uo - lo) - angle_of(upper_outer - lower_outer);
  const auto on_upright = [&](const P2& p) -> P2 {
    return lo + rotated(p - lower_outer, pose.upright);
  };
  pose.g[0] = P2(0, zc);
  pose.g[1] = (li + lo) / 2;
  pose.g[2] = (ui + uo) / 2;
  pose.g[3] = on_upright(upright_g);
  pose.g[4] = on_upright(wheel_centre);
  // The point of the wheel's mid-plane farthest down: the centre less the
  // radius along the plane's downward direction (sin b, -cos b).
  pose.contact = pose.g[4] + wheel_radius * P2(std::sin(pose.upright), -std::cos(pose.upright));
  pose.spring_length = (spring_top + lift - (li + rotated(P2(spring_on_arm, 0), q))).norm();
  return pose;
}

State quarter_car_state(double zc, double q, double zd = 0, double qd = 0, double spin_rate = 0) {
  State s;
  s.q = Eigen::Vector3d(zc, q, 0);
  s.qd = Eigen::Vector3d(zd, qd, spin_rate);
  return s;
}

const SimpleTyreProperties& tyre() {
  static const SimpleTyreProperties p = [] {
    SimpleTyreProperties t;
    t.radius = wheel_radius;
    t.stiffness = 250e3;
    t.damping = 300;
    return t;
  }();
  return p;
}

std::shared_ptr<PointSpringDamper> add_spring(MultibodySystem& system, double damping,
                                              double free_length = spring_free_length) {
  const Model& model = system.model();
  const double lower = (lower_outer - lower_inner).norm();
  const BodyPoint arm{model.body_index("lower_wishbone"), Vec3(0, spring_on_arm - lower / 2, 0)};
  const BodyPoint chassis{model.body_index("chassis"),
                          Vec3(0, spring_top.x(), spring_top.y() - design_height)};
  return system.add<PointSpringDamper>("spring", arm, chassis, spring_rate, free_length, damping);
}

// ---- Stewart platform -------------------------------------------------------

constexpr double platform_mass = 40, cylinder_mass = 3.0, piston_mass = 1.5;
constexpr double cylinder_g = 0.275, piston_g = 0.25;

// The joints of models/stewart.cpp: base joint i at angle 120°·(i/2) ∓ 15°,
// radius 0.5; platform joint at 120°·(i/2) ∓ 45°, radius 0.3, 0.05 below G.
Vec3 base_joint(int i) {
  const double a = (120 * (i / 2) + (i % 2 ? 15 : -15)) * pi / 180;
  return {0.5 * std::cos(a), 0.5 * std::sin(a), 0};
}
Vec3 platform_joint(int i) {
  const double a = (120 * (i / 2) + (i % 2 ? 45 : -45)) * pi / 180;
  return {0.3 * std::cos(a), 0.3 * std::sin(a), -0.05};
}

// The platform's pose in the extended state: position, rotation z-y-x.
struct Pose {
  Vec3 position;
  Mat3 rotation;
};
Pose platform_pose(const State& x) {
  const auto about = [](double a, const Vec3& axis) {
    return Eigen::AngleAxisd(a, axis).toRotationMatrix();
  };
  return {x.q.segment<3>(6), about(x.q(9), Vec3::UnitZ()) * about(x.q(10), Vec3::UnitY()) *
                                 about(x.q(11), Vec3::UnitX())};
}

State stewart_state(const Vector& lengths, const Vector& rates) {
  State s;
  s.q = lengths;
  s.qd = rates;
  return s;
}

// accelerations() at s against the direct product of the tree's matrices at
// the extended state x: qdd = (Tᵀ·M_x·T)⁻¹·Tᵀ·(-h_x - M_x·c), T and c from
// extended_accelerations (xdd = T·qdd + c), M_x and h_x the emitted ones, dense.
double accelerations_against_product(MultibodySystem& system, const State& s) {
  Vector qdd, yd;
  system.accelerations(s, qdd, yd);
  const Eigen::Index n = s.q.size();
  const Vector c = system.extended_accelerations(s, Vector::Zero(n));
  Matrix T(c.size(), n);
  for (Eigen::Index j = 0; j < n; ++j)
    T.col(j) = system.extended_accelerations(s, Vector::Unit(n, j)) - c;
  const State x = system.extended_state(s);
  Matrix M_x;
  Vector h_x;
  system.mass_matrix(x, M_x);
  system.bias_forces_emitted(x, h_x);
  const Matrix M = T.transpose() * M_x * T;
  const Vector expected = M.lu().solve(T.transpose() * (-h_x - M_x * c));
  return max_abs(qdd - expected) / std::max(1.0, max_abs(expected));
}

}  // namespace

TEST_CASE("the mechanisms' accelerations are the direct product of the tree's matrices reduced",
          "[models][loops]") {
  // The reduction takes the emitted M_x's coupling of p with the other
  // coordinates once: at random states (none of them where it was taken)
  // the results are those of the dense products.
  std::mt19937 rng(61u);
  std::uniform_real_distribution<double> change(-0.1, 0.1), rate(-0.5, 0.5);
  MultibodySystem stewart(Model::from<gen::stewart>()), car(Model::from<gen::quarter_car>());
  for (MultibodySystem* system : {&stewart, &car}) {
    CAPTURE(system->model().name());
    const State start = system->initial_state();
    for (int k = 0; k < 20; ++k) {
      State s = start;
      for (Eigen::Index i = 0; i < s.q.size(); ++i) s.q(i) += change(rng), s.qd(i) = rate(rng);
      system->reset_loops();
      CHECK(accelerations_against_product(*system, s) <= 1e-11);
    }
  }
}

TEST_CASE("the quarter car's camber and track over the wheel travel are the planar construction's",
          "[models][loops][quarter_car]") {
  MultibodySystem system(Model::from<gen::quarter_car>());
  REQUIRE(system.num_coordinates() == 3);
  CHECK(system.model().loop_names() == std::vector<std::string>{"upper_ball_joint"});
  const double design = angle_of(lower_outer - lower_inner);
  // The wheel from 8 cm of rebound to 6 cm of bump, each solve from the last.
  double camber_bump = 0, track_bump = 0;
  for (int k = -20; k <= 15; ++k) {
    const double q = design + 0.01 * k, zc = design_height + 0.002 * k;
    CAPTURE(q, zc);
    const State s = quarter_car_state(zc, q);
    const State x = system.extended_state(s);
    const QuarterCarPose expected = quarter_car_geometry(zc, q);
    CHECK(std::abs(x.q(3) - expected.upper) <= 1e-12);
    CHECK(std::abs(x.q(4) - expected.upright) <= 1e-12);
    const Kinematics& kin = system.evaluate_kinematics(s);
    for (int i = 0; i < 5; ++i) {
      CHECK(std::abs(kin.x(i).x()) <= 1e-14);  // the mechanism stays in its plane
      CHECK((kin.x(i).tail<2>() - expected.g[i]).norm() <= 1e-12);
    }
    // The tyre's contact point (its lowest point on the wheel) is the construction's.
    const SimpleTyre t("tyre", 4, tyre());
    CHECK((t.evaluate(kin).contact_point.tail<2>() - expected.contact).norm() <= 1e-12);
    if (k == 15) camber_bump = -x.q(4), track_bump = expected.contact.x() - wheel_centre.x();
  }
  // The short-long arms: negative camber and the track growing in bump (here by
  // 1.8 degrees and 5 mm at 6 cm of bump).
  CHECK(camber_bump < -0.03);
  CHECK(track_bump > 0.004);
}

TEST_CASE("the quarter car at rest on its tyre: the spring force by virtual work",
          "[models][loops][quarter_car]") {
  MultibodySystem system(Model::from<gen::quarter_car>());
  auto spring = add_spring(system, 3000);
  system.add<SimpleTyre>("tyre", system.model().body_index("wheel"), tyre());
  StaticsOptions options;
  options.locked = {2};  // the wheel's spin: neutral
  options.tolerance = 1e-11;
  const StaticsReport r = solve_statics(system, system.initial_state(), options);
  INFO(r.summary());
  const double zc = r.state.q(0), q = r.state.q(1);
  // The chassis' equation (a vertical translation of everything, the spring's
  // length unchanged): the tyre carries the whole weight.
  const Kinematics& kin = system.evaluate_kinematics(r.state);
  const double load = SimpleTyre("tyre", 4, tyre()).evaluate(kin).normal_force;
  double weight = 0;
  for (double m : masses) weight += m * g;
  CHECK(std::abs(load - weight) <= 1e-6 * weight);
  // The wishbone's equation, the chassis held: T·dL = N·dz_P - g·Σ m_i·dz_i
  // (dz_P of the wheel's material point at the contact, which the construction's
  // lowest point follows to first order), by central differences in q.
  const double h = 1e-6;
  const QuarterCarPose plus = quarter_car_geometry(zc, q + h),
                       minus = quarter_car_geometry(zc, q - h);
  const double dL = (plus.spring_length - minus.spring_length) / (2 * h);
  const double dzP = (plus.contact.y() - minus.contact.y()) / (2 * h);
  double dW = 0;
  for (int i = 1; i < 5; ++i) dW += masses[i] * g * (plus.g[i].y() - minus.g[i].y()) / (2 * h);
  const double installation_ratio = dL / dzP;
  const double tension = (load - dW / dzP) / installation_ratio;
  const double length = quarter_car_geometry(zc, q).spring_length;
  CHECK(std::abs(spring->length(kin) - length) <= 1e-12);
  const double spring_tension = spring_rate * (length - spring_free_length);
  CAPTURE(installation_ratio, tension, spring_tension, load);
  CHECK(installation_ratio == Approx(-0.59).margin(0.02));  // the spring compressed in bump
  CHECK(std::abs(spring_tension - tension) <= 1e-6 * std::abs(tension));
}

TEST_CASE("the quarter car keeps its loop closed on its tyre and its energy in a free drop",
          "[models][loops][quarter_car]") {
  IntegratorOptions o;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-10;
  o.output_interval = 0.01;
  const double design = angle_of(lower_outer - lower_inner);
  SECTION("dropped 5 cm onto its tyre, damped: the loop closed at every output") {
    MultibodySystem system(Model::from<gen::quarter_car>());
    add_spring(system, 3000);
    system.add<SimpleTyre>("tyre", 4, tyre());
    const State start = quarter_car_state(design_height + 0.05, design + 0.05, 0, 0, 0);
    Gaps worst{0, 0};
    double lowest = 1;
    o.on_output = [&](const State& s, const Vector&, const Vector&) {
      const Gaps gaps = loop_gaps(system, s);
      worst = {std::max(worst.position, gaps.position), std::max(worst.velocity, gaps.velocity)};
      lowest = std::min(lowest, s.q(0));
    };
    const State end = make_integrator("dopri5", o)->integrate(system, start, 2.0);
    CHECK(end.t == 2.0);
    CHECK(lowest < design_height - 0.02);  // it landed and compressed its tyre and spring
    CHECK(worst.position <= 1e-12);        // m
    CHECK(worst.velocity <= 1e-12);        // m/s
  }
  SECTION("falling freely, the spring undamped: the energy conserved") {
    // The spring at its free length in the design position (its preload, with
    // nothing under the wheel, would throw the wishbone to its full droop).
    MultibodySystem system(Model::from<gen::quarter_car>());
    add_spring(system, 0, quarter_car_geometry(design_height, design).spring_length);
    const State start = quarter_car_state(design_height, design + 0.03, 0.5, 3.0, 30.0);
    const double e0 = system.energies(start).total();
    double drift = 0, elastic = 0, kinetic = 0;
    o.on_output = [&](const State& s, const Vector&, const Vector&) {
      const Energies e = system.energies(s);
      drift = std::max(drift, std::abs(e.total() - e0));
      elastic = std::max(elastic, e.elastic);
      kinetic = std::max(kinetic, e.kinetic);
    };
    make_integrator("dopri5", o)->integrate(system, start, 1.0);
    CHECK(elastic > 10);  // J: the wheel oscillated on its spring
    CHECK(drift <= 1e-7 * elastic);
    CHECK(drift <= 1e-10 * kinetic);  // the fall's
  }
}

TEST_CASE("the Stewart platform's loops close at random leg lengths, its pose their inverse",
          "[models][loops][stewart]") {
  MultibodySystem system(Model::from<gen::stewart>());
  REQUIRE(system.num_coordinates() == 6);
  REQUIRE(system.model().ncon() == 18);
  const State home = system.initial_state();
  std::mt19937 rng(42u);
  std::uniform_real_distribution<double> change(-0.12, 0.12), rate(-0.5, 0.5);
  for (int k = 0; k < 50; ++k) {
    Vector lengths = home.q, rates(6);
    for (int i = 0; i < 6; ++i) lengths(i) += change(rng), rates(i) = rate(rng);
    CAPTURE(k, lengths.transpose());
    system.reset_loops();  // each from the guesses: the home pose
    const State s = stewart_state(lengths, rates);
    const Gaps gaps = loop_gaps(system, s);
    CHECK(gaps.position <= 1e-12);
    CHECK(gaps.velocity <= 1e-12);
    // Inverse kinematics: the base-to-platform joint distances are the lengths,
    // and their rates the leg rates.
    const State x = system.extended_state(s);
    const Pose pose = platform_pose(x);
    const Kinematics& kin = system.evaluate_kinematics(s);
    const Vec3 w = kin.w(0), v = kin.v(0);
    for (int i = 0; i < 6; ++i) {
      const Vec3 arm = pose.rotation * platform_joint(i);
      const Vec3 leg = pose.position + arm - base_joint(i);
      CHECK(std::abs(leg.norm() - lengths(i)) <= 1e-12);
      CHECK(std::abs(leg.normalized().dot(v + w.cross(arm)) - rates(i)) <= 1e-12);
    }
  }
}

TEST_CASE("the Stewart platform's static leg forces are J^-T times the weights' wrench",
          "[models][loops][stewart]") {
  MultibodySystem system(Model::from<gen::stewart>());
  const State home = system.initial_state();
  std::mt19937 rng(3u);
  std::uniform_real_distribution<double> change(-0.1, 0.1);
  for (int k = 0; k < 10; ++k) {
    Vector lengths = home.q;
    for (int i = 0; i < 6; ++i) lengths(i) += change(rng);
    CAPTURE(k, lengths.transpose());
    const State s = stewart_state(lengths, Vector::Zero(6));
    // At rest M·qdd + h = f: the leg forces (pushing) holding the platform are h.
    Vector h;
    system.bias_forces_emitted(s, h);
    // Independently: the platform's twist (v, w at G) gives the leg rates
    // ld_i = u_i·(v + w × r_i), ld = J·(v, w); the leg forces f hold the
    // weights' wrench W (force, moment about G) when Jᵀ·f + W = 0. A leg's own
    // weight reaches the platform through its ball joint: with its cylinder's
    // G at c from the base and its piston's at d from the ball joint, both on
    // the leg, their velocities are (c/L)·(I - u·uᵀ)·v_P and
    // v_P - (d/L)·(I - u·uᵀ)·v_P, so the leg's weight acts at P as
    // (m_p·I + ((m_c·c - m_p·d)/L)·(I - u·uᵀ))·g_vec.
    const Pose pose = platform_pose(system.extended_state(s));
    const Vec3 gravity(0, 0, -g);
    Eigen::Matrix<double, 6, 6> J;
    Eigen::Matrix<double, 6, 1> W;
    W << platform_mass * gravity, Vec3::Zero();
    for (int i = 0; i < 6; ++i) {
      const Vec3 r = pose.rotation * platform_joint(i);
      const Vec3 leg = pose.position + r - base_joint(i);
      const double L = leg.norm();
      const Vec3 u = leg / L;
      J.row(i) << u.transpose(), r.cross(u).transpose();
      const Mat3 across = Mat3::Identity() - u * u.transpose();
      const Vec3 F = (piston_mass * Mat3::Identity() +
                      (cylinder_mass * cylinder_g - piston_mass * piston_g) / L * across) *
                     gravity;
      W.head<3>() += F;
      W.tail<3>() += r.cross(F);
    }
    const Eigen::Matrix<double, 6, 1> f = J.transpose().partialPivLu().solve(-W);
    CAPTURE(f.transpose(), h.transpose());
    CHECK(max_abs(h - f) <= 1e-10 * max_abs(f));
  }
  // At the home pose the mechanism's symmetry (three-fold, each pair of legs
  // mirrored) shares the weights equally among the legs, which push.
  Vector h;
  system.bias_forces_emitted(home, h);
  CHECK(h.minCoeff() > 0);
  CHECK(h.maxCoeff() - h.minCoeff() <= 1e-10 * h.maxCoeff());
}

TEST_CASE("the Stewart platform on leg springs keeps its loops closed and its energy",
          "[models][loops][stewart]") {
  MultibodySystem system(Model::from<gen::stewart>());
  const State home = system.initial_state();
  // Undamped springs along the legs, base joint to platform joint, holding
  // the platform near its home pose.
  const int platform = system.model().body_index("platform");
  for (int i = 0; i < 6; ++i)
    system.add<PointSpringDamper>("leg" + std::to_string(i), BodyPoint{ground, base_joint(i)},
                                  BodyPoint{platform, platform_joint(i)}, 20e3, home.q(i) + 0.02);
  State start = home;
  start.qd << 0.3, -0.2, 0.1, 0.25, -0.3, 0.05;
  const double e0 = system.energies(start).total();
  double drift = 0, kinetic = 0;
  Gaps worst{0, 0};
  IntegratorOptions o;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-10;
  o.output_interval = 0.01;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    const Energies e = system.energies(s);
    drift = std::max(drift, std::abs(e.total() - e0));
    kinetic = std::max(kinetic, e.kinetic);
    const Gaps gaps = loop_gaps(system, s);
    worst = {std::max(worst.position, gaps.position), std::max(worst.velocity, gaps.velocity)};
  };
  const State end = make_integrator("dopri5", o)->integrate(system, start, 2.0);
  CHECK(end.t == 2.0);
  CHECK(kinetic > 0.5);  // J
  CHECK(drift <= 1e-7 * kinetic);
  CHECK(worst.position <= 1e-12);
  CHECK(worst.velocity <= 1e-12);
}

TEST_CASE("the Stewart platform swaying on its leg springs for 100 s keeps its loops closed",
          "[models][loops][stewart]") {
  // The scenario's motion (models/scenarios/stewart.json): undamped leg
  // springs of 100 kN/m free at the home lengths, leg 0 started 1 cm long.
  MultibodySystem system(Model::from<gen::stewart>());
  const State home = system.initial_state();
  for (int i = 0; i < 6; ++i)
    system.add<CoordinateSpringDamper>("leg" + std::to_string(i), i, 1e5, 0.0, home.q(i));
  State start = home;
  start.q(0) += 0.01;
  Gaps worst{0, 0};
  double legs = 0, sway = 0;  // the largest leg length error (inverse kinematics), platform x
  IntegratorOptions o;
  o.relative_tolerance = 1e-8;
  o.absolute_tolerance = 1e-8;
  o.output_interval = 0.01;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    const Gaps gaps = loop_gaps(system, s);
    worst = {std::max(worst.position, gaps.position), std::max(worst.velocity, gaps.velocity)};
    const Pose pose = platform_pose(system.extended_state(s));
    for (int i = 0; i < 6; ++i) {
      const Vec3 leg = pose.position + pose.rotation * platform_joint(i) - base_joint(i);
      legs = std::max(legs, std::abs(leg.norm() - s.q(i)));
    }
    sway = std::max(sway, std::abs(pose.position.x()));
  };
  const State end = make_integrator("dopri5", o)->integrate(system, start, 100.0);
  CHECK(end.t == 100.0);
  CHECK(sway > 1e-3);              // m: it moved sideways, not only up and down
  CHECK(worst.position <= 1e-10);  // m
  CHECK(worst.velocity <= 1e-10);  // m/s
  CHECK(legs <= 1e-10);            // m
}

namespace {

// A prescribed platform motion: heave z = 0.85 + 0.03·sin(w·t) and roll
// 0.05·sin(1.5·w·t), w = 2π rad/s; the legs' lengths and their first two
// derivatives by the inverse kinematics, l = |p + R·r_i - B_i| differentiated
// by hand: ld = u·vP, ldd = u·aP + (|vP|² - ld²)/l.
struct LegMotion {
  Vector l = Vector(6), ld = Vector(6), ldd = Vector(6);
};
LegMotion prescribed_legs(double t) {
  const double w = 2 * pi, heave = 0.03, tilt = 0.05;
  const Vec3 p(0, 0, 0.85 + heave * std::sin(w * t)), v(0, 0, heave * w * std::cos(w * t)),
      a(0, 0, -heave * w * w * std::sin(w * t));
  const double roll = tilt * std::sin(1.5 * w * t),
               roll_rate = tilt * 1.5 * w * std::cos(1.5 * w * t),
               roll_acceleration = -tilt * 2.25 * w * w * std::sin(1.5 * w * t);
  const Vec3 omega = roll_rate * Vec3::UnitX(), alpha = roll_acceleration * Vec3::UnitX();
  const Mat3 R = Eigen::AngleAxisd(roll, Vec3::UnitX()).toRotationMatrix();
  LegMotion m;
  for (int i = 0; i < 6; ++i) {
    const Vec3 r = R * platform_joint(i);
    const Vec3 leg = p + r - base_joint(i);
    const Vec3 vP = v + omega.cross(r), aP = a + alpha.cross(r) + omega.cross(omega.cross(r));
    m.l(i) = leg.norm();
    const Vec3 u = leg / m.l(i);
    m.ld(i) = u.dot(vP);
    m.ldd(i) = u.dot(aP) + (vP.squaredNorm() - m.ld(i) * m.ld(i)) / m.l(i);
  }
  return m;
}

}  // namespace

TEST_CASE("the Stewart platform's inverse dynamics, applied as leg forces, gives back its motion",
          "[models][loops][stewart]") {
  // Inverse dynamics: the leg forces f = M·ldd + h of the prescribed motion.
  MultibodySystem inverse(Model::from<gen::stewart>());
  const auto leg_forces = [&](double t) {
    const LegMotion m = prescribed_legs(t);
    State s = stewart_state(m.l, m.ld);
    s.t = t;
    Vector f, none, g_extra;
    inverse.residual(s, m.ldd, none, f, g_extra);
    return Vector(f);
  };
  // Forward dynamics under those forces, from the prescribed initial state.
  MultibodySystem forward(Model::from<gen::stewart>());
  forward.add<UserForce>(
      "legs",
      [&](const State& s, const Kinematics&, Loads& loads) {
        const Vector f = leg_forces(s.t);
        for (int i = 0; i < 6; ++i) loads.add_generalized(i, f(i));
      },
      KinematicsLevel::none);
  const LegMotion start = prescribed_legs(0.0);
  IntegratorOptions o;
  o.relative_tolerance = 1e-11;
  o.absolute_tolerance = 1e-11;
  double worst = 0;
  o.output_interval = 0.05;
  o.on_output = [&](const State& s, const Vector&, const Vector&) {
    const LegMotion m = prescribed_legs(s.t);
    worst = std::max({worst, max_abs(s.q - m.l), max_abs(s.qd - m.ld) / 10});
  };
  const State end =
      make_integrator("dopri5", o)->integrate(forward, stewart_state(start.l, start.ld), 1.0);
  CHECK(end.t == 1.0);
  CHECK(worst <= 1e-7);  // m (and s·m/s)
  // The platform's pose at the end is the prescribed one.
  const Pose pose = platform_pose(forward.extended_state(end));
  CHECK(std::abs(pose.position.z() - 0.85) <= 1e-7);
  CHECK((pose.rotation - Eigen::AngleAxisd(0.0, Vec3::UnitX()).toRotationMatrix()).norm() <= 1e-7);
  // The legs push, here at the top of the heave.
  const Vector f = leg_forces(0.25);
  CHECK(f.minCoeff() > 0);
}
