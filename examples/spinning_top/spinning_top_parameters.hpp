#pragma once
// The top's data, shared by the model (spinning_top.cpp) and the simulation,
// which checks the motion against the closed form of steady precession.

#include <cmath>

namespace spinning_top {

// A disc of radius 6 cm on a massless stem, its centre of mass 5 cm from the tip.
constexpr double kMass = 0.1;                              // kg
constexpr double kTipToCentre = 0.05;                      // m
constexpr double kAxialInertia = kMass * 0.06 * 0.06 / 2;  // kg m², about the axis at G
constexpr double kTransverseInertia = kAxialInertia / 2;   // kg m², about a diameter at G
constexpr double kGravity = 9.81;                          // m/s²

// Initial state: tilted by kNutation from the vertical, spinning at kSpin about its axis.
constexpr double kNutation = 0.5;  // rad
constexpr double kSpin = 100.0;    // rad/s, the axial angular velocity w3

// The slow steady precession rate at kNutation and kSpin: with I1 the transverse
// inertia about the tip, theta'' = 0 when  I1 cos(theta) W² - I3 w3 W + m g l = 0.
inline double steady_precession_rate() {
  const double i1 = kTransverseInertia + kMass * kTipToCentre * kTipToCentre;
  const double a = i1 * std::cos(kNutation);
  const double b = kAxialInertia * kSpin;
  const double c = kMass * kGravity * kTipToCentre;
  return (b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
}

}  // namespace spinning_top
