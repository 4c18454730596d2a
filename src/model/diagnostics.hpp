#pragma once
// What the runtime needs, on its cold path, to name why a simulation failed in
// the model's own words (docs/errors.md): the generator emits both as data.
//
// Domain checks: every operation of a dependent parameter whose function has a
// restricted real domain (asin, acos, sqrt, log, pow with an exponent that is not
// a positive integer), innermost first, dependent parameters in declaration
// order (inlined ones too: their names are kept), each operation with the first
// dependent parameter that has it. Evaluated in that order, the first argument
// outside its domain is the culprit of a non-finite value: "dependent parameter
// 'alpha': asin(1.2)".
//
// Angle sequences: a body whose rotation (its own motion's steps) contains three
// consecutive elementary rotations about x, y or z, each by a coordinate, the
// first two and the last two about different axes. Such a sequence loses a
// degree of freedom where its first and third axes align: cos(middle) = 0 for a
// Tait-Bryan sequence (Z-Y-X: all three axes different), sin(middle) = 0 for a
// proper Euler sequence (Z-X-Z: first and third the same).

#include <array>
#include <string>
#include <vector>

#include <symdyn/model/model.hpp>

namespace symdyn::model {

struct DomainCheck {
  std::string dependent;  // the dependent parameter's name
  std::string function;   // "asin", "acos", "sqrt", "log" or "pow"
  Expr argument;  // the argument (pow: the base), as written, of q, t, parameters, dependents
  Expr exponent;  // pow: the exponent; otherwise 0
  // The magnitude of the terms the argument is a sum of (|argument| when it is not
  // a sum): the argument's rounding is of the order of 1e-16 of it, so that the
  // runtime measures its distance to an edge at 0 relative to it. A sum of
  // squares is its own scale: it has no edge but 0 itself.
  Expr scale;
};

// In evaluation order (see above); each distinct operation once.
std::vector<DomainCheck> domain_checks(const Model& model);

struct AngleSequence {
  int body = 0;                      // index into Model::bodies()
  std::array<int, 3> coordinates{};  // indices into Model::coordinates()
  std::array<char, 3> axes{};        // 'x', 'y' or 'z'
  bool proper() const {
    return axes[0] == axes[2];
  }                          // Euler (Z-X-Z) rather than Tait-Bryan (Z-Y-X)
  std::string name() const;  // "Z-Y-X"
};

// Every body's sequences, bodies in model order, at most one per body (the first).
std::vector<AngleSequence> angle_sequences(const Model& model);

}  // namespace symdyn::model
