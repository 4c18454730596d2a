#include <fmt/format.h>

#include <cmath>
#include <utility>

#include <symdyn/runtime/element_properties.hpp>

namespace symdyn::runtime {

PropertyError::PropertyError(const std::string& element, std::string property, std::string detail)
    : ModelError(fmt::format("{}: {}: {}", element, property, detail)),
      property_(std::move(property)),
      detail_(std::move(detail)) {}

const char* requirement(Sign sign) {
  switch (sign) {
    case Sign::non_negative:
      return " >= 0";
    case Sign::positive:
      return " > 0";
    case Sign::any:
      break;
  }
  return "";
}

namespace {

bool satisfies(double v, Sign sign) {
  if (!std::isfinite(v)) return false;
  return sign == Sign::any || (sign == Sign::positive ? v > 0.0 : v >= 0.0);
}

std::string vector_text(const Vec3& v) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", v(0), v(1), v(2));
}

}  // namespace

void check_property(const std::string& element, const char* property, double value, Sign sign) {
  if (satisfies(value, sign)) return;
  throw PropertyError(
      element, property,
      fmt::format("expected a finite number{}, found {:.6g}", requirement(sign), value));
}

void check_property(const std::string& element, const char* property, const Vec3& value,
                    Sign sign) {
  for (int i = 0; i < 3; ++i) {
    if (satisfies(value(i), sign)) continue;
    throw PropertyError(element, property,
                        fmt::format("expected 3 finite numbers{}, found {} ({:.6g} at {})",
                                    requirement(sign), vector_text(value), value(i), i));
  }
}

void check_direction(const std::string& element, const char* property, const Vec3& value) {
  if (value.allFinite() && value.norm() > 0.0 && std::isfinite(value.norm())) return;
  throw PropertyError(element, property,
                      fmt::format("expected a non-zero direction, found {}", vector_text(value)));
}

void check_axes(const std::string& element, const char* property, const Mat3& axes) {
  const double error = axes.allFinite()
                           ? (axes.transpose() * axes - Mat3::Identity()).cwiseAbs().maxCoeff()
                           : INFINITY;
  if (!(error <= 1e-6)) {
    throw PropertyError(
        element, property,
        fmt::format(
            "expected orthonormal axes (the columns of a rotation), found |AᵀA - I| = {:.3g}",
            error));
  }
  if (!(axes.determinant() > 0.0)) {
    throw PropertyError(element, property,
                        "expected right-handed axes, found a reflection (determinant -1)");
  }
}

}  // namespace symdyn::runtime
