#pragma once
// Straight-line programs: output expressions scheduled into instructions over
// numbered slots, ready to be interpreted or printed as C++.
//
//   Program p = compile_program(inputs, outputs);    // inputs: symbols, outputs: any expressions
//   Program p = compile_program(inputs, outputs, definitions);  // plus named intermediates
//   p.run<double>(input_values, output_values, workspace);
//   std::string body = emit_cpp(p, naming);          // "const double t0 = q[0]*q[1];" ...
//
// Instructions and slots. An instruction applies one opcode (table below) to
// zero, one or two operand slots and defines one result slot (two for sincos).
// Slots are SSA values numbered in schedule order: the results of instruction k
// are numbered after those of instruction k-1, every slot is defined exactly
// once, and always before it is read. `const` and `input` load a constant or
// the i-th input; every other opcode computes. Output i is the value of slot
// `output_slots()[i]`.
//
// What the compiler does with each kind of node (see expr.hpp):
//   - sums and products are binarized into n-1 adds or multiplies;
//   - signs fold away: a + (-1)·b is a - b; a negative sign travels up through
//     products, quotients and negations ((-x)·y/z = -(x·y/z)) until a sum
//     absorbs it as a subtraction; a negative constant is loaded negative; an
//     explicit `neg` remains only where nothing can absorb the sign (a function
//     argument, the base of a non-integer power, an output, a sum with no
//     positive term), and even there it goes into the instructions computing
//     its operand when nothing else reads them and that costs nothing:
//     -(x·y + z) = (-x)·y - z where -x is computed anyway;
//   - a product with negative powers is one division: x·y⁻¹·z⁻² = x/(y·z·z);
//     when two or more divisions share a denominator d, 1/d is computed once
//     and the divisions become multiplications (a division costs 4 multiplies);
//   - integer powers up to 32 become multiplications by repeated squaring
//     (x² = x·x, x³ = x·x·x, x⁻² = 1/(x·x)); x^(k/2) is x^((k-1)/2)·sqrt(x)
//     (x^(-1/2) = 1/sqrt(x)); any other exponent is a `pow`;
//   - functions are calls, sin and cos of one argument one `sincos`.
//
// Definitions: a symbol may stand for an expression over the inputs and other
// definitions (a named intermediate). It is computed once, where an output
// needs it, as the value of its expression, never substituted into its users:
// a sum over a defined symbol stays a sum of two operands instead of merging
// the definition's terms into its own. That is what keeps chains of
// definitions (each body's kinematics composed from its reference's) linear
// in size. Definitions may come in any order; a cycle is an error.
//
// Guarantees:
//   - Sharing: every distinct node of the DAG is computed once (interning makes
//     this free), and so is every repeated instruction made by lowering. Beyond
//     it, pair CSE: when two or more sums (or products) share a pair of
//     operands, the pair is computed once; the most frequent pair is extracted
//     first, repeatedly, ties broken by the operands' order of creation, or
//     first by how many of the sums (products) are the pair itself (c3·c5
//     beside c3·s4·c5: extracting it leaves s4 to pair elsewhere), whichever
//     makes the output groups shorter (compile_program). Sums
//     and products with more than 128 operands take no part (the pair table
//     grows as the square of the operand count).
//   - Dead code: only what the outputs need is scheduled; an input no output
//     depends on is never read.
//   - sincos: a `sincos` instruction defines sin(a) in its first result slot
//     and cos(a) in the second. It prints as two adjacent statements
//     std::sin(a), std::cos(a), which g++ 12 -O2 compiles into one call to
//     sincos (clang 14 does so with -fno-math-errno).
//   - Determinism: the same outputs, built the same way, give the same program
//     byte for byte. Scheduling decisions follow node ids and the order of the
//     outputs, never addresses or hashes. Permuting the outputs permutes the
//     schedule but computes the same set of instructions (same operation
//     count); a repeated output costs nothing.
//
// Domain: the program computes what the expressions say, in the scalar type;
// it adds no NaN (no rule divides by something the expression does not).

