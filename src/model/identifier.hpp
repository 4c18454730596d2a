#pragma once
// Two rules for the names that end up in emitted C++. A name (a model, a
// variant, a body, a symbol) is only ever printed inside a string literal or as
// part of a longer identifier: it has the shape of an identifier. A name the
// emitted code declares (the struct, the namespace) must moreover be one a
// program may declare: not a keyword, not reserved to the implementation.

#include <optional>
#include <string>
#include <string_view>

namespace symdyn::model {

// Why `name` does not have the shape of an identifier ([A-Za-z_][A-Za-z0-9_]*),
// or nothing when it has.
std::optional<std::string> name_problem(std::string_view name);

// Throws ModelError "<what> '<name>' <problem>" unless name_problem finds none.
void check_name(std::string_view name, std::string_view what);

// Why `name` is not an identifier a program may declare ("is a C++ keyword",
// "starts with a digit", ...), or nothing when it is one.
std::optional<std::string> identifier_problem(std::string_view name);

// Throws ModelError "<what> '<name>' <problem>" unless `name` is such an identifier.
void check_identifier(std::string_view name, std::string_view what);

}  // namespace symdyn::model
