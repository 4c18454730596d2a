#include <console_bridge/console.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <symdyn/model/urdf.hpp>

namespace symdyn::model {

namespace {

// urdfdom reports its parse errors through console_bridge and returns null:
// while parsing, they are collected here to be put in the ModelError.
class CollectedMessages : public console_bridge::OutputHandler {
 public:
  CollectedMessages() { console_bridge::useOutputHandler(this); }
  ~CollectedMessages() override { console_bridge::restorePreviousOutputHandler(); }
  CollectedMessages(const CollectedMessages&) = delete;
  CollectedMessages& operator=(const CollectedMessages&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_.push_back(text);
  }
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  std::vector<std::string> errors_;
};

// urdfdom's model, freed whole: links own their children through shared
// pointers, so a closed loop (which urdfdom lets through) would never be freed.
class ParsedRobot {
 public:
  explicit ParsedRobot(urdf::ModelInterfaceSharedPtr robot) : robot_(std::move(robot)) {}
  ~ParsedRobot() {
    for (auto& [name, link] : robot_->links_) {
      link->child_links.clear();
      link->child_joints.clear();
    }
  }
  ParsedRobot(const ParsedRobot&) = delete;
  ParsedRobot& operator=(const ParsedRobot&) = delete;
  const urdf::ModelInterface& operator*() const { return *robot_; }
  const urdf::ModelInterface* operator->() const { return robot_.get(); }

 private:
  urdf::ModelInterfaceSharedPtr robot_;
};

// urdfdom logs an error and still returns the robot for some bad numbers
// (a <mass> or <inertia> that does not parse leaves the link with mass 0, a
// frame): any error it logs refuses the file.
ParsedRobot parse(std::string_view xml) {
  CollectedMessages messages;
  urdf::ModelInterfaceSharedPtr robot = urdf::parseURDF(std::string(xml));
  if (!robot || !messages.errors().empty()) {
    const std::string why = messages.errors().empty()
                                ? "not a URDF robot"
                                : fmt::format("{}", fmt::join(messages.errors(), "; "));
    throw ModelError(fmt::format("URDF: {}", why));
  }
  return ParsedRobot(std::move(robot));
}

// The numbers as written, read again from the XML: urdfdom's message for a
// number that is not finite ("nan", "inf", "1e400") names neither the link nor
// the attribute, and it keeps rpy as a quaternion whose getRPY rounds a pitch
// within 0.0045 rad of ±90° to ±π/2. Every attribute of a link or joint that
// holds numbers is checked here, and the rpy angles are kept as written.
using Rpy = std::array<double, 3>;

struct WrittenNumbers {
  std::map<std::string, Rpy> joint_rpy;     // <joint><origin rpy>, by joint name
  std::map<std::string, Rpy> inertial_rpy;  // <link><inertial><origin rpy>, by link name
};

// The attributes that hold numbers, by element (anywhere inside a link or joint).
const std::map<std::string_view, std::vector<const char*>>& numeric_attributes() {
  static const std::map<std::string_view, std::vector<const char*>> table{
      {"origin", {"xyz", "rpy"}},
      {"mass", {"value"}},
      {"inertia", {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}},
      {"axis", {"xyz"}},
      {"limit", {"lower", "upper", "effort", "velocity"}},
      {"dynamics", {"damping", "friction"}},
      {"safety_controller", {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}},
      {"calibration", {"rising", "falling", "reference_position"}},
      {"mimic", {"multiplier", "offset"}},
      {"box", {"size"}},
      {"cylinder", {"radius", "length"}},
      {"sphere", {"radius"}},
      {"mesh", {"scale"}},
      {"color", {"rgba"}},
  };
  return table;
}

// The numbers of an attribute, each finite: ModelError naming the owner (link
// or joint), the element's path and the attribute. A word that is not a
// number is left to urdfdom's own message.
std::vector<double> finite_numbers(const std::string& owner, const std::string& element,
                                   const char* attribute, const std::string& text) {
  std::vector<double> out;
  std::istringstream words(text);
  std::string word;
  while (words >> word) {
    const char* first = word.data() + (word.starts_with('+') ? 1 : 0);
    const char* last = word.data() + word.size();
    double v = 0.0;
    const auto [end, ec] = std::from_chars(first, last, v);
    const auto refuse = [&](const char* why) {
      throw ModelError(fmt::format("URDF {}: <{} {}=\"{}\">: '{}' {}", owner, element, attribute,
                                   text, word, why));
    };
    if (ec == std::errc::result_out_of_range) refuse("is beyond the range of a double");
    if (ec != std::errc() || end != last) return {};
    if (!std::isfinite(v)) refuse("is not a finite number");
    out.push_back(v);
  }
  return out;
}

void check_element(const TiXmlElement& e, const std::string& owner, const std::string& path) {
  const auto row = numeric_attributes().find(e.ValueStr());
  if (row != numeric_attributes().end()) {
    for (const char* attribute : row->second) {
      if (const char* text = e.Attribute(attribute)) finite_numbers(owner, path, attribute, text);
    }
  }
  for (const TiXmlElement* child = e.FirstChildElement(); child != nullptr;
       child = child->NextSiblingElement()) {
    check_element(*child, owner, path + "><" + child->ValueStr());
  }
}

// The rpy of `origin` as written (0 0 0 when absent or not three numbers: urdfdom says why).
Rpy written_rpy(const TiXmlElement* origin, const std::string& owner, const std::string& path) {
  Rpy rpy{0.0, 0.0, 0.0};
  const char* text = origin != nullptr ? origin->Attribute("rpy") : nullptr;
  if (text == nullptr) return rpy;
  const std::vector<double> v = finite_numbers(owner, path, "rpy", text);
  if (v.size() == 3) std::copy(v.begin(), v.end(), rpy.begin());
  return rpy;
}

WrittenNumbers read_written_numbers(std::string_view xml) {
  WrittenNumbers out;
  TiXmlDocument document;
  document.Parse(std::string(xml).c_str());
  const TiXmlElement* robot = document.Error() ? nullptr : document.FirstChildElement("robot");
  if (robot == nullptr) return out;  // urdfdom says what is wrong
  for (const TiXmlElement* e = robot->FirstChildElement(); e != nullptr;
       e = e->NextSiblingElement()) {
    const bool link = e->ValueStr() == "link", joint = e->ValueStr() == "joint";
    if (!link && !joint) continue;
    const char* name = e->Attribute("name");
    const std::string owner = fmt::format("{} '{}'", e->ValueStr(), name != nullptr ? name : "");
    for (const TiXmlElement* c = e->FirstChildElement(); c != nullptr;
         c = c->NextSiblingElement()) {
      check_element(*c, owner, c->ValueStr());
    }
    if (name == nullptr) continue;
    if (joint) {
      out.joint_rpy[name] = written_rpy(e->FirstChildElement("origin"), owner, "origin");
    } else if (const TiXmlElement* inertial = e->FirstChildElement("inertial")) {
      out.inertial_rpy[name] =
          written_rpy(inertial->FirstChildElement("origin"), owner, "inertial><origin");
    }
  }
  return out;
}

// A URDF name as a symdyn name: every character that cannot be in an identifier becomes '_'.
std::string identifier_shaped(const std::string& name) {
  std::string out = name;
  for (char& c : out) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out.front())))
    out.insert(out.begin(), '_');
  return out;
}

