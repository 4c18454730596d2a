#pragma once
// The motion of a model as a glTF 2.0 binary file (.glb), which Blender, the
// browsers' viewers and most 3D tools open.
//
// One node per body, named after it, holding one mesh primitive per shape
// (tessellated in the body's frame, with its colour as a material); the body's
// motion as two animation channels, translation and rotation, sampled at the
// recorded instants with linear interpolation (spherical for rotations). The
// bodies hang under a root node "world" that turns the model's up direction
// (against gravity) onto glTF's +Y. The nodes start in the first frame's pose.

#include <filesystem>
#include <ostream>

#include <symdyn/runtime/animation.hpp>
#include <symdyn/runtime/scene.hpp>

namespace symdyn::runtime {

// Writes the scene animated by the frames recorded (at least one); OptionError
// when there is none or the scene and the animation differ in bodies.
void write_glb(std::ostream& out, const Scene& scene, const Animation& animation);
void write_glb(const std::filesystem::path& file, const Scene& scene, const Animation& animation);

}  // namespace symdyn::runtime
