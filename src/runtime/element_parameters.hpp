#pragma once
// The constants of each force element, described once: name, unit, meaning,
// range and default. The elements' constructors check their values against
// this table; scenario files (apps/sim), the Python module, the scenario
// schema and docs/scenarios.md read their names, defaults and ranges from it.
// What an element acts on (bodies, points, planes, laws) is not a constant and
// is not listed.

#include <array>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/runtime/bushing.hpp>
#include <symdyn/runtime/contact.hpp>
#include <symdyn/runtime/element_properties.hpp>
#include <symdyn/runtime/generalized_forces.hpp>
#include <symdyn/runtime/gim_tyre.hpp>
#include <symdyn/runtime/point_forces.hpp>

namespace symdyn::runtime {

// A number, 3 numbers, or 3 numbers that are a direction (not all zero).
enum class ParameterShape { number, vector, direction };

struct Parameter {
  std::string_view name;  // the scenario key and the Python keyword
  std::string_view unit;  // SI ("N/m"), empty for a pure number
  std::string_view meaning;
  ParameterShape shape = ParameterShape::number;
  Sign sign = Sign::any;  // of each number
  bool required = false;
  std::array<double, 3> fallback{};  // the default when not required (a number: the first)
};

struct ElementParameters {
  std::string_view type;  // as scenario files name it: "plane_contact"
  std::span<const Parameter> parameters;
  const Parameter* find(std::string_view name) const;
};

// Every force element type that has constants, in the documentation's order.
std::span<const ElementParameters> element_parameter_table();
// One type's row (ModelError for an unknown type).
const ElementParameters& element_parameters(std::string_view type);

// "a number >= 0", "3 numbers", "a non-zero direction": what a value must be.
std::string requirement(const Parameter& p);
// "a number >= 0, N/m: k in Q = ...": what it must be, its unit and meaning.
std::string description(const Parameter& p);

// Checks `value` against the table's row for `type` and `name` (PropertyError
// naming `element` and the parameter, as check_property does).
void check_parameter(const std::string& element, std::string_view type, std::string_view name,
                     double value);
void check_parameter(const std::string& element, std::string_view type, std::string_view name,
                     const Vec3& value);

// The names among `known` close to `given` (a typing slip: an edit distance of
// at most 2, or a difference of case), nearest first.
std::vector<std::string_view> close_names(std::string_view given,
                                          std::span<const std::string_view> known);

// The constants of one element: the defaults, and the values given by name.
class ParameterValues {
 public:
  explicit ParameterValues(std::string_view type);
  const ElementParameters& row() const { return *row_; }
  // ModelError for a name the type does not have.
  void set(std::string_view name, double value);
  void set(std::string_view name, const Vec3& value);
  bool given(std::string_view name) const;
  // The first required parameter not given, or nullptr.
  const Parameter* missing() const;
  // A value (ModelError when required and not given).
  double number(std::string_view name) const;
  Vec3 vector(std::string_view name) const;

 private:
  std::size_t index(std::string_view name) const;
  const ElementParameters* row_;
  std::vector<Vec3> values_;
  std::vector<bool> given_;
};

// The elements built from their constants by name (the table's names bound to
// the constructors' arguments here, once); the constructors check them.
std::shared_ptr<CoordinateSpringDamper> make_coordinate_spring_damper(std::string name,
                                                                      int coordinate,
                                                                      const ParameterValues& v);
std::shared_ptr<CoordinateTracking> make_coordinate_tracking(std::string name, int coordinate,
                                                             CoordinateTracking::Reference r,
                                                             CoordinateTracking::Reference rate,
                                                             const ParameterValues& v);
std::shared_ptr<PointSpringDamper> make_point_spring_damper(std::string name, BodyPoint a,
                                                            BodyPoint b, const ParameterValues& v);
std::shared_ptr<Bushing> make_bushing(std::string name, BodyFrame a, BodyFrame b,
                                      std::string_view order, const ParameterValues& v);
std::shared_ptr<PlaneContact> make_plane_contact(std::string name, int body, const Plane& plane,
                                                 FrictionRegularization regularization,
                                                 const ParameterValues& v);
std::shared_ptr<SimpleTyre> make_simple_tyre(std::string name, int body, const Plane& ground,
                                             const ParameterValues& v);
std::shared_ptr<GimTyre> make_gim_tyre(std::string name, int body, const Plane& ground,
                                       const ParameterValues& v);

// The properties structs from the constants (their defaults are the table's:
// tested).
ContactProperties contact_properties(const ParameterValues& v);
SimpleTyreProperties simple_tyre_properties(const ParameterValues& v);
GimTyreProperties gim_tyre_properties(const ParameterValues& v);
BushingProperties bushing_properties(const ParameterValues& v);

}  // namespace symdyn::runtime
