#pragma once
// The "shapes" of a scenario (docs/scenarios.md, Shapes): what the pictures of
// a run (--html, --glb, --easyanim) draw each body as, by body name:
//   "shapes": {
//     "chassis": {"type": "box", "size": [1.8, 0.6, 0.25], "colour": "#4e79a7"},
//     "front_wheel": [{"type": "cylinder", "radius": 0.3, "length": 0.12, "axis": [0, 1, 0]}],
//     "rear_axle": []
//   }
// A body not named keeps its default shapes (runtime/scene.hpp); an empty list
// hides it. Every error is a ScenarioError at the culprit's JSON path.

#include "scenario.hpp"
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/scene.hpp>

namespace symdyn::sim {

// The scene of the scenario's model: its "shapes" over the default shapes.
// Mesh files are relative to the scenario's directory.
runtime::Scene read_scene(const Scenario& scenario, const runtime::Model& model);

}  // namespace symdyn::sim
