#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <numeric>
#include <utility>

#include <symdyn/runtime/element_parameters.hpp>

namespace symdyn::runtime {

namespace {

constexpr Sign any = Sign::any, non_negative = Sign::non_negative, positive = Sign::positive;
constexpr ParameterShape number = ParameterShape::number, vector = ParameterShape::vector,
                         direction = ParameterShape::direction;
constexpr bool required = true;

// Rows: name, unit, meaning, shape, sign of each number, required, default.
const Parameter kCoordinateSpringDamper[] = {
    {"stiffness", "N/m or N·m/rad", "k in Q = -k (q - free_value) - c qd", number, non_negative,
     required},
    {"damping", "N·s/m or N·m·s/rad", "c", number, non_negative},
    {"free_value", "m or rad", "the coordinate's value where the spring is relaxed", number, any},
};

const Parameter kCoordinateTracking[] = {
    {"kp", "N/m or N·m/rad", "kp in Q = -kp (q - r) - kd (qd - rd)", number, non_negative,
     required},
    {"kd", "N·s/m or N·m·s/rad", "kd", number, non_negative},
};

const Parameter kPointSpringDamper[] = {
    {"stiffness", "N/m", "k in the tension T = k (L - free_length) + c dL/dt", number, non_negative,
     required},
    {"free_length", "m", "the length L where the spring is relaxed", number, non_negative,
     required},
    {"damping", "N·s/m", "c", number, non_negative},
};

const Parameter kBushing[] = {
    {"stiffness", "N/m", "along each axis of frame a", vector, non_negative},
    {"damping", "N·s/m", "along each axis of frame a", vector, non_negative},
    {"rotational_stiffness", "N·m/rad", "per Cardan angle", vector, non_negative},
    {"rotational_damping", "N·m·s/rad", "per Cardan angle", vector, non_negative},
    {"preload_force", "N", "on b, in a's axes, at zero deflection", vector, any},
    {"preload_torque", "N·m", "per Cardan angle, at zero deflection", vector, any},
};

const Parameter kPlaneContact[] = {
    {"point", "m", "the sphere's centre in body coordinates from G", vector, any},
    {"radius", "m", "the sphere's radius (0: a point)", number, non_negative},
    {"stiffness", "N/m^pk", "Kn in N = Kn delta^pk + Cd delta^pd deltad", number, positive,
     required},
    {"stiffness_exponent", "", "pk", number, positive, false, {1.0}},
    {"damping", "N·s/m^(pd+1)", "Cd", number, non_negative},
    {"damping_exponent", "", "pd", number, non_negative},
    {"friction", "", "mu, Coulomb's coefficient", number, non_negative},
    {"slip_speed",
     "m/s",
     "v_s, below which friction is regularized",
     number,
     positive,
     false,
     {1e-3}},
};

const Parameter kSimpleTyre[] = {
    {"radius", "m", "R", number, positive, false, {0.3}},
    {"stiffness", "N/m", "k in N = k delta - c vP.n", number, positive, false, {2e5}},
    {"damping", "N·s/m", "c", number, non_negative, false, {500.0}},
    {"friction", "", "mu", number, non_negative, false, {0.9}},
    {"epsilon", "m/s", "eps, below which friction is regularized", number, positive, false, {0.05}},
    {"axis", "", "the spin axis in body axes", direction, any, false, {0.0, 1.0, 0.0}},
    {"centre", "m", "the wheel's centre in body coordinates from G", vector, any},
};

const Parameter kGimTyre[] = {
    {"r1", "m", "outer radius", number, positive, false, {0.3}},
    {"r2", "m", "section radius (<= r1)", number, positive, false, {0.1}},
    {"Kz", "N/m", "vertical stiffness", number, positive, false, {2e5}},
    {"Cz", "N·s/m", "vertical damping at Fznom", number, non_negative, false, {500.0}},
    {"Fznom", "N", "nominal load", number, positive, false, {3000.0}},
    {"Clongnom", "N", "longitudinal slip stiffness at Fznom", number, non_negative, false, {5e4}},
    {"nlong", "", "exponent of Fz/Fznom in the longitudinal stiffness", number, any, false, {1.0}},
    {"Clatnom", "N", "lateral slip stiffness at Fznom", number, non_negative, false, {4e4}},
    {"nlat", "", "exponent of Fz/Fznom in the lateral stiffness", number, any, false, {1.0}},
    {"Ccambernom", "N/rad", "camber stiffness at Fznom", number, any, false, {2e3}},
    {"ncamber", "", "exponent of Fz/Fznom in the camber stiffness", number, any, false, {1.0}},
    {"mu_static", "", "friction at zero slip", number, non_negative, false, {1.0}},
    {"mu_dynamic", "", "friction from a slip of 1 on", number, non_negative, false, {0.8}},
    {"axis", "", "the spin axis in body axes", direction, any, false, {0.0, 1.0, 0.0}},
    {"centre", "m", "the wheel's centre in body coordinates from G", vector, any},
};

const ElementParameters kTable[] = {
    {"coordinate_spring_damper", kCoordinateSpringDamper},
    {"coordinate_tracking", kCoordinateTracking},
    {"point_spring_damper", kPointSpringDamper},
    {"bushing", kBushing},
    {"plane_contact", kPlaneContact},
    {"simple_tyre", kSimpleTyre},
    {"gim_tyre", kGimTyre},
};

const Parameter& parameter(std::string_view type, std::string_view name) {
  const ElementParameters& row = element_parameters(type);
  const Parameter* p = row.find(name);
  if (p == nullptr) throw ModelError(fmt::format("a {} has no parameter '{}'", type, name));
  return *p;
}

// Levenshtein's distance, ignoring case.
std::size_t distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      const std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

}  // namespace

const Parameter* ElementParameters::find(std::string_view name) const {
  const auto it = std::find_if(parameters.begin(), parameters.end(),
                               [&](const Parameter& p) { return p.name == name; });
  return it == parameters.end() ? nullptr : &*it;
}

std::span<const ElementParameters> element_parameter_table() {
  return kTable;
}

const ElementParameters& element_parameters(std::string_view type) {
  const auto it = std::find_if(std::begin(kTable), std::end(kTable),
                               [&](const ElementParameters& e) { return e.type == type; });
  if (it == std::end(kTable)) throw ModelError(fmt::format("no force element type '{}'", type));
  return *it;
}

std::string requirement(const Parameter& p) {
  if (p.shape == ParameterShape::direction) return "a direction: 3 numbers not all 0";
  return fmt::format("{}{}", p.shape == ParameterShape::number ? "a number" : "3 numbers",
                     requirement(p.sign));
}

std::string description(const Parameter& p) {
  return fmt::format("{}{}{}: {}", requirement(p), p.unit.empty() ? "" : ", ", p.unit, p.meaning);
}

void check_parameter(const std::string& element, std::string_view type, std::string_view name,
                     double value) {
  const Parameter& p = parameter(type, name);
  check_property(element, p.name.data(), value, p.sign);
}

void check_parameter(const std::string& element, std::string_view type, std::string_view name,
                     const Vec3& value) {
  const Parameter& p = parameter(type, name);
  if (p.shape == ParameterShape::direction) {
    check_direction(element, p.name.data(), value);
  } else {
    check_property(element, p.name.data(), value, p.sign);
  }
}

std::vector<std::string_view> close_names(std::string_view given,
                                          std::span<const std::string_view> known) {
  std::vector<std::pair<std::size_t, std::string_view>> near;
  for (const std::string_view k : known) {
    const std::size_t d = distance(given, k);
    if (d <= 2 && d < std::max(given.size(), k.size())) near.emplace_back(d, k);
  }
  std::stable_sort(near.begin(), near.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string_view> out;
  for (const auto& n : near) out.push_back(n.second);
  return out;
}

ParameterValues::ParameterValues(std::string_view type) : row_(&element_parameters(type)) {
  for (const Parameter& p : row_->parameters) {
    values_.emplace_back(p.fallback[0], p.fallback[1], p.fallback[2]);
    given_.push_back(false);
  }
}

std::size_t ParameterValues::index(std::string_view name) const {
  return static_cast<std::size_t>(&parameter(row_->type, name) - row_->parameters.data());
}

void ParameterValues::set(std::string_view name, double value) {
  const std::size_t i = index(name);
  if (row_->parameters[i].shape != ParameterShape::number)
    throw ModelError(fmt::format("{} of a {} is 3 numbers", name, row_->type));
  values_[i] = Vec3(value, 0.0, 0.0);
  given_[i] = true;
}

void ParameterValues::set(std::string_view name, const Vec3& value) {
  const std::size_t i = index(name);
  if (row_->parameters[i].shape == ParameterShape::number)
    throw ModelError(fmt::format("{} of a {} is a number", name, row_->type));
  values_[i] = value;
  given_[i] = true;
}

bool ParameterValues::given(std::string_view name) const {
  return given_[index(name)];
}

const Parameter* ParameterValues::missing() const {
  for (std::size_t i = 0; i < given_.size(); ++i) {
    if (row_->parameters[i].required && !given_[i]) return &row_->parameters[i];
  }
  return nullptr;
}

double ParameterValues::number(std::string_view name) const {
  return vector(name)(0);
}

Vec3 ParameterValues::vector(std::string_view name) const {
  const std::size_t i = index(name);
  if (row_->parameters[i].required && !given_[i]) {
    throw ModelError(
        fmt::format("a {} needs its {} ({})", row_->type, name, requirement(row_->parameters[i])));
  }
  return values_[i];
}

std::shared_ptr<CoordinateSpringDamper> make_coordinate_spring_damper(std::string name,
                                                                      int coordinate,
                                                                      const ParameterValues& v) {
  return std::make_shared<CoordinateSpringDamper>(std::move(name), coordinate,
                                                  v.number("stiffness"), v.number("damping"),
                                                  v.number("free_value"));
}

std::shared_ptr<CoordinateTracking> make_coordinate_tracking(std::string name, int coordinate,
                                                             CoordinateTracking::Reference r,
                                                             CoordinateTracking::Reference rate,
                                                             const ParameterValues& v) {
  return std::make_shared<CoordinateTracking>(std::move(name), coordinate, v.number("kp"),
                                              v.number("kd"), std::move(r), std::move(rate));
}

std::shared_ptr<PointSpringDamper> make_point_spring_damper(std::string name, BodyPoint a,
                                                            BodyPoint b, const ParameterValues& v) {
  return std::make_shared<PointSpringDamper>(std::move(name), a, b, v.number("stiffness"),
                                             v.number("free_length"), v.number("damping"));
}

std::shared_ptr<Bushing> make_bushing(std::string name, BodyFrame a, BodyFrame b,
                                      std::string_view order, const ParameterValues& v) {
  return std::make_shared<Bushing>(std::move(name), a, b, bushing_properties(v), order);
}

std::shared_ptr<PlaneContact> make_plane_contact(std::string name, int body, const Plane& plane,
                                                 FrictionRegularization regularization,
                                                 const ParameterValues& v) {
  ContactProperties p = contact_properties(v);
  p.regularization = regularization;
  return std::make_shared<PlaneContact>(std::move(name), body, v.vector("point"),
                                        v.number("radius"), plane, p);
}

std::shared_ptr<SimpleTyre> make_simple_tyre(std::string name, int body, const Plane& ground,
                                             const ParameterValues& v) {
  return std::make_shared<SimpleTyre>(std::move(name), body, simple_tyre_properties(v), ground);
}

std::shared_ptr<GimTyre> make_gim_tyre(std::string name, int body, const Plane& ground,
                                       const ParameterValues& v) {
  return std::make_shared<GimTyre>(std::move(name), body, gim_tyre_properties(v), ground);
}

namespace {

// A properties struct's member bound to the constant of its name.
template <class P>
struct Field {
  std::string_view name;
  double P::*number = nullptr;
  Vec3 P::*vector = nullptr;
};

// The struct with the constants given or defaulted (a required one not given
// keeps the struct's own value: the constructor refuses it).
template <class P>
P properties_from(const ParameterValues& v, std::initializer_list<Field<P>> fields) {
  P p;
  for (const Field<P>& f : fields) {
    if (!v.given(f.name) && v.row().find(f.name)->required) continue;
    if (f.number != nullptr) {
      p.*f.number = v.number(f.name);
    } else {
      p.*f.vector = v.vector(f.name);
    }
  }
  return p;
}

}  // namespace

ContactProperties contact_properties(const ParameterValues& v) {
  using P = ContactProperties;
  return properties_from<P>(v, {{"stiffness", &P::stiffness},
                                {"stiffness_exponent", &P::stiffness_exponent},
                                {"damping", &P::damping},
                                {"damping_exponent", &P::damping_exponent},
                                {"friction", &P::friction},
                                {"slip_speed", &P::slip_speed}});
}

SimpleTyreProperties simple_tyre_properties(const ParameterValues& v) {
  using P = SimpleTyreProperties;
  return properties_from<P>(v, {{"radius", &P::radius},
                                {"stiffness", &P::stiffness},
                                {"damping", &P::damping},
                                {"friction", &P::friction},
                                {"epsilon", &P::epsilon},
                                {"axis", nullptr, &P::axis},
                                {"centre", nullptr, &P::centre}});
}

GimTyreProperties gim_tyre_properties(const ParameterValues& v) {
  using P = GimTyreProperties;
  return properties_from<P>(v, {{"r1", &P::r1},
                                {"r2", &P::r2},
                                {"Kz", &P::Kz},
                                {"Cz", &P::Cz},
                                {"Fznom", &P::Fznom},
                                {"Clongnom", &P::Clongnom},
                                {"nlong", &P::nlong},
                                {"Clatnom", &P::Clatnom},
                                {"nlat", &P::nlat},
                                {"Ccambernom", &P::Ccambernom},
                                {"ncamber", &P::ncamber},
                                {"mu_static", &P::mu_static},
                                {"mu_dynamic", &P::mu_dynamic},
                                {"axis", nullptr, &P::axis},
                                {"centre", nullptr, &P::centre}});
}

BushingProperties bushing_properties(const ParameterValues& v) {
  using P = BushingProperties;
  return properties_from<P>(v, {{"stiffness", nullptr, &P::stiffness},
                                {"damping", nullptr, &P::damping},
                                {"rotational_stiffness", nullptr, &P::rotational_stiffness},
                                {"rotational_damping", nullptr, &P::rotational_damping},
                                {"preload_force", nullptr, &P::preload_force},
                                {"preload_torque", nullptr, &P::preload_torque}});
}

}  // namespace symdyn::runtime
