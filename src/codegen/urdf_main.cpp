// symdyn-urdf: the generator for a robot described in URDF (docs/urdf.md).
//
//   symdyn-urdf --urdf FILE [--floating-base] [--gravity GX GY GZ] --out DIR
//               [--basename NAME] [--stats] [--shapes FILE.json] [every option of
//               generator_cli.hpp]
//
// The model is named after the robot (<robot>_default.hpp unless --basename).
// --shapes writes the robot's <visual> elements as a scenario's "shapes"
// (docs/scenarios.md), placed on the bodies, for symdyn-sim's pictures: a
// scenario names the file ("shapes": "arm_shapes.json").
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include <symdyn/codegen/generator_cli.hpp>
#include <symdyn/model/urdf.hpp>

namespace {

using namespace symdyn;

struct UrdfArguments {
  std::string path;
  bool floating_base = false;
  std::vector<double> gravity = {0.0, 0.0, -9.81};
  std::string shapes;  // where to write the visuals, if asked
};

// The robot's visuals as a scenario's "shapes": body name -> list of shapes,
// mesh files relative to the file written; a note for each visual left out.
void write_shapes(const std::string& xml, const UrdfArguments& args) {
  namespace fs = std::filesystem;
  std::vector<std::string> skipped;
  const auto visuals =
      model::urdf_visuals(xml, fs::path(args.path).parent_path().string(), &skipped);
  const fs::path folder = fs::absolute(args.shapes).parent_path();
  nlohmann::ordered_json shapes = nlohmann::ordered_json::object();
  for (const model::UrdfVisual& v : visuals) {
    nlohmann::ordered_json s = {{"type", v.type}};
    if (v.type == "box") s["size"] = v.size;
    if (v.type == "sphere") s["radius"] = v.size[0];
    if (v.type == "cylinder") {
      s["radius"] = v.size[0];
      s["length"] = v.size[1];
    }
    if (v.type == "mesh") {
      s["file"] = fs::proximate(fs::absolute(v.mesh), folder).string();
      if (v.scale != std::array<double, 3>{1.0, 1.0, 1.0}) s["scale"] = v.scale;
    }
    if (v.origin != std::array<double, 3>{}) s["origin"] = v.origin;
    if (v.axes != model::UrdfVisual{}.axes) {
      s["axes"] = {{v.axes[0], v.axes[1], v.axes[2]},
                   {v.axes[3], v.axes[4], v.axes[5]},
                   {v.axes[6], v.axes[7], v.axes[8]}};
    }
    if (v.rgba) s["colour"] = *v.rgba;
    shapes[v.body].push_back(s);
  }
  // One line a shape.
  std::ofstream out(args.shapes);
  out << "{";
  for (auto body = shapes.begin(); body != shapes.end(); ++body) {
    out << (body == shapes.begin() ? "\n" : ",\n") << "  " << nlohmann::json(body.key()).dump()
        << ": [";
    for (std::size_t k = 0; k < body->size(); ++k)
      out << (k ? ",\n    " : "\n    ") << (*body)[k].dump();
    out << "\n  ]";
  }
  out << "\n}\n";
  if (!out) throw model::ModelError(fmt::format("--shapes: cannot write '{}'", args.shapes));
  for (const std::string& line : skipped) std::cerr << "note: left out " << line << '\n';
}

// Reads and parses the file once, and registers the robot as the only model.
void register_robot(const UrdfArguments& args) {
  const std::string xml = model::read_urdf_file(args.path);
  model::UrdfOptions options;
  options.floating_base = args.floating_base;
  std::copy(args.gravity.begin(), args.gravity.end(), options.gravity);
  std::string name;
  try {
    name = model::urdf_robot_name(xml);
  } catch (const model::ModelError& e) {
    throw model::ModelError(args.path + ": " + e.what());
  }
  if (!args.shapes.empty()) write_shapes(xml, args);
  model::registry().push_back(
      {name, {"default"}, [xml, options, path = args.path](model::Model& m, std::string_view) {
         try {
           model::add_urdf(m, xml, options);
         } catch (const model::ModelError& e) {
           throw model::ModelError(path + ": " + e.what());
         }
       }});
}

}  // namespace

int main(int argc, char** argv) {
  UrdfArguments args;
  codegen::GeneratorHooks hooks;
  hooks.description =
      "symdyn-urdf: derives a URDF robot's kinematics and equations of motion and emits C++";
  hooks.add_options = [&](CLI::App& app) {
    app.add_option("--urdf", args.path, "the robot's URDF file")->required();
    app.add_option("--shapes", args.shapes,
                   "write the robot's visuals as a scenario's \"shapes\" (JSON)");
    app.add_flag("--floating-base", args.floating_base,
                 "the root link moves freely (6 coordinates)");
    app.add_option("--gravity", args.gravity, "gravity in the URDF world frame")
        ->expected(3)
        ->capture_default_str()
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
              double v = 0.0;
              if (CLI::detail::lexical_cast(text, v) && std::isfinite(v)) return {};
              return "expected a finite number, found '" + text + "'";
            },
            "FINITE"));
  };
  hooks.prepare = [&] { register_robot(args); };
  return codegen::run_generator(argc, argv, hooks);
}
