#pragma once
// The bridge between one compiled emitted model, loaded as a shared object
// (dlopen), and the paper_tables timing program. The emitted struct's static
// members are copied into plain pointers here, by adapter.cpp compiled with
// the emitted header; the program turns them into a runtime::ModelDescription.
// No Eigen and no runtime header, so that the adapter compiles in a blink.

namespace symdyn::paper {

// Entry points, with the signatures of docs/emitted_interface.md.
struct PluginModel {
  const char* model = nullptr;
  const char* variant = nullptr;
  int nq = 0, nbody = 0, ndep = 0, nparam = 0;
  const char* const* q_names = nullptr;      // (nq)
  const char* const* body_names = nullptr;   // (nbody)
  const char* const* param_names = nullptr;  // (nparam)
  const double* param_defaults = nullptr;    // (nparam)
  const double* q_initial = nullptr;         // (nq)
  const double* qd_initial = nullptr;        // (nq)
  const double* gravity = nullptr;           // (3)
  const int* reference_body = nullptr;       // (nbody)
  void (*inertia)(const double*, double*, double*) = nullptr;
  void (*positions)(double, const double*, const double*, double*, double*) = nullptr;
  void (*velocities)(double, const double*, const double*, const double*, double*, double*, double*,
                     double*) = nullptr;
  void (*accelerations)(double, const double*, const double*, const double*, const double*, double*,
                        double*, double*, double*, double*, double*) = nullptr;
  void (*partial_velocities)(double, const double*, const double*, double*, double*) = nullptr;
  void (*dependent_parameters)(double, const double*, const double*, const double*, const double*,
                               double*, double*, double*) = nullptr;
  void (*mass_matrix)(double, const double*, const double*, double*) = nullptr;  // null without EoM
  void (*bias_forces)(double, const double*, const double*, const double*, double*) = nullptr;
};

// The symbol adapter.cpp exports: extern "C" const PluginModel* symdyn_paper_model();
inline constexpr const char* plugin_symbol = "symdyn_paper_model";

}  // namespace symdyn::paper
