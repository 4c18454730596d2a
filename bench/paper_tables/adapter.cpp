// Compiled by run.sh into the shared object of one emitted model:
//   g++ -O2 -fPIC -include <basename>.hpp -DSYMDYN_PAPER_STRUCT=symdyn_generated::<basename> -c
//   adapter.cpp
// It exports the emitted struct's members as a PluginModel (plugin.hpp).
#include "plugin.hpp"

#ifndef SYMDYN_PAPER_STRUCT
#error \
    "define SYMDYN_PAPER_STRUCT as the emitted struct, e.g. symdyn_generated::double_pendulum_absolute"
#endif

namespace {

// A template, so that the entry points a --no-eom model lacks are never named.
template <class G>
symdyn::paper::PluginModel describe() {
  symdyn::paper::PluginModel p;
  p.model = G::model;
  p.variant = G::variant;
  p.nq = G::nq;
  p.nbody = G::nbody;
  p.ndep = G::ndep;
  p.nparam = G::nparam;
  p.q_names = G::q_names;
  p.body_names = G::body_names;
  p.param_names = G::param_names;
  p.param_defaults = G::param_defaults;
  p.q_initial = G::q_initial;
  p.qd_initial = G::qd_initial;
  p.gravity = G::gravity;
  p.reference_body = G::reference_body;
  p.inertia = &G::inertia;
  p.positions = &G::positions;
  p.velocities = &G::velocities;
  p.accelerations = &G::accelerations;
  p.partial_velocities = &G::partial_velocities;
  p.dependent_parameters = &G::dependent_parameters;
  if constexpr (requires {
                  &G::mass_matrix;
                  &G::bias_forces;
                }) {
    if (G::has_equations_of_motion) {
      p.mass_matrix = &G::mass_matrix;
      p.bias_forces = &G::bias_forces;
    }
  }
  return p;
}

const symdyn::paper::PluginModel plugin = describe<SYMDYN_PAPER_STRUCT>();

}  // namespace

extern "C" __attribute__((visibility("default"))) const symdyn::paper::PluginModel*
symdyn_paper_model() {
  return &plugin;
}
