// make_integrator: the table of integrators by name.

#include <array>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "runtime/cvode_integrator.hpp"
#include "runtime/errors.hpp"
#include "runtime/integrator.hpp"
#include "runtime/newmark.hpp"
#include "runtime/runge_kutta.hpp"

namespace symdyn::runtime {

namespace {

struct Entry {
  std::string_view name;
  std::unique_ptr<Integrator> (*make)(IntegratorOptions);
};

constexpr std::array<Entry, 5> integrators = {{
    {"newmark", make_newmark},
    {"generalized-alpha", make_generalized_alpha},
    {"rk4", make_rk4},
    {"dopri5", make_dopri5},
    {"cvode", make_cvode},
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
