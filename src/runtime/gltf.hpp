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
#include <string>
#include <vector>

#include <symdyn/runtime/animation.hpp>
#include <symdyn/runtime/scene.hpp>

namespace symdyn::runtime {

// A named animation: the motion, or a mode shape (animation.hpp's mode_animation).
struct Clip {
  std::string name;
  const Animation* animation;
};

// Writes the scene animated by each clip (a glTF animation each, in order); the
// nodes start in the first clip's first pose. OptionError when a clip has no
// frame or the scene and a clip differ in bodies.
void write_glb(std::ostream& out, const Scene& scene, const std::vector<Clip>& clips);
void write_glb(const std::filesystem::path& file, const Scene& scene,
               const std::vector<Clip>& clips);
// One clip, "motion".
void write_glb(std::ostream& out, const Scene& scene, const Animation& animation);
void write_glb(const std::filesystem::path& file, const Scene& scene, const Animation& animation);

}  // namespace symdyn::runtime
