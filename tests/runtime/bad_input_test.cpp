// Every bad input of the runtime API, one case each: the exception type and the
// culprit named in its message (docs/errors.md). The models of models/ are made
// to fail in the model's own terms: a crank longer than its rod (a dependent
// parameter out of its function's domain) and free bodies at their gimbal lock.

#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <regex>
#include <string>

#include "gimbal_zxz.hpp"
#include "gimbal_zyx.hpp"
#include "long_crank_asin.hpp"
#include "long_crank_sqrt.hpp"
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/runtime.hpp>

namespace {

using namespace symdyn::runtime;
using symdyn_generated::gimbal_zxz;
using symdyn_generated::gimbal_zyx;
using symdyn_generated::long_crank_asin;
using symdyn_generated::long_crank_sqrt;

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();
constexpr double pi = std::numbers::pi;

// The message of the exception of type E that f throws; fails the test if f
// throws nothing or another type.
template <typename E, typename F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    FAIL("another exception: " << e.what());
  }
  FAIL("no exception");
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The number after `prefix` in the message, e.g. the argument of "asin(".
double number_after(const std::string& message, const std::string& prefix) {
  const auto at = message.find(prefix);
  REQUIRE(at != std::string::npos);
  return std::stod(message.substr(at + prefix.size()));
}

State state(double t, std::initializer_list<double> q, std::initializer_list<double> qd) {
  State s;
  s.t = t;
  s.q = Eigen::Map<const Vector>(q.begin(), static_cast<Eigen::Index>(q.size()));
  s.qd = Eigen::Map<const Vector>(qd.begin(), static_cast<Eigen::Index>(qd.size()));
  s.y.resize(0);
  return s;
}

// A crank of 0.4 on a rod of 0.3: the rod cannot follow past sin(q0) = 0.75.
MultibodySystem long_crank(Model model) {
  model.set_parameter("l1", 0.4);
  return MultibodySystem(std::move(model));
}

// q0 = 1.2: l1·sin(q0)/l2 = 1.2427..., outside asin's [-1, 1]; l2² - (l1·sin(q0))² < 0.
constexpr double q_out = 1.2;
const double sqrt_argument = 0.3 * 0.3 - std::pow(0.4 * std::sin(q_out), 2);

void check_asin_named(const std::string& m, double t) {
  INFO(m);
  CHECK(m.rfind(fmt::format("t = {}: dependent parameter 'alpha': asin(", t), 0) == 0);
  CHECK(contains(m, "outside its function's domain [domain of asin: [-1, 1]]"));
  // The state named (q_out, or a difference step away from it) and the argument there.
  const double q = number_after(m, "(q0 = ");
  CHECK(q == Approx(q_out).epsilon(1e-5));
  CHECK(number_after(m, "asin(") == Approx(0.4 * std::sin(q) / 0.3).epsilon(1e-12));
}

void check_sqrt_named(const std::string& m) {
  INFO(m);
  CHECK(contains(m, "dependent parameter 's': sqrt("));
  CHECK(number_after(m, "sqrt(") == Approx(sqrt_argument).epsilon(1e-12));
  CHECK(contains(m, "outside its function's domain [domain of sqrt: [0, inf)]"));
}

}  // namespace

// --- run-time parameters and names ---------------------------------------------

TEST_CASE("bad input: an unknown parameter name is named", "[runtime][bad_input]") {
  Model m = Model::from<long_crank_asin>();
  CHECK(message_of<ModelError>([&] { m.set_parameter("l3", 1.0); }) ==
        "model 'long_crank': no parameter named 'l3' (parameters: l1, l2, rod_mass, slider_mass)");
}

