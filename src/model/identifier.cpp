#include <fmt/format.h>

#include <algorithm>
#include <iterator>

#include <symdyn/model/errors.hpp>
#include <symdyn/model/identifier.hpp>

namespace symdyn::model {

namespace {

// The keywords and alternative tokens of C++20 ([lex.key], [lex.digraph]).
constexpr std::string_view kKeywords[] = {"alignas",       "alignof",     "and",
                                          "and_eq",        "asm",         "auto",
                                          "bitand",        "bitor",       "bool",
                                          "break",         "case",        "catch",
                                          "char",          "char8_t",     "char16_t",
                                          "char32_t",      "class",       "compl",
                                          "concept",       "const",       "consteval",
                                          "constexpr",     "constinit",   "const_cast",
                                          "continue",      "co_await",    "co_return",
                                          "co_yield",      "decltype",    "default",
                                          "delete",        "do",          "double",
                                          "dynamic_cast",  "else",        "enum",
                                          "explicit",      "export",      "extern",
                                          "false",         "float",       "for",
                                          "friend",        "goto",        "if",
                                          "inline",        "int",         "long",
                                          "mutable",       "namespace",   "new",
                                          "noexcept",      "not",         "not_eq",
                                          "nullptr",       "operator",    "or",
                                          "or_eq",         "private",     "protected",
                                          "public",        "register",    "reinterpret_cast",
                                          "requires",      "return",      "short",
                                          "signed",        "sizeof",      "static",
                                          "static_assert", "static_cast", "struct",
                                          "switch",        "template",    "this",
                                          "thread_local",  "throw",       "true",
                                          "try",           "typedef",     "typeid",
                                          "typename",      "union",       "unsigned",
                                          "using",         "virtual",     "void",
                                          "volatile",      "wchar_t",     "while",
                                          "xor",           "xor_eq"};

bool is_ascii_letter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}
bool is_ascii_digit(char c) {
  return c >= '0' && c <= '9';
}

}  // namespace

std::optional<std::string> name_problem(std::string_view name) {
  if (name.empty()) return "is empty";
  const auto bad = std::find_if(name.begin(), name.end(), [](char c) {
    return !is_ascii_letter(c) && !is_ascii_digit(c) && c != '_';
  });
  if (bad != name.end()) {
    return fmt::format("is not a C++ identifier (character '{}' at {})", *bad, bad - name.begin());
  }
  if (is_ascii_digit(name[0])) return std::string("is not a C++ identifier (starts with a digit)");
  return std::nullopt;
}

void check_name(std::string_view name, std::string_view what) {
  if (auto problem = name_problem(name))
    throw ModelError(fmt::format("{} '{}' {}", what, name, *problem));
}

std::optional<std::string> identifier_problem(std::string_view name) {
  if (auto problem = name_problem(name)) return problem;
  if (std::find(std::begin(kKeywords), std::end(kKeywords), name) != std::end(kKeywords)) {
    return std::string("is a C++ keyword");
  }
  if (name.find("__") != std::string_view::npos) {
    return std::string("is reserved to the C++ implementation (contains '__')");
  }
  if (name[0] == '_') return std::string("is reserved to the C++ implementation (starts with '_')");
  return std::nullopt;
}

void check_identifier(std::string_view name, std::string_view what) {
  if (auto problem = identifier_problem(name))
    throw ModelError(fmt::format("{} '{}' {}", what, name, *problem));
}

}  // namespace symdyn::model
