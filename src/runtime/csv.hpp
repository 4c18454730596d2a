#pragma once
// Time histories as CSV: one header line naming every column, then one line
// per recorded state. Columns, in order, each group unless switched off:
//   t, each q by name, each qd as "<name>_dot", each qdd as "<name>_ddot"
//   (off by default: write(s, qdd) gives them), each extra state by name,
//   kinetic_energy, gravitational_energy, elastic_energy, total_energy,
//   then the user channels in the order added.
// Numbers print in the shortest form that reads back exactly. A row is
// formatted into a buffer kept from one row to the next: writing allocates
// nothing once the first row is out.

#include <fmt/format.h>

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <symdyn/runtime/multibody_system.hpp>

namespace symdyn::runtime {

class CsvRecorder {
 public:
  using Channel = std::function<double(const State& s)>;
  struct Columns {
    bool coordinates = true;     // q
    bool rates = true;           // qd
    bool accelerations = false;  // qdd
    bool extra_states = true;    // y
    bool energies = true;
  };

  CsvRecorder(std::ostream& out, MultibodySystem& system);
  CsvRecorder(std::ostream& out, MultibodySystem& system, Columns columns);
  // Adds a user column; ModelError once the header has been written.
  void add_channel(std::string name, Channel channel);
  // The column names (the header).
  std::vector<std::string> columns() const;
  // Writes the header on the first call, then one line for s. Without qdd
  // (nq), the accelerations are computed from s when they are written.
  void write(const State& s);
  void write(const State& s, const Vector& qdd);

 private:
  void write_header();

  std::ostream& out_;
  MultibodySystem& system_;
  Columns groups_;
  std::vector<std::string> names_;
  std::vector<Channel> channels_;
  bool header_written_ = false;
  Vector qdd_, yd_;          // (nq), (m): write(s) computes them
  fmt::memory_buffer line_;  // the row being formatted
};

}  // namespace symdyn::runtime
