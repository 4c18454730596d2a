#include <iterator>
#include <utility>

#include <symdyn/runtime/csv.hpp>
#include <symdyn/runtime/errors.hpp>

namespace symdyn::runtime {

CsvRecorder::CsvRecorder(std::ostream& out, MultibodySystem& system)
    : CsvRecorder(out, system, Columns{}) {}

CsvRecorder::CsvRecorder(std::ostream& out, MultibodySystem& system, Columns columns)
    : out_(out), system_(system), groups_(columns) {}

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
  const auto coordinates = [&](bool on, const char* suffix) {
    if (!on) return;
    for (int j = 0; j < n; ++j) c.push_back(system_.coordinate_name(j) + suffix);
  };
  coordinates(groups_.coordinates, "");
  coordinates(groups_.rates, "_dot");
  coordinates(groups_.accelerations, "_ddot");
  if (groups_.extra_states) {
    for (int j = 0; j < system_.num_extra_states(); ++j) c.push_back(system_.extra_state_name(j));
  }
  if (groups_.energies) {
    for (const char* e :
         {"kinetic_energy", "gravitational_energy", "elastic_energy", "total_energy"}) {
      c.emplace_back(e);
    }
  }
  c.insert(c.end(), names_.begin(), names_.end());
  return c;
}

void CsvRecorder::write_header() {
  const auto c = columns();
  for (std::size_t i = 0; i < c.size(); ++i) out_ << (i ? "," : "") << c[i];
  out_ << '\n';
  header_written_ = true;
}

void CsvRecorder::write(const State& s) {
  if (groups_.accelerations) {
    qdd_.resize(s.q.size());
    yd_.resize(s.y.size());
    system_.accelerations(s, qdd_, yd_);
  }
  write(s, qdd_);
}

void CsvRecorder::write(const State& s, const Vector& qdd) {
  if (!header_written_) write_header();
  line_.clear();
  auto out = std::back_inserter(line_);
  fmt::format_to(out, "{}", s.t);
  const auto values = [&](bool on, const Vector& v) {
    if (!on) return;
    for (Eigen::Index j = 0; j < v.size(); ++j) fmt::format_to(out, ",{}", v(j));
  };
  values(groups_.coordinates, s.q);
  values(groups_.rates, s.qd);
  if (groups_.accelerations && qdd.size() != s.q.size()) {
    throw ModelError(fmt::format("CSV row at t = {}: qdd has {} entries, the system {} coordinates",
                                 s.t, qdd.size(), s.q.size()));
  }
  values(groups_.accelerations, qdd);
  values(groups_.extra_states, s.y);
  if (groups_.energies) {
    const Energies e = system_.energies(s);
    fmt::format_to(out, ",{},{},{},{}", e.kinetic, e.gravitational, e.elastic, e.total());
  }
  for (const auto& ch : channels_) fmt::format_to(out, ",{}", ch(s));
  line_.push_back('\n');
  out_.write(line_.data(), static_cast<std::streamsize>(line_.size()));
}

}  // namespace symdyn::runtime
