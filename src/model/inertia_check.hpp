#pragma once
// Physical admissibility of a body's mass and inertia tensor.

#include <array>
#include <string_view>

namespace symdyn::model {

// Throws ModelError naming `where` unless, as the runtime requires at
// construction: the mass is finite and positive; the tensor (row-major, at G)
// is finite and symmetric; its principal moments are positive (positive
// definite); and they satisfy the triangle inequalities I1 + I2 >= I3 (a real
// mass distribution always does).
void check_inertia(std::string_view where, double mass, const std::array<double, 9>& inertia);

// Principal moments of a symmetric 3x3 tensor, ascending.
std::array<double, 3> principal_moments(const std::array<double, 9>& inertia);

}  // namespace symdyn::model
