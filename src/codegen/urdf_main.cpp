// symdyn-urdf: the generator for a robot described in URDF (docs/urdf.md).
//
//   symdyn-urdf --urdf FILE [--floating-base] [--gravity GX GY GZ] --out DIR
//               [--basename NAME] [--stats] [every option of generator_cli.hpp]
//
// The model is named after the robot (<robot>_default.hpp unless --basename).
#include <CLI/CLI.hpp>
#include <cmath>

#include <symdyn/codegen/generator_cli.hpp>
#include <symdyn/model/urdf.hpp>

namespace {

using namespace symdyn;

struct UrdfArguments {
  std::string path;
  bool floating_base = false;
  std::vector<double> gravity = {0.0, 0.0, -9.81};
};

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
