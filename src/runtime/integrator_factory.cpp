// make_integrator: the table of integrators by name.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <array>

#include <symdyn/runtime/detail/arkode_integrator.hpp>
#include <symdyn/runtime/detail/cvode_integrator.hpp>
#include <symdyn/runtime/detail/dop853.hpp>
#include <symdyn/runtime/detail/midpoint.hpp>
#include <symdyn/runtime/detail/newmark.hpp>
#include <symdyn/runtime/detail/runge_kutta.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/integrator.hpp>

namespace symdyn::runtime {

namespace {

struct Entry {
  std::string_view name;
  std::unique_ptr<Integrator> (*make)(IntegratorOptions);
};

constexpr std::array<Entry, 8> integrators = {{
    {"newmark", make_newmark},
    {"generalized-alpha", make_generalized_alpha},
    {"rk4", make_rk4},
    {"dopri5", make_dopri5},
    {"dop853", make_dop853},
    {"midpoint", make_midpoint},
    {"cvode", make_cvode},
    {"arkode", make_arkode},
}};

}  // namespace

std::vector<std::string> integrator_names() {
  std::vector<std::string> names;
  for (const auto& e : integrators) names.emplace_back(e.name);
  return names;
}

std::unique_ptr<Integrator> make_integrator(std::string_view name, IntegratorOptions options) {
  for (const auto& e : integrators) {
    if (e.name == name) return e.make(std::move(options));
  }
  throw OptionError(fmt::format("unknown integrator '{}'; valid names: {}", name,
                                fmt::join(integrator_names(), ", ")));
}

}  // namespace symdyn::runtime
