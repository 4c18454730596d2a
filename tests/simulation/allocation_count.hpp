#pragma once
// Heap allocations (malloc, calloc, realloc: operator new and Eigen's
// dynamic-size storage both end there) made by this test program so far, or
// nullopt where they cannot be counted (under AddressSanitizer, which owns
// malloc). A difference of two readings around a call tells whether it allocated.
#include <cstddef>
#include <optional>

namespace symdyn_test {
std::optional<std::size_t> allocation_count();
}  // namespace symdyn_test