TEST_CASE("bad input: a NaN or infinite parameter is named, the old values kept",
          "[runtime][bad_input]") {
  Model m = Model::from<long_crank_asin>();
  CHECK(message_of<ModelError>([&] { m.set_parameter("l2", not_a_number); }) ==
        "model 'long_crank': parameter 'l2' must be finite, not nan");
  CHECK(message_of<ModelError>([&] { m.set_parameter("l1", -INFINITY); }) ==
        "model 'long_crank': parameter 'l1' must be finite, not -inf");
  CHECK(m.parameters() == std::vector<double>{0.1, 0.3, 0.5, 0.3});
}

TEST_CASE("bad input: a parameter making a mass non-positive names the body",
          "[runtime][bad_input]") {
  Model m = Model::from<long_crank_asin>();
  CHECK(message_of<ModelError>([&] { m.set_parameter("rod_mass", 0.0); }) ==
        "body 'rod': mass 0 is not positive");
  CHECK(message_of<ModelError>([&] { m.set_parameter("slider_mass", -2.0); }) ==
        "body 'slider': mass -2 is not positive");
  CHECK(m.mass(1) == 0.5);
}

TEST_CASE("bad input: the wrong number of parameter values", "[runtime][bad_input]") {
  Model m = Model::from<long_crank_asin>();
  CHECK(message_of<ModelError>([&] {
          m.set_parameters({0.1, 0.3});
        }) == "model 'long_crank': 2 parameter values given, expected 4");
}

TEST_CASE("bad input: unknown body and coordinate names (force elements find them by name)",
          "[runtime][bad_input]") {
  const Model m = Model::from<gimbal_zyx>();
  CHECK(message_of<ModelError>([&] { (void)m.body_index("wheel"); }) ==
        "model 'gimbal': no body named 'wheel' (bodies: frame)");
  CHECK(message_of<ModelError>([&] { (void)m.coordinate_index("heading"); }) ==
        "model 'gimbal': no coordinate named 'heading' (coordinates: x, y, z, yaw, pitch, roll)");
  CHECK(m.coordinate_index("pitch") == 4);
}

// --- a description that cannot be right -----------------------------------------

namespace {
void unit_inertia(const double*, double* m, double* I) {
  m[0] = 1.0;
  for (int k = 0; k < 9; ++k) I[k] = k % 4 == 0 ? 1.0 : 0.0;
}
ModelDescription one_body() {
  ModelDescription d;
  d.model = "toy";
  d.nq = 1;
  d.nbody = 1;
  d.q_names = {"q"};
  d.q_initial = {0.0};
  d.qd_initial = {0.0};
  d.body_names = {"b"};
  d.reference_body = {-1};
  d.inertia = unit_inertia;
  return d;
}
}  // namespace

TEST_CASE("bad input: a description with arrays of the wrong size names the array",
          "[runtime][bad_input]") {
  ModelDescription d = one_body();
  d.q_names.clear();
  CHECK(message_of<ModelError>([&] { Model{d}; }) ==
        "model 'toy': q_names has 0 entries, expected 1");
}

TEST_CASE("bad input: a missing entry point is named", "[runtime][bad_input]") {
  ModelDescription d = one_body();
  d.inertia = nullptr;
  CHECK(message_of<ModelError>([&] { Model{d}; }) ==
        "model 'toy' (variant ''): entry point 'inertia' was not emitted");
  const Model m(one_body());
  double M = 0.0;
  const double q = 0.0;
  CHECK(message_of<ModelError>([&] { m.mass_matrix(0.0, &q, &M); }) ==
        "model 'toy' (variant ''): entry point 'mass_matrix' was not emitted");
  CHECK(message_of<ModelError>([&] { MultibodySystem{Model(one_body())}; }) ==
        "model 'toy': a multibody system needs the entry point 'velocities'");
}

TEST_CASE("bad input: malformed diagnostics in a description are named", "[runtime][bad_input]") {
  ModelDescription d = one_body();
  d.angle_sequences = {{0, {0, 0, 3}, "zyx"}};
  CHECK(message_of<ModelError>([&] { Model{d}; }) ==
        "model 'toy': angle sequence 'zyx' of body 0 is malformed");
  d = one_body();
  d.ndep = 1;
  d.dependent_names = {"p"};
  d.domain_checks = {{"p", "tan"}};
  d.domain_arguments = [](double, const double*, const double*, double*) {};
  CHECK(message_of<ModelError>([&] { Model{d}; }) ==
        "model 'toy': domain check of unknown function 'tan'");
}

