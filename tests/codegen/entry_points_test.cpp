// The entry-point catalogue (src/codegen/detail/entry_points.cpp): its rows
// are well formed, and docs/emitted_interface.md declares every entry point
// with the signature the generator emits.
#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <regex>
#include <sstream>

#include <symdyn/codegen/detail/cpp_text.hpp>
#include <symdyn/codegen/detail/entry_points.hpp>
#include <symdyn/codegen/detail/selection.hpp>

using namespace symdyn::codegen::detail;

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The declaration "static <returns> <name>(...);" in `text`, whitespace runs
// as one space, without the semicolon; empty if there is none.
std::string declaration(const std::string& text, const EntryPointSpec& spec) {
  const std::string head =
      "static " + std::string(spec.returns) + " " + std::string(spec.name) + "(";
  const std::size_t begin = text.find(head);
  if (begin == std::string::npos) return "";
  const std::size_t end = text.find(");", begin);
  return std::regex_replace(text.substr(begin, end + 1 - begin), std::regex("\\s+"), " ");
}

}  // namespace

TEST_CASE("catalogue: docs/emitted_interface.md declares every entry point as emitted",
          "[codegen][catalogue]") {
  const std::string doc = read(SYMDYN_DOCS_DIR "/emitted_interface.md");
  for (const EntryPointSpec& spec : catalogue()) {
    INFO(spec.name);
    CHECK(declaration(doc, spec) == "static " + signature(spec, "", false));
  }
}

TEST_CASE("catalogue: rows are well formed", "[codegen][catalogue]") {
  const Sizes sizes{.nq = 2, .nbody = 3, .ndep = 1};
  for (const EntryPointSpec& spec : catalogue()) {
    INFO(spec.name);
    CHECK_FALSE(spec.doc.empty());
    // Inputs in the order of kInputs, each once: the shared program's inputs are in that order.
    CHECK(std::is_sorted(spec.inputs.begin(), spec.inputs.end()));
    CHECK(std::adjacent_find(spec.inputs.begin(), spec.inputs.end()) == spec.inputs.end());
    CHECK_FALSE(spec.outputs.empty());
    for (const OutputSpec& o : spec.outputs) {
      INFO(o.name);
      CHECK_NOTHROW(shape_size(o.shape, sizes));
      // A hand-written body writes its outputs; a program computes each from its source.
      CHECK(static_cast<bool>(o.source) == (spec.body == nullptr));
      // Only a program knows which of its entries are structural zeros, to leave them alone.
      if (o.sparse) CHECK(spec.body == nullptr);
    }
    CHECK((spec.body == nullptr) == spec.note.empty());
    if (!spec.calls.empty()) CHECK(is_entry_point(spec.calls));
    if (spec.needs.equations_of_motion || spec.needs.recursive_dynamics)
      CHECK(spec.needs.absolute_motion);
    if (spec.needs.recursive_dynamics) CHECK(spec.needs.equations_of_motion);
  }
}

TEST_CASE("catalogue: the forms of one name differ only in their partial velocities",
          "[codegen][catalogue]") {
  for (const std::string_view name : entry_point_names()) {
    std::vector<const EntryPointSpec*> forms;
    for (const EntryPointSpec& spec : catalogue()) {
      if (spec.name == name) forms.push_back(&spec);
    }
    INFO(name);
    for (const EntryPointSpec* form : forms) {
      // One declaration in the header and the docs, whichever form is emitted.
      CHECK(signature(*form, "", false) == signature(*forms.front(), "", false));
      if (forms.size() > 1) CHECK(form->needs.partials != Partials::either);
    }
    if (forms.size() == 2) CHECK(forms[0]->needs.partials != forms[1]->needs.partials);
    CHECK(forms.size() <= 2);
  }
}

TEST_CASE("catalogue: shapes print with the model's sizes", "[codegen][catalogue]") {
  const Sizes sizes{.nq = 5, .nbody = 3, .ndep = 0};
  CHECK(shape_text("nbody x nq x 3", sizes) == "(3 x 5 x 3)");
  CHECK(shape_size("nbody x nq x 3", sizes) == 45);
  CHECK(shape_text("ndep", sizes) == "(0)");
  CHECK(shape_size("nq x 2", sizes) == 10);
  CHECK_THROWS_AS(shape_size("nbody x 3x3", sizes), std::logic_error);
}

TEST_CASE("catalogue: what a selection needs derived", "[codegen][catalogue]") {
  CHECK(Selection({}, true).needs_absolute_motion());
  CHECK(Selection({}, true).needs_equations_of_motion());
  CHECK_FALSE(Selection({"relative_accelerations", "dependent_parameters", "inertia"}, true)
                  .needs_absolute_motion());
  CHECK(Selection({"relative_accelerations", "positions"}, true).needs_absolute_motion());
  CHECK(Selection({"nope"}, true).needs_absolute_motion());  // the error comes after the derivation
  CHECK_FALSE(Selection({"positions", "partial_velocities"}, true).needs_equations_of_motion());
  CHECK(Selection({"positions", "forward_dynamics"}, true).needs_equations_of_motion());
}
