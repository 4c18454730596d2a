#pragma once
// Scenarios: what symdyn-sim runs for each reference model of models.md.
//
// A scenario is data: the model's name, the generated variants it can run
// (each a factory of runtime::Model from a generated struct), the default end
// time, integrator, tolerance and output interval, the initial state when it
// differs from the model's, and three small functions:
//   configure  adds the force elements to the system and returns the extra
//              CSV channels (called once per run, before integration);
//   headline   turns a finished run into the few numbers that say whether it
//              behaved (each with the band it is expected in).
// One file per model (models/sim/<model>_scenario.cpp) registers its scenario
// with a static Registration; symdyn-sim and the tests find it by name.

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/runtime/csv.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::sim {

// One generated variant: its name and how to make the runtime model.
struct Variant {
  std::string name;
  runtime::Model (*make)();
};

// A CSV column computed from the state (the system is evaluated as needed).
struct Channel {
  std::string name;
  runtime::CsvRecorder::Channel value;
};

// One output instant of a run.
struct Sample {
  runtime::State state;
  runtime::Energies energies;
};

// A number that characterizes a run, and the band [low, high] it should be in.
struct Headline {
  std::string name;
  double value = 0.0;
  std::string unit;
  double low = 0.0, high = 0.0;
  bool ok() const { return value >= low && value <= high; }
};

struct RunResult;

struct Scenario {
  std::string model;        // the model's name in models.md
  std::string description;  // one line, for --list
  std::vector<Variant> variants;  // the first is the default

  double t_end = 1.0;
  std::string integrator = "dopri5";
  double tolerance = 1e-8;        // relative and absolute
  double output_interval = 0.01;  // s

  // Initial q and qd (nq each); empty: the model's own initial state.
  std::vector<double> q0, qd0;

  std::function<std::vector<Channel>(runtime::MultibodySystem& system)> configure;
  std::function<std::vector<Headline>(const RunResult& run, runtime::MultibodySystem& system)>
      headline;

  // The variant called name; OptionError naming the valid ones if unknown.
  const Variant& variant(std::string_view name) const;
};

// Registers a scenario at static initialization (one per scenario file).
struct Registration {
  explicit Registration(Scenario s);
};

// Every registered scenario, sorted by model name.
std::vector<const Scenario*> scenarios();
// The scenario of a model; OptionError naming the known models if absent.
const Scenario& find_scenario(std::string_view model);

}  // namespace symdyn::sim