// --- states ----------------------------------------------------------------------

TEST_CASE("bad input: a NaN or infinite coordinate names it", "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  Vector qdd, yd;
  CHECK(message_of<NumericError>([&] {
          sys.accelerations(state(0.25, {not_a_number}, {1.0}), qdd, yd);
        }) == "t = 0.25: coordinate 'q0' is not finite (q = nan, qd = 1)");
  CHECK(message_of<NumericError>([&] {
          sys.accelerations(state(0.25, {0.1}, {INFINITY}), qdd, yd);
        }) == "t = 0.25: coordinate 'q0' is not finite (q = 0.1, qd = inf)");
}

TEST_CASE("bad input: a time that is not finite", "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  Vector qdd, yd;
  CHECK(message_of<NumericError>([&] {
          sys.accelerations(state(not_a_number, {0.1}, {1.0}), qdd, yd);
        }) == "time is not finite (nan)");
}

TEST_CASE("bad input: a state of the wrong size is a ModelError with both sizes",
          "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  Vector qdd, yd, f, g;
  CHECK(message_of<ModelError>([&] {
          sys.accelerations(state(0.0, {0.1, 0.2}, {1.0}), qdd, yd);
        }) == "model 'long_crank': a state with 2 q, 1 qd, 0 y given; expected 1, 1, 0");
  CHECK(message_of<ModelError>([&] {
          sys.residual(state(0.0, {0.1}, {}), Vector::Zero(1), yd, f, g);
        }) == "model 'long_crank': a state with 1 q, 0 qd, 0 y given; expected 1, 1, 0");
}

TEST_CASE("bad input: extra states: mismatched names, missing equations, a NaN value",
          "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  CHECK(message_of<ModelError>([&] {
          sys.set_extra_states({"current", "flux"}, Vector::Zero(1), {});
        }) == "2 extra states named but 1 initial values given");
  CHECK(message_of<ModelError>([&] { sys.set_extra_states({"current"}, Vector::Zero(1), {}); }) ==
        "extra states need their equations");
  sys.set_extra_states({"current"}, Vector::Zero(1),
                       [](const State&, const Kinematics&, Eigen::Ref<Vector> yd) { yd(0) = 0.0; });
  State s = sys.initial_state();
  s.y(0) = not_a_number;
  Vector qdd, yd;
  CHECK(message_of<NumericError>([&] { sys.accelerations(s, qdd, yd); }) ==
        "t = 0: extra state 'current' is not finite (nan)");
}

// --- force elements ---------------------------------------------------------------

TEST_CASE("bad input: a null force element", "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  CHECK(message_of<ModelError>([&] { sys.add(nullptr); }) == "a null force element was added");
}

TEST_CASE("bad input: a force element's non-finite load names the element and the body",
          "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<gimbal_zyx>());
  sys.add<PointLoad>("thruster", BodyPoint{sys.model().body_index("frame"), Vec3::Zero()},
                     [](const State&, const Kinematics&, Vec3& f, Vec3&) { f(2) = not_a_number; });
  Vector qdd, yd;
  CHECK(message_of<NumericError>([&] { sys.accelerations(sys.initial_state(), qdd, yd); }) ==
        "t = 0: load 'thruster': force or moment on body 'frame' is not finite");
}

TEST_CASE("bad input: a non-finite generalized force names the element and the coordinate",
          "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<gimbal_zyx>());
  sys.add<CoordinateForce>("motor", sys.model().coordinate_index("roll"),
                           [](double, double, double, const State&) { return INFINITY; });
  Vector qdd, yd;
  CHECK(message_of<NumericError>([&] { sys.accelerations(sys.initial_state(), qdd, yd); }) ==
        "t = 0: coordinate force 'motor': generalized force on coordinate 'roll' is not finite");
}

