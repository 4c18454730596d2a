#include <fmt/format.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <symdyn/detail/inertia.hpp>
#include <symdyn/runtime/model.hpp>

namespace symdyn::runtime {

namespace {

// The index of `name` in `names`, else a ModelError that lists them.
int find_name(const std::vector<std::string>& names, std::string_view name, const char* what,
              const char* plural, const std::string& model) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    throw ModelError(fmt::format("model '{}': no {} named '{}' ({})", model, what, name,
                                 names.empty()
                                     ? fmt::format("it has no {}", plural)
                                     : fmt::format("{}: {}", plural, fmt::join(names, ", "))));
  }
  return static_cast<int>(it - names.begin());
}

// Throws ModelError naming the body when (m, I) is not a rigid body's inertia.
void validate_inertia(const std::string& body, double m, const Mat3& I) {
  std::array<double, 9> row_major{};
  for (int k = 0; k < 9; ++k) row_major[k] = I(k / 3, k % 3);
  const std::string problem = symdyn::detail::inertia_problem(m, row_major);
  if (!problem.empty()) throw ModelError(fmt::format("body '{}': {}", body, problem));
}

// Where each function with a restricted domain is defined (x its argument, e
// the exponent of pow), its edge (defined, but with an infinite derivative, so
// that a rate or an acceleration is not finite there), and the distance to its
// edges relative to the scale of x (s: the magnitude of the terms x is a sum of,
// emitted beside it): the rounding of x is about 1e-16·s, so that where the
// distance is d the rate carries a relative error of about 1e-16/d, and half its
// digits are lost at d = 1e-8 (Model::kDomainMargin). asin and acos: 1 - |x|
// (rate 1/sqrt(1 - x²), whose edges ±1 are their own scale); sqrt and log: x/s
// (rates x'/(2 sqrt x), x'/x); pow: x/s, or |x|/s for an integer exponent (a
// division, defined on both sides of 0), +inf where the exponent is 2 or more
// (an acceleration, x^(e - 2)·x'², stays finite). Negative outside the domain.
struct RestrictedDomain {
  std::string_view function;
  std::string_view domain;  // as a message says it
  bool (*inside)(double x, double e);
  bool (*edge)(double x, double e);
  double (*distance)(double x, double e, double s);
  bool edge_at_zero;  // sqrt, log, pow: the edge is x = 0, the distance relative to x's scale
};

bool is_integer(double e) {
  return std::nearbyint(e) == e;
}

// x/s, 0 at x = 0 whatever s (a sum of squares, all zero).
double relative(double x, double s) {
  return x == 0.0 ? 0.0 : x / s;
}

double distance_of_power(double x, double e, double s) {
  if (e >= 2.0) return std::numeric_limits<double>::infinity();
  return relative(is_integer(e) ? std::abs(x) : x, s);
}

constexpr RestrictedDomain kRestrictedDomains[] = {
    {"asin", "[-1, 1]", [](double x, double) { return std::abs(x) <= 1.0; },
     [](double x, double) { return std::abs(x) == 1.0; },
     [](double x, double, double) { return 1.0 - std::abs(x); }, false},
    {"acos", "[-1, 1]", [](double x, double) { return std::abs(x) <= 1.0; },
     [](double x, double) { return std::abs(x) == 1.0; },
     [](double x, double, double) { return 1.0 - std::abs(x); }, false},
    {"sqrt", "[0, inf)", [](double x, double) { return x >= 0.0; },
     [](double x, double) { return x == 0.0; },
     [](double x, double, double s) { return relative(x, s); }, true},
    {"log", "(0, inf)", [](double x, double) { return x > 0.0; },
     [](double, double) { return false; },
     [](double x, double, double s) { return relative(x, s); }, true},
    {"pow", "a base > 0, or 0 with an exponent > 0, or < 0 with an integer exponent",
     [](double x, double e) {
       return x > 0.0 || (x == 0.0 && e > 0.0) || (x < 0.0 && is_integer(e));
     },
     [](double x, double e) { return x == 0.0 && e > 0.0 && e < 1.0; }, distance_of_power, true},
};

const RestrictedDomain* restricted_domain(std::string_view function) {
  for (const RestrictedDomain& r : kRestrictedDomains) {
    if (r.function == function) return &r;
  }
  return nullptr;
}

