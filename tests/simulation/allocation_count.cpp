#include "allocation_count.hpp"

#include <atomic>
#include <cstddef>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SYMDYN_ADDRESS_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(SYMDYN_ADDRESS_SANITIZER)

std::optional<std::size_t> symdyn_test::allocation_count() {
  return std::nullopt;
}

#else

// glibc's allocator under its own names: this program's malloc, calloc and
// realloc count and forward to them (free stays glibc's: the same allocator).
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* __libc_calloc(std::size_t n, std::size_t size);
extern "C" void* __libc_realloc(void* p, std::size_t size);

namespace {
std::atomic<std::size_t> count{0};
}  // namespace

std::optional<std::size_t> symdyn_test::allocation_count() {
  return count.load(std::memory_order_relaxed);
}

extern "C" void* malloc(std::size_t size) {
  count.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
extern "C" void* calloc(std::size_t n, std::size_t size) {
  count.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, size);
}
extern "C" void* realloc(void* p, std::size_t size) {
  count.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}

#endif