#include <fmt/format.h>

#include <array>
#include <complex>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <symdyn/symbolic/errors.hpp>
#include <symdyn/symbolic/expr.hpp>
#include <symdyn/symbolic/scalar_ops.hpp>

namespace symdyn::symbolic {

struct OperationCount;

// The instruction set, written once:
//   X(Opcode, "name", arity, results, "C++ format", "C++ format of the 2nd result", counted as)
// In a format, {0} and {1} are the operands, {2} the constant (a C++ literal)
// and {3} the input's C++ name. `counted as` is the OperationCount field one
// execution increments (none for loads).
#define SYMDYN_FOR_EACH_CORE_OPCODE(X)               \
  X(Const, "const", 0, 1, "{2}", "", none)           \
  X(Input, "input", 0, 1, "{3}", "", none)           \
  X(Add, "add", 2, 1, "{0} + {1}", "", add)          \
  X(Sub, "sub", 2, 1, "{0} - {1}", "", add)          \
  X(Mul, "mul", 2, 1, "{0}*{1}", "", mul)            \
  X(Div, "div", 2, 1, "{0}/{1}", "", div)            \
  X(Neg, "neg", 1, 1, "-{0}", "", neg)               \
  X(Sqrt, "sqrt", 1, 1, "std::sqrt({0})", "", sqrt)  \
  X(Pow, "pow", 1, 1, "std::pow({0}, {2})", "", pow) \
  X(SinCos, "sincos", 1, 2, "std::sin({0})", "std::cos({0})", sincos)
// Every function kind of node_kinds.hpp is also an opcode of the same name,
// arity and C++ spelling ("std::atan2({0}, {1})"), counted per kind.

enum class Opcode : std::uint8_t {
#define SYMDYN_OPCODE_ENUM(op, ...) op,
  SYMDYN_FOR_EACH_CORE_OPCODE(SYMDYN_OPCODE_ENUM) SYMDYN_FOR_EACH_FUNCTION_KIND(SYMDYN_OPCODE_ENUM)
#undef SYMDYN_OPCODE_ENUM
};

struct OpcodeInfo {
  std::string_view name;
  int arity;
  int results;
  std::string_view format;
  std::string_view format2;  // sincos only
  bool is_call;              // a function kind
  Kind kind;                 // its kind, when is_call
};
const OpcodeInfo& info(Opcode op);

// One step of a program. Slots are SSA values (see the top of this file).
struct Instruction {
  Opcode op = Opcode::Const;
  std::array<std::uint32_t, 2> results{};  // results[1]: sincos only (the cosine)
  std::array<std::uint32_t, 2> args{};     // the first `arity` are meaningful
  double constant = 0.0;                   // const: the value; pow: the exponent
  std::uint32_t input = 0;                 // input: its index among the inputs
};

inline constexpr std::size_t kFunctionKindCount = 0
#define SYMDYN_COUNT_KIND(...) +1
    SYMDYN_FOR_EACH_FUNCTION_KIND(SYMDYN_COUNT_KIND);
#undef SYMDYN_COUNT_KIND

// How many operations a program executes, by kind. Loads are free.
struct OperationCount {
  int add = 0;  // additions and subtractions
  int mul = 0;
  int div = 0;
  int neg = 0;
  int sqrt = 0;
  int pow = 0;     // std::pow calls
  int sincos = 0;  // fused sin/cos pairs (each also one call, not counted in calls)
  std::array<int, kFunctionKindCount> calls{};  // other calls, per function kind