TEST_CASE("bad input: an element that reads no kinematics but pushes a body is named",
          "[runtime][bad_input]") {
  MultibodySystem sys(Model::from<gimbal_zyx>());
  sys.add<UserForce>(
      "wind",
      [](const State&, const Kinematics&, Loads& loads) {
        loads.add_force(0, Vec3(1.0, 0.0, 0.0));
      },
      KinematicsLevel::none);
  Vector qdd, yd;
  CHECK(contains(
      message_of<ModelError>([&] { sys.accelerations(sys.initial_state(), qdd, yd); }),
      "user force 'wind' applies a force on a body but declares that it reads no kinematics"));
}

// --- dependent parameters out of their domain --------------------------------------

TEST_CASE(
    "bad input: asin out of its domain names the dependent parameter, the function and its "
    "argument",
    "[runtime][bad_input][domain]") {
  MultibodySystem sys = long_crank(Model::from<long_crank_asin>());
  Vector qdd, yd, f, g;
  check_asin_named(
      message_of<NumericError>([&] { sys.accelerations(state(0.5, {q_out}, {2.0}), qdd, yd); }),
      0.5);
  // The residual form (implicit integrators, statics) and the kinematics (energies) say the same.
  check_asin_named(message_of<NumericError>([&] {
                     sys.residual(state(0.5, {q_out}, {2.0}), Vector::Zero(1), yd, f, g);
                   }),
                   0.5);
  check_asin_named(message_of<NumericError>([&] { sys.energies(state(0.5, {q_out}, {2.0})); }),
                   0.5);
  // Inside the domain, nothing is refused.
  REQUIRE_NOTHROW(sys.accelerations(state(0.5, {0.8}, {2.0}), qdd, yd));
}

TEST_CASE("bad input: the assembled equations name the same dependent parameter",
          "[runtime][bad_input][domain]") {
  MultibodySystem sys = long_crank(Model::from<long_crank_asin>());
  sys.set_source(EquationsSource::assembled);
  Vector qdd, yd;
  check_asin_named(
      message_of<NumericError>([&] { sys.accelerations(state(0.5, {q_out}, {2.0}), qdd, yd); }),
      0.5);
}

TEST_CASE("bad input: sqrt of a negative names the dependent parameter",
          "[runtime][bad_input][domain]") {
  MultibodySystem sys = long_crank(Model::from<long_crank_sqrt>());
  Vector qdd, yd;
  check_sqrt_named(
      message_of<NumericError>([&] { sys.accelerations(state(0.0, {q_out}, {2.0}), qdd, yd); }));
}

TEST_CASE(
    "bad input: a domain error with force elements attached is named before the body it breaks",
    "[runtime][bad_input][domain]") {
  MultibodySystem sys = long_crank(Model::from<long_crank_asin>());
  sys.add<PointLoad>("push", BodyPoint{sys.model().body_index("slider"), Vec3::Zero()},
                     Vec3(1.0, 0.0, 0.0));
  Vector qdd, yd;
  check_asin_named(
      message_of<NumericError>([&] { sys.accelerations(state(0.5, {q_out}, {2.0}), qdd, yd); }),
      0.5);
}

namespace {
// A model whose only restricted operation evaluates to exactly 1: defined, but
// its derivative is infinite there.
void at_edge(double, const double*, const double*, double* arguments) {
  arguments[0] = 1.0;
  arguments[1] = 0.0;
  arguments[2] = 1.0;
}
}  // namespace

TEST_CASE("bad input: a dependent parameter at the edge of its domain is named as such",
          "[runtime][bad_input][domain]") {
  ModelDescription d = one_body();
  d.ndep = 1;
  d.dependent_names = {"beta"};
  d.domain_checks = {{"beta", "acos"}};
  d.domain_arguments = at_edge;
  const Model m(d);
  const double q = 0.0;
  CHECK(m.domain_error(0.0, &q) ==
        "dependent parameter 'beta': acos(1) is at the edge of its function's domain, where its "
        "derivative is "
        "infinite [domain of acos: [-1, 1]]");
}

