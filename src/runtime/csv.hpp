#pragma once
// Time histories as CSV: one header line naming every column, then one line
// per recorded state. Columns, in order:
//   t, each q by name, each qd as "<name>_dot", each extra state by name,
//   kinetic_energy, gravitational_energy, elastic_energy, total_energy,
//   then the user channels in the order added.
// Numbers print in the shortest form that reads back exactly.

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::runtime {

class CsvRecorder {
 public:
  using Channel = std::function<double(const State& s)>;

  CsvRecorder(std::ostream& out, MultibodySystem& system);
  // Adds a user column; ModelError once the header has been written.
  void add_channel(std::string name, Channel channel);
  // The column names (the header).
  std::vector<std::string> columns() const;
  // Writes the header on the first call, then one line for s.
  void write(const State& s);

 private:
  std::ostream& out_;
  MultibodySystem& system_;
  std::vector<std::string> names_;
  std::vector<Channel> channels_;
  bool header_written_ = false;
};

}  // namespace symdyn::runtime
