// docs/emitted_interface.md's header (fixtures/emitted_interface.hpp) against the
// one the generator emits for double_pendulum_absolute: the same constants, and
// the same signature for every entry point both declare. Compiled only: a
// difference stops the build. (The link-time guard's fingerprint is the page's
// example, not checked: it changes with every change of the emitted code.)
#include <string_view>
#include <type_traits>

#include "double_pendulum_absolute.hpp"

namespace documented {
#include "fixtures/emitted_interface.hpp"
}  // namespace documented

namespace {

using Emitted = symdyn_generated::double_pendulum_absolute;
using Documented = documented::symdyn_generated::double_pendulum_absolute;

template <typename T, std::size_t N>
constexpr bool same(const T (&a)[N], const T (&b)[N]) {
  for (std::size_t i = 0; i < N; ++i) {
    if constexpr (std::is_same_v<T, const char*>) {
      if ((a[i] == nullptr) != (b[i] == nullptr) ||
          (a[i] != nullptr && std::string_view(a[i]) != b[i])) {
        return false;
      }
    } else if (a[i] != b[i]) {
      return false;
    }
  }
  return true;
}

static_assert(std::string_view(Emitted::model) == Documented::model);
static_assert(std::string_view(Emitted::variant) == Documented::variant);
static_assert(Emitted::nq == Documented::nq && Emitted::nbody == Documented::nbody);
static_assert(Emitted::ndep == Documented::ndep && Emitted::nparam == Documented::nparam);
static_assert(Emitted::has_equations_of_motion == Documented::has_equations_of_motion);
static_assert(Emitted::has_inverse_dynamics == Documented::has_inverse_dynamics);
static_assert(Emitted::has_forward_dynamics == Documented::has_forward_dynamics);
static_assert(Emitted::has_inverse_dynamics_derivatives ==
              Documented::has_inverse_dynamics_derivatives);
static_assert(same(Emitted::q_names, Documented::q_names));
static_assert(same(Emitted::body_names, Documented::body_names));
static_assert(same(Emitted::param_names, Documented::param_names));
static_assert(same(Emitted::param_defaults, Documented::param_defaults));
static_assert(same(Emitted::q_initial, Documented::q_initial));
static_assert(same(Emitted::qd_initial, Documented::qd_initial));
static_assert(same(Emitted::gravity, Documented::gravity));
static_assert(same(Emitted::reference_body, Documented::reference_body));
static_assert(same(Emitted::dependent_names, Documented::dependent_names));
static_assert(Emitted::ndomain == Documented::ndomain);
static_assert(same(Emitted::domain_dependents, Documented::domain_dependents));
static_assert(same(Emitted::domain_functions, Documented::domain_functions));
static_assert(Emitted::nangle_sequences == Documented::nangle_sequences);
static_assert(same(Emitted::angle_sequence_body, Documented::angle_sequence_body));
static_assert(same(Emitted::angle_sequence_q, Documented::angle_sequence_q));
static_assert(same(Emitted::angle_sequence_axes, Documented::angle_sequence_axes));

// The entry points double_pendulum_absolute has (its variant emits no closed
// loops nor forward dynamics: tests/codegen/entry_points_test.cpp checks those
// declarations against the generator's catalogue).
template <auto emitted, auto documented>
constexpr bool same_signature = std::is_same_v<decltype(emitted), decltype(documented)>;
static_assert(same_signature<&Emitted::inertia, &Documented::inertia>);
static_assert(same_signature<&Emitted::positions, &Documented::positions>);
static_assert(same_signature<&Emitted::velocities, &Documented::velocities>);
static_assert(same_signature<&Emitted::accelerations, &Documented::accelerations>);
static_assert(same_signature<&Emitted::partial_velocities, &Documented::partial_velocities>);
static_assert(
    same_signature<&Emitted::relative_accelerations, &Documented::relative_accelerations>);
static_assert(same_signature<&Emitted::relative_partial_velocities,
                             &Documented::relative_partial_velocities>);
static_assert(
    same_signature<&Emitted::accelerations_partials, &Documented::accelerations_partials>);
static_assert(same_signature<&Emitted::relative_accelerations_partials,
                             &Documented::relative_accelerations_partials>);
static_assert(same_signature<&Emitted::dependent_parameters, &Documented::dependent_parameters>);
static_assert(same_signature<&Emitted::mass_matrix, &Documented::mass_matrix>);
static_assert(same_signature<&Emitted::bias_forces, &Documented::bias_forces>);
static_assert(same_signature<&Emitted::dynamics, &Documented::dynamics>);
static_assert(same_signature<&Emitted::dynamics_positions, &Documented::dynamics_positions>);
static_assert(same_signature<&Emitted::dynamics_velocities, &Documented::dynamics_velocities>);
static_assert(same_signature<&Emitted::inverse_dynamics, &Documented::inverse_dynamics>);
static_assert(same_signature<&Emitted::inverse_dynamics_derivatives,
                             &Documented::inverse_dynamics_derivatives>);
static_assert(
    same_signature<&Emitted::inverse_dynamics_jacobians, &Documented::inverse_dynamics_jacobians>);
static_assert(
    same_signature<&Emitted::kinematics_derivatives, &Documented::kinematics_derivatives>);
static_assert(same_signature<&Emitted::joint_reactions, &Documented::joint_reactions>);
static_assert(same_signature<&Emitted::domain_arguments, &Documented::domain_arguments>);

}  // namespace