// --- singular mass matrices: angle sequences at their lock -------------------------

TEST_CASE("bad input: a Z-Y-X sequence at pitch = 90 deg is named as such",
          "[runtime][bad_input][gimbal]") {
  MultibodySystem sys(Model::from<gimbal_zyx>());
  REQUIRE(
      sys.model()
          .has_forward_dynamics());  // its failed pivot falls back to M, which names the culprit
  Vector qdd, yd;
  for (double pitch : {pi / 2, -pi / 2, 3 * pi / 2}) {
    // The emitted forward dynamics flags the body's last angle: its pivot is rounding.
    const double q[6] = {0, 0, 0, 0.3, pitch, -0.2}, zero[6] = {};
    double solved[6];
    CHECK(gimbal_zyx::forward_dynamics(1.5, q, zero, zero, gimbal_zyx::param_defaults, solved) ==
          sys.model().coordinate_index("roll"));
    const std::string m = message_of<NumericError>([&] {
      sys.accelerations(state(1.5, {0, 0, 0, 0.3, pitch, -0.2}, {0, 0, 0, 0, 0, 0}), qdd, yd);
    });
    INFO(m);
    CHECK(m.rfind("t = 1.5: mass matrix is singular or indefinite: coordinates 'yaw', 'pitch', "
                  "'roll' of body "
                  "'frame' form a Z-Y-X angle sequence singular at pitch = " +
                      fmt::format("{} deg", std::round(pitch * 180 / pi)),
                  0) == 0);
    CHECK(number_after(m, "(pitch = ") == Approx(pitch).epsilon(1e-15));
  }
  // A micro-radian away the inertia left is small but real: solved (the test stays relative).
  REQUIRE_NOTHROW(sys.accelerations(
      state(0, {0, 0, 0, 0.3, pi / 2 - 1e-6, -0.2}, {0, 0, 0, 0, 0, 0}), qdd, yd));
  CHECK(qdd.allFinite());
}

TEST_CASE("bad input: a Z-X-Z (proper Euler) sequence at nutation = 0 is named",
          "[runtime][bad_input][gimbal]") {
  MultibodySystem sys(Model::from<gimbal_zxz>());
  REQUIRE(sys.model().has_forward_dynamics());
  Vector qdd, yd;
  const std::string m = message_of<NumericError>([&] {
    sys.accelerations(state(0, {0.4, 0.0, 1.0}, {0, 0, 0}), qdd, yd);
  });
  CHECK(contains(
      m,
      "coordinates 'precession', 'nutation', 'spin' of body 'frame' form a Z-X-Z angle sequence "
      "singular at nutation = 0 deg (nutation = 0 rad"));
  REQUIRE_NOTHROW(sys.accelerations(state(0, {0.4, 1e-6, 1.0}, {0, 0, 0}), qdd, yd));
}

// --- integrator options and states -------------------------------------------------