// Zero mass makes a frame; any other mass a body, a negative or NaN one refused by the builder's
// checks naming it.
bool is_massive(const urdf::Link& link) {
  return link.inertial && link.inertial->mass != 0.0;
}

// Translation by xyz, then rotation Rz(yaw)·Ry(pitch)·Rx(roll) with the
// angles as written; factors that do nothing are left out.
Transform pose_transform(const urdf::Pose& pose, const Rpy& rpy) {
  const auto [roll, pitch, yaw] = rpy;
  Transform t;
  const urdf::Vector3& p = pose.position;
  if (p.x != 0.0 || p.y != 0.0 || p.z != 0.0) t *= Tdisp(p.x, p.y, p.z);
  if (yaw != 0.0) t *= Trotz(yaw);
  if (pitch != 0.0) t *= Troty(pitch);
  if (roll != 0.0) t *= Trotx(roll);
  return t;
}

Transform inverse_pose_transform(const urdf::Pose& pose, const Rpy& rpy) {
  const auto [roll, pitch, yaw] = rpy;
  Transform t;
  if (roll != 0.0) t *= Trotx(-roll);
  if (pitch != 0.0) t *= Troty(-pitch);
  if (yaw != 0.0) t *= Trotz(-yaw);
  const urdf::Vector3& p = pose.position;
  if (p.x != 0.0 || p.y != 0.0 || p.z != 0.0) t *= Tdisp(-p.x, -p.y, -p.z);
  return t;
}

