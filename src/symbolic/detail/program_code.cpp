// Value-numbered emission of instructions (see program_code.hpp).
#include <algorithm>
#include <bit>
#include <utility>

#include <symdyn/symbolic/detail/program_code.hpp>
#include <symdyn/symbolic/detail/program_ir.hpp>

namespace symdyn::symbolic::detail {

std::uint32_t CodeBuilder::emit(Opcode op, std::array<std::uint32_t, 2> args, double constant) {
  Instruction ins;
  ins.op = op;
  ins.args = args;
  ins.constant = constant;
  return emit(ins);
}

std::uint32_t CodeBuilder::emit(Instruction ins) {
  ins = canonical(ins);
  if (2 * (code_.size() + 1) > index_.size()) grow_index();
  const std::size_t mask = index_.size() - 1;
  std::size_t i = hash(ins) & mask;
  for (; index_[i] != 0; i = (i + 1) & mask) {
    if (same(code_[index_[i] - 1], ins)) return index_[i] - 1;
  }
  const auto slot = static_cast<std::uint32_t>(code_.size());
  index_[i] = slot + 1;
  ins.results[0] = slot;
  code_.push_back(ins);
  return slot;
}

std::optional<std::uint32_t> CodeBuilder::find(Opcode op, std::array<std::uint32_t, 2> args,
                                               double constant) const {
  if (index_.empty()) return std::nullopt;
  Instruction ins;
  ins.op = op;
  ins.args = args;
  ins.constant = constant;
  ins = canonical(ins);
  const std::size_t mask = index_.size() - 1;
  for (std::size_t i = hash(ins) & mask; index_[i] != 0; i = (i + 1) & mask) {
    if (same(code_[index_[i] - 1], ins)) return index_[i] - 1;
  }
  return std::nullopt;
}

Instruction CodeBuilder::canonical(Instruction ins) const {
  if (ins.op == Opcode::Add || ins.op == Opcode::Mul) {
    auto rank = [&](std::uint32_t s) { return std::pair{code_[s].op != Opcode::Const, s}; };
    if (rank(ins.args[1]) < rank(ins.args[0])) std::swap(ins.args[0], ins.args[1]);
  }
  return ins;
}

// An instruction's value-numbering key: opcode, operands and payload.
std::size_t CodeBuilder::hash(const Instruction& ins) {
  std::size_t h = static_cast<std::size_t>(ins.op);
  for (std::uint64_t v : {std::uint64_t{ins.args[0]}, std::uint64_t{ins.args[1]},
                          std::bit_cast<std::uint64_t>(ins.constant), std::uint64_t{ins.input}}) {
    h = ir::mix_hash(h, v);
  }
  return ir::finish_hash(h);
}

bool CodeBuilder::same(const Instruction& a, const Instruction& b) {
  return a.op == b.op && a.args == b.args && a.input == b.input &&
         std::bit_cast<std::uint64_t>(a.constant) == std::bit_cast<std::uint64_t>(b.constant);
}

void CodeBuilder::reserve(std::size_t n) {
  code_.reserve(n);
  const std::size_t size = std::bit_ceil(2 * n + 2);
  if (size > index_.size()) rehash(size);
}

void CodeBuilder::grow_index() {
  rehash(std::max<std::size_t>(1024, 2 * index_.size()));
}

// The index at `size` entries (a power of two), every instruction entered anew.
void CodeBuilder::rehash(std::size_t size) {
  index_.assign(size, 0);
  const std::size_t mask = index_.size() - 1;
  for (std::uint32_t slot = 0; slot < code_.size(); ++slot) {
    std::size_t i = hash(code_[slot]) & mask;
    while (index_[i] != 0) i = (i + 1) & mask;
    index_[i] = slot + 1;
  }
}

}  // namespace symdyn::symbolic::detail
