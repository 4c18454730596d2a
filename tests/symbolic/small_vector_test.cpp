// SmallVector: the same elements as a std::vector given the same pushes,
// inline and past its inline capacity.
#include "symbolic/small_vector.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <vector>

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
