#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <symdyn/model/errors.hpp>
#include <symdyn/model/inertia_check.hpp>

namespace symdyn::model {

// Closed-form eigenvalues of a symmetric 3x3 matrix (trigonometric method).
std::array<double, 3> principal_moments(const std::array<double, 9>& A) {
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

// The runtime's checks at construction (runtime/model.cpp, validate_inertia),
// with its tolerances, so that a model the generator accepts is one it accepts.
void check_inertia(std::string_view where, double mass, const std::array<double, 9>& I) {
  if (!std::isfinite(mass)) throw ModelError(fmt::format("{}: mass {} is not finite", where, mass));
  if (!(mass > 0.0)) throw ModelError(fmt::format("{}: mass {} is not positive", where, mass));
  double scale = 0.0;
  for (int k = 0; k < 9; ++k) {
    if (!std::isfinite(I[k])) {
      throw ModelError(
          fmt::format("{}: inertia I{}{} = {} is not finite", where, k / 3, k % 3, I[k]));
    }
    scale = std::max(scale, std::abs(I[k]));
  }
  scale = std::max(scale, 1e-300);
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      if (std::abs(I[3 * i + j] - I[3 * j + i]) > 1e-9 * scale) {
        throw ModelError(fmt::format("{}: inertia is not symmetric (I{}{} = {} but I{}{} = {})",
                                     where, i, j, I[3 * i + j], j, i, I[3 * j + i]));
      }
    }
  }
  const auto m = principal_moments(I);
  if (!(m[0] > 0.0)) {
    throw ModelError(
        fmt::format("{}: inertia is not positive definite (principal moments {}, {}, {})", where,
                    m[0], m[1], m[2]));
  }
  // A thin rod or disc is exactly at the limit: rounding allowed.
  if (m[0] + m[1] < m[2] * (1.0 - 1e-9)) {
    throw ModelError(
        fmt::format("{}: inertia violates the triangle inequality (principal moments {} + {} < {})",
                    where, m[0], m[1], m[2]));
  }
}

}  // namespace symdyn::model