Vec3 unit_axis(const urdf::Joint& joint) {
  const urdf::Vector3& a = joint.axis;
  const double norm = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    throw ModelError(fmt::format("URDF joint '{}': the axis ({}, {}, {}) has no direction",
                                 joint.name, a.x, a.y, a.z));
  }
  return {Expr(a.x / norm), Expr(a.y / norm), Expr(a.z / norm)};
}

const char* type_name(const urdf::Joint& joint) {
  switch (joint.type) {
    case urdf::Joint::FIXED:
      return "fixed";
    case urdf::Joint::REVOLUTE:
      return "revolute";
    case urdf::Joint::CONTINUOUS:
      return "continuous";
    case urdf::Joint::PRISMATIC:
      return "prismatic";
    case urdf::Joint::FLOATING:
      return "floating";
    case urdf::Joint::PLANAR:
      return "planar";
    default:
      return "unknown";
  }
}

// The first of `name`, `name_2`, `name_3`, ... that is not taken(candidate).
template <class Taken>
std::string first_free(const std::string& name, const Taken& taken) {
  std::string candidate = name;
  for (int k = 2; taken(candidate); ++k) candidate = fmt::format("{}_{}", name, k);
  return candidate;
}

class Importer {
 public:
  Importer(Model& m, const urdf::ModelInterface& robot, const WrittenNumbers& written,
           const UrdfOptions& options)
      : m_(m), robot_(robot), written_(written), options_(options) {
    // What the model holds already (add_urdf into a model of the builder) is taken.
    symbols_.insert(m_.time().name());
    for (const Coordinate& c : m_.coordinates()) take_coordinate(c);
    for (const Parameter& p : m_.parameters()) symbols_.insert(p.symbol.name());
    for (const Dependent& d : m_.dependents()) symbols_.insert(d.symbol.name());
    for (const Body& b : m_.bodies()) bodies_.insert(b.name());
  }

  std::vector<UrdfJoint> run() {
    const urdf::Link& root = *robot_.getRoot();
    Transform placement;
    if (options_.floating_base) {
      UrdfJoint base{root.name, "floating", {}, std::nullopt, {}};
      placement = floating_motion(root.name, base.coordinates);
      joints_.push_back(base);
    }
    const bool massive = visit(root, placement, std::nullopt);
    if (options_.floating_base && !massive) {
      throw ModelError(fmt::format(
          "URDF: floating base '{}' moves no body: no link of the robot has mass", root.name));
    }
    check_all_links_reached();
    m_.gravity(options_.gravity[0], options_.gravity[1], options_.gravity[2]);
    return std::move(joints_);
  }

 private:
  // Adds the link (a body if it has mass) and the links beyond it; `placement`
  // goes from the reference's frame (G of the nearest massive ancestor, or the
  // ground) to the link's frame. Returns whether any of them has mass.
  bool visit(const urdf::Link& link, const Transform& placement,
             const std::optional<std::string>& reference) {
    if (!visited_.insert(link.name).second) {
      throw ModelError(fmt::format(
          "URDF: link '{}' is reached twice: the joints form a closed loop", link.name));
    }
    Transform to_link = placement;
    std::optional<std::string> children_reference = reference;
    if (is_massive(link)) {
      children_reference = add_body(link, placement, reference);
      to_link = inverse_pose_transform(link.inertial->origin, inertial_rpy(link));
    }
    bool massive = is_massive(link);
    for (const urdf::JointSharedPtr& joint : link.child_joints) {
      const urdf::LinkConstSharedPtr child = robot_.getLink(joint->child_link_name);
      const std::size_t coordinates_before = m_.coordinates().size();
      const Transform motion = joint_motion(*joint);
      const bool child_massive = visit(
          *child,
          to_link * pose_transform(joint->parent_to_joint_origin_transform, joint_rpy(*joint)) *
              motion,
          children_reference);
      if (!child_massive && m_.coordinates().size() > coordinates_before) {
        throw ModelError(fmt::format(
            "URDF joint '{}' ({}) moves no body: link '{}' and the links beyond it have no mass",
            joint->name, type_name(*joint), joint->child_link_name));
      }
      massive = massive || child_massive;
    }
    return massive;
  }

