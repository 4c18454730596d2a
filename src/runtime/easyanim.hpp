#pragma once
// EasyDyn's animation files, so that EasyDyn users keep their viewer, EasyAnim.
//
//   .vol  the scene: a title line; the node count, then "name x y z" per node
//         (its position in the first frame); the edge count (none are written)
//         and the face count, then "name 3 n1 n2 n3 colour" per triangle, n1..n3
//         node names. Nodes and faces are named by their number, from 0.
//   .van  every frame: each node's "x y z", one per line, in .vol order, frames
//         one after the other without header.
//   .vmo  every mode: a line "re im freq damping" (the pole, the natural
//         frequency in Hz and the damping ratio), then the nodes displaced by
//         the real part of the mode shape, then by its imaginary part.
// Colours are EasyAnim's 16 indices, the nearest of the EGA palette (0 black,
// 1 blue, 2 green, 3 cyan, 4 red, 5 magenta, 6 brown, 7 light grey, 8 dark grey,
// 9-14 their light versions and yellow, 15 white).

#include <filesystem>
#include <vector>

#include <symdyn/runtime/animation.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/scene.hpp>

namespace symdyn::runtime {

class Model;

// Writes <stem>.vol and <stem>.van.
void write_easyanim(const std::filesystem::path& stem, const Scene& scene,
                    const Animation& animation, const std::string& title);

// Writes <stem>.vol (the scene at the reference state) and <stem>.vmo: each mode
// of the linearization about `reference`, its shape scaled so that the largest
// coordinate moves by `amplitude` (rad or m).
void write_easyanim_modes(const std::filesystem::path& stem, const Scene& scene, const Model& model,
                          const State& reference, const Linearization& lin,
                          const std::vector<Mode>& modes, double amplitude,
                          const std::string& title);

// EasyAnim's colour index nearest to a colour.
int easyanim_colour(const Colour& c);

}  // namespace symdyn::runtime