  int& call(Kind kind);  // throws UsageError unless kind is a function kind
  int call(Kind kind) const;
  int total() const;  // every operation once; a sincos counts once
  // Weighted by rough cost relative to a multiply: add, mul, neg 1; div and
  // sqrt 4; pow 16; sincos 15; calls the `cost` column of node_kinds.hpp.
  int weighted() const;
  std::string str() const;  // "3 add, 2 mul, 1 sin", non-zero fields only
  friend bool operator==(const OperationCount&, const OperationCount&) = default;
};

class Program {
 public:
  std::size_t input_count() const { return input_count_; }
  std::size_t output_count() const { return outputs_.size(); }
  std::size_t slot_count() const { return slot_count_; }
  std::span<const Instruction> instructions() const { return instructions_; }
  std::span<const std::uint32_t> output_slots() const { return outputs_; }
  OperationCount operation_count() const;

  // Interpreter: computes the outputs from the inputs in any scalar type with
  // the arithmetic of double (double, long double, std::complex<double> for the
  // complex step, ...). Allocates nothing.
  //   inputs    (input_count())    values of the symbols, in the order given to compile_program
  //   outputs   (output_count())   written
  //   workspace (workspace_size()) scratch; slots are reused by liveness
  // Throws UsageError on a size mismatch.
  std::size_t workspace_size() const { return workspace_size_; }
  template <class S>
  void run(std::span<const S> inputs, std::span<S> outputs, std::span<S> workspace) const;

  // The same, allocating its outputs and workspace: for tests and tools.
  template <class S>
  std::vector<S> evaluate(std::span<const S> inputs) const;

  // The program of some of the outputs, in the order given, over some of the
  // inputs (indices of this program's, in the order given): the instructions
  // they need, in this program's order, and nothing else. What a function
  // computing those outputs alone runs (emit_cpp_shared). Throws UsageError
  // for an index out of range, or if the outputs need an input not given.
  Program subprogram(std::span<const std::size_t> outputs,
                     std::span<const std::size_t> inputs) const;

 private:
  friend Program compile_program(std::span<const Expr> inputs, std::span<const Expr> outputs,
                                 std::span<const Definition> definitions,
                                 std::span<const std::vector<std::size_t>> groups);
  void check_sizes(std::size_t inputs, std::size_t outputs, std::size_t workspace) const;
  void allocate_workspace();

