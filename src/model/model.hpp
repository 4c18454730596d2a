#pragma once
// The builder API: a multibody system described as CAGeM users know it.
//
//   Model m("slider_crank");
//   const Expr q0 = m.coordinate("q0");
//   const Expr l1 = m.parameter("l1", 0.1), l2 = m.parameter("l2", 0.3);
//   const Expr alpha = m.dependent("alpha", asin(l1 * sin(q0) / l2));
//   const Expr x = m.dependent("x", l1 * cos(q0) + l2 * cos(alpha));
//   m.body("crank").mass(1.0).inertia(1e-4, 8.3e-4, 8.3e-4).motion(Trotz(q0) * Tdisp(l1 / 2, 0,
//   0)); m.body("rod").mass(0.5).inertia(1e-4, 3.75e-3, 3.75e-3)
//       .motion(Tdisp(x, 0, 0) * Trotz(-alpha) * Tdisp(-l2 / 2, 0, 0));
//   m.gravity(0, -9.81, 0);
//   m.initial(q0, 0.0, 50.0);
//
// Symbols:
//   coordinates q     minimal coordinates, one per DOF; their rates qd and
//                     accelerations qdd are made alongside;
//   parameters        model constants: folded into the code as numbers, or kept
//                     as run-time inputs (one generated code for a sweep);
//   dependent p       explicit functions of q, time and earlier dependent
//                     parameters; kept as intermediate variables, or inlined
//                     (substituted) when `inline_dependents(true)`;
//   time t            for motions prescribed in time;
//   implicit p        dependent parameters of a closed kinematic loop, defined
//                     implicitly by the loop's equations g(t, q, p) = 0 with a
//                     starting guess (implicit_dependent, constraint,
//                     close_loop); the generator treats them as extra tree
//                     coordinates after q, the runtime solves them (docs/builder.md).
//
// Bodies have a mass, an inertia tensor at G in body axes, and a motion: a
// product of elementary transformations (transform.hpp), absolute or relative
// to another body. Mistakes raise ModelError naming the culprit.
// What is checked where (builder, validate(), generator, runtime): docs/errors.md.

#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/model/errors.hpp>
#include <symdyn/model/transform.hpp>
#include <symdyn/symbolic/diff.hpp>

namespace symdyn::model {

// A builder argument: an expression, or a plain number kept unchecked until
// the call that takes it, so that a NaN or an infinity is reported naming the
// body or gravity (Expr(double) itself refuses them without a name).
class Scalar {
 public:
  Scalar(Expr e) : expr_(e), is_number_(false) {}  // NOLINT(google-explicit-constructor)
  Scalar(double v) : number_(v) {}                 // NOLINT(google-explicit-constructor)
  // The expression; throws ModelError "<what> is not finite (nan)" for a non-finite number.
  Expr to_expr(std::string_view what) const;

 private:
  Expr expr_;
  double number_ = 0.0;
  bool is_number_ = true;
};

class Body {
 public:
  Body& mass(Scalar m);
  Body& inertia(Scalar ixx, Scalar iyy, Scalar izz);  // principal, diagonal in body axes
  Body& inertia(const Mat3& tensor);                  // full, symmetric
  Body& motion(const Transform& T0G);                 // absolute, or T_BG when relative_to
  Body& relative_to(std::string_view reference);

  const std::string& name() const { return name_; }
  Expr mass() const { return mass_; }
  const Mat3& inertia() const { return inertia_; }
  const Transform& motion() const { return motion_; }
  const std::optional<std::string>& reference() const { return reference_; }
  bool has_motion() const { return has_motion_; }

 private:
  friend class Model;
  explicit Body(std::string name);
  std::string name_;
  Expr mass_;
  Mat3 inertia_{};
  Transform motion_;
  std::optional<std::string> reference_;
  bool has_motion_ = false;
};

// A dependent parameter p = expression, with its rate and acceleration symbols.
struct Dependent {
  Expr symbol, rate, acceleration;
  Expr expression;
};

// A coordinate q with its rate and acceleration symbols and initial values;
// or an implicit dependent parameter (implicit, its initial value the guess
// the runtime's first solve starts from).
struct Coordinate {
  Expr q, qd, qdd;
  double initial = 0.0;
  double initial_rate = 0.0;
  bool implicit = false;
};

// A closed kinematic loop: its name and its equations g(t, q, p) = 0, none
// identically zero. A loop closed by close_loop has the bodies it joins, the
// point in global axes (body a's, x_a + R_a·point_a) and the axis (0, 1, 2:
// x, y, z) of the gap each equation is a component of; a loop given by its
// equations has body_a = body_b = -1 and no axes.
struct Loop {
  std::string name;
  std::vector<Expr> equations;
  int body_a = -1, body_b = -1;
  Vec3 point{};
  std::vector<int> axes;  // (equations) with body_a >= 0
};

// A dependent parameter substituted where it is used (inline_dependents): its
// name and expression kept for the diagnostics alone (model/diagnostics.hpp).
struct InlinedDependent {
  std::string name;
  Expr expression;
};

struct Parameter {
  Expr symbol;
  double value;
};

class Model {
 public:
  explicit Model(std::string name);

  const std::string& name() const { return name_; }

