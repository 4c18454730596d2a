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

// g++ -O2 spends time superlinear in a function's length (register
// allocation, CSE, alias walks over the stores before each load): amru5's
// 10 000-instruction mass matrix took most of a 51 s compilation. Why 500:
// amru5 dependent with everything emitted (40 000 instructions) compiled in
// 56 s in one function per entry point, 30 s in parts of 1000, 25 s of 500,
// 22 s of 250 and 20 s of 125 (g++ 12 -O2, CPU time on a loaded machine,
// constant runs not yet printed as loops); below 500, values crossing parts
// (loads and stores of the scratch array) grow faster than the gain: 13 100
// loads at 500, 15 700 at 250, 19 300 at 125. With runs of 8 constants as
// loops, 500 and 250 gave 16.3 s and 17.4 s.
inline constexpr std::size_t kDefaultPartInstructions = 500;

struct Options {
  bool simplify = true;             // trigonometric simplification of the relative kinematics; each
                                    // entry point keeps the shorter of the simplified and plain programs
  bool symbolic_partials = true;    // false: EasyDyn's numeric partial velocities (qd = e_j)
  bool equations_of_motion = true;  // emit mass_matrix and bias_forces (needs symbolic partials)
  std::string name_space = "symdyn_generated";
  // An entry point longer than this many computing instructions is emitted as
  // internal functions of at most this many each (symbolic::emit_cpp_parts);
  // 0: never split. Why this value: see kDefaultPartInstructions.
  std::size_t part_instructions = kDefaultPartInstructions;
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
