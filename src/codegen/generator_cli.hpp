#pragma once
// The generator's command line, shared by every generator: a model file (models/*.cpp)
// linked with generator_main.cpp is the generator for that model (or models:
// chain.cpp registers several), and symdyn-urdf (urdf_main.cpp) is the
// generator for a URDF file:
//
//   double_pendulum_generator --out DIR [--model M] [--variant V] [--no-simplify]
//                             [--partials numeric|symbolic] [--no-eom] [--basename NAME]
//                             [--dynamics auto|mass-matrix|recursive]
//                             [--part-size N] [--split-above N] [--stats]
//   double_pendulum_generator --list [--model M]
//   double_pendulum_generator --describe [--model M] [--variant V]   (the model as JSON)
//
// Exit codes: 0 success, 1 invalid model or generation failure, 2 bad command
// line (every argument is checked before anything is derived or written).
// What each error names: docs/errors.md.

#include <functional>
#include <stdexcept>
#include <string>

namespace CLI {
class App;
}

namespace symdyn::codegen {

// What a generator adds to the common command line.
struct GeneratorHooks {
  std::string description;                     // --help's first line; empty: the models' generator
  std::function<void(CLI::App&)> add_options;  // its own options, added before parsing
  // Called once the command line is parsed, before anything is listed or
  // generated (e.g. to register the models the options name); a
  // model::ModelError it throws exits with code 1, a CommandLineError with 2.
  std::function<void()> prepare;
};

// An argument that cannot be right, whatever the model (exit code 2).
class CommandLineError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses the command line and generates the model of model::registry() it names.
int run_generator(int argc, char** argv, const GeneratorHooks& hooks = {});

}  // namespace symdyn::codegen
