#pragma once
// symdyn::runtime: everything a simulation program needs next to its generated
// model (docs/emitted_interface.md): the equations of motion, force elements,
// integrators, statics, linearization and outputs.

#include <symdyn/runtime/animation.hpp>
#include <symdyn/runtime/breakpoints.hpp>
#include <symdyn/runtime/bushing.hpp>
#include <symdyn/runtime/cardan.hpp>
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/csv.hpp>
#include <symdyn/runtime/dynamic_system.hpp>
#include <symdyn/runtime/easyanim.hpp>
#include <symdyn/runtime/element_parameters.hpp>
#include <symdyn/runtime/element_properties.hpp>
#include <symdyn/runtime/energy.hpp>
#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/force_element.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/gim_tyre.hpp>
#include <symdyn/runtime/gltf.hpp>
#include <symdyn/runtime/html_viewer.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/kinematics.hpp>
#include <symdyn/runtime/kinematics_derivatives.hpp>
#include <symdyn/runtime/linearization.hpp>
#include <symdyn/runtime/loop_closure.hpp>
#include <symdyn/runtime/model.hpp>
#include <symdyn/runtime/model_module.hpp>
#include <symdyn/runtime/multibody_system.hpp>
#include <symdyn/runtime/point_forces.hpp>
#include <symdyn/runtime/progress_bar.hpp>
#include <symdyn/runtime/relative_motion.hpp>
#include <symdyn/runtime/scene.hpp>
#include <symdyn/runtime/spd_solver.hpp>
#include <symdyn/runtime/statics.hpp>
#include <symdyn/runtime/step_derivatives.hpp>
#include <symdyn/runtime/tree_solver.hpp>
