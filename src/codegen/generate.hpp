#pragma once
// From a model to the emitted C++ of docs/emitted_interface.md.
//
// Each entry point computes only what it needs: positions() never touches a
// velocity, and a dependent parameter nobody uses is never computed (dead
// code eliminated per entry point). A short model prints each entry point as
// one straight-line function; a long one shares work between them: one
// program of all their outputs, cut into internal functions (parts), each
// run by exactly the entry points that need its statements (positions(),
// velocities() and accelerations() run the same parts for the rotations), so
// that the compiler sees every statement once. The output is deterministic:
// the same model and options give the same bytes. Errors and what is checked
// where: docs/errors.md.

#include <optional>
#include <string>
#include <vector>

#include <symdyn/model/model.hpp>
#include <symdyn/symbolic/program.hpp>

namespace symdyn::codegen {

// The instructions per part of a long entry point: g++ -O2 spends time
// superlinear in a function's length, and shorter parts compile faster down to
// about this size (bench/results/emitted_code_layout.md).
inline constexpr std::size_t kDefaultPartInstructions = 125;

// Only a model whose entry points are longer than this together (their shared
// program's statements) is printed as parts: the calls cost a short one more than
// its compilation gains (bench/results/emitted_code_layout.md).
inline constexpr std::size_t kSplitAbove = 500;

// A source file of the emitted code holds at least this many bytes of the
// definitions (Options::sources): compiling a file costs about 0.02 s of
// parsing the header before its first definition (0.14 s more where it calls
// a function of <cmath>), and compiling 200 kB of definitions about 1 s
// (bench/results/build_loop.md).
inline constexpr std::size_t kBytesPerSource = 200'000;
// The most source files a model is spread over (Options::sources): more
// than there are definitions, or processors, compile no faster.
inline constexpr std::size_t kMaxSources = 256;

// How the accelerations are computed (docs/emitted_interface.md): by the
// mass matrix and bias forces and a Cholesky factorization at run time, or by
// the emitted recursive forward_dynamics() (the articulated-body algorithm);
// automatic: the one of fewer operations, counting ~nq³/6 + nq² for the
// factorization and solve.
enum class DynamicsMethod { automatic, mass_matrix, recursive };

// Which exact derivatives are emitted (Options::derivatives), each level including the one before.
enum class Derivatives { none, dynamics, all };

struct Options {
  bool simplify =
      true;  // trigonometric simplification of the relative kinematics; the code
             // keeps the shorter of the simplified and plain programs (detail/derivation.cpp)
  bool symbolic_partials = true;    // false: EasyDyn's numeric partial velocities (qd = e_j)
  bool equations_of_motion = true;  // emit mass_matrix, bias_forces and inverse_dynamics
  // Also emit exact derivatives, which the runtime uses wherever it needs a
  // Jacobian (docs/runtime.md): of the equations of motion
  // (inverse_dynamics_derivatives, growing as nq²), and with `all` of the
  // kinematics force elements at body points read (kinematics_derivatives,
  // growing as nbody·nq²: chain_64's are too long to compile quickly).
  Derivatives derivatives = Derivatives::none;
  // Also emit joint_reactions: the wrench every body's joint transmits
  // (docs/emitted_interface.md), which the runtime reports where emitted.
  bool joint_reactions = false;
  // recursive: forward_dynamics where the articulated-body algorithm applies
  // (else the mass matrix, GeneratedCode::dynamics says why).
  DynamicsMethod dynamics = DynamicsMethod::automatic;
  std::string name_space = "symdyn_generated";
  // Entry points longer than split_above statements together are emitted as
  // internal functions of at most part_instructions statements each, shared
  // between them (symbolic::emit_cpp_shared); 0: each entry point whole. Why
  // these values: see kDefaultPartInstructions and kSplitAbove.
  std::size_t part_instructions = kDefaultPartInstructions;
  std::size_t split_above = kSplitAbove;
  // The definitions are spread over up to this many source files, compiled in
  // parallel: <basename>.cpp, then <basename>.2.cpp ... <basename>.N.cpp
  // (GeneratedCode::more_sources), each with source_bytes of them or more;
  // the files left over hold a comment alone, so that a build can name them
  // all in advance. 1: one file.
  std::size_t sources = 1;
  std::size_t source_bytes = kBytesPerSource;
  // Emit only these entry points (and those their hand-written bodies call),
  // to call them directly: code to draw a scene needs positions() alone.
  // Empty: every entry point, which MultibodySystem needs. A name not emitted
  // with these options is an error naming the ones that are.
  std::vector<std::string> entry_points;
};

// One emitted function: its input arrays (among t, q, qd, qdd, tau, param,
// F_applied, M_applied, in order), its output arrays, and the program it runs
// (the instructions of the parts it calls, when shared), so that tests can
// run the interpreter on exactly what was emitted.
struct EmittedFunction {
  std::string name;
  std::vector<std::string> inputs;
  std::vector<std::pair<std::string, std::size_t>> outputs;  // name, size
  std::optional<symbolic::Program> program;  // absent for numeric partial velocities (a loop)
  symbolic::OperationCount operations;
};

// Which way the accelerations go, and why.
struct DynamicsChoice {
  bool recursive = false;                  // forward_dynamics emitted
  std::size_t recursive_operations = 0;    // of forward_dynamics (0: not derived)
  std::size_t mass_matrix_operations = 0;  // of dynamics() plus nq³/6 + nq² for Cholesky and solve
  std::string reason;                      // one line for --stats and the header
};

struct GeneratedCode {
  std::string struct_name;  // the basename
  DynamicsChoice dynamics;
  std::string derivatives;  // which form of tau inverse_dynamics_derivatives differentiates, and
                            // why (or empty)
  std::string header;       // <basename>.hpp
  std::string source;       // <basename>.cpp
  std::vector<std::string> more_sources;  // <basename>.2.cpp ... (Options::sources - 1 of them)
  std::vector<EmittedFunction> functions;
};

// Throws model::ModelError naming the culprit unless the basename and each
// component of the namespace are C++ identifiers a program may declare (not
// keywords, not reserved: no '__', no leading '_'), and the variant, printed
// only inside a string literal, has the shape of one (model/identifier.hpp).
void check_options(std::string_view variant, std::string_view basename, const Options& options);

// Derives and emits the model. `basename` names the files (the source includes
// "<basename>.hpp") and the struct (by default the generator uses
// <model>_<variant>). Checks the options (check_options) and the model
// (Model::validate) first; throws model::ModelError for an invalid model, the
// errors of the symbolic engine during derivation included.
GeneratedCode generate(const model::Model& model, std::string_view variant,
                       std::string_view basename, const Options& options = {});

}  // namespace symdyn::codegen