// "asin(1.2)", "pow(-0.5, 0.3)".
std::string call(std::string_view function, double x, double e) {
  return function == "pow" ? fmt::format("pow({}, {})", x, e) : fmt::format("{}({})", function, x);
}

}  // namespace

Model::Model(ModelDescription d) : description_(std::move(d)) {
  const auto check_size = [&](std::size_t got, int want, const char* what) {
    if (got != static_cast<std::size_t>(want)) {
      throw ModelError(fmt::format("model '{}': {} has {} entries, expected {}", description_.model,
                                   what, got, want));
    }
  };
  if (description_.nq < 0 || description_.nbody < 0 || description_.ndep < 0 ||
      description_.nparam < 0) {
    throw ModelError(fmt::format("model '{}': negative size", description_.model));
  }
  check_size(description_.q_names.size(), description_.nq, "q_names");
  check_size(description_.q_initial.size(), description_.nq, "q_initial");
  check_size(description_.qd_initial.size(), description_.nq, "qd_initial");
  check_size(description_.body_names.size(), description_.nbody, "body_names");
  check_size(description_.reference_body.size(), description_.nbody, "reference_body");
  check_size(description_.param_names.size(), description_.nparam, "param_names");
  check_size(description_.param_defaults.size(), description_.nparam, "param_defaults");
  if (description_.inertia == nullptr) missing("inertia");
  if (description_.nindependent < 0) description_.nindependent = description_.nq;
  validate_loops();
  validate_diagnostics();
  for (const DomainCheck& c : description_.domain_checks) {
    margin_distances_.push_back(restricted_domain(c.function)->distance);
    zero_edges_.push_back(restricted_domain(c.function)->edge_at_zero);
  }
  zeros_.assign(std::max(description_.nq, 1), 0.0);
  param_ = description_.param_defaults;
  if (param_.empty()) param_.push_back(0.0);
  evaluate_inertia(param_, mass_, inertia_);
}

void Model::validate_loops() const {
  const auto fail = [&](const std::string& what) {
    throw ModelError(fmt::format("model '{}': {}", description_.model, what));
  };
  if (description_.nindependent > description_.nq)
    fail(fmt::format("nindependent {} > nq {}", description_.nindependent, description_.nq));
  if (!has_loops()) return;
  if (description_.constraints == nullptr || description_.constraint_bias == nullptr)
    fail("closed loops without the entry points constraints and constraint_bias");
  if (description_.constraint_loop.size() != static_cast<std::size_t>(ncon()))
    fail(fmt::format("constraint_loop has {} entries, expected {}",
                     description_.constraint_loop.size(), ncon()));
  for (int l : description_.constraint_loop) {
    if (l < 0 || l >= static_cast<int>(description_.loop_names.size()))
      fail(fmt::format("constraint_loop names loop {} of {}", l, description_.loop_names.size()));
  }
  if (description_.loop_bodies.empty() && description_.constraint_axis.empty()) return;
  if (description_.loop_bodies.size() != 2 * description_.loop_names.size() ||
      description_.constraint_axis.size() != static_cast<std::size_t>(ncon()))
    fail(fmt::format("loop_bodies has {} entries, constraint_axis {}; expected {}, {}",
                     description_.loop_bodies.size(), description_.constraint_axis.size(),
                     2 * description_.loop_names.size(), ncon()));
  for (int b : description_.loop_bodies) {
    if (b < -1 || b >= description_.nbody)
      fail(fmt::format("loop_bodies names body {} of {}", b, description_.nbody));
  }
  for (int axis : description_.constraint_axis) {
    if (axis < -1 || axis > 2) fail(fmt::format("constraint_axis {} is not -1, 0, 1 or 2", axis));
  }
}

void Model::closure_points(double t, const double* x, double* point) const {
  if (description_.closure_points == nullptr) missing("closure_points");
  description_.closure_points(t, x, param_.data(), point);
}

