// A double-wishbone quarter car (docs/models.md): the chassis moves
// vertically, the lower and upper wishbones are hinged to it about the
// longitudinal axis x, the upright (knuckle) is carried by the lower
// wishbone's ball joint and closes the loop at the upper wishbone's ball
// joint, the wheel spins on the upright. Steer is held as a tie rod parallel
// to the wishbones would hold it: the upright only turns about x. No closed
// form is given: the upper wishbone's angle and the upright's are implicit.
//
// The y axis points out of the car, z up, the ground is z = 0. The points
// below are those of the design position (chassis G at z = 0.6, lower
// wishbone angle lower_design), in metres.
#include <cmath>

#include <symdyn/model/model.hpp>

namespace {

using namespace symdyn::model;

struct Point {
  double y, z;
};
constexpr double chassis_height = 0.6;  // G of the chassis
constexpr Point lower_inner{0.20, 0.18}, lower_outer{0.60, 0.15};
constexpr Point upper_inner{0.30, 0.48}, upper_outer{0.57, 0.50};
constexpr Point upright_g{0.61, 0.30}, wheel_centre{0.72, 0.30};

double length(Point a, Point b) {
  return std::hypot(b.y - a.y, b.z - a.z);
}
double angle(Point a, Point b) {  // about x, from y towards z
  return std::atan2(b.z - a.z, b.y - a.y);
}
// A point relative to the chassis' G, and relative to the lower ball joint.
Transform from_chassis(Point p) {
  return Tdisp(0, p.y, p.z - chassis_height);
}
Point from_lower_ball_joint(Point p) {
  return {p.y - lower_outer.y, p.z - lower_outer.z};
}
Point operator-(Point a, Point b) {
  return {a.y - b.y, a.z - b.z};
}

void build(Model& m, std::string_view) {
  const double lower = length(lower_inner, lower_outer), upper = length(upper_inner, upper_outer);
  const Expr z = m.coordinate("z");        // chassis G height
  const Expr q = m.coordinate("lower");    // lower wishbone angle about x
  const Expr spin = m.coordinate("spin");  // wheel about its axle (y)
  const Expr alpha = m.implicit_dependent("upper", angle(upper_inner, upper_outer));
  const Expr beta = m.implicit_dependent("upright", 0.0);  // camber = -upright
  m.body("chassis").mass(350).inertia(120, 60, 150).motion(Tdisp(0, 0, z));
  m.body("lower_wishbone")
      .mass(4.0)
      .inertia(0.06, 0.03, 0.08)
      .relative_to("chassis")
      .motion(from_chassis(lower_inner) * Trotx(q) * Tdisp(0, lower / 2, 0));
  m.body("upper_wishbone")
      .mass(2.5)
      .inertia(0.02, 0.012, 0.03)
      .relative_to("chassis")
      .motion(from_chassis(upper_inner) * Trotx(alpha) * Tdisp(0, upper / 2, 0));
  // Axes parallel to the chassis' at upright = 0, whatever the lower angle.
  const Point g = from_lower_ball_joint(upright_g);
  m.body("upright")
      .mass(6.0)
      .inertia(0.04, 0.03, 0.02)
      .relative_to("lower_wishbone")
      .motion(Tdisp(0, lower / 2, 0) * Trotx(beta - q) * Tdisp(0, g.y, g.z));
  const Point axle = from_lower_ball_joint(wheel_centre) - g;
  m.body("wheel")
      .mass(18.0)
      .inertia(0.8, 1.4, 0.8)
      .relative_to("upright")
      .motion(Tdisp(0, axle.y, axle.z) * Troty(spin));
  const Point ball_joint = from_lower_ball_joint(upper_outer) - g;
  m.close_loop("upper_ball_joint", "upper_wishbone", {0, upper / 2, 0}, "upright",
               {0, ball_joint.y, ball_joint.z});
  m.gravity(0, 0, -9.81);
  m.initial(z, chassis_height);
  m.initial(q, angle(lower_inner, lower_outer));
}

const Registration registration({"quarter_car", {"default"}, build});

}  // namespace
