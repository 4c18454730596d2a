#include <symdyn/runtime/csv.hpp>

#include <fmt/format.h>

#include <utility>

#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime {

CsvRecorder::CsvRecorder(std::ostream& out, MultibodySystem& system)
    : out_(out), system_(system) {}

void CsvRecorder::add_channel(std::string name, Channel channel) {
  if (header_written_) {
    throw ModelError(fmt::format("CSV channel '{}' added after the header was written", name));
  }
  names_.push_back(std::move(name));
  channels_.push_back(std::move(channel));
}

std::vector<std::string> CsvRecorder::columns() const {
  std::vector<std::string> c{"t"};
  const int n = system_.num_coordinates();
  for (int j = 0; j < n; ++j) c.push_back(system_.coordinate_name(j));
  for (int j = 0; j < n; ++j) c.push_back(system_.coordinate_name(j) + "_dot");
  for (int j = 0; j < system_.num_extra_states(); ++j) c.push_back(system_.extra_state_name(j));
  for (const char* e : {"kinetic_energy", "gravitational_energy", "elastic_energy", "total_energy"}) {
    c.emplace_back(e);
  }
  c.insert(c.end(), names_.begin(), names_.end());
  return c;
}

void CsvRecorder::write(const State& s) {
  if (!header_written_) {
    const auto c = columns();
    for (std::size_t i = 0; i < c.size(); ++i) out_ << (i ? "," : "") << c[i];
    out_ << '\n';
    header_written_ = true;
  }
  const Energies e = system_.energies(s);
  std::string line = fmt::format("{}", s.t);
  for (Eigen::Index j = 0; j < s.q.size(); ++j) line += fmt::format(",{}", s.q(j));
  for (Eigen::Index j = 0; j < s.qd.size(); ++j) line += fmt::format(",{}", s.qd(j));
  for (Eigen::Index j = 0; j < s.y.size(); ++j) line += fmt::format(",{}", s.y(j));
  line += fmt::format(",{},{},{},{}", e.kinetic, e.gravitational, e.elastic, e.total());
  for (const auto& ch : channels_) line += fmt::format(",{}", ch(s));
  out_ << line << '\n';
}

}  // namespace symdyn::runtime