std::string Model::loop_reaction_name(int k) const {
  const int loop = constraint_loop(k);
  const std::string& name = description_.loop_names[static_cast<std::size_t>(loop)];
  if (constraint_axis(k) >= 0) return fmt::format("{}.F{}", name, "xyz"[constraint_axis(k)]);
  int j = 0;  // the equation's rank in its loop
  for (int e = 0; e < k; ++e) j += constraint_loop(e) == loop;
  return fmt::format("{}.lambda{}", name, j);
}

void Model::constraints(double t, const double* x, double* g, double* g_q, double* g_p,
                        double* g_t) const {
  if (description_.constraints == nullptr) missing("constraints");
  description_.constraints(t, x, param_.data(), g, g_q, g_p, g_t);
}

void Model::constraint_bias(double t, const double* x, const double* xd, double* gamma) const {
  if (description_.constraint_bias == nullptr) missing("constraint_bias");
  description_.constraint_bias(t, x, xd, param_.data(), gamma);
}

void Model::constraint_derivatives(double t, const double* x, const double* xd, const double* xdd,
                                   const double* mu, double* a_x, double* a_xd,
                                   double* hessian) const {
  if (description_.constraint_derivatives == nullptr) missing("constraint_derivatives");
  description_.constraint_derivatives(t, x, xd, xdd, param_.data(), mu, a_x, a_xd, hessian);
}

void Model::validate_diagnostics() const {
  const auto fail = [&](const std::string& what) {
    throw ModelError(fmt::format("model '{}': {}", description_.model, what));
  };
  if (!description_.dependent_names.empty() &&
      description_.dependent_names.size() != static_cast<std::size_t>(description_.ndep)) {
    fail(fmt::format("dependent_names has {} entries, expected {}",
                     description_.dependent_names.size(), description_.ndep));
  }
  if (!description_.domain_checks.empty() && description_.domain_arguments == nullptr)
    fail("domain checks without domain_arguments");
  for (const DomainCheck& c : description_.domain_checks) {
    if (c.dependent.empty()) fail("domain check of an unnamed dependent parameter");
    if (restricted_domain(c.function) == nullptr)
      fail(fmt::format("domain check of unknown function '{}'", c.function));
  }
  for (const AngleSequence& a : description_.angle_sequences) {
    const bool indices = a.body >= 0 && a.body < description_.nbody &&
                         std::all_of(a.coordinates.begin(), a.coordinates.end(),
                                     [&](int j) { return j >= 0 && j < description_.nq; });
    if (!indices || a.axes.size() != 3)
      fail(fmt::format("angle sequence '{}' of body {} is malformed", a.axes, a.body));
  }
}

