#pragma once
// Checks of a force element's constants when it is made: every number
// finite, and of the sign its law needs (a contact's stiffness > 0, a
// damping >= 0). The runtime's elements call them in their constructors
// (through check_parameter, element_parameters.hpp, for the constants of its
// table), so scenario files and the Python module are refused alike. A PropertyError
// names the element and the property and keeps what was expected apart, for
// a scenario file to report it at the property's JSON path:
//   contact 'foot': stiffness: expected a number > 0, found -5

#include <string>

#include <symdyn/runtime/errors.hpp>
#include <symdyn/runtime/kinematics.hpp>

namespace symdyn::runtime {

class PropertyError : public ModelError {
 public:
  // element: the element's name() ("contact 'foot'"); property: its name as
  // the element's parameters spell it ("stiffness", "plane_normal").
  PropertyError(const std::string& element, std::string property, std::string detail);
  const std::string& property() const { return property_; }
  // What was expected and found: "expected a number > 0, found -5".
  const std::string& detail() const { return detail_; }

 private:
  std::string property_, detail_;
};

enum class Sign { any, non_negative, positive };
// " >= 0", " > 0" or "": what a sign asks of a number, for messages.
const char* requirement(Sign sign);

// Each throws PropertyError naming `element` and `property`.
void check_property(const std::string& element, const char* property, double value,
                    Sign sign = Sign::any);
void check_property(const std::string& element, const char* property, const Vec3& value,
                    Sign sign = Sign::any);
// A direction: finite and not zero.
void check_direction(const std::string& element, const char* property, const Vec3& value);
// A frame's axes (columns): finite and orthonormal, right-handed, to 1e-6.
void check_axes(const std::string& element, const char* property, const Mat3& axes);

}  // namespace symdyn::runtime
