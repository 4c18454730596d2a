#include <fmt/format.h>

#include <cmath>
#include <string>

#include <symdyn/runtime/detail/non_finite.hpp>

namespace symdyn::runtime::detail {

std::string at_time(double t, const std::string& what) {
  // A message from the system already names its time.
  if (what.rfind("t = ", 0) == 0) return what;
  return fmt::format("t = {}: {}", t, what);
}

std::string non_finite_entry(const DynamicSystem& system, const char* quantity, const Vector& v,
                             bool extra) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (std::isfinite(v[i])) continue;
    const int k = static_cast<int>(i);
    return extra ? fmt::format("{} of extra state '{}' is {}", quantity, system.extra_state_name(k),
                               v[i])
                 : fmt::format("{} of coordinate '{}' is {}", quantity, system.coordinate_name(k),
                               v[i]);
  }
  return {};
}

std::string non_finite_value(const DynamicSystem& system, const State& s, const Vector& qdd,
                             const Vector& yd) {
  if (s.q.allFinite() && s.qd.allFinite() && s.y.allFinite() && qdd.allFinite() && yd.allFinite())
    return {};
  struct Entry {
    const char* quantity;
    const Vector& v;
    bool extra;
  };
  const Entry entries[] = {{"q", s.q, false},
                           {"qd", s.qd, false},
                           {"y", s.y, true},
                           {"qdd", qdd, false},
                           {"yd", yd, true}};
  for (const auto& e : entries) {
    std::string bad = non_finite_entry(system, e.quantity, e.v, e.extra);
    if (!bad.empty()) return bad;
  }
  return {};
}

}  // namespace symdyn::runtime::detail