  Expr coordinate(std::string_view name);
  std::vector<Expr> coordinates(int n, std::string_view prefix = "q");  // q0, q1, ...
  // A constant: the number itself, or a run-time parameter symbol when
  // `runtime` is set or run-time parameters are requested for the whole model.
  Expr parameter(std::string_view name, double value, bool runtime = false);
  Expr dependent(std::string_view name, Expr expression);
  // A dependent parameter of a closed loop, determined by the loops'
  // equations (constraint, close_loop) and solved at run time from `guess`
  // (the first time) or from its last value. Declared as a coordinate after
  // every independent one (coordinates() holds q, then these).
  Expr implicit_dependent(std::string_view name, double guess);
  // Loop `name`: equations g(t, q, p) = 0 in the coordinates, the implicit
  // and explicit dependent parameters, t and run-time parameters. Equations
  // that are identically zero are dropped.
  void constraint(std::string_view name, std::vector<Expr> equations);
  // Loop `name` closed by a point of body_a coinciding with a point of body_b
  // (each in its body's axes, about its G): the components of
  // x_a + R_a·point_a - x_b - R_b·point_b that do not simplify to 0 (z in a
  // planar mechanism) are its equations. Both bodies, and the bodies they
  // are relative to, must have their motion already.
  void close_loop(std::string_view name, std::string_view body_a, const Vec3& point_a,
                  std::string_view body_b, const Vec3& point_b);
  Expr time() const { return time_; }
  Body& body(std::string_view name);
  void gravity(Scalar gx, Scalar gy, Scalar gz);
  void initial(Expr q, double value, double rate = 0.0);

  void inline_dependents(bool on) { inline_dependents_ = on; }
  void runtime_parameters(bool on) { runtime_parameters_ = on; }

  // The coordinates: the independent ones q first, then the implicit dependent
  // parameters p (the extended coordinates x = (q, p) of the tree).
  const std::vector<Coordinate>& coordinates() const { return coordinates_; }
  std::size_t num_independent() const { return coordinates_.size() - num_implicit_; }
  std::size_t num_implicit() const { return num_implicit_; }
  const std::vector<Loop>& loops() const { return loops_; }
  const std::vector<Dependent>& dependents() const { return dependents_; }
  const std::vector<InlinedDependent>& inlined_dependents() const { return inlined_dependents_; }
  const std::vector<Parameter>& parameters() const { return parameters_; }
  const std::deque<Body>& bodies() const { return bodies_; }
  const Vec3& gravity() const { return gravity_; }
  int body_index(std::string_view name) const;  // -1 if unknown
  // Each symbol's rate, for d/dt: q -> qd -> qdd of every coordinate (implicit ones too),
  // p -> pd -> pdd of every dependent parameter.
  symbolic::RateMap rates() const;
  // Index of each body's reference, or -1 for an absolute motion.
  std::vector<int> reference_indices() const;
  // Whether some body's motion is relative to each body.
  std::vector<bool> referenced() const;
  // Bodies in an order where every reference comes before the bodies relative to it.
  std::vector<int> topological_order() const;

  // Checks the whole model as the runtime will (docs/errors.md): structure,
  // masses and inertias (constant, positive, positive definite, triangle
  // inequalities), gravity, every coordinate moving a body, and every dependent
  // parameter and motion defined at the initial configuration. Throws ModelError naming
  // the first culprit.
  void validate() const;

  // The same mechanics, with each body whose motion begins with the whole
  // motion of another body of the same reference, a motion that rotates, made
  // relative to it (the longest such), keeping the rest of its motion. A chain
  // described from the ground then costs what the chain described link by link
  // costs: the earlier link's quantities are computed once and named, instead
  // of each later body's expressions expanding the product of rotations before
  // it again. A mere translation is left shared: it costs no products, and
  // naming it would hide its terms from the simplifier (the slider-crank's rod
  // and slider: 89 operations instead of 93).
  Model with_shared_motions_relative() const;

 private:
  void check_declared(Expr e, std::string_view where) const;
  bool is_declared(Expr symbol) const;
  void validate_structure() const;
  void validate_bodies() const;
  void validate_body(const Body& body) const;
  void validate_gravity() const;
  void validate_coordinates_move_bodies() const;
  void validate_initial_configuration() const;
  void validate_loops() const;
  // Body `name`'s absolute pose; ModelError naming `loop` unless it and its
  // references have motions.
  Transform::Pose absolute_pose(std::string_view name, std::string_view loop) const;
  void check_loop_name(std::string_view name) const;
  // A loop of the equations that are not identically 0 (the indices of those
  // kept into `kept`).
  Loop& add_loop(std::string_view name, std::vector<Expr> equations,
                 std::vector<int>* kept = nullptr);

  std::string name_;
  std::vector<Coordinate> coordinates_;  // independent, then implicit
  std::size_t num_implicit_ = 0;
  std::vector<Loop> loops_;
  std::vector<Dependent> dependents_;
  std::vector<InlinedDependent> inlined_dependents_;
  std::vector<Parameter> parameters_;
  std::deque<Body> bodies_;  // stable references for body()
  Vec3 gravity_;
  Expr time_;
  bool inline_dependents_ = false;
  bool runtime_parameters_ = false;
};

// What a model file provides to the generator: a name, its variants and how
// to build each.
struct Definition {
  std::string name;
  std::vector<std::string> variants;  // the first is the default
  std::function<void(Model&, std::string_view variant)> build;

  // Builds the given variant (the default if empty); throws ModelError naming
  // the valid variants when it is unknown.
  Model make(std::string_view variant = {}) const;
};

// Model files register their definition with a static Registration; the
// generator's main and the tests find them here by name.
std::vector<Definition>& registry();
const Definition& find_definition(
    std::string_view name);  // throws ModelError listing the known ones

struct Registration {
  explicit Registration(Definition definition) { registry().push_back(std::move(definition)); }
};

}  // namespace symdyn::model