std::optional<std::string> Model::domain_error(double t, const double* q) const {
  const std::size_t n = description_.domain_checks.size();
  if (n == 0) return std::nullopt;
  std::vector<double> args(kDomainValues * n);
  description_.domain_arguments(t, q, param_.data(), args.data());
  const auto describe = [&](std::size_t k, const char* what) {
    const DomainCheck& c = description_.domain_checks[k];
    return fmt::format("dependent parameter '{}': {} is {} [domain of {}: {}]", c.dependent,
                       call(c.function, args[kDomainValues * k], args[kDomainValues * k + 1]), what,
                       c.function, restricted_domain(c.function)->domain);
  };
  // Outside first, in evaluation order (an inner failure makes the outer arguments NaN: skipped).
  for (std::size_t k = 0; k < n; ++k) {
    const double x = args[kDomainValues * k], e = args[kDomainValues * k + 1];
    if (std::isfinite(x) && std::isfinite(e) &&
        !restricted_domain(description_.domain_checks[k].function)->inside(x, e)) {
      return describe(k, "outside its function's domain");
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (restricted_domain(description_.domain_checks[k].function)
            ->edge(args[kDomainValues * k], args[kDomainValues * k + 1])) {
      return describe(k, "at the edge of its function's domain, where its derivative is infinite");
    }
  }
  return std::nullopt;
}

Model::DomainMargin Model::smallest_domain_margin(double t, const double* q,
                                                  double* arguments) const {
  DomainMargin smallest;
  if (margin_distances_.empty()) return smallest;
  description_.domain_arguments(t, q, param_.data(), arguments);
  for (std::size_t k = 0; k < margin_distances_.size(); ++k) {
    const double* a = arguments + kDomainValues * k;  // x, e, scale
    // Negative outside; a NaN argument (an inner check failed) is skipped.
    const double margin = margin_distances_[k](a[0], a[1], a[2]);
    if (margin < smallest.margin) smallest = {margin, static_cast<int>(k)};
  }
  return smallest;
}

std::string Model::describe_domain_margin(double t, const double* q, const DomainMargin& m) const {
  std::vector<double> args(kDomainValues * description_.domain_checks.size());
  description_.domain_arguments(t, q, param_.data(), args.data());
  const DomainCheck& c = description_.domain_checks.at(static_cast<std::size_t>(m.check));
  const double* a = args.data() + kDomainValues * static_cast<std::size_t>(m.check);
  const RestrictedDomain& r = *restricted_domain(c.function);
  return fmt::format(
      "dependent parameter '{}': {} is {:.3g} from the edge of its function's domain{}, where its "
      "derivative is infinite and has lost more than half its digits within {:g} of it [domain "
      "of {}: {}]",
      c.dependent, call(c.function, a[0], a[1]), r.distance(a[0], a[1], a[2]),
      !r.edge_at_zero ? ""
                      : fmt::format(" relative to the {:.3g} of the terms it is a sum of", a[2]),
      kDomainMargin, c.function, r.domain);
}

int Model::domain_edge_crossed(const double* before, const double* after) const {
  for (std::size_t k = 0; k < description_.domain_checks.size(); ++k) {
    const double a = before[kDomainValues * k], b = after[kDomainValues * k];
    if (zero_edges_[k] && ((a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0)))
      return static_cast<int>(k);
  }
  return -1;
}

std::optional<std::string> Model::angle_sequence_near_singular(const double* q,
                                                               double within) const {
  const double pi = std::numbers::pi;
  for (const AngleSequence& a : description_.angle_sequences) {
    const int j = a.coordinates[1];
    // Singular at b = offset + k·pi: pi/2 + k·pi (Tait-Bryan), k·pi (proper Euler).
    const double offset = a.axes.front() == a.axes.back() ? 0.0 : pi / 2;
    const double distance = std::abs(std::remainder(q[j] - offset, pi));
    if (!(distance < within)) continue;
    const double singular = offset + pi * std::nearbyint((q[j] - offset) / pi);
    std::string axes;
    for (char c : a.axes)
      axes += fmt::format("{}{}", axes.empty() ? "" : "-", static_cast<char>(std::toupper(c)));
    const auto& names = description_.q_names;
    return fmt::format(
        "coordinates '{}', '{}', '{}' of body '{}' form a {} angle sequence {:.3g} rad from its "
        "singular configuration {} = {} deg ({} = {} rad)",
        names[a.coordinates[0]], names[j], names[a.coordinates[2]], description_.body_names[a.body],
        axes, distance, names[j], std::round(singular * 180.0 / pi), names[j], q[j]);
  }
  return std::nullopt;
}

std::optional<std::string> Model::singular_angle_sequence(const double* q, const Matrix& M) const {
  if (description_.angle_sequences.empty() || M.rows() != description_.nq || M.rows() == 0 ||
      !M.allFinite())
    return std::nullopt;
  const Eigen::JacobiSVD<Matrix> svd(M, Eigen::ComputeFullV);
  const Vector u =
      svd.matrixV().col(M.cols() - 1);  // the null direction (singular values decrease)
  const AngleSequence* best = nullptr;
  double best_share = 0.5;  // at least half of the null direction
  for (const AngleSequence& a : description_.angle_sequences) {
    const double b = q[a.coordinates[1]];
    const bool proper = a.axes.front() == a.axes.back();
    // The first and third axes align where cos b = 0 (Tait-Bryan) or sin b = 0 (proper Euler).
    if (!((proper ? std::abs(std::sin(b)) : std::abs(std::cos(b))) < 1e-4)) continue;
    double share = 0.0;
    for (int j : a.coordinates) share += u(j) * u(j);
    if (share >= best_share) {
      best = &a;
      best_share = share;
    }
  }
  if (best == nullptr) return std::nullopt;
  const int j = best->coordinates[1];
  const double pi = std::numbers::pi, b = q[j];
  const double offset = best->axes.front() == best->axes.back() ? 0.0 : pi / 2;
  const double singular = offset + pi * std::nearbyint((b - offset) / pi);
  std::string axes;
  for (char c : best->axes)
    axes += fmt::format("{}{}", axes.empty() ? "" : "-", static_cast<char>(std::toupper(c)));
  const auto& names = description_.q_names;
  return fmt::format(
      "coordinates '{}', '{}', '{}' of body '{}' form a {} angle sequence singular at {} = {} deg "
      "({} = {} rad = {:.9g} deg): its first and third axes are aligned",
      names[best->coordinates[0]], names[j], names[best->coordinates[2]],
      description_.body_names[best->body], axes, names[j], std::round(singular * 180.0 / pi),
      names[j], b, b * 180.0 / pi);
}

void Model::evaluate_inertia(const std::vector<double>& param, std::vector<double>& mass,
                             std::vector<Mat3>& inertia) const {
  const int nb = std::max(description_.nbody, 1);
  std::vector<double> m(nb, 0.0), I(9 * nb, 0.0);
  description_.inertia(param.data(), m.data(), I.data());
  mass.assign(m.begin(), m.begin() + description_.nbody);
  inertia.resize(description_.nbody);
  for (int i = 0; i < description_.nbody; ++i) {
    inertia[i] = Eigen::Map<const RowMat3>(&I[9 * i]);
    validate_inertia(description_.body_names[i], mass[i], inertia[i]);
  }
}

void Model::missing(const char* entry) const {
  throw ModelError(fmt::format("model '{}' (variant '{}'): entry point '{}' was not emitted",
                               description_.model, description_.variant, entry));
}

int Model::body_index(std::string_view name) const {
  return find_name(description_.body_names, name, "body", "bodies", description_.model);
}
int Model::coordinate_index(std::string_view name) const {
  return find_name(description_.q_names, name, "coordinate", "coordinates", description_.model);
}
int Model::parameter_index(std::string_view name) const {
  return find_name(description_.param_names, name, "parameter", "parameters", description_.model);
}

State Model::initial_state() const {
  State s;
  s.t = 0.0;
  s.q = Eigen::Map<const Vector>(description_.q_initial.data(), description_.nq);
  s.qd = Eigen::Map<const Vector>(description_.qd_initial.data(), description_.nq);
  s.y.resize(0);
  return s;
}

void Model::set_parameter(std::string_view name, double value) {
  std::vector<double> p = param_;
  p[parameter_index(name)] = value;
  set_parameters(std::vector<double>(p.begin(), p.begin() + description_.nparam));
}

void Model::set_parameters(const std::vector<double>& values) {
  if (values.size() != static_cast<std::size_t>(description_.nparam)) {
    throw ModelError(fmt::format("model '{}': {} parameter values given, expected {}",
                                 description_.model, values.size(), description_.nparam));
  }
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) {
      throw ModelError(fmt::format("model '{}': parameter '{}' must be finite, not {}",
                                   description_.model, description_.param_names[k], values[k]));
    }
  }
  std::vector<double> p = values;
  if (p.empty()) p.push_back(0.0);
  std::vector<double> mass;
  std::vector<Mat3> inertia;
  evaluate_inertia(p, mass, inertia);  // throws before anything changes
  param_ = std::move(p);
  mass_ = std::move(mass);
  inertia_ = std::move(inertia);
}

