#pragma once
// How hard the reference-model tests look at each model: where its random
// states lie and how many there are. Big models get few states so that the
// label stays under about a minute in release.

#include <string>
#include <string_view>

namespace symdyn::testing {

struct TestPlan {
  std::string_view model;
  // q = q_initial + amplitude·u, u in [-1, 1]: amru5's legs close only near
  // their initial configuration (the knee's law of cosines needs
  // |a - b| <= |PQ| <= a + b), every other model anywhere.
  double amplitude;
  int states;                  // random states per check
  bool simplified_derivation;  // also check the simplified derivation in process (costs its
                               // generation time)
};

inline constexpr TestPlan test_plans[] = {
    {"double_pendulum", 1.0, 10, true}, {"robot3d", 1.0, 10, true},
    {"slider_crank", 1.0, 10, true},    {"trike", 1.0, 5, true},
    {"amru5", 0.1, 1, false},           {"hexapod_tree", 1.0, 2, true},
    {"chain_2", 1.0, 5, true},          {"chain_4", 1.0, 5, true},
    {"chain_8", 1.0, 3, true},          {"chain_16", 1.0, 2, false},
    {"chain_32", 1.0, 1, false},        {"chain_64", 1.0, 1, false},
};

// The plan of a model; an unknown model gets none (states = 0) so that a test
// over the registry notices it.
inline TestPlan test_plan(std::string_view model) {
  for (const TestPlan& p : test_plans) {
    if (p.model == model) return p;
  }
  return {model, 1.0, 0, false};
}

}  // namespace symdyn::testing
