#pragma once
// The equations of motion reduced modulo sin²x + cos²x = 1.
//
// Why: M and h are sums over bodies of products of rotations; entries such
// as a free body's M_00 (its total mass times the squared norm of a rotation
// column) are constants or short only once the terms of every body are
// expanded and collected, which no local rule does (symbolic/trig_polynomial.hpp).

#include <symdyn/model/dynamics.hpp>

namespace symdyn::model {

// Every entry of M and h, and every definition of the dynamics, replaced by
// its normal form (the kinematics' intermediates seen through) where that is
// cheaper, then kept for the definitions, M and h each only where the
// programs of M and h come out shorter; the values are unchanged (to rounding).
void reduce_trigonometry(Dynamics& dynamics, const Kinematics& kinematics);

}  // namespace symdyn::model
