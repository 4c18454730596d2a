#pragma once
// A self-contained HTML file to watch a simulation in any browser: the scene
// and its clips as embedded glTF (the motion, then e.g. each mode), the time
// histories plotted beside it with a cursor at the current time, and the
// viewer itself (three.js, bundled into the runtime at build time from
// viewer/). Play/pause, a time slider, speed, orbit/zoom/pan with the mouse,
// body names on hover. Nothing is fetched: the file opens offline.
//
// The URL's hash chooses where it starts: file.html#t=1.5 (paused there),
// #clip=1 (the second clip), #paused.

#include <filesystem>
#include <string>
#include <vector>

#include <symdyn/runtime/gltf.hpp>

namespace symdyn::runtime {

class Model;

// Time histories: names[0] is the time, columns[k] the values of names[k] in
// units[k] (the plot groups series by unit; no units, or an empty one: none).
struct TimeSeries {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  std::vector<std::string> units;
};

// Arrows drawn in the scene (the loops' reaction forces; none unless given):
// arrow k named names[k], at points[k] (m) along vectors[k] (N), each 3 values
// (global axes) per time of the series; the viewer shows those of the last
// output instant up to its time, scaled together (the longest a fifth of the
// bodies' size).
struct Arrows {
  std::vector<std::string> names;
  std::vector<std::vector<double>> points, vectors;
};

// The unit of each coordinate of a model: "rad" when it turns a body (about the
// model's initial state), else "m"; empty when the model has no kinematics.
std::vector<std::string> coordinate_units(const Model& model);

// Whether this runtime was built with the viewer (npm was found at build time).
bool html_viewer_available();

// Writes the viewer; OptionError if the runtime was built without it, or for
// bad clips (write_glb), series of unequal lengths or arrows not 3 values per
// time of the series.
void write_html(const std::filesystem::path& file, const std::string& title, const Scene& scene,
                const std::vector<Clip>& clips, const TimeSeries& series = {},
                const Arrows& arrows = {});

}  // namespace symdyn::runtime
