#pragma once
// Physical admissibility of a body's mass and inertia tensor, one check for the
// generator (model::Model::validate) and the runtime (runtime::Model at
// construction and on every parameter change), so that a model the generator
// accepts is one the runtime accepts. Header-only and std + fmt only: the
// runtime may include it while knowing nothing of the model part.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

namespace symdyn::detail {

// Principal moments of a symmetric 3x3 tensor (row-major), ascending: its
// eigenvalues in closed form (the trigonometric method).
inline std::array<double, 3> principal_moments(const std::array<double, 9>& A) {
  const double p1 = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
  const double trace = A[0] + A[4] + A[8];
  std::array<double, 3> e{A[0], A[4], A[8]};
  if (p1 > 0.0) {
    const double q = trace / 3.0;
    const double p2 =
        (A[0] - q) * (A[0] - q) + (A[4] - q) * (A[4] - q) + (A[8] - q) * (A[8] - q) + 2.0 * p1;
    const double p = std::sqrt(p2 / 6.0);
    std::array<double, 9> B{};
    for (int i = 0; i < 9; ++i) B[i] = (A[i] - (i % 4 == 0 ? q : 0.0)) / p;
    const double det = B[0] * (B[4] * B[8] - B[5] * B[7]) - B[1] * (B[3] * B[8] - B[5] * B[6]) +
                       B[2] * (B[3] * B[7] - B[4] * B[6]);
    const double phi = std::acos(std::clamp(det / 2.0, -1.0, 1.0)) / 3.0;
    e[2] = q + 2.0 * p * std::cos(phi);
    e[0] = q + 2.0 * p * std::cos(phi + 2.0 * std::numbers::pi / 3.0);
    e[1] = trace - e[0] - e[2];
  }
  std::sort(e.begin(), e.end());
  return e;
}

// "" when (mass, I) is a rigid body's: the mass finite and positive; the tensor
// (row-major, at G) finite and symmetric (to 1e-9 of its largest entry), its
// principal moments positive and satisfying the triangle inequality
// I1 + I2 >= I3 (a real mass distribution always does). Otherwise what is wrong,
// e.g. "mass -2 is not positive".
inline std::string inertia_problem(double mass, const std::array<double, 9>& I) {
  if (!std::isfinite(mass)) return fmt::format("mass {} is not finite", mass);
  if (!(mass > 0.0)) return fmt::format("mass {} is not positive", mass);
  double scale = 0.0;
  for (int k = 0; k < 9; ++k) {
    if (!std::isfinite(I[k]))
      return fmt::format("inertia I{}{} = {} is not finite", k / 3, k % 3, I[k]);
    scale = std::max(scale, std::abs(I[k]));
  }
  scale = std::max(scale, 1e-300);
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      if (std::abs(I[3 * i + j] - I[3 * j + i]) > 1e-9 * scale) {
        return fmt::format("inertia is not symmetric (I{}{} = {} but I{}{} = {})", i, j,
                           I[3 * i + j], j, i, I[3 * j + i]);
      }
    }
  }
  const auto m = principal_moments(I);
  if (!(m[0] > 0.0)) {
    return fmt::format("inertia is not positive definite (principal moments {}, {}, {})", m[0],
                       m[1], m[2]);
  }
  // A thin rod or disc is exactly at the limit: rounding allowed.
  if (m[0] + m[1] < m[2] * (1.0 - 1e-9)) {
    return fmt::format("inertia violates the triangle inequality (principal moments {} + {} < {})",
                       m[0], m[1], m[2]);
  }
  return {};
}

}  // namespace symdyn::detail
