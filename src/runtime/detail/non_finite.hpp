#pragma once
// Private to the runtime: the messages that name a non-finite value and its time,
// shared by every integrator (integrator.cpp's global-tolerance loops, the step
// loop, the SUNDIALS callbacks).

#include <string>

#include <symdyn/runtime/dynamic_system.hpp>

namespace symdyn::runtime::detail {

// "" when every entry of v is finite, else "<quantity> of coordinate 'x' is nan"
// (extra = false: v is indexed like q; extra = true: like y).
std::string non_finite_entry(const DynamicSystem& system, const char* quantity, const Vector& v,
                             bool extra);

// The first non-finite value among q, qd, y, qdd, yd, or "".
std::string non_finite_value(const DynamicSystem& system, const State& s, const Vector& qdd,
                             const Vector& yd);

// "t = <t>: <what>" with t printed round-trip.
std::string at_time(double t, const std::string& what);

}  // namespace symdyn::runtime::detail
