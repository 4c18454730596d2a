#include <fmt/format.h>

#include <algorithm>

#include <symdyn/codegen/detail/dynamics_choice.hpp>

namespace symdyn::codegen::detail {

DynamicsChoice weigh_dynamics(DynamicsMethod method, std::size_t nq,
                              std::size_t mass_matrix_operations,
                              std::optional<std::size_t> recursive_operations,
                              const std::string& why_not) {
  DynamicsChoice c;
  c.mass_matrix_operations = mass_matrix_operations + nq * nq * nq / 6 + nq * nq;
  if (!recursive_operations) {
    c.reason = why_not.empty()
                   ? "mass matrix (as asked)"
                   : fmt::format("mass matrix: the recursive forward dynamics does not apply ({})",
                                 why_not);
    return c;
  }
  c.recursive_operations = *recursive_operations;
  const bool fewer = c.recursive_operations < c.mass_matrix_operations;
  c.recursive =
      method == DynamicsMethod::recursive || (method == DynamicsMethod::automatic && fewer);
  const char* how = method == DynamicsMethod::automatic ? "fewer operations" : "as asked";
  c.reason = fmt::format(
      "{} ({}): recursive forward dynamics {} operations, mass matrix {} (dynamics() and "
      "nq³/6 + nq² for Cholesky and solve)",
      c.recursive ? "recursive" : "mass matrix", how, c.recursive_operations,
      c.mass_matrix_operations);
  return c;
}

void choose_dynamics(std::vector<EntryPoint>& entries, std::optional<DynamicsChoice>& choice,
                     const DynamicsWays& ways) {
  const auto named = [&](std::string_view name) {
    return std::find_if(entries.begin(), entries.end(),
                        [&](const EntryPoint& e) { return e.name() == name; });
  };
  const auto mass_matrix = named(kMassMatrixWay), recursive = named(kRecursiveWay);
  if (!choice && mass_matrix != entries.end()) {
    const std::size_t mass_matrix_operations = ways.operations(*mass_matrix);
    std::optional<std::size_t> recursive_operations;
    if (recursive != entries.end()) recursive_operations = ways.operations(*recursive);
    choice = weigh_dynamics(ways.method, ways.nq, mass_matrix_operations, recursive_operations,
                            ways.why_not);
  }
  if (!(choice && choice->recursive)) {
    std::erase_if(entries, [](const EntryPoint& e) { return e.spec->needs.recursive_dynamics; });
  }
}

}  // namespace symdyn::codegen::detail
