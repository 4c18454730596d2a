#pragma once
// The derivation of the selected entry points: the kinematics, the equations
// of motion where an entry point needs them, each entry point's outputs (the
// catalogue's sources), and one program of all their outputs, also compiled
// per entry point where the code is short enough to print each whole.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/codegen/detail/input_symbols.hpp>
#include <symdyn/codegen/detail/selection.hpp>
#include <symdyn/codegen/generate.hpp>
#include <symdyn/model/kinematics.hpp>
#include <symdyn/symbolic/program.hpp>

namespace symdyn::codegen::detail {

// The entry points of one derivation and the program computing all their
// outputs (those of hand-written bodies aside), each distinct output array
// once. A short program is printed as one function per entry point, each its
// own program (`whole`, by entry point; absent for a hand-written body); a
// longer one as parts shared between the entry points (emit_cpp_shared).
struct Derivation {
  std::vector<EntryPoint> entries;
  std::vector<OutputArray> arrays;  // distinct output arrays, with names unique among them
  std::vector<std::vector<std::size_t>> arrays_of;  // (entries) its arrays, indices into `arrays`
  std::vector<symbolic::Definition> definitions;    // dependent symbols and intermediates
  symbolic::Program program;
  std::vector<std::optional<symbolic::Program>> whole;  // empty: shared
  bool simplified = false;                              // simplification changed some expression
};

// The outputs (indices among the program's) of each entry point with a
// program, in order: what each runs of the shared program.
std::vector<std::vector<std::size_t>> entry_outputs(const Derivation& d);

class Deriver {
 public:
  Deriver(const model::Model& model, const Options& options, const Selection& selection,
          const InputSymbols& inputs);

  // The derivation whose code is emitted: with simplification, the shorter
  // of the simplified and plain ones (see the definition).
  Derivation run();

  // Made by the first derivation with the equations of motion.
  const std::optional<DynamicsChoice>& dynamics_choice() const { return choice_; }
  // Which form of tau the derivatives differentiate, and why (empty: none derived).
  const std::string& derivatives_reason() const { return derivatives_reason_; }

 private:
  model::DeriveOptions derive_options(model::SimplifyFunction simplify = {}) const;
  Derivation derive(bool simplify);
  void compile_programs(Derivation& d) const;
  std::vector<EntryPoint> build_entry_points(const Quantities& quantities) const;
  bool derivable(const Needs& needs, const Quantities& quantities) const;
  // `with_kinematics`: also the kinematics' derivatives (Derivatives::all).
  DynamicsDerivatives derive_derivatives(
      const model::Dynamics& dynamics, const model::Kinematics& kinematics, bool with_kinematics,
      const std::vector<symbolic::Definition>& definitions) const;
  std::optional<symbolic::Program> compile(
      const EntryPoint& e, const std::vector<symbolic::Definition>& definitions) const;
  std::optional<symbolic::Program> whole_program(const Derivation& d, std::size_t e) const;

  const model::Model& model_;
  const Options& options_;
  const Selection& selection_;
  const InputSymbols& inputs_;
  Sizes sizes_;
  std::optional<model::Kinematics> plain_kinematics_;  // made first when simplifying (run())
  std::optional<DynamicsChoice> choice_;
  std::string derivatives_reason_;
};

}  // namespace symdyn::codegen::detail