  // The link's body, named after it (an identifier, unique); returns the body's name.
  std::string add_body(const urdf::Link& link, const Transform& placement,
                       const std::optional<std::string>& reference) {
    const urdf::Inertial& in = *link.inertial;
    const std::string name = first_free(identifier_shaped(link.name),
                                        [&](const std::string& n) { return bodies_.count(n) > 0; });
    bodies_.insert(name);
    Body& body = m_.body(name);
    body.mass(in.mass)
        .inertia(Mat3{Expr(in.ixx), Expr(in.ixy), Expr(in.ixz), Expr(in.ixy), Expr(in.iyy),
                      Expr(in.iyz), Expr(in.ixz), Expr(in.iyz), Expr(in.izz)})
        .motion(placement * pose_transform(in.origin, inertial_rpy(link)));
    if (reference) body.relative_to(*reference);
    return name;
  }

  // The joint's own motion, declaring its coordinates; refuses what symdyn cannot represent.
  Transform joint_motion(const urdf::Joint& joint) {
    UrdfJoint record{joint.name, type_name(joint), {}, std::nullopt, {}};
    if (joint.limits) {
      record.limits = UrdfJoint::Limits{joint.limits->lower, joint.limits->upper,
                                        joint.limits->velocity, joint.limits->effort};
    }
    Transform motion;
    switch (joint.type) {
      case urdf::Joint::FIXED:
        break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        motion = Trot(unit_axis(joint), variable(joint, record));
        break;
      case urdf::Joint::PRISMATIC: {
        const Vec3 axis = unit_axis(joint);
        const Expr q = variable(joint, record);
        motion = Tdisp(axis[0] * q, axis[1] * q, axis[2] * q);
        break;
      }
      case urdf::Joint::FLOATING:
        motion = floating_motion(joint.name, record.coordinates);
        break;
      default:
        throw ModelError(fmt::format(
            "URDF joint '{}': {} joints are not supported (fixed, revolute, continuous, "
            "prismatic, floating are)",
            joint.name, type_name(joint)));
    }
    if (joint.mimic && record.mimic.empty()) {
      throw ModelError(fmt::format(
          "URDF joint '{}': a {} joint cannot mimic '{}' (revolute, continuous and prismatic "
          "joints can)",
          joint.name, type_name(joint), joint.mimic->joint_name));
    }
    joints_.push_back(std::move(record));
    return motion;
  }

  // Six coordinates named <base>_x ... <base>_roll: translation, then Rz(yaw)·Ry(pitch)·Rx(roll).
  Transform floating_motion(const std::string& base, std::vector<std::string>& names) {
    std::vector<Expr> q;
    for (const char* suffix : {"_x", "_y", "_z", "_yaw", "_pitch", "_roll"}) {
      q.push_back(coordinate(identifier_shaped(base) + suffix));
      names.push_back(q.back().name());
    }
    return Tdisp(q[0], q[1], q[2]) * Trotz(q[3]) * Troty(q[4]) * Trotx(q[5]);
  }

  // The joint's variable: its coordinate, or for a mimic joint the dependent
  // parameter multiplier·q + offset of the joint it mimics, named after it.
  Expr variable(const urdf::Joint& joint, UrdfJoint& record) {
    if (!joint.mimic) return values_[joint.name] = declare(joint, record);
    const urdf::JointMimic& mimic = *joint.mimic;
    const auto mimicked = values_.find(mimic.joint_name);
    if (mimicked == values_.end()) {
      throw ModelError(fmt::format(
          "URDF joint '{}' mimics '{}', which is not a revolute, continuous or prismatic joint "
          "met before it (from the root, parents first)",
          joint.name, mimic.joint_name));
    }
    record.mimic = mimic.joint_name;
    return values_[joint.name] = dependent(identifier_shaped(joint.name),
                                           mimic.multiplier * mimicked->second + mimic.offset);
  }

  // One coordinate named after the joint, starting at 0 or at the nearest limit when 0 is outside
  // them.
  Expr declare(const urdf::Joint& joint, UrdfJoint& record) {
    const Expr q = coordinate(identifier_shaped(joint.name));
    record.coordinates.push_back(q.name());
    const bool bounded = joint.type != urdf::Joint::CONTINUOUS && record.limits &&
                         record.limits->lower <= record.limits->upper;
    if (bounded) m_.initial(q, std::clamp(0.0, record.limits->lower, record.limits->upper));
    return q;
  }

