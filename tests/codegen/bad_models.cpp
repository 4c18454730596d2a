// Models the generator must refuse, each wrong in one way, linked into one
// generator (symdyn_generator_bad_models) that the command-line tests run.
#include <limits>

#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

// A valid pendulum: every model below spoils it once.
Expr pendulum(Model& m) {
  const Expr q0 = m.coordinate("q0");
  m.body("rod").mass(1.0).inertia(0.001, 0.08, 0.08).motion(Trotz(q0) * Tdisp(0.5, 0, 0));
  m.gravity(0, -9.81, 0);
  return q0;
}

void valid(Model& m, std::string_view) {
  pendulum(m);
}

void zero_mass(Model& m, std::string_view) {
  const Expr q0 = pendulum(m);
  m.body("arm").mass(0.0).inertia(0.1, 0.1, 0.1).motion(Trotz(q0));
}

void still_coordinate(Model& m, std::string_view) {
  pendulum(m);
  m.coordinate("q1");
}

void nan_gravity(Model& m, std::string_view) {
  pendulum(m);
  m.gravity(0, std::numeric_limits<double>::quiet_NaN(), 0);
}

void mass_of_q(Model& m, std::string_view) {
  const Expr q0 = pendulum(m);
  m.body("arm").mass(2 + cos(q0)).inertia(0.1, 0.1, 0.1).motion(Trotz(q0));
}

void constant_asin(Model& m, std::string_view) {
  const Expr q0 = pendulum(m);
  const Expr l1 = m.parameter("l1", 0.4), l2 = m.parameter("l2", 0.2);
  m.body("arm").mass(1.0).inertia(0.1, 0.1, 0.1).motion(Trotz(q0 + asin(l1 / l2)));
}

void dependent_domain(Model& m, std::string_view) {
  const Expr q0 = pendulum(m);
  const Expr l1 = m.parameter("l1", 0.5, true), l2 = m.parameter("l2", 0.2, true);
  m.body("arm")
      .mass(1.0)
      .inertia(0.1, 0.1, 0.1)
      .motion(Trotz(m.dependent("alpha", asin(l1 / l2 * cos(q0)))));
}

const Registration registrations[] = {
    Registration({"valid", {"default", "inline"}, valid}),
    Registration({"zero_mass", {"default"}, zero_mass}),
    Registration({"still_coordinate", {"default"}, still_coordinate}),
    Registration({"nan_gravity", {"default"}, nan_gravity}),
    Registration({"mass_of_q", {"default"}, mass_of_q}),
    Registration({"constant_asin", {"default"}, constant_asin}),
    Registration({"dependent_domain", {"default"}, dependent_domain}),
    Registration({"bad_variant", {"two words"}, valid}),
};

}  // namespace
