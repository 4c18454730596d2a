// The link-time guard (docs/emitted_interface.md): every file including the
// header refers to this model's own symbol, so the linker pulls this model's
// object even from a static library, and a second, different model of the
// same struct name then collides with it on symdyn_model_<struct>.
#include <fmt/format.h>

#include <array>

#include <symdyn/codegen/detail/cpp_text.hpp>

namespace symdyn::codegen::detail {

// FNV-1a's step over little-endian 8-byte words in 4 independent lanes, then
// over the lanes' bytes: byte by byte, its chain of dependent multiplications
// would be slow to run over the whole source.
std::uint64_t text_hash(std::string_view text) {
  constexpr std::uint64_t kBasis = 14695981039346656037ull, kPrime = 1099511628211ull;
  constexpr std::size_t kLanes = 4, kBlock = 8 * kLanes;
  const auto byte = [&](std::size_t i) {
    return std::uint64_t{static_cast<unsigned char>(text[i])};
  };
  std::array<std::uint64_t, kLanes> lanes;
  lanes.fill(kBasis);
  std::size_t i = 0;
  for (; i + kBlock <= text.size(); i += kBlock) {
    for (std::size_t k = 0; k < kLanes; ++k) {
      std::uint64_t word = 0;
      for (std::size_t b = 0; b < 8; ++b) word |= byte(i + 8 * k + b) << (8 * b);
      lanes[k] = (lanes[k] ^ word) * kPrime;
    }
  }
  std::uint64_t h = kBasis;
  for (std::uint64_t lane : lanes) {
    for (std::size_t b = 0; b < 8; ++b) h = (h ^ ((lane >> (8 * b)) & 0xff)) * kPrime;
  }
  for (; i < text.size(); ++i) h = (h ^ byte(i)) * kPrime;
  return h;
}

std::string link_guard_reference(const TextContext& c, const std::string& unique) {
  return fmt::format(
      "// Link-time guard: two different models named {name} in one program fail to link\n"
      "// (multiple definition of {ns}::symdyn_model_{name}).\n"
      "extern const char {unique}[];\n"
      "[[gnu::used]] static const char* const symdyn_model_{name}_link = {unique};\n\n",
      fmt::arg("name", c.basename), fmt::arg("ns", c.options.name_space),
      fmt::arg("unique", unique));
}

std::string link_guard_definitions(const TextContext& c, const std::string& unique) {
  const std::string what = fmt::format("\"model '{}', variant '{}'\"", c.model.name(), c.variant);
  return fmt::format(
      "\n// Link-time guard: see the header.\nextern const char symdyn_model_{0}[];\n"
      "const char symdyn_model_{0}[] = {1};\nconst char {2}[] = {1};\n",
      c.basename, what, unique);
}

}  // namespace symdyn::codegen::detail