  std::size_t input_count_ = 0;
  std::size_t slot_count_ = 0;
  std::vector<Instruction> instructions_;
  std::vector<std::uint32_t> outputs_;
  // The same instructions over workspace slots reused by liveness.
  std::vector<Instruction> exec_;
  std::vector<std::uint32_t> exec_outputs_;
  std::size_t workspace_size_ = 0;
};

// Schedules `outputs` into a program whose inputs are `inputs`, in that order.
// `groups`: sets of outputs (indices) computed together, such as the
// functions of emit_cpp_shared, each running Program::subprogram of its
// outputs; none: all outputs, one group. Pair CSE breaks its ties two ways
// (see Guarantees) and keeps the second only where it makes some group
// shorter and none longer.
// Throws UsageError if an input is not a symbol or is given twice, if a
// definition's symbol is not a symbol, is an input or is defined twice, if
// definitions depend on themselves, if an output uses a symbol that is
// neither an input nor defined (the message names it), or if a group names
// an output out of range.
Program compile_program(std::span<const Expr> inputs, std::span<const Expr> outputs,
                        std::span<const Definition> definitions = {},
                        std::span<const std::vector<std::size_t>> groups = {});

// A readable listing, one instruction a line: "s4 = mul s1 s3", "s0 = input 2",
// then "out 0 = s4".
std::string to_string(const Program& program);

// How emit_cpp names things. The input and output texts are pasted as they are:
// an input's must be a primary or postfix expression ("q[0]", "qd_1").
struct CppNaming {
  std::vector<std::string> inputs;     // (input_count)  C++ text of each input, e.g. "q[0]"
  std::vector<std::string> outputs;    // (output_count) lvalue of each output, e.g. "x[3]"
  std::string temporary_prefix = "t";  // temporaries are <prefix>0, <prefix>1, ... in order
  std::string scalar_type = "double";
  std::string indent = "  ";
  std::string scratch = "s";  // emit_cpp_shared: the array shared between parts
  // Optional, the input arrays in order, (name, size) each, covering every
  // input: emit_cpp_shared then says which arrays each part reads.
  std::vector<std::pair<std::string, std::size_t>> input_arrays;
  // Optional, the output arrays in order, (name, size) each, covering every
  // output: output i is then element i - (sizes before) of its array, and a
  // long array of many zeros is zeroed by one loop (see kZeroedArrayShare).
  // Empty: every output is assigned alone.
  std::vector<std::pair<std::string, std::size_t>> output_arrays;
  // Optional, (output_arrays) whether each is written sparsely: its +0.0
  // outputs are never assigned, so the caller zeroes the array once, before
  // the first call, and keeps it for these outputs alone. Empty: none is.
  // Such an array is planned as the others (the parts are cut and ordered
  // alike) and printed without its zeros, by a loop or one by one.
  std::vector<bool> sparse_arrays;
};

// An output array (not written sparsely, CppNaming::sparse_arrays) of at least
// kMinZeroedArray elements, of which at least 1/kZeroedArrayShare are +0.0
// (and that one set of functions wants, emit_cpp_shared), is zeroed whole by
// one loop, for (int i = 0; i < 3528; ++i) dv[i] = 0.0;, before its other
// elements are assigned; its zeros are not assigned again. Why: g++ turns the
// loop into memset, cheaper than many separate stores of zero to compile and
// to run, but not on a short array (bench/results/emitted_code_layout.md).
inline constexpr std::size_t kMinZeroedArray = 64;
inline constexpr std::size_t kZeroedArrayShare = 2;

// The program as C++ statements, one a line:
//   <indent>const double t0 = q[0]*q[1];
//   <indent>x[0] = t0 + 2.0;
// Loads print inline (inputs by name, constants as round-trip literals, negative
// ones in parentheses); every temporary is used; long arrays of many zeros
// are zeroed first (see CppNaming::output_arrays), outputs are assigned last,
// in order.
// Warning-free under -Wall -Wextra -Wpedantic. Throws UsageError if the naming
// has the wrong number of inputs or outputs, output arrays of another total
// size, or sparse_arrays of another size than output_arrays (if not empty).
std::string emit_cpp(const Program& program, const CppNaming& naming);

// Functions computing some outputs of one program each (entry points of
// generated code that share work: positions, velocities and accelerations
// compute the same rotations), printed as parts: statements shared between
// functions are compiled once, and a compiler's superlinear passes (register
// allocation, CSE, alias walks) see short pieces.
//
//   CppShared code = emit_cpp_shared(program, naming, {{0, 1}, {0, 1, 2, 3}}, 125);
//   // code.parts[i].body: statements of the i-th part, to be a function's body;
//   // code.functions[f].parts: the parts function f calls, in order, all with
//   // a scratch array <naming.scratch> of code.functions[f].scratch_size scalars.
//
// `functions` lists each function's outputs (indices). Function f runs every
// computing instruction its outputs need, and no other: a group gathers the
// instructions needed by exactly the same set of functions, in program order,
// and each group is cut into the fewest parts of at most `max_instructions`
// statements (0: no limit), as even as possible. Groups run in order of how
// many functions need them, most first: what a group reads is needed by at
// least its functions, hence computed by a group before it. Loads print
// inline and belong to no part. A value computed in one part and read in a
// later one is stored to its scratch entry right after it is defined and read
// from there (`s[12]`) afterwards; entries are reused once their last reader
// has run, which is safe in every function since each runs parts in the
// same order.
//
// Outputs: when there are several parts, an output wanted by exactly the
// functions that need its value is assigned right after the value's
// definition (after the scratch store, in output order); any other output
// (a load, or a value other functions need too) is assigned at the end of
// the group of its own functions, in output order. Why: a value assigned at
// the end of its part stays live through it, and g++ spills and reloads it
// (bench/results/emitted_code_layout.md). So outputs are written before
// later statements and parts read inputs: output arrays must not overlap
// inputs (generated parts take __restrict parameters). A part assigns only
// outputs every function that runs it wants. A long array of many zeros (see
// kZeroedArrayShare) is zeroed at the start of the first part of its
// functions' group, before any of its elements is assigned.
//
// One function of every output in one part (max_instructions 0, or at least
// the program's statements) prints exactly what emit_cpp prints, with scratch
// size 0. Throws UsageError like emit_cpp, for more than 64 functions, an
// output index out of range or an output no function wants.
struct CppPart {
  std::string body;                        // its statements
  std::vector<std::size_t> functions;      // the functions that run it
  std::vector<std::size_t> input_arrays;   // the naming's input arrays it reads (indices)
  std::vector<std::size_t> output_arrays;  // the naming's output arrays it writes (indices)
  bool scratch = false;                    // it reads or writes the scratch array
};
struct CppFunctionParts {
  std::vector<std::size_t> parts;  // the parts it calls, in order
  std::size_t scratch_size = 0;    // scalars of scratch its parts use
};
struct CppShared {
  std::vector<CppPart> parts;
  std::vector<CppFunctionParts> functions;
};
CppShared emit_cpp_shared(const Program& program, const CppNaming& naming,
                          std::span<const std::vector<std::size_t>> functions,
                          std::size_t max_instructions);

// ---------------------------------------------------------------------------
// Implementation of the interpreter.

template <class S>
void Program::run(std::span<const S> inputs, std::span<S> outputs, std::span<S> workspace) const {
  check_sizes(inputs.size(), outputs.size(), workspace.size());
  S* w = workspace.data();
  for (const Instruction& ins : exec_) {
    const auto r = ins.results[0];
    const auto a = ins.args[0];
    const auto b = ins.args[1];
    switch (ins.op) {
      case Opcode::Const:
        w[r] = S(ins.constant);
        break;
      case Opcode::Input:
        w[r] = inputs[ins.input];
        break;
      case Opcode::Add:
        w[r] = w[a] + w[b];
        break;
      case Opcode::Sub:
        w[r] = w[a] - w[b];
        break;
      case Opcode::Mul:
        w[r] = w[a] * w[b];
        break;
      case Opcode::Div:
        w[r] = w[a] / w[b];
        break;
      case Opcode::Neg:
        w[r] = -w[a];
        break;
      case Opcode::Sqrt: {
        using std::sqrt;
        w[r] = sqrt(w[a]);
        break;
      }
      case Opcode::Pow: {
        using std::pow;
        w[r] = pow(w[a], S(ins.constant));
        break;
      }
      case Opcode::SinCos: {
        using std::cos;
        using std::sin;
        w[r] = sin(w[a]);
        w[ins.results[1]] =
            cos(w[a]);  // never the argument's slot: results and arguments are distinct
        break;
      }
#define SYMDYN_RUN_CALL(kind, name, arity, ...)                    \
  case Opcode::kind:                                               \
    w[r] = scalar::apply<Kind::kind>(w[a], w[arity == 2 ? b : a]); \
    break;
        SYMDYN_FOR_EACH_FUNCTION_KIND(SYMDYN_RUN_CALL)
#undef SYMDYN_RUN_CALL
    }
  }
  for (std::size_t i = 0; i < exec_outputs_.size(); ++i) outputs[i] = w[exec_outputs_[i]];
}

template <class S>
std::vector<S> Program::evaluate(std::span<const S> inputs) const {
  std::vector<S> outputs(output_count());
  std::vector<S> workspace(workspace_size());
  run<S>(inputs, outputs, workspace);
  return outputs;
}

}  // namespace symdyn::symbolic
