#pragma once
// The force elements of a scenario file ("forces": [...]), one row of the
// table in elements.cpp per type: its keys, how it is built from them, and
// the quantities it reports to outputs and checks (<element>.<quantity>).
// Their constants (stiffness, ...) are the runtime's table's
// (runtime/element_parameters.hpp): names, defaults and ranges.
// Bodies and coordinates are given by name ("ground" for the fixed frame).

#include <memory>
#include <vector>

#include "quantities.hpp"
#include "scenario.hpp"

namespace symdyn::sim {

// What building an element needs: the model's names, the run's symbols, and
// the variables its laws read (values owned by the run, changed by events).
struct ElementContext {
  const Names& names;
  SymbolTable& table;
  const std::vector<double>& variables;
};

// Builds the element described at `node` (ScenarioError naming the culprit).
std::shared_ptr<ScenarioElement> make_element(const Node& node, const ElementContext& context);

// The element types, for messages and the documentation test.
std::vector<std::string> element_types();

// The members a type takes besides type and name ("enabled" first); empty for
// an unknown type.
std::vector<std::string> element_members(std::string_view type);

// An expression-valued member: a number or a text (ScenarioError at the
// member's path when it does not parse or names something unknown).
Expression read_expression(const Node& node, const Resolver& resolver);

}  // namespace symdyn::sim