Model::JointPoints Model::joint_points() const {
  JointPoints out;
  if (!has_joint_points()) return out;
  const int nb = std::max(description_.nbody, 1);
  std::vector<double> joint(3 * nb, 0.0), anchor(3 * nb, 0.0);
  description_.joint_points(param_.data(), joint.data(), anchor.data());
  for (int i = 0; i < description_.nbody; ++i) {
    out.joint.emplace_back(joint[3 * i], joint[3 * i + 1], joint[3 * i + 2]);
    out.anchor.emplace_back(anchor[3 * i], anchor[3 * i + 1], anchor[3 * i + 2]);
  }
  return out;
}

Mat3 Model::global_inertia(int i, const Kinematics& k) const {
  const Mat3 R = k.R(i);
  return R * inertia_[i] * R.transpose();
}

void Model::positions(double t, const double* q, Kinematics& k) const {
  if (description_.positions != nullptr) {
    description_.positions(t, q, param_.data(), k.R_data(), k.x_data());
    k.clear_rates();
    return;
  }
  // Positions are a by-product of the velocities at qd = 0.
  if (description_.velocities == nullptr) missing("positions");
  velocities(t, q, zeros_.data(), k);
}

void Model::velocities(double t, const double* q, const double* qd, Kinematics& k) const {
  if (description_.velocities == nullptr) missing("velocities");
  description_.velocities(t, q, qd, param_.data(), k.R_data(), k.x_data(), k.v_data(), k.w_data());
}

