#pragma once
// From a model to the emitted C++ of docs/emitted_interface.md.
//
// Each entry point is one straight-line program over its own inputs, so it
// computes only what it needs: positions() never touches a velocity, and a
// dependent parameter nobody uses is never computed (dead code eliminated per
// entry point). The output is deterministic: the same model and options give
// the same bytes.

#include <optional>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "symbolic/program.hpp"

namespace symdyn::codegen {

struct Options {
  bool simplify = true;             // trigonometric simplification of the relative kinematics; each
                                    // entry point keeps the shorter of the simplified and plain programs
  bool symbolic_partials = true;    // false: EasyDyn's numeric partial velocities (qd = e_j)
  bool equations_of_motion = true;  // emit mass_matrix and bias_forces (needs symbolic partials)
  std::string name_space = "symdyn_generated";
};

// One emitted function: its input arrays (among t, q, qd, qdd, param, in
// order), its output arrays, and the program it prints, so that tests can run
// the interpreter on exactly what was emitted.
struct EmittedFunction {
  std::string name;
  std::vector<std::string> inputs;
  std::vector<std::pair<std::string, std::size_t>> outputs;  // name, size
  std::optional<symbolic::Program> program;  // absent for numeric partial velocities (a loop)
  symbolic::OperationCount operations;
};

struct GeneratedCode {
  std::string struct_name;  // the basename, made an identifier
  std::string header;       // <basename>.hpp
  std::string source;       // <basename>.cpp
  std::vector<EmittedFunction> functions;
};

// Derives and emits the model. `basename` names the files (the source includes
// "<basename>.hpp") and the struct (by default the generator uses <model>_<variant>). Throws model::ModelError for an invalid model.
GeneratedCode generate(const model::Model& model, std::string_view variant, std::string_view basename,
                       const Options& options = {});

}  // namespace symdyn::codegen
