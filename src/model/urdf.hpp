#pragma once
// A robot described in URDF, imported as a symdyn model (docs/urdf.md); the
// library symdyn::urdf, which alone needs urdfdom.
//
//   const model::UrdfRobot robot = model::import_urdf_file("arm.urdf");
//   codegen::generate(robot.model, "default", "arm");
//   for (const model::UrdfJoint& j : robot.joints) ... j.limits ...
//
// Mapping:
//   link with <inertial> and a mass     a body, its frame at the centre of mass
//                                       with the axes of the <inertial> origin,
//                                       its full inertia tensor as given;
//   link without mass (or of mass 0)    a frame: its children hang on its
//                                       nearest massive ancestor;
//   body motion                         relative to the nearest massive ancestor
//                                       (or the ground): inverse of that
//                                       ancestor's inertial origin, then along the
//                                       path each joint's origin (xyz, then
//                                       rpy = Rz(yaw)·Ry(pitch)·Rx(roll)) and
//                                       motion, then the link's inertial origin;
//   fixed                               no coordinate;
//   revolute, continuous                one coordinate <joint>: Trot(axis, q);
//   prismatic                           one coordinate <joint>: Tdisp(axis·q);
//   floating                            six: <joint>_x, _y, _z (translation in
//                                       the joint frame), then <joint>_yaw,
//                                       _pitch, _roll: Rz·Ry·Rx;
//   planar, mimic                       refused (ModelError naming the joint).
// The root link is fixed to the ground unless UrdfOptions::floating_base: then
// it moves as by a floating joint named after it (<root>_x ... <root>_roll).
// Coordinates come depth-first from the root, a link's children in the order of
// their joints' names (urdfdom keeps them sorted). Names that are not
// identifiers have each other character replaced by '_'.
//
// Errors (ModelError, naming the file, link or joint): unreadable file, urdfdom's
// parse errors (any it logs, even when it returns a robot), a number that is
// not finite or beyond a double's range (naming the element and attribute),
// unsupported joints, an axis of zero length, a coordinate that moves no body
// (a movable joint with no mass beyond it), closed loops; the builder's own
// checks name the body of a non-physical mass or inertia. rpy angles are read
// as written (urdfdom's getRPY rounds a pitch near ±90° to ±π/2).
// urdfdom reports its errors through console_bridge's global output handler,
// which the importer takes over while parsing: import from one thread at a time.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/model/model.hpp>

namespace symdyn::model {

struct UrdfOptions {
  bool floating_base = false;             // the root link moves freely (6 coordinates)
  double gravity[3] = {0.0, 0.0, -9.81};  // in the URDF world frame
  std::string name;                       // the model's name; empty: the robot's
};

// What a URDF says of one joint that symdyn keeps as data: its type, its
// coordinates (none for fixed) and its limits, when declared.
struct UrdfJoint {
  struct Limits {
    double lower = 0.0, upper = 0.0;  // rad or m; revolute and prismatic only
    double velocity = 0.0;            // rad/s or m/s
    double effort = 0.0;              // N·m or N
  };
  std::string name;  // as in the URDF
  std::string type;  // "fixed", "revolute", "continuous", "prismatic", "floating"
  std::vector<std::string> coordinates;  // the names given to the model's coordinates
  std::optional<Limits> limits;
  // For a <mimic> joint, the joint it mimics: its variable is then the dependent
  // parameter multiplier·q + offset named after it, and `coordinates` is empty.
  std::string mimic;
};

struct UrdfRobot {
  Model model;
  std::vector<UrdfJoint> joints;  // in the order of their coordinates, fixed joints included
};

// Adds the robot's bodies, coordinates and gravity to `model` (whose name is
// kept); returns the joints. For model::Definition::build.
std::vector<UrdfJoint> add_urdf(Model& model, std::string_view urdf_xml,
                                const UrdfOptions& options = {});

UrdfRobot import_urdf(std::string_view urdf_xml, const UrdfOptions& options = {});
UrdfRobot import_urdf_file(const std::string& path, const UrdfOptions& options = {});

// A <visual> of a link, placed on the body it moves with: what a viewer draws
// (symdyn-urdf --shapes writes them as a scenario's "shapes", docs/urdf.md).
// The pose is in the body's frame (G, the inertial axes): origin, and axes
// (the shape's x, y, z as columns, column-major). A link without mass hangs its
// visuals on the body it is fixed to (through fixed joints only).
struct UrdfVisual {
  std::string body;              // the model's body name
  std::string type;              // "box", "sphere", "cylinder" or "mesh"
  std::array<double, 3> size{};  // box: edges; sphere: radius, -, -; cylinder: radius, length, -
  std::string mesh;              // mesh: the file, resolved against the URDF's directory
  std::array<double, 3> scale{1.0, 1.0, 1.0};  // mesh
  std::array<double, 3> origin{};
  std::array<double, 9> axes{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::optional<std::array<double, 4>> rgba;  // the material's colour, if given
};

// The visuals of a robot; `directory` resolves relative mesh files and
// package://name/... (against the nearest folder called name above it, else
// the directory itself). `skipped` gets a line for each visual left out (on a
// link moved by no body, or of no geometry).
std::vector<UrdfVisual> urdf_visuals(std::string_view urdf_xml, const std::string& directory,
                                     std::vector<std::string>* skipped = nullptr);

// The contents of a URDF file; throws ModelError naming it when unreadable.
std::string read_urdf_file(const std::string& path);
// The robot's name, as a model name (an identifier); throws ModelError on a parse error.
std::string urdf_robot_name(std::string_view urdf_xml);

}  // namespace symdyn::model
