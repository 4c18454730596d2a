#pragma once
// A hash map from 64-bit keys to small values, for the engine's hot tables.
//
// Why: std::unordered_map and std::map allocate a node per entry and chase
// pointers on every lookup; the pair tables of CSE make millions of lookups.
// This one is a single array with open addressing (linear probing) and never
// erases: an entry whose value has dropped back to its default stays, which is
// what counters want. Iteration order is not exposed, so nothing built on it
// can depend on hashing.
#include <bit>
#include <cstdint>
#include <utility>
#include <vector>

namespace symdyn::symbolic::detail {

template <class Value>
class FlatMap64 {
 public:
  explicit FlatMap64(std::size_t expected = 16) { rehash(std::bit_ceil(2 * expected + 2)); }

  // The value of `key`, inserted as `fresh` if absent; second: whether inserted.
  // The reference stays valid until the next insertion.
  std::pair<Value*, bool> try_emplace(std::uint64_t key, Value fresh = Value{}) {
    if (2 * (size_ + 1) > slots_.size()) rehash(2 * slots_.size());
    std::size_t i = slot_of(key);
    while (slots_[i].used) {
      if (slots_[i].key == key) return {&slots_[i].value, false};
      i = (i + 1) & mask_;
    }
    slots_[i] = {key, std::move(fresh), true};
    ++size_;
    return {&slots_[i].value, true};
  }

  // The value of `key`, or nullptr.
  const Value* find(std::uint64_t key) const {
    for (std::size_t i = slot_of(key); slots_[i].used; i = (i + 1) & mask_) {
      if (slots_[i].key == key) return &slots_[i].value;
    }
    return nullptr;
  }

  std::size_t size() const { return size_; }

 private:
  struct Slot {
    std::uint64_t key = 0;
    Value value{};
    bool used = false;
  };

  // Fibonacci hashing: the high bits of key·φ spread consecutive ids.
  std::size_t slot_of(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ULL) >> shift_) & mask_;
  }

  void rehash(std::size_t capacity) {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
    size_ = 0;
    for (Slot& s : old) {
      if (!s.used) continue;
      std::size_t i = slot_of(s.key);
      while (slots_[i].used) i = (i + 1) & mask_;
      slots_[i] = std::move(s);
      ++size_;
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace symdyn::symbolic::detail
