#pragma once
// Private to the program compiler (program*.cpp): instructions value-numbered
// as they are emitted, so that a pass building code never computes one value
// twice. Instruction k defines slot k.

#include <cstdint>
#include <optional>
#include <vector>

#include <symdyn/symbolic/program.hpp>

namespace symdyn::symbolic::detail {

class CodeBuilder {
 public:
  // The slot of an instruction equal to `ins` (opcode, operands, payload),
  // appended if there is none. Commutative operands are put in one order,
  // constants first ("2.0*x").
  std::uint32_t emit(Instruction ins);
  std::uint32_t emit(Opcode op, std::array<std::uint32_t, 2> args, double constant = 0.0);
  // The slot of that instruction if it is emitted already.
  std::optional<std::uint32_t> find(Opcode op, std::array<std::uint32_t, 2> args,
                                    double constant = 0.0) const;

  // Room for about n instructions: the index sized once instead of doubled up to it.
  void reserve(std::size_t n);
  const Instruction& operator[](std::uint32_t slot) const { return code_[slot]; }
  std::size_t size() const { return code_.size(); }
  std::vector<Instruction>& code() { return code_; }

 private:
  Instruction canonical(Instruction ins) const;
  static std::size_t hash(const Instruction& ins);
  static bool same(const Instruction& a, const Instruction& b);
  void grow_index();
  void rehash(std::size_t size);

  std::vector<Instruction> code_;
  // Open addressing over code_, each entry a slot + 1 (0: empty). Looked up,
  // never iterated.
  std::vector<std::uint32_t> index_;
};

// Negations taken by the instructions that compute their operands where that
// saves the neg (see program_negation.cpp). `code` defines slot k at
// instruction k, and so does the result; `outputs` are slots, renumbered.
std::vector<Instruction> absorb_negations(const CodeBuilder& code,
                                          std::vector<std::uint32_t>& outputs);

}  // namespace symdyn::symbolic::detail