TEST_CASE("bad input: integrator options are named", "[runtime][bad_input][integrator]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  const State s0 = sys.initial_state();
  CHECK(message_of<OptionError>([&] { make_integrator("leapfrog"); }) ==
        "unknown integrator 'leapfrog'; valid names: newmark, generalized-alpha, rk4, dopri5, "
        "dop853, midpoint, "
        "cvode, arkode");
  IntegratorOptions o;
  o.absolute_tolerance = 0.0;
  CHECK(message_of<OptionError>([&] { make_integrator("dop853", o)->integrate(sys, s0, 1.0); }) ==
        "integrator 'dop853': tolerances must be finite and positive (relative 1e-06, absolute 0)");
  o = {};
  o.min_step = 1e-3;
  o.max_step = 1e-4;
  CHECK(message_of<OptionError>([&] { make_integrator("newmark", o)->integrate(sys, s0, 1.0); }) ==
        "integrator 'newmark': need 0 <= min_step <= max_step, 0 < max_step (min_step 0.001, "
        "max_step 0.0001)");
  o = {};
  o.q_scale = {1.0, 1.0};
  CHECK(message_of<OptionError>([&] { make_integrator("arkode", o)->integrate(sys, s0, 1.0); }) ==
        "integrator 'arkode': q_scale has 2 entries, the system has 1 coordinates");
  o = {};
  o.output_interval = 0.1;
  o.output_times = {0.5};
  CHECK(message_of<OptionError>([&] { make_integrator("dopri5", o)->integrate(sys, s0, 1.0); }) ==
        "integrator 'dopri5': give either output_times or output_interval, not both");
  CHECK(message_of<OptionError>([&] { make_integrator("midpoint")->integrate(sys, s0, 1.0); }) ==
        "integrator 'midpoint': a fixed-step run needs initial_step > 0 (the step)");
}

TEST_CASE("bad input: integrator options that are not finite are named",
          "[runtime][bad_input][integrator]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  const State s0 = sys.initial_state();
  const auto refused = [&](const IntegratorOptions& o) {
    return message_of<OptionError>([&] { make_integrator("dopri5", o)->integrate(sys, s0, 1.0); });
  };
  IntegratorOptions o;
  o.relative_tolerance = INFINITY;  // every step accepted: a silently wrong run
  CHECK(
      refused(o) ==
      "integrator 'dopri5': tolerances must be finite and positive (relative inf, absolute 1e-08)");
  o = {};
  o.absolute_tolerance = NAN;
  CHECK(
      refused(o) ==
      "integrator 'dopri5': tolerances must be finite and positive (relative 1e-06, absolute nan)");
  o = {};
  o.initial_step = INFINITY;
  CHECK(refused(o) == "integrator 'dopri5': initial_step inf must be finite and >= 0");
  o = {};
  o.output_interval = NAN;
  CHECK(refused(o) == "integrator 'dopri5': output_interval nan must be finite and >= 0");
  o = {};
  o.output_times = {0.5, NAN};
  CHECK(refused(o) == "integrator 'dopri5': output time nan is outside [0, 1]");
}

TEST_CASE(
    "bad input: a force element's constants are checked when it is made, naming it and the "
    "property",
    "[runtime][bad_input]") {
  CHECK(message_of<PropertyError>([] {
          PointLoad("push", {0, Vec3::Zero()}, Vec3(0, NAN, 0));
        }) == "load 'push': force: expected 3 finite numbers, found (0, nan, 0) (nan at 1)");
  ContactProperties contact;
  contact.stiffness = 1e5;
  CHECK(message_of<PropertyError>([&] {
          PlaneContact("foot", 0, Vec3::Zero(), 0.0, {Vec3::Zero(), Vec3::Zero()}, contact);
        }) == "contact 'foot': plane_normal: expected a non-zero direction, found (0, 0, 0)");
  contact.stiffness = 0.0;
  CHECK(message_of<PropertyError>([&] {
          PlaneContact("foot", 0, Vec3::Zero(), 0.0, {}, contact);
        }) == "contact 'foot': stiffness: expected a finite number > 0, found 0");
  BodyFrame skewed;
  skewed.axes << 1, 0.1, 0, 0, 1, 0, 0, 0, 1;
  CHECK_THAT(message_of<PropertyError>([&] { Bushing("mount", skewed, BodyFrame{}, {}); }),
             Catch::Matchers::StartsWith("bushing 'mount': a/axes: expected orthonormal axes"));
  const PropertyError e("spring 's'", "damping", "expected a finite number >= 0, found -1");
  CHECK(e.property() == "damping");
  CHECK(e.detail() == "expected a finite number >= 0, found -1");
}

