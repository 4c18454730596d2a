#include <catch2/catch.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "fixtures/spring_mass.hpp"
#include "test_util.hpp"
#include <symdyn/runtime/csv.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/point_forces.hpp>

using namespace symdyn::runtime;
using namespace symdyn::runtime::test;
namespace fx = symdyn_fixtures;

TEST_CASE("CSV time histories name every column", "[runtime][csv]") {
  const double k = 4.0 * std::numbers::pi * std::numbers::pi;
  MultibodySystem sm(Model::from<fx::spring_mass>());
  auto spring = sm.add<PointSpringDamper>("spring", BodyPoint{ground, Vec3::Zero()},
                                          BodyPoint{0, Vec3::Zero()}, k, 2.0);
  sm.set_extra_states(
      {"integral"}, Vector::Constant(1, 0.25),
      [](const State& s, const Kinematics&, Eigen::Ref<Vector> yd) { yd(0) = s.q(0); });
  std::ostringstream out;
  CsvRecorder csv(out, sm);
  csv.add_channel("length",
                  [&](const State& s) { return spring->length(sm.evaluate_kinematics(s)); });
  State s = sm.initial_state();
  csv.write(s);
  s.t = 0.1;
  s.q(0) = 1.25;
  s.qd(0) = -0.5;
  csv.write(s);
  CHECK_THROWS_AS(csv.add_channel("late", [](const State&) { return 0.0; }), ModelError);

  std::istringstream lines(out.str());
  std::string header, row0, row1;
  std::getline(lines, header);
  std::getline(lines, row0);
  std::getline(lines, row1);
  CHECK(
      header ==
      "t,s,s_dot,integral,kinetic_energy,gravitational_energy,elastic_energy,total_energy,length");
  const double T = 0.125, V = k * 1.25, E = 0.5 * k * 0.75 * 0.75;
  std::vector<double> values;
  std::istringstream fields(row1);
  for (std::string f; std::getline(fields, f, ',');) values.push_back(std::stod(f));
  const std::vector<double> expected{0.1, 1.25, -0.5, 0.25, T, V, E, T + V + E, 1.25};
  REQUIRE(values.size() == expected.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    CHECK(values[i] == Approx(expected[i]).epsilon(1e-14));
  CHECK(row0.rfind("0,1.5,0,0.25,0,", 0) == 0);
}

TEST_CASE("CSV accelerations: given, or computed from the state", "[runtime][csv]") {
  // spring_mass: q'' = -(2 pi)² (q - 1), so at q = 1.25, qdd = -(2 pi)² / 4.
  const double k = 4.0 * std::numbers::pi * std::numbers::pi;
  MultibodySystem sm(Model::from<fx::spring_mass>());
  sm.add<PointSpringDamper>("spring", BodyPoint{ground, Vec3::Zero()}, BodyPoint{0, Vec3::Zero()},
                            k, 2.0);
  std::ostringstream out;
  CsvRecorder csv(out, sm,
                  {.coordinates = true,
                   .rates = false,
                   .accelerations = true,
                   .extra_states = false,
                   .energies = false});
  CHECK(csv.columns() == std::vector<std::string>{"t", "s", "s_ddot"});
  State s = sm.initial_state();
  s.q(0) = 1.25;
  csv.write(s);
  csv.write(s, Vector::Constant(1, 3.5));
  CHECK_THROWS_AS(csv.write(s, Vector::Zero(2)), ModelError);
  std::istringstream lines(out.str());
  std::string header, computed, given;
  std::getline(lines, header);
  std::getline(lines, computed);
  std::getline(lines, given);
  CHECK(header == "t,s,s_ddot");
  REQUIRE(computed.rfind("0,1.25,", 0) == 0);
  CHECK(std::stod(computed.substr(7)) == Approx(-k / 4.0).epsilon(1e-12));
  CHECK(given == "0,1.25,3.5");
}
