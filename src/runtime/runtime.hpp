#pragma once
// symdyn::runtime, the multibody half: everything a simulation program needs
// next to its generated model (docs/emitted_interface.md).

#include "runtime/bushing.hpp"
#include "runtime/cardan.hpp"
#include "runtime/contact.hpp"
#include "runtime/csv.hpp"
#include "runtime/dynamic_system.hpp"
#include "runtime/energy.hpp"
#include "runtime/errors.hpp"
#include "runtime/force_element.hpp"
#include "runtime/generalized_forces.hpp"
#include "runtime/gim_tyre.hpp"
#include "runtime/kinematics.hpp"
#include "runtime/linearization.hpp"
#include "runtime/model.hpp"
#include "runtime/multibody_system.hpp"
#include "runtime/point_forces.hpp"
#include "runtime/statics.hpp"