TEST_CASE("bad input: an initial state of the wrong size or not finite",
          "[runtime][bad_input][integrator]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  CHECK(message_of<ModelError>([&] {
          make_integrator("cvode")->integrate(sys, state(0, {0, 0}, {0, 0}), 1.0);
        }) ==
        "integrator 'cvode': the initial state has q (2), qd (2), y (0); the system has 1 "
        "coordinates and 0 extra "
        "states");
  CHECK(message_of<NumericError>([&] {
          make_integrator("dopri5")->integrate(sys, state(0, {0.1}, {not_a_number}), 1.0);
        }) == "t = 0: qd of coordinate 'q0' is nan (initial state)");
}

TEST_CASE("bad input: an initial state out of a dependent parameter's domain, every integrator",
          "[runtime][bad_input][integrator][domain]") {
  MultibodySystem sys = long_crank(Model::from<long_crank_asin>());
  for (const std::string& name : integrator_names()) {
    CAPTURE(name);
    IntegratorOptions o;
    o.initial_step = 1e-3;
    check_asin_named(message_of<NumericError>([&] {
                       make_integrator(name, o)->integrate(sys, state(0.5, {q_out}, {2.0}), 1.0);
                     }),
                     0.5);
  }
}

// --- statics and linearization --------------------------------------------------------

TEST_CASE("bad input: statics and linearization lock coordinates that exist",
          "[runtime][bad_input][statics]") {
  MultibodySystem sys(Model::from<long_crank_asin>());
  StaticsOptions so;
  so.locked = {1};
  CHECK(message_of<ModelError>([&] { solve_statics(sys, sys.initial_state(), so); }) ==
        "statics: no coordinate 1 to lock");
  LinearizationOptions lo;
  lo.locked = {-1};
  CHECK(message_of<ModelError>([&] { linearize(sys, sys.initial_state(), lo); }) ==
        "linearize: no coordinate -1 to lock");
}

TEST_CASE("bad input: statics and linearization at a state out of a dependent parameter's domain",
          "[runtime][bad_input][statics][domain]") {
  MultibodySystem sys = long_crank(Model::from<long_crank_asin>());
  check_asin_named(
      message_of<NumericError>([&] { solve_statics(sys, state(0.5, {q_out}, {0.0})); }), 0.5);
  check_asin_named(message_of<NumericError>([&] { linearize(sys, state(0.5, {q_out}, {0.0})); }),
                   0.5);
  LinearizationOptions given;
  given.qdd = Vector::Zero(1);  // no accelerations first: the residual's differences meet it
  check_asin_named(
      message_of<NumericError>([&] { linearize(sys, state(0.5, {q_out}, {0.0}), given); }), 0.5);
  MultibodySystem root = long_crank(Model::from<long_crank_sqrt>());
  check_sqrt_named(
      message_of<NumericError>([&] { solve_statics(root, state(0.0, {q_out}, {0.0})); }));
}

TEST_CASE("bad input: statics and linearization at a gimbal lock name the angle sequence",
          "[runtime][bad_input][statics][gimbal]") {
  MultibodySystem sys(Model::from<gimbal_zyx>());
  const State lock = state(0, {0, 0, 0, 0.3, pi / 2, -0.2}, {0, 0, 0, 0, 0, 0});
  LinearizationOptions lo;
  lo.qdd = Vector::Zero(6);
  const std::string lin = message_of<NumericError>([&] { linearize(sys, lock, lo); });
  CHECK(lin.rfind("linearize: mass matrix is singular or indefinite at t = 0: coordinates 'yaw', "
                  "'pitch', 'roll' of "
                  "body 'frame' form a Z-Y-X angle sequence singular at pitch = 90 deg",
                  0) == 0);
  const std::string st = message_of<NumericError>([&] { solve_statics(sys, lock); });
  CHECK(contains(st, "statics: iteration matrix 100·M + K is singular at iteration 1"));
  CHECK(contains(
      st,
      "coordinates 'yaw', 'pitch', 'roll' of body 'frame' form a Z-Y-X angle sequence singular at "
      "pitch = 90 deg"));
}
