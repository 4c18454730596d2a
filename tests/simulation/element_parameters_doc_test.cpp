// The force elements' constants as the runtime's table describes them
// (runtime/element_parameters.hpp), against docs/scenario.schema.json and the
// table of docs/scenarios.md: both are generated from it. A mismatch writes
// the generated file next to the test (the schema whole, the doc's table as a
// block) for the docs to take.
#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "elements.hpp"
#include <symdyn/runtime/element_parameters.hpp>

namespace {

using nlohmann::ordered_json;
using symdyn::runtime::Parameter;
using symdyn::runtime::ParameterShape;
using symdyn::runtime::Sign;

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// "N/m: k in ..." or the meaning alone.
std::string schema_description(const Parameter& p) {
  return p.unit.empty() ? std::string(p.meaning) : fmt::format("{}: {}", p.unit, p.meaning);
}

ordered_json number_schema(Sign sign) {
  ordered_json n{{"type", "number"}};
  if (sign == Sign::non_negative) n["minimum"] = 0;
  if (sign == Sign::positive) n["exclusiveMinimum"] = 0;
  return n;
}

// A parameter's property in the schema.
ordered_json property_schema(const Parameter& p) {
  ordered_json s{{"description", schema_description(p)}};
  if (p.shape == ParameterShape::number) {
    s.update(number_schema(p.sign));
    if (!p.required) s["default"] = p.fallback[0];
    return s;
  }
  s["type"] = "array";
  s["items"] = number_schema(p.sign);
  s["minItems"] = 3;
  s["maxItems"] = 3;
  if (p.shape == ParameterShape::direction) s["not"] = {{"items", {{"const", 0}}}};
  if (!p.required) s["default"] = p.fallback;
  return s;
}

// The schema with each element's constants as the table has them (the other
// members as they are).
ordered_json generated_schema(ordered_json schema) {
  for (ordered_json& element : schema["properties"]["forces"]["items"]["oneOf"]) {
    const std::string type = element["properties"]["type"]["const"];
    const auto members = symdyn::sim::element_members(type);
    const bool has_constants = std::any_of(symdyn::runtime::element_parameter_table().begin(),
                                           symdyn::runtime::element_parameter_table().end(),
                                           [&](const auto& row) { return row.type == type; });
    if (!has_constants) continue;
    // Members in the reader's order: type, name, then element_members.
    ordered_json properties{{"type", element["properties"]["type"]},
                            {"name", element["properties"]["name"]}};
    ordered_json required{"type", "name"};
    const auto& row = symdyn::runtime::element_parameters(type);
    for (const std::string& m : members) {
      if (const Parameter* p = row.find(m)) {
        properties[m] = property_schema(*p);
        if (p->required) required.push_back(m);
      } else {
        properties[m] = element["properties"].value(m, ordered_json::object());
        for (const auto& r : element["required"]) {
          if (r == m) required.push_back(m);
        }
      }
    }
    element["required"] = required;
    element["properties"] = properties;
  }
  return schema;
}

std::string default_text(const Parameter& p) {
  if (p.required) return "required";
  if (p.shape == ParameterShape::number) return fmt::format("{:g}", p.fallback[0]);
  return fmt::format("[{:g}, {:g}, {:g}]", p.fallback[0], p.fallback[1], p.fallback[2]);
}

// docs/scenarios.md's table of constants.
std::string generated_doc_table() {
  std::string out =
      "| element | constant | unit | value | default | meaning |\n"
      "|---|---|---|---|---|---|\n";
  for (const auto& row : symdyn::runtime::element_parameter_table()) {
    for (const Parameter& p : row.parameters) {
      out += fmt::format("| `{}` | `{}` | {} | {} | {} | {} |\n", row.type, p.name, p.unit,
                         symdyn::runtime::requirement(p), default_text(p), p.meaning);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("docs/scenario.schema.json: each element's constants are the runtime's table's",
          "[scenario][docs]") {
  const std::string path = std::string(SYMDYN_DOCS) + "/scenario.schema.json";
  const std::string text = text_of(path);
  const ordered_json schema = ordered_json::parse(text);
  const std::string generated = generated_schema(schema).dump(2) + "\n";
  const bool same = generated == text;
  if (!same) std::ofstream("scenario.schema.generated.json") << generated;
  INFO(
      "docs/scenario.schema.json differs from the table's: see scenario.schema.generated.json "
      "in the test's folder");
  CHECK(same);
}

TEST_CASE("docs/scenarios.md: the table of constants is the runtime's table", "[scenario][docs]") {
  const std::string doc = text_of(std::string(SYMDYN_DOCS) + "/scenarios.md");
  const std::string table = generated_doc_table();
  const bool found = doc.find(table) != std::string::npos;
  if (!found) std::ofstream("scenarios.constants.generated.md") << table;
  INFO(
      "docs/scenarios.md lacks the table of constants: see scenarios.constants.generated.md in "
      "the test's folder\n"
      << table);
  CHECK(found);
}
