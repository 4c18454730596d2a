#pragma once
// Which entry points are emitted (Options::entry_points, --only): every one
// by default, else those named and those their hand-written bodies call. The
// names also decide what is derived: the equations of motion only when one of
// them needs them, the bodies' absolute motion only when one needs it.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/codegen/generate.hpp>

namespace symdyn::codegen::detail {

class Selection {
 public:
  // `equations_of_motion`: Options::equations_of_motion, for the error message.
  Selection(std::vector<std::string> wanted, bool equations_of_motion);

  bool selected(std::string_view name) const;
  bool needs_absolute_motion() const;  // a name not in the catalogue counts as needing it
  bool needs_equations_of_motion()
      const;  // whether Options::equations_of_motion asks for them or not
  // Which derivatives are derived: those asked for (Options::derivatives)
  // with every entry point, else the most that a named entry point needs.
  Derivatives needs_derivatives(Derivatives asked) const;
  // Whether the joint reactions are derived: `asked` (Options::joint_reactions)
  // with every entry point, else whether they are named.
  bool needs_reactions(bool asked) const;

  // Throws model::ModelError naming a wanted entry point that is not among
  // `entries` (those derived with these options), with the list of those
  // that are; then keeps in `entries` the selected ones and those they call.
  void apply(std::vector<EntryPoint>& entries, const std::optional<DynamicsChoice>& choice) const;

 private:
  void check(const std::vector<EntryPoint>& entries,
             const std::optional<DynamicsChoice>& choice) const;

  std::vector<std::string> wanted_;  // empty: every entry point
  bool equations_of_motion_;
};

}  // namespace symdyn::codegen::detail
