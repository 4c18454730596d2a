// The table of force-element constants (element_parameters.hpp) against the
// elements themselves: its defaults are the properties structs' own, each range
// it states is the one the element's constructor enforces (a value just outside
// refused naming the constant, one on the edge accepted), and close_names finds
// typing slips.
#include <catch2/catch.hpp>
#include <limits>
#include <string>

#include <symdyn/runtime/element_parameters.hpp>

namespace {

using namespace symdyn::runtime;

// Builds an element of `type` from `v` (bodies 0 and 1, the default plane).
void make(std::string_view type, const ParameterValues& v) {
  if (type == "coordinate_spring_damper") {
    make_coordinate_spring_damper("k", 0, v);
  } else if (type == "coordinate_tracking") {
    make_coordinate_tracking("servo", 0, nullptr, nullptr, v);
  } else if (type == "point_spring_damper") {
    make_point_spring_damper("s", BodyPoint{0, Vec3::Zero()}, BodyPoint{1, Vec3::Zero()}, v);
  } else if (type == "bushing") {
    make_bushing("mount", BodyFrame{0}, BodyFrame{1}, "xyz", v);
  } else if (type == "plane_contact") {
    make_plane_contact("foot", 0, Plane{}, FrictionRegularization::linear, v);
  } else if (type == "simple_tyre") {
    make_simple_tyre("wheel", 0, Plane{}, v);
  } else if (type == "gim_tyre") {
    make_gim_tyre("wheel", 0, Plane{}, v);
  } else {
    FAIL("no builder for " << type);
  }
}

// The required constants at a value inside their range.
ParameterValues valid(std::string_view type) {
  ParameterValues v(type);
  for (const Parameter& p : v.row().parameters) {
    if (p.required) v.set(p.name, 1.0);
  }
  return v;
}

void set(ParameterValues& v, const Parameter& p, double x) {
  if (p.shape == ParameterShape::number) {
    v.set(p.name, x);
  } else {
    v.set(p.name, Vec3(1.0, x, 1.0));
  }
}

// Each member of `a` equal to that of `b`.
template <class P, class... M>
void same_members(const P& a, const P& b, M... members) {
  ([&] { CHECK(a.*members == b.*members); }(), ...);
}

}  // namespace

TEST_CASE("The constants' table: every type of the table is built from its defaults",
          "[runtime][forces]") {
  for (const ElementParameters& row : element_parameter_table()) {
    CAPTURE(row.type);
    CHECK_NOTHROW(make(row.type, valid(row.type)));
  }
}

TEST_CASE("The constants' table: each range is the one the element's constructor enforces",
          "[runtime][forces]") {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  for (const ElementParameters& row : element_parameter_table()) {
    for (const Parameter& p : row.parameters) {
      CAPTURE(row.type, p.name);
      const auto refused = [&](double x) {
        ParameterValues v = valid(row.type);
        set(v, p, x);
        try {
          make(row.type, v);
        } catch (const PropertyError& e) {
          return e.property() == p.name;
        }
        return false;
      };
      CHECK(refused(nan));  // every constant is finite
      if (p.shape == ParameterShape::direction) {
        ParameterValues v = valid(row.type);
        v.set(p.name, Vec3::Zero());
        CHECK_THROWS_AS(make(row.type, v), PropertyError);
        continue;
      }
      CHECK(refused(-1e-3) == (p.sign != Sign::any));
      CHECK(refused(0.0) == (p.sign == Sign::positive));
    }
  }
}

TEST_CASE("The constants' table: the properties structs' defaults are the table's",
          "[runtime][forces]") {
  using C = ContactProperties;
  same_members(contact_properties(ParameterValues("plane_contact")), C{}, &C::stiffness,
               &C::stiffness_exponent, &C::damping, &C::damping_exponent, &C::friction,
               &C::slip_speed);
  using S = SimpleTyreProperties;
  same_members(simple_tyre_properties(ParameterValues("simple_tyre")), S{}, &S::radius,
               &S::stiffness, &S::damping, &S::friction, &S::epsilon, &S::axis, &S::centre);
  using G = GimTyreProperties;
  same_members(gim_tyre_properties(ParameterValues("gim_tyre")), G{}, &G::r1, &G::r2, &G::Kz,
               &G::Cz, &G::Fznom, &G::Clongnom, &G::nlong, &G::Clatnom, &G::nlat, &G::Ccambernom,
               &G::ncamber, &G::mu_static, &G::mu_dynamic, &G::axis, &G::centre);
  using B = BushingProperties;
  same_members(bushing_properties(ParameterValues("bushing")), B{}, &B::stiffness, &B::damping,
               &B::rotational_stiffness, &B::rotational_damping, &B::preload_force,
               &B::preload_torque);
}

TEST_CASE("The constants' table: a required constant, an unknown name", "[runtime][forces]") {
  ParameterValues v("point_spring_damper");
  REQUIRE(v.missing() != nullptr);
  CHECK(v.missing()->name == "stiffness");
  v.set("stiffness", 10.0);
  CHECK(v.missing()->name == "free_length");
  CHECK_THROWS_WITH(v.number("free_length"),
                    "a point_spring_damper needs its free_length (a number >= 0)");
  v.set("free_length", 0.5);
  CHECK(v.missing() == nullptr);
  CHECK(v.number("damping") == 0.0);
  CHECK_THROWS_WITH(v.set("stifness", 1.0), "a point_spring_damper has no parameter 'stifness'");
  CHECK_THROWS_WITH(ParameterValues("spring"), "no force element type 'spring'");
}

TEST_CASE("close_names: the known names a typing slip away, nearest first", "[runtime][forces]") {
  const std::string_view known[] = {"stiffness", "damping", "free_value", "Kz", "Cz", "radius"};
  using V = std::vector<std::string_view>;
  CHECK(close_names("stifness", known) == V{"stiffness"});
  CHECK(close_names("radious", known) == V{"radius"});
  CHECK(close_names("kz", known) == V{"Kz", "Cz"});  // case first, then one letter
  CHECK(close_names("Damping", known) == V{"damping"});
  CHECK(close_names("elasticity", known).empty());
  CHECK(close_names("x", known).empty());  // no name is one letter away from everything
}
