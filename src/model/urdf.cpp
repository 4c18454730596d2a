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

// Six coordinates named <base>_x ... <base>_roll: translation, then Rz(yaw)·Ry(pitch)·Rx(roll).
Transform floating_motion(Model& m, const std::string& base, std::vector<std::string>& names) {
  std::vector<Expr> q;
  for (const char* suffix : {"_x", "_y", "_z", "_yaw", "_pitch", "_roll"}) {
    names.push_back(base + suffix);
    q.push_back(m.coordinate(names.back()));
  }
  return Tdisp(q[0], q[1], q[2]) * Trotz(q[3]) * Troty(q[4]) * Trotx(q[5]);
}

class Importer {
 public:
  Importer(Model& m, const urdf::ModelInterface& robot, const WrittenNumbers& written,
           const UrdfOptions& options)
      : m_(m), robot_(robot), written_(written), options_(options) {}

  std::vector<UrdfJoint> run() {
    const urdf::Link& root = *robot_.getRoot();
    Transform placement;
    if (options_.floating_base) {
      UrdfJoint base{root.name, "floating", {}, std::nullopt, {}};
      placement = floating_motion(m_, identifier_shaped(root.name), base.coordinates);
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
      add_body(link, placement, reference);
      to_link = inverse_pose_transform(link.inertial->origin, inertial_rpy(link));
      children_reference = identifier_shaped(link.name);
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

  void add_body(const urdf::Link& link, const Transform& placement,
                const std::optional<std::string>& reference) {
    const urdf::Inertial& in = *link.inertial;
    Body& body = m_.body(identifier_shaped(link.name));
    body.mass(in.mass)
        .inertia(Mat3{Expr(in.ixx), Expr(in.ixy), Expr(in.ixz), Expr(in.ixy), Expr(in.iyy),
                      Expr(in.iyz), Expr(in.ixz), Expr(in.iyz), Expr(in.izz)})
        .motion(placement * pose_transform(in.origin, inertial_rpy(link)));
    if (reference) body.relative_to(*reference);
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
        motion = floating_motion(m_, identifier_shaped(joint.name), record.coordinates);
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
    return values_[joint.name] = m_.dependent(identifier_shaped(joint.name),
                                              mimic.multiplier * mimicked->second + mimic.offset);
  }

  // One coordinate named after the joint, starting at 0 or at the nearest limit when 0 is outside
  // them.
  Expr declare(const urdf::Joint& joint, UrdfJoint& record) {
    record.coordinates.push_back(identifier_shaped(joint.name));
    const Expr q = m_.coordinate(record.coordinates.back());
    const bool bounded = joint.type != urdf::Joint::CONTINUOUS && record.limits &&
                         record.limits->lower <= record.limits->upper;
    if (bounded) m_.initial(q, std::clamp(0.0, record.limits->lower, record.limits->upper));
    return q;
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
