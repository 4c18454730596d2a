#pragma once
// The catalogue of entry points: one row per emitted function (its name, doc,
// inputs, outputs with their shapes, what it needs derived, and where each
// output comes from). The table itself is in entry_points.cpp; the emitter,
// the selection (Options::entry_points) and its error messages, the header's
// declarations and docs/emitted_interface.md's check (tests/codegen/
// entry_points_test.cpp) all read it, so that an entry point is added in one
// place. Internal to codegen: not installed.

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/codegen/detail/constraint_derivatives.hpp>
#include <symdyn/codegen/detail/dynamics_derivatives.hpp>
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/constraints.hpp>
#include <symdyn/model/dynamics.hpp>
#include <symdyn/model/kinematics.hpp>
#include <symdyn/model/model.hpp>

namespace symdyn::codegen::detail {

// The input arrays of the emitted functions; an entry point takes some of
// them, always in this order (t is a scalar). F_applied and M_applied are
// the loads at every body's G in global axes (nbody x 3 each); mu weighs the
// loops' equations (ncon, empty without loops).
enum class Input { t, q, qd, qdd, tau, param, F_applied, M_applied, mu };
inline constexpr Input kInputs[] = {Input::t,         Input::q,         Input::qd,
                                    Input::qdd,       Input::tau,       Input::param,
                                    Input::F_applied, Input::M_applied, Input::mu};
std::string_view input_name(Input input);  // "t", "q", ...

// What one derivation made, from which the outputs are taken.
struct Quantities {
  const model::Model& model;
  const model::Kinematics& kinematics;
  const model::Dynamics* dynamics;  // null unless the equations of motion were derived
  const DynamicsDerivatives* derivatives = nullptr;  // null unless their derivatives were derived
  const model::Constraints* constraints = nullptr;   // null unless the model has closed loops
  // null unless the model has closed loops and the derivatives were derived
  const ConstraintDerivatives* constraint_derivatives = nullptr;
};

// The expressions of one output array, row-major.
using Source = std::function<std::vector<model::Expr>(const Quantities&)>;

struct OutputSpec {
  std::string_view name{};
  // Dimensions separated by " x ", each a number or nq, nbody, ndep, nind,
  // ncon: "nbody x 3 x 3".
  std::string_view shape{};
  Source source{};  // empty for the outputs of a hand-written body
  // Written sparsely: the emitted code writes only the entries it computes,
  // never its structural zeros (the entries +0.0 at every call); they are the
  // caller's, who zeroes the array once before the first call and keeps it
  // for this output alone. Otherwise every entry is written at every call
  // (symbolic::kZeroedArrayShare). For the long outputs of mostly structural
  // zeros that the runtime keeps in buffers of its own (the partial
  // velocities and their derivatives), where zeroing them at every call is
  // most of the work.
  bool sparse = false;
};

// The model's sizes that shapes and hand-written bodies are written in.
// With closed loops, nq counts the extended coordinates x = (q, p): nind
// independent ones, then the ncon implicit dependent parameters (one per
// loop equation).
struct Sizes {
  std::size_t nq = 0, nbody = 0, ndep = 0, nind = 0, ncon = 0;
};

// "(2 x 3 x 3)" for "nbody x 3 x 3" with 2 bodies.
std::string shape_text(std::string_view shape, const Sizes& sizes);
// The number of entries of an array of that shape.
std::size_t shape_size(std::string_view shape, const Sizes& sizes);

// Partial velocities dv/dqd, dw/dqd: symbolic (differentiated), or numeric
// (EasyDyn's v(qd = e_j) - v(qd = 0), Options::symbolic_partials false).
enum class Partials { either, symbolic, numeric };

// What must be derived, asked or chosen for an entry point to be emitted.
struct Needs {
  // The bodies' absolute motion; without it an entry point reads only each
  // body's motion relative to its reference (what CAGeM emitted), and when
  // only such entry points are selected no absolute motion is composed.
  bool absolute_motion = false;
  Partials partials = Partials::either;  // emitted only with these partial velocities
  bool equations_of_motion = false;      // Options::equations_of_motion: model::Dynamics derived
  bool recursive_dynamics =
      false;  // the articulated-body algorithm applies and was chosen (DynamicsChoice)
  Derivatives derivatives =
      Derivatives::none;   // at least this Options::derivatives (or named alone)
  bool reactions = false;  // Options::joint_reactions (or named alone)
  bool loops = false;      // only for a model with closed loops (model::Constraints derived)
};

// A hand-written C++ body, in place of a program.
using WriteBody = std::string (*)(const Sizes& sizes);

struct EntryPointSpec {
  std::string_view name{};
  std::string_view doc{};       // the header's comment; several lines are separated by '\n'
  std::vector<Input> inputs{};  // in the order of kInputs
  std::vector<OutputSpec> outputs{};
  Needs needs{};
  std::string_view returns = "void";  // the C++ return type
  // A hand-written body instead of a program (a loop, a check), what the
  // header says of it instead of an operation count, and the entry point it
  // calls (emitted with it when selected alone).
  WriteBody body = nullptr;
  std::string_view note{};
  std::string_view calls{};
  // Off the runtime's hot path: not counted when deciding whether the code is
  // short enough to print each entry point whole (Options::split_above).
  bool cold = false;
};

// Every entry point, in the order they are emitted. A name has one row, or one
// per form where Needs::partials tells the forms apart (partial_velocities).
std::span<const EntryPointSpec> catalogue();

// The distinct names of the catalogue, in order.
std::vector<std::string_view> entry_point_names();

// Whether `name` is in the catalogue.
bool is_entry_point(std::string_view name);

// An entry point of one derivation: its row, and the expressions of its
// outputs (none for a hand-written body).
struct OutputArray {
  std::string name;
  std::string shape;  // "(2 x 3 x 3)"
  std::vector<model::Expr> values;
  bool sparse = false;  // OutputSpec::sparse
};

struct EntryPoint {
  const EntryPointSpec* spec = nullptr;
  std::vector<OutputArray> outputs;
  std::string body;  // the hand-written body, if any

  std::string_view name() const { return spec->name; }
  bool hand_written() const { return spec->body != nullptr; }
};

// The row with its outputs taken from `quantities`.
EntryPoint build_entry_point(const EntryPointSpec& spec, const Quantities& quantities,
                             const Sizes& sizes);

}  // namespace symdyn::codegen::detail