  // A coordinate named `name`, or `name_2`, ... when that name, its rate's or its
  // acceleration's is a symbol of the model already (joints "a-b" and "a_b"; "t").
  Expr coordinate(const std::string& name) {
    const Expr q = m_.coordinate(first_free(name, [&](const std::string& n) {
      return symbols_.count(n) || symbols_.count(n + "_d") || symbols_.count(n + "_dd");
    }));
    take_coordinate(m_.coordinates().back());
    return q;
  }
  // A dependent parameter named `name`, or `name_2`, ... when that name is taken (a mimic
  // joint's variable), with its rate's and acceleration's names taken too.
  Expr dependent(const std::string& name, Expr expression) {
    const Expr p = m_.dependent(first_free(name,
                                           [&](const std::string& n) {
                                             return symbols_.count(n) || symbols_.count(n + "_d") ||
                                                    symbols_.count(n + "_dd");
                                           }),
                                expression);
    for (const std::string& n : {p.name(), p.name() + "_d", p.name() + "_dd"}) symbols_.insert(n);
    return p;
  }
  void take_coordinate(const Coordinate& c) {
    for (const Expr& s : {c.q, c.qd, c.qdd}) symbols_.insert(s.name());
  }

  Rpy joint_rpy(const urdf::Joint& joint) const {
    const auto it = written_.joint_rpy.find(joint.name);
    return it != written_.joint_rpy.end() ? it->second : Rpy{0.0, 0.0, 0.0};
  }
  Rpy inertial_rpy(const urdf::Link& link) const {
    const auto it = written_.inertial_rpy.find(link.name);
    return it != written_.inertial_rpy.end() ? it->second : Rpy{0.0, 0.0, 0.0};
  }

  void check_all_links_reached() const {
    for (const auto& [name, link] : robot_.links_) {
      if (!visited_.count(name)) {
        throw ModelError(
            fmt::format("URDF: link '{}' is not connected to the root link '{}' (a closed loop?)",
                        name, robot_.getRoot()->name));
      }
    }
  }

  Model& m_;
  const urdf::ModelInterface& robot_;
  const WrittenNumbers& written_;
  const UrdfOptions& options_;
  std::vector<UrdfJoint> joints_;
  std::set<std::string> visited_;
  std::set<std::string> symbols_;       // the model's symbols' names: no coordinate may take one
  std::set<std::string> bodies_;        // the model's bodies' names
  std::map<std::string, Expr> values_;  // each one-variable joint's coordinate or dependent
};

}  // namespace

std::vector<UrdfJoint> add_urdf(Model& model, std::string_view urdf_xml,
                                const UrdfOptions& options) {
  const WrittenNumbers written = read_written_numbers(urdf_xml);
  const ParsedRobot robot = parse(urdf_xml);
  return Importer(model, *robot, written, options).run();
}

std::string urdf_robot_name(std::string_view urdf_xml) {
  read_written_numbers(urdf_xml);  // its refusals name the link or joint and the attribute
  return identifier_shaped(parse(urdf_xml)->getName());
}

UrdfRobot import_urdf(std::string_view urdf_xml, const UrdfOptions& options) {
  const WrittenNumbers written = read_written_numbers(urdf_xml);
  const ParsedRobot robot = parse(urdf_xml);
  UrdfRobot out{Model(options.name.empty() ? identifier_shaped(robot->getName()) : options.name),
                {}};
  out.joints = Importer(out.model, *robot, written, options).run();
  return out;
}

namespace {

// Rigid poses with urdfdom's quaternions: (a b).p = a.p + a.R b.p.
urdf::Pose compose(const urdf::Pose& a, const urdf::Pose& b) {
  urdf::Pose out;
  out.rotation = a.rotation * b.rotation;
  const urdf::Vector3 turned = a.rotation * b.position;
  out.position =
      urdf::Vector3(a.position.x + turned.x, a.position.y + turned.y, a.position.z + turned.z);
  return out;
}

urdf::Pose inverse(const urdf::Pose& a) {
  urdf::Pose out;
  out.rotation = a.rotation.GetInverse();
  const urdf::Vector3 back = out.rotation * a.position;
  out.position = urdf::Vector3(-back.x, -back.y, -back.z);
  return out;
}

// package://name/rest: rest under the nearest folder called name above
// `directory` (a ROS package's root), else under `directory`.
std::string resolve_mesh(const std::string& file, const std::string& directory) {
  namespace fs = std::filesystem;
  const std::string package = "package://", scheme = "file://";
  if (file.starts_with(scheme)) return file.substr(scheme.size());
  if (!file.starts_with(package)) return (fs::path(directory) / file).lexically_normal().string();
  const std::string rest = file.substr(package.size());
  const std::string name = rest.substr(0, rest.find('/'));
  const std::string inside =
      rest.find('/') == std::string::npos ? "" : rest.substr(rest.find('/') + 1);
  for (fs::path at = fs::absolute(directory); !at.empty(); at = at.parent_path()) {
    if (at.filename() == name) return (at / inside).lexically_normal().string();
    if (at == at.parent_path()) break;
  }
  return (fs::path(directory) / inside).lexically_normal().string();
}

}  // namespace

