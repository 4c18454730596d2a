// SmallVector: the same elements as a std::vector given the same pushes,
// inserts and erases, inline and past its inline capacity, and after copies
// and moves.
#include <catch2/catch.hpp>
#include <random>
#include <utility>
#include <vector>

#include <symdyn/symbolic/detail/small_vector.hpp>

namespace {

struct Pair {
  int key;
  double weight;
};

}  // namespace

TEST_CASE("SmallVector holds what a std::vector holds, across growth", "[small_vector]") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = std::uniform_int_distribution<std::size_t>(0, 40)(rng);
    symdyn::symbolic::detail::SmallVector<Pair, 4> small;
    std::vector<Pair> reference;
    if (trial % 3 == 0) small.reserve(n / 2);
    for (std::size_t i = 0; i < n; ++i) {
      const Pair p{static_cast<int>(rng() % 1000), static_cast<double>(rng() % 97) / 4};
      small.push_back(p);
      reference.push_back(p);
    }
    REQUIRE(small.size() == reference.size());
    REQUIRE(small.empty() == reference.empty());
    for (std::size_t i = 0; i < n; ++i) {
      CHECK(small[i].key == reference[i].key);
      CHECK(small[i].weight == reference[i].weight);
    }
    if (n > 0) CHECK(small.back().key == reference.back().key);
    const std::size_t keep = n / 3;
    small.truncate(keep);
    CHECK(small.size() == keep);
    CHECK(static_cast<std::size_t>(small.end() - small.begin()) == keep);
    small.push_back({-1, 0.5});
    CHECK(small[keep].key == -1);
    for (std::size_t i = 0; i < keep; ++i) CHECK(small[i].key == reference[i].key);
  }
}

TEST_CASE("SmallVector copies, moves, inserts and erases as a std::vector does", "[small_vector]") {
  using Small = symdyn::symbolic::detail::SmallVector<int, 4>;
  std::mt19937 rng(11);
  auto same = [](const Small& small, const std::vector<int>& reference) {
    return std::vector<int>(small.begin(), small.end()) == reference;
  };
  for (int trial = 0; trial < 200; ++trial) {
    Small small;
    std::vector<int> reference;
    const int steps = std::uniform_int_distribution<int>(0, 30)(rng);
    for (int step = 0; step < steps; ++step) {
      const int value = static_cast<int>(rng() % 100);
      const std::size_t at = reference.empty() ? 0 : rng() % (reference.size() + 1);
      if (rng() % 3 == 0 && !reference.empty()) {
        const std::size_t gone = at % reference.size();
        small.erase(small.begin() + gone);
        reference.erase(reference.begin() + static_cast<std::ptrdiff_t>(gone));
      } else {
        small.insert(small.begin() + at, value);
        reference.insert(reference.begin() + static_cast<std::ptrdiff_t>(at), value);
      }
      REQUIRE(same(small, reference));
    }
    const Small copy = small;
    CHECK(copy == small);
    CHECK(same(copy, reference));
    Small assigned{1, 2, 3};
    assigned = copy;
    CHECK(same(assigned, reference));
    Small moved = std::move(assigned);
    CHECK(same(moved, reference));
    CHECK(assigned.empty());  // NOLINT(bugprone-use-after-move): a moved-from SmallVector is empty
    Small target{7};
    target = std::move(moved);
    CHECK(same(target, reference));
    target.push_back(5);
    CHECK(!(target == copy));
  }
}
