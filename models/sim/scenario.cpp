#include "scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <utility>

#include <symdyn/runtime/errors.hpp>

namespace symdyn::sim {

namespace {

// A deque keeps references stable while later files register.
std::deque<Scenario>& registry() {
  static std::deque<Scenario> all;
  return all;
}

}  // namespace

const Variant& Scenario::variant(std::string_view name) const {
  for (const auto& v : variants) {
    if (v.name == name) return v;
  }
  std::vector<std::string> names;
  for (const auto& v : variants) names.push_back(v.name);
  throw runtime::OptionError(fmt::format("model '{}' has no variant '{}' (built variants: {})", model,
                                         name, fmt::join(names, ", ")));
}

Registration::Registration(Scenario s) {
  if (s.variants.empty()) return;  // none of its generated variants is built
  registry().push_back(std::move(s));
}

std::vector<const Scenario*> scenarios() {
  std::vector<const Scenario*> out;
  for (const auto& s : registry()) out.push_back(&s);
  std::sort(out.begin(), out.end(), [](const Scenario* a, const Scenario* b) { return a->model < b->model; });
  return out;
}

const Scenario& find_scenario(std::string_view model) {
  std::vector<std::string> names;
  for (const Scenario* s : scenarios()) {
    if (s->model == model) return *s;
    names.push_back(s->model);
  }
  throw runtime::OptionError(
      fmt::format("no scenario for model '{}' (known: {})", model, fmt::join(names, ", ")));
}

}  // namespace symdyn::sim
