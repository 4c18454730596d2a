#pragma once
// How the accelerations are computed (Options::dynamics): by the mass matrix
// and bias forces with a Cholesky factorization at run time, or by the
// emitted recursive forward dynamics (the articulated-body algorithm) where
// it applies. Automatic: the way of fewer operations.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/codegen/generate.hpp>

namespace symdyn::codegen::detail {

// What each way costs: the mass-matrix way this entry point's operations
// (M and h in one call) plus ~nq³/6 + nq² for the factorization and solve,
// the recursive way this one's.
inline constexpr std::string_view kMassMatrixWay = "dynamics";
inline constexpr std::string_view kRecursiveWay = "forward_dynamics_pivots";

// The choice between the two ways, with its reason. `recursive_operations`:
// none where the recursive way was not derived (`why_not` says why, empty
// where the mass matrix was asked for).
DynamicsChoice weigh_dynamics(DynamicsMethod method, std::size_t nq,
                              std::size_t mass_matrix_operations,
                              std::optional<std::size_t> recursive_operations,
                              const std::string& why_not);

// What choose_dynamics needs of the derivation.
struct DynamicsWays {
  DynamicsMethod method = DynamicsMethod::automatic;
  std::size_t nq = 0;
  std::string why_not;                                       // model::Dynamics::why_not
  std::function<std::size_t(const EntryPoint&)> operations;  // of the entry point's own program
};

// Weighs the two ways once (`choice` empty: the first derivation with the
// equations of motion), then drops the entry points that need the recursive
// dynamics unless it was chosen: a later derivation, compared entry point
// by entry point with the first, follows the first one's choice.
void choose_dynamics(std::vector<EntryPoint>& entries, std::optional<DynamicsChoice>& choice,
                     const DynamicsWays& ways);

}  // namespace symdyn::codegen::detail