std::vector<UrdfVisual> urdf_visuals(std::string_view urdf_xml, const std::string& directory,
                                     std::vector<std::string>* skipped) {
  const ParsedRobot robot = parse(urdf_xml);
  std::vector<UrdfVisual> out;
  const auto skip = [&](std::string why) {
    if (skipped != nullptr) skipped->push_back(std::move(why));
  };
  // Depth first: each link with the body it moves with and the pose of its
  // frame in that body's (none: moved by a joint with no body on this side).
  struct Placed {
    const urdf::Link* link;
    std::optional<std::string> body;
    urdf::Pose in_body;
  };
  std::vector<Placed> stack{{robot->getRoot().get(), std::nullopt, {}}};
  while (!stack.empty()) {
    Placed at = stack.back();
    stack.pop_back();
    const urdf::Link& link = *at.link;
    if (is_massive(link)) {
      at.body = identifier_shaped(link.name);
      at.in_body = inverse(link.inertial->origin);
    }
    for (const urdf::VisualSharedPtr& v : link.visual_array) {
      if (!v || !v->geometry) continue;
      if (!at.body) {
        skip(fmt::format("a visual of link '{}': the link moves with no body", link.name));
        continue;
      }
      UrdfVisual visual;
      visual.body = *at.body;
      const urdf::Pose pose = compose(at.in_body, v->origin);
      visual.origin = {pose.position.x, pose.position.y, pose.position.z};
      for (int c = 0; c < 3; ++c) {
        const urdf::Vector3 column =
            pose.rotation * urdf::Vector3(c == 0 ? 1 : 0, c == 1 ? 1 : 0, c == 2 ? 1 : 0);
        visual.axes[3 * c] = column.x;
        visual.axes[3 * c + 1] = column.y;
        visual.axes[3 * c + 2] = column.z;
      }
      const urdf::Geometry& g = *v->geometry;
      if (g.type == urdf::Geometry::BOX) {
        const auto& b = static_cast<const urdf::Box&>(g);
        visual.type = "box";
        visual.size = {b.dim.x, b.dim.y, b.dim.z};
      } else if (g.type == urdf::Geometry::SPHERE) {
        visual.type = "sphere";
        visual.size = {static_cast<const urdf::Sphere&>(g).radius, 0.0, 0.0};
      } else if (g.type == urdf::Geometry::CYLINDER) {
        const auto& c = static_cast<const urdf::Cylinder&>(g);
        visual.type = "cylinder";
        visual.size = {c.radius, c.length, 0.0};
      } else if (g.type == urdf::Geometry::MESH) {
        const auto& m = static_cast<const urdf::Mesh&>(g);
        visual.type = "mesh";
        visual.mesh = resolve_mesh(m.filename, directory);
        visual.scale = {m.scale.x, m.scale.y, m.scale.z};
      } else {
        skip(fmt::format("a visual of link '{}': unknown geometry", link.name));
        continue;
      }
      if (v->material) {
        // urdfdom keeps floats: 0.6 as written, not 0.6000000238.
        const auto written = [](float f) { return std::stod(fmt::format("{}", f)); };
        const urdf::Color& c = v->material->color;
        visual.rgba = std::array<double, 4>{written(c.r), written(c.g), written(c.b), written(c.a)};
      }
      out.push_back(std::move(visual));
    }
    for (const urdf::JointSharedPtr& joint : link.child_joints) {
      Placed child{robot->getLink(joint->child_link_name).get(), std::nullopt, {}};
      if (joint->type == urdf::Joint::FIXED && at.body) {
        child.body = at.body;
        child.in_body = compose(at.in_body, joint->parent_to_joint_origin_transform);
      }
      stack.push_back(child);
    }
  }
  return out;
}

std::string read_urdf_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(fmt::format("URDF file '{}' cannot be read", path));
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw ModelError(fmt::format("URDF file '{}' cannot be read", path));
  return text.str();
}

UrdfRobot import_urdf_file(const std::string& path, const UrdfOptions& options) {
  try {
    return import_urdf(read_urdf_file(path), options);
  } catch (const ModelError& e) {
    const std::string what = e.what();
    if (what.find(path) != std::string::npos) throw;
    throw ModelError(fmt::format("{}: {}", path, what));
  }
}

}  // namespace symdyn::model