void Model::accelerations(double t, const double* q, const double* qd, const double* qdd,
                          Kinematics& k) const {
  if (description_.accelerations == nullptr) missing("accelerations");
  description_.accelerations(t, q, qd, qdd, param_.data(), k.R_data(), k.x_data(), k.v_data(),
                             k.w_data(), k.a_data(), k.dw_data());
}

void Model::relative_accelerations(double t, const double* q, const double* qd, const double* qdd,
                                   RelativeMotion& rel) const {
  if (description_.relative_accelerations == nullptr) missing("relative_accelerations");
  Kinematics& r = rel.relative();
  description_.relative_accelerations(t, q, qd, qdd, param_.data(), r.R_data(), r.x_data(),
                                      r.v_data(), r.w_data(), r.a_data(), r.dw_data());
}

void Model::relative_partial_velocities(double t, const double* q, RelativeMotion& rel) const {
  if (description_.relative_partial_velocities == nullptr) missing("relative_partial_velocities");
  description_.relative_partial_velocities(t, q, param_.data(), rel.relative().dv_dqd_data(),
                                           rel.relative().dw_dqd_data());
}

void Model::partial_velocities(double t, const double* q, Kinematics& k) const {
  if (description_.partial_velocities == nullptr) missing("partial_velocities");
  description_.partial_velocities(t, q, param_.data(), k.dv_dqd_data(), k.dw_dqd_data());
}

void Model::dependent_parameters(double t, const double* q, const double* qd, const double* qdd,
                                 Kinematics& k) const {
  if (description_.dependent_parameters == nullptr) missing("dependent_parameters");
  description_.dependent_parameters(t, q, qd, qdd, param_.data(), k.p_data(), k.pd_data(),
                                    k.pdd_data());
}

void Model::mass_matrix(double t, const double* q, double* M) const {
  if (description_.mass_matrix == nullptr) missing("mass_matrix");
  description_.mass_matrix(t, q, param_.data(), M);
}

void Model::bias_forces(double t, const double* q, const double* qd, double* h) const {
  if (description_.bias_forces == nullptr) missing("bias_forces");
  description_.bias_forces(t, q, qd, param_.data(), h);
}

void Model::dynamics(double t, const double* q, const double* qd, KinematicsLevel level, double* M,
                     double* h, Kinematics& k) const {
  const double* p = param_.data();
  using enum KinematicsLevel;
  if (level == none && description_.dynamics != nullptr)
    return description_.dynamics(t, q, qd, p, M, h);
  if (level == positions && description_.dynamics_positions != nullptr) {
    return description_.dynamics_positions(t, q, qd, p, M, h, k.R_data(), k.x_data(),
                                           k.dv_dqd_data(), k.dw_dqd_data());
  }
  if (level == velocities && description_.dynamics_velocities != nullptr) {
    return description_.dynamics_velocities(t, q, qd, p, M, h, k.R_data(), k.x_data(), k.v_data(),
                                            k.w_data(), k.dv_dqd_data(), k.dw_dqd_data());
  }
  dynamics_separately(t, q, qd, level, M, h, k);
}

void Model::inverse_dynamics(double t, const double* q, const double* qd, const double* qdd,
                             double* tau) const {
  if (description_.inverse_dynamics == nullptr) missing("inverse_dynamics");
  description_.inverse_dynamics(t, q, qd, qdd, param_.data(), tau);
}

void Model::joint_reactions(double t, const double* q, const double* qd, const double* qdd,
                            const double* F, const double* M, double* reaction) const {
  if (description_.joint_reactions == nullptr) missing("joint_reactions");
  description_.joint_reactions(t, q, qd, qdd, param_.data(), F, M, reaction);
}

