#pragma once
// symdyn::model: the builder API (model.hpp, docs/builder.md), its checks and
// the derivation of kinematics and equations of motion as expressions. Not
// urdf.hpp: URDF import is a library of its own (symdyn::urdf, docs/urdf.md).
// The part's umbrella is all.hpp because model.hpp is the builder.

#include <symdyn/model/constraints.hpp>
#include <symdyn/model/diagnostics.hpp>
#include <symdyn/model/dynamics.hpp>
#include <symdyn/model/dynamics_derivatives.hpp>
#include <symdyn/model/errors.hpp>
#include <symdyn/model/identifier.hpp>
#include <symdyn/model/kinematics.hpp>
#include <symdyn/model/model.hpp>
#include <symdyn/model/transform.hpp>
#include <symdyn/model/trig_reduction.hpp>
#include <symdyn/model/vector3.hpp>
