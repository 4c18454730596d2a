#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include <symdyn/codegen/detail/selection.hpp>
#include <symdyn/model/errors.hpp>

namespace symdyn::codegen::detail {
namespace {

template <class Predicate>
bool any_row(Predicate predicate) {
  return std::any_of(catalogue().begin(), catalogue().end(), predicate);
}

}  // namespace

Selection::Selection(std::vector<std::string> wanted, bool equations_of_motion)
    : wanted_(std::move(wanted)), equations_of_motion_(equations_of_motion) {}

bool Selection::selected(std::string_view name) const {
  return wanted_.empty() || std::find(wanted_.begin(), wanted_.end(), name) != wanted_.end();
}

bool Selection::needs_absolute_motion() const {
  const auto absolute = [](const std::string& name) {
    return !is_entry_point(name) || any_row([&](const EntryPointSpec& e) {
      return e.name == name && e.needs.absolute_motion;
    });
  };
  return wanted_.empty() || std::any_of(wanted_.begin(), wanted_.end(), absolute);
}

bool Selection::needs_equations_of_motion() const {
  return any_row(
      [&](const EntryPointSpec& e) { return e.needs.equations_of_motion && selected(e.name); });
}

Derivatives Selection::needs_derivatives(Derivatives asked) const {
  if (wanted_.empty()) return asked;
  Derivatives most = Derivatives::none;
  for (const EntryPointSpec& e : catalogue()) {
    if (selected(e.name)) most = std::max(most, e.needs.derivatives);
  }
  return most;
}

bool Selection::needs_reactions(bool asked) const {
  if (wanted_.empty()) return asked;
  return any_row([&](const EntryPointSpec& e) { return e.needs.reactions && selected(e.name); });
}

void Selection::apply(std::vector<EntryPoint>& entries,
                      const std::optional<DynamicsChoice>& choice) const {
  if (wanted_.empty()) return;
  check(entries, choice);
  // A hand-written body calls another entry point (EntryPointSpec::calls), which comes with it.
  std::vector<std::string_view> kept;
  for (const EntryPoint& e : entries) {
    if (!selected(e.name())) continue;
    kept.push_back(e.name());
    if (!e.spec->calls.empty()) kept.push_back(e.spec->calls);
  }
  std::erase_if(entries, [&](const EntryPoint& e) {
    return std::find(kept.begin(), kept.end(), e.name()) == kept.end();
  });
}

void Selection::check(const std::vector<EntryPoint>& entries,
                      const std::optional<DynamicsChoice>& choice) const {
  std::vector<std::string_view> names;
  for (const EntryPoint& e : entries) names.push_back(e.name());
  // The equations of motion are derived only for a selected entry point that
  // needs them: where none is, theirs count as emitted all the same (asking
  // for one derives them).
  const bool derived = std::any_of(entries.begin(), entries.end(), [](const EntryPoint& e) {
    return e.spec->needs.equations_of_motion;
  });
  if (equations_of_motion_ && !derived) {
    for (const EntryPointSpec& e : catalogue()) {
      if (e.needs.equations_of_motion &&
          std::find(names.begin(), names.end(), e.name) == names.end()) {
        names.push_back(e.name);
      }
    }
  }
  for (const std::string& name : wanted_) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      const std::string why = choice ? fmt::format("; accelerations: {}", choice->reason) : "";
      throw model::ModelError(
          fmt::format("entry point '{}' is not emitted with these options (emitted: {}{})", name,
                      fmt::join(names, ", "), why));
    }
  }
}

}  // namespace symdyn::codegen::detail