namespace {

// A square matrix transposed in place by swaps: Eigen's blocked in-place
// transpose costs several times more on the sizes of models (2 to 64).
void transpose_square(Matrix& a) {
  const Eigen::Index n = a.rows();
  double* x = a.data();
  for (Eigen::Index j = 1; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) std::swap(x[i + j * n], x[j + i * n]);
  }
}

}  // namespace

void Model::inverse_dynamics_derivatives(double t, const double* q, const double* qd,
                                         const double* qdd, Matrix& dtau_dq,
                                         Matrix& dtau_dqd) const {
  // Emitted row-major into column-major storage: each is its transpose until turned.
  emit_inverse_dynamics_derivatives(t, q, qd, qdd, dtau_dq, dtau_dqd, nullptr);
  transpose_square(dtau_dq);
  transpose_square(dtau_dqd);
}

void Model::inverse_dynamics_derivatives(double t, const double* q, const double* qd,
                                         const double* qdd, RowMajorMatrix& dtau_dq,
                                         RowMajorMatrix& dtau_dqd) const {
  emit_inverse_dynamics_derivatives(t, q, qd, qdd, dtau_dq, dtau_dqd, nullptr);
}

void Model::inverse_dynamics_jacobians(double t, const double* q, const double* qd,
                                       const double* qdd, Matrix& dtau_dq, Matrix& dtau_dqd,
                                       Matrix& M) const {
  // dtau_dq and dtau_dqd turned as above, M symmetric as it is.
  emit_inverse_dynamics_derivatives(t, q, qd, qdd, dtau_dq, dtau_dqd, &M);
  transpose_square(dtau_dq);
  transpose_square(dtau_dqd);
}

void Model::inverse_dynamics_jacobians(double t, const double* q, const double* qd,
                                       const double* qdd, RowMajorMatrix& dtau_dq,
                                       RowMajorMatrix& dtau_dqd, Matrix& M) const {
  emit_inverse_dynamics_derivatives(t, q, qd, qdd, dtau_dq, dtau_dqd, &M);
}

template <class Storage>
void Model::emit_inverse_dynamics_derivatives(double t, const double* q, const double* qd,
                                              const double* qdd, Storage& dtau_dq,
                                              Storage& dtau_dqd, Matrix* M) const {
  const int n = description_.nq;
  dtau_dq.resize(n, n);
  dtau_dqd.resize(n, n);
  if (M == nullptr) {
    if (description_.inverse_dynamics_derivatives == nullptr)
      missing("inverse_dynamics_derivatives");
    description_.inverse_dynamics_derivatives(t, q, qd, qdd, param_.data(), dtau_dq.data(),
                                              dtau_dqd.data());
    return;
  }
  if (description_.inverse_dynamics_jacobians == nullptr) missing("inverse_dynamics_jacobians");
  M->resize(n, n);
  description_.inverse_dynamics_jacobians(t, q, qd, qdd, param_.data(), dtau_dq.data(),
                                          dtau_dqd.data(), M->data());
}

void Model::kinematics_derivatives(double t, const double* q, const double* qd,
                                   KinematicsDerivatives& dk) const {
  if (description_.kinematics_derivatives == nullptr) missing("kinematics_derivatives");
  description_.kinematics_derivatives(t, q, qd, param_.data(), dk.dv_dq_data(), dk.dw_dq_data(),
                                      dk.ddv_dq_data(), dk.ddw_dq_data());
}

int Model::forward_dynamics(double t, const double* q, const double* qd, const double* tau,
                            double* qdd) const {
  if (description_.forward_dynamics == nullptr) missing("forward_dynamics");
  return description_.forward_dynamics(t, q, qd, tau, param_.data(), qdd);
}

void Model::dynamics_separately(double t, const double* q, const double* qd, KinematicsLevel level,
                                double* M, double* h, Kinematics& k) const {
  if (level == KinematicsLevel::positions) positions(t, q, k);
  if (level == KinematicsLevel::velocities) velocities(t, q, qd, k);
  if (level != KinematicsLevel::none) partial_velocities(t, q, k);
  mass_matrix(t, q, M);
  bias_forces(t, q, qd, h);
}

}  // namespace symdyn::runtime
