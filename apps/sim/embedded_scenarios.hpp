#pragma once
// The scenario files of models/scenarios, embedded in symdyn-sim by
// apps/sim/CMakeLists.txt (embedded_scenarios.cpp is generated).
#include <vector>

namespace symdyn::sim {

struct EmbeddedScenario {
  const char* name;  // the file's stem
  const char* text;
};
const std::vector<EmbeddedScenario>& embedded_scenarios();

}  // namespace symdyn::sim
