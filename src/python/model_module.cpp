// The bindings behind every model's Python module (model_module.hpp,
// docs/python.md). Python sees:
//   constants        model, variant, nq, nbody, ndep, nparam, q_names, body_names,
//                    param_names, param_defaults, q_initial, qd_initial, gravity
//   System           the model with its run-time parameters and force elements
//                    (runtime::MultibodySystem): kinematics, equations of motion,
//                    simulate, solve_statics, linearize, modes
//   force elements   CoordinateSpringDamper(...), ...: descriptions that name
//                    bodies and coordinates, resolved against the model when
//                    added to a system or passed to one call (forces=[...])
//   exceptions       Error; ModelError and OptionError (also ValueError);
//                    NumericError (also RuntimeError): the runtime's messages
// Arrays: NumPy in (any sequence of numbers is accepted) and out, copied.
// The GIL is held throughout: a Python callable used as a force runs inside
// the integrator like any other code, and its exceptions propagate unchanged.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <symdyn/python/model_module.hpp>
#include <symdyn/runtime/integrator.hpp>
#include <symdyn/runtime/runtime.hpp>

namespace py = pybind11;

namespace symdyn::python {
namespace {

using runtime::Kinematics;
using runtime::Matrix;
using runtime::Model;
using runtime::MultibodySystem;
using runtime::State;
using runtime::Vec3;
using runtime::Vector;

// ---------------------------------------------------------------- exceptions

// The exception classes of this module (each model's module is its own shared
// object, so these are per module).
PyObject* error_type = nullptr;
PyObject* model_error_type = nullptr;
PyObject* option_error_type = nullptr;
PyObject* numeric_error_type = nullptr;

PyObject* add_exception(py::module_& module, const char* name, const py::object& bases,
                        const char* doc) {
  const std::string qualified = fmt::format("{}.{}", PyModule_GetName(module.ptr()), name);
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  module.add_object(name, py::handle(type));
  return type;
}

// Most derived first: an unhandled type falls through to pybind11's own.
void translate_runtime_error(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const runtime::ModelError& e) {
    PyErr_SetString(model_error_type, e.what());
  } catch (const runtime::OptionError& e) {
    PyErr_SetString(option_error_type, e.what());
  } catch (const runtime::NumericError& e) {
    PyErr_SetString(numeric_error_type, e.what());
  } catch (const runtime::RuntimeError& e) {
    PyErr_SetString(error_type, e.what());
  }
}

void define_exceptions(py::module_& module) {
  error_type = add_exception(module, "Error", py::reinterpret_borrow<py::object>(PyExc_Exception),
                             "Base of every error of the symdyn runtime.");
  const auto both = [](PyObject* python_base) {
    return py::make_tuple(py::handle(error_type), py::handle(python_base));
  };
  model_error_type = add_exception(module, "ModelError", both(PyExc_ValueError),
                                   "A model that cannot be simulated as given: an unknown name, "
                                   "a bad size, an inertia that is not physical.");
  option_error_type = add_exception(module, "OptionError", both(PyExc_ValueError),
                                    "A setting the caller got wrong: an unknown integrator, a "
                                    "tolerance <= 0, a fixed-step run without a step.");
  numeric_error_type = add_exception(module, "NumericError", both(PyExc_RuntimeError),
                                     "A computation that went numerically wrong: a value not "
                                     "finite, a singular matrix, no convergence.");
  py::register_local_exception_translator(&translate_runtime_error);
}

// ------------------------------------------------------------------ arguments

using InArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// n numbers from any sequence or array; ValueError naming `what` otherwise.
Vector vector_arg(const py::handle& value, Eigen::Index n, std::string_view what) {
  const auto a = py::cast<InArray>(value);
  if (a.ndim() != 1 || a.size() != n) {
    throw py::value_error(fmt::format("{}: {} numbers expected, got an array of shape ({})", what,
                                      n, fmt::join(a.shape(), a.shape() + a.ndim(), ", ")));
  }
  return Eigen::Map<const Vector>(a.data(), n);
}

Vec3 vec3_arg(const py::handle& value, std::string_view what) {
  return vector_arg(value, 3, what);
}

// A 3 x 3 matrix from a nested sequence or array.
runtime::Mat3 mat3_arg(const py::handle& value, std::string_view what) {
  const auto a = py::cast<InArray>(value);
  if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) {
    throw py::value_error(fmt::format("{}: a 3 x 3 matrix expected", what));
  }
  return Eigen::Map<const runtime::RowMat3>(a.data());
}

// A coordinate by name (ModelError listing the names) or index.
int coordinate_arg(const Model& model, const py::handle& c) {
  if (py::isinstance<py::str>(c)) return model.coordinate_index(c.cast<std::string>());
  const int j = c.cast<int>();
  if (j < 0 || j >= model.nq()) {
    throw py::index_error(fmt::format("coordinate index {} outside [0, {})", j, model.nq()));
  }
  return j;
}

// A body by name or index; None or "ground" (unless a body has that name) is the ground.
int body_arg(const Model& model, const py::handle& b) {
  if (b.is_none()) return runtime::ground;
  if (py::isinstance<py::str>(b)) {
    const auto name = b.cast<std::string>();
    const auto& names = model.body_names();
    if (name == "ground" && std::find(names.begin(), names.end(), name) == names.end()) {
      return runtime::ground;
    }
    return model.body_index(name);
  }
  const int i = b.cast<int>();
  if (i < 0 || i >= model.nbody()) {
    throw py::index_error(fmt::format("body index {} outside [0, {})", i, model.nbody()));
  }
  return i;
}

std::vector<int> coordinates_arg(const Model& model, const py::iterable& list) {
  std::vector<int> out;
  for (const auto& c : list) out.push_back(coordinate_arg(model, c));
  return out;
}

// The element's name in messages: the one given, else what it acts on.
std::string name_or(const py::object& name, const py::handle& fallback) {
  if (!name.is_none()) return name.cast<std::string>();
  return fallback.is_none() ? std::string("ground") : py::str(fallback).cast<std::string>();
}

// Every value finite: ValueError naming the coordinate (positions() and the
// other kinematics would return NaN silently).
void check_finite(const Vector& v, const Model& m, std::string_view what) {
  for (Eigen::Index j = 0; j < v.size(); ++j) {
    if (std::isfinite(v(j))) continue;
    throw py::value_error(fmt::format("{}: coordinate '{}' is {}, not a finite number", what,
                                      m.q_names()[static_cast<std::size_t>(j)], v(j)));
  }
}

// The state (t, q, qd) of a call: the model's initial values where None.
State state_arg(const MultibodySystem& system, double t, const py::object& q,
                const py::object& qd) {
  State s = system.initial_state();
  if (!std::isfinite(t)) throw py::value_error(fmt::format("t = {} is not a finite time", t));
  s.t = t;
  if (!q.is_none()) s.q = vector_arg(q, system.num_coordinates(), "q");
  if (!qd.is_none()) s.qd = vector_arg(qd, system.num_coordinates(), "qd");
  check_finite(s.q, system.model(), "q");
  check_finite(s.qd, system.model(), "qd");
  return s;
}

// ------------------------------------------------------------------- outputs

py::object namespace_of(const py::dict& fields) {
  return py::module_::import("types").attr("SimpleNamespace")(**fields);
}

// Values as an array (n), and rows of `columns` values each as an array (rows x columns).
py::array_t<double> column(const std::vector<double>& values) {
  return py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data());
}

py::array_t<double> rows_array(const std::vector<double>& values, Eigen::Index columns) {
  const auto rows =
      columns == 0 ? py::ssize_t{0} : static_cast<py::ssize_t>(values.size()) / columns;
  py::array_t<double> a({rows, static_cast<py::ssize_t>(columns)});
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(double));
  return a;
}

// A per-body array of the kinematics buffer: (nbody x 3) or (nbody x 3 x 3).
py::array_t<double> body_array(const double* data, int nbody, bool matrix) {
  std::vector<py::ssize_t> shape{nbody, 3};
  if (matrix) shape.push_back(3);
  py::array_t<double> a(shape);
  std::memcpy(a.mutable_data(), data, static_cast<std::size_t>(a.size()) * sizeof(double));
  return a;
}

py::dict energies_dict(const runtime::Energies& e) {
  py::dict d;
  d["kinetic"] = e.kinetic;
  d["gravitational"] = e.gravitational;
  d["elastic"] = e.elastic;
  d["total"] = e.total();
  return d;
}

// ------------------------------------------------------------ force elements

using ElementPtr = std::shared_ptr<const runtime::ForceElement>;

// A force element described by names, made for a given model.
struct Force {
  std::string description;
  std::function<ElementPtr(const Model&)> make;
};

// Removes and returns a keyword argument, or `fallback`.
py::object take(py::kwargs& kwargs, const char* key, py::object fallback) {
  if (!kwargs.contains(key)) return fallback;
  py::object value = kwargs[key];
  PyDict_DelItemString(kwargs.ptr(), key);
  return value;
}

// The constants of an element of `type` (runtime::element_parameters): the
// positional values in the table's order, then the keywords; TypeError for an
// unknown keyword (naming the close ones), a value given twice or a required
// one missing. Their ranges are checked when the element is made.
runtime::ParameterValues parameters_from(std::string_view type, std::string_view function,
                                         const py::args& args, const py::kwargs& kwargs) {
  runtime::ParameterValues values(type);
  const auto parameters = values.row().parameters;
  std::vector<std::string_view> names;
  for (const auto& p : parameters) names.push_back(p.name);
  const auto set = [&](const runtime::Parameter& p, const py::handle& value) {
    if (values.given(p.name))
      throw py::type_error(fmt::format("{}: '{}' given twice", function, p.name));
    if (p.shape == runtime::ParameterShape::number) {
      values.set(p.name, py::cast<double>(value));
    } else {
      values.set(p.name, vec3_arg(value, fmt::format("{} {}", function, p.name)));
    }
  };
  if (args.size() > parameters.size()) {
    throw py::type_error(fmt::format("{}: {} constants given by position, at most {} ({})",
                                     function, args.size(), parameters.size(),
                                     fmt::join(names, ", ")));
  }
  for (std::size_t i = 0; i < args.size(); ++i) set(parameters[i], args[i]);
  for (const auto& [key, value] : kwargs) {
    const auto name = py::cast<std::string>(key);
    const runtime::Parameter* p = values.row().find(name);
    if (p == nullptr) {
      const auto close = runtime::close_names(name, names);
      throw py::type_error(fmt::format(
          "{}: unknown property '{}' (properties: {}){}", function, name, fmt::join(names, ", "),
          close.empty() ? "" : fmt::format("; did you mean {}?", fmt::join(close, " or "))));
    }
    set(*p, value);
  }
  if (const runtime::Parameter* p = values.missing()) {
    throw py::type_error(
        fmt::format("{}: missing property '{}' ({})", function, p->name, runtime::description(*p)));
  }
  return values;
}

// `lead`, then the element's constants as the table describes them.
const char* element_doc(std::string_view type, std::string_view lead) {
  static std::deque<std::string> docs;  // pybind keeps the pointer
  std::string doc = fmt::format("{}\n\nConstants:", lead);
  for (const auto& p : runtime::element_parameters(type).parameters) {
    const std::string fallback = p.required ? "required"
                                 : p.shape == runtime::ParameterShape::number
                                     ? fmt::format("default {:g}", p.fallback[0])
                                     : fmt::format("default [{:g}, {:g}, {:g}]", p.fallback[0],
                                                   p.fallback[1], p.fallback[2]);
    doc += fmt::format("\n  {} ({}{}{}; {}): {}", p.name, runtime::requirement(p),
                       p.unit.empty() ? "" : ", ", p.unit, fallback, p.meaning);
  }
  return docs.emplace_back(std::move(doc)).c_str();
}

runtime::Plane plane_from(py::kwargs& kwargs, std::string_view element) {
  runtime::Plane plane;
  plane.point = vec3_arg(take(kwargs, "plane_point", py::cast(std::vector<double>{0, 0, 0})),
                         fmt::format("{} plane_point", element));
  plane.normal = vec3_arg(take(kwargs, "plane_normal", py::cast(std::vector<double>{0, 0, 1})),
                          fmt::format("{} plane_normal", element));
  return plane;
}

std::string name_from(py::kwargs& kwargs, const py::handle& fallback) {
  return name_or(take(kwargs, "name", py::none()), fallback);
}

Force coordinate_spring_damper(const py::object& coordinate, const py::args& args,
                               py::kwargs kwargs) {
  const std::string n = name_from(kwargs, coordinate);
  const auto v =
      parameters_from("coordinate_spring_damper", "CoordinateSpringDamper", args, kwargs);
  return {fmt::format("CoordinateSpringDamper('{}')", n), [=](const Model& m) -> ElementPtr {
            return runtime::make_coordinate_spring_damper(n, coordinate_arg(m, coordinate), v);
          }};
}

Force coordinate_tracking(const py::object& coordinate, const py::args& args, py::kwargs kwargs) {
  const std::string n = name_from(kwargs, coordinate);
  const double reference = take(kwargs, "reference", py::float_(0.0)).cast<double>();
  const double rate = take(kwargs, "rate", py::float_(0.0)).cast<double>();
  const auto v = parameters_from("coordinate_tracking", "CoordinateTracking", args, kwargs);
  // The runtime's element takes functions of time: the constants are checked here.
  runtime::check_property(fmt::format("coordinate tracking '{}'", n), "reference", reference);
  runtime::check_property(fmt::format("coordinate tracking '{}'", n), "rate", rate);
  return {fmt::format("CoordinateTracking('{}')", n), [=](const Model& m) -> ElementPtr {
            return runtime::make_coordinate_tracking(
                n, coordinate_arg(m, coordinate), [reference](double) { return reference; },
                [rate](double) { return rate; }, v);
          }};
}

// derivatives(t, q, qd), when given, returns (dQ/dq, dQ/dqd) of the law at the same
// arguments: the coordinate's entries of its row of the Jacobians.
Force coordinate_force(const py::object& coordinate, const py::function& law,
                       const py::object& name, const py::object& derivatives) {
  const std::string n = name_or(name, coordinate);
  if (!derivatives.is_none() && !PyCallable_Check(derivatives.ptr())) {
    throw py::type_error(fmt::format("CoordinateForce '{}': derivatives is not callable", n));
  }
  return {fmt::format("CoordinateForce('{}')", n), [=](const Model& m) -> ElementPtr {
            const int j = coordinate_arg(m, coordinate);
            runtime::CoordinateForce::LawDerivatives d;
            if (!derivatives.is_none()) {
              d = [derivatives, j, n](double t, double q, double qd, const State&, Vector& dQ_dq,
                                      Vector& dQ_dqd) {
                const py::object pair = derivatives(t, q, qd);
                if (!py::isinstance<py::sequence>(pair) || py::len(pair) != 2) {
                  throw py::type_error(fmt::format(
                      "CoordinateForce '{}': derivatives must return (dQ/dq, dQ/dqd)", n));
                }
                dQ_dq(j) = pair[py::int_(0)].cast<double>();
                dQ_dqd(j) = pair[py::int_(1)].cast<double>();
              };
            }
            return std::make_shared<runtime::CoordinateForce>(
                n, j,
                [law](double t, double q, double qd, const State&) {
                  return law(t, q, qd).cast<double>();
                },
                std::move(d));
          }};
}

Force point_spring_damper(const py::object& body_a, const py::object& point_a,
                          const py::object& body_b, const py::object& point_b, const py::args& args,
                          py::kwargs kwargs) {
  const std::string n = name_from(kwargs, body_b);
  const Vec3 pa = vec3_arg(point_a, "point_a"), pb = vec3_arg(point_b, "point_b");
  const auto v = parameters_from("point_spring_damper", "PointSpringDamper", args, kwargs);
  return {fmt::format("PointSpringDamper('{}')", n), [=](const Model& m) -> ElementPtr {
            return runtime::make_point_spring_damper(n, runtime::BodyPoint{body_arg(m, body_a), pa},
                                                     runtime::BodyPoint{body_arg(m, body_b), pb},
                                                     v);
          }};
}

Force point_load(const py::object& body, const py::object& point, const py::object& force,
                 const py::object& torque, const py::object& name) {
  const std::string n = name_or(name, body);
  const Vec3 p = vec3_arg(point, "point"), f = vec3_arg(force, "force"),
             tq = vec3_arg(torque, "torque");
  return {fmt::format("PointLoad('{}')", n), [=](const Model& m) -> ElementPtr {
            return std::make_shared<runtime::PointLoad>(n, runtime::BodyPoint{body_arg(m, body), p},
                                                        f, tq);
          }};
}

Force plane_contact(const py::object& body, const py::args& args, py::kwargs kwargs) {
  const std::string n = name_from(kwargs, body);
  const runtime::Plane plane = plane_from(kwargs, "PlaneContact");
  const std::string reg = take(kwargs, "regularization", py::str("linear")).cast<std::string>();
  if (reg != "linear" && reg != "smooth") {
    throw py::value_error(fmt::format(
        "PlaneContact '{}': regularization '{}' is neither 'linear' nor 'smooth'", n, reg));
  }
  const auto regularization = reg == "smooth" ? runtime::FrictionRegularization::smooth
                                              : runtime::FrictionRegularization::linear;
  const auto v = parameters_from("plane_contact", "PlaneContact", args, kwargs);
  return {fmt::format("PlaneContact('{}')", n), [=](const Model& m) -> ElementPtr {
            return runtime::make_plane_contact(n, body_arg(m, body), plane, regularization, v);
          }};
}

Force simple_tyre(const py::object& body, py::kwargs kwargs) {
  const std::string n = name_from(kwargs, body);
  const runtime::Plane plane = plane_from(kwargs, "SimpleTyre");
  const auto v = parameters_from("simple_tyre", "SimpleTyre", py::args(), kwargs);
  return {fmt::format("SimpleTyre('{}')", n), [=](const Model& m) -> ElementPtr {
            return runtime::make_simple_tyre(n, body_arg(m, body), plane, v);
          }};
}

Force gim_tyre(const py::object& body, py::kwargs kwargs) {
  const std::string n = name_from(kwargs, body);
  const runtime::Plane plane = plane_from(kwargs, "GimTyre");
  const auto v = parameters_from("gim_tyre", "GimTyre", py::args(), kwargs);
  return {fmt::format("GimTyre('{}')", n), [=](const Model& m) -> ElementPtr {
            return runtime::make_gim_tyre(n, body_arg(m, body), plane, v);
          }};
}

Force bushing(const py::object& body_a, const py::object& body_b, const py::object& origin_a,
              const py::object& origin_b, const py::object& axes_a, const py::object& axes_b,
              const std::string& order, const py::object& name, py::kwargs kwargs) {
  const std::string n = name_or(name, body_b);
  const Vec3 oa = vec3_arg(origin_a, "origin_a"), ob = vec3_arg(origin_b, "origin_b");
  const runtime::Mat3 ra =
      axes_a.is_none() ? runtime::Mat3::Identity() : mat3_arg(axes_a, "axes_a");
  const runtime::Mat3 rb =
      axes_b.is_none() ? runtime::Mat3::Identity() : mat3_arg(axes_b, "axes_b");
  const auto v = parameters_from("bushing", "Bushing", py::args(), kwargs);
  return {fmt::format("Bushing('{}')", n), [=](const Model& m) -> ElementPtr {
            return runtime::make_bushing(n, runtime::BodyFrame{body_arg(m, body_a), oa, ra},
                                         runtime::BodyFrame{body_arg(m, body_b), ob, rb}, order, v);
          }};
}

void define_forces(py::module_& module) {
  using namespace py::literals;
  py::class_<Force>(module, "Force",
                    "A force element described by names; add it to a System (System.add, "
                    "System(forces=...)) or pass it to one call (forces=[...]).")
      .def("__repr__", [](const Force& f) { return f.description; });
  const py::object none = py::none();
  const auto origin = py::cast(std::vector<double>{0, 0, 0});
  module.def("CoordinateSpringDamper", &coordinate_spring_damper, "coordinate"_a,
             element_doc("coordinate_spring_damper",
                         "Q = -stiffness (q - free_value) - damping qd on a coordinate (name or "
                         "index); name=None."));
  module.def("CoordinateTracking", &coordinate_tracking, "coordinate"_a,
             element_doc("coordinate_tracking",
                         "PD tracking of a constant reference: Q = -kp (q - reference) - kd (qd - "
                         "rate); reference=0, rate=0, name=None."));
  module.def("CoordinateForce", &coordinate_force, "coordinate"_a, "law"_a, "name"_a = none,
             "derivatives"_a = none,
             "Q = law(t, q, qd) on a coordinate, law a Python callable returning a float "
             "(called with the GIL held; its exceptions stop the call that evaluates it); "
             "derivatives(t, q, qd), when given, returns (dQ/dq, dQ/dqd) for exact Jacobians "
             "(else they difference the law).");
  module.def("PointSpringDamper", &point_spring_damper, "body_a"_a, "point_a"_a, "body_b"_a,
             "point_b"_a,
             element_doc("point_spring_damper",
                         "Spring and damper between two body points (body axes from G; None or "
                         "'ground' for a fixed global point): T = stiffness (L - free_length) + "
                         "damping dL/dt; name=None."));
  module.def("PointLoad", &point_load, "body"_a, "point"_a = origin, "force"_a = origin,
             "torque"_a = origin, "name"_a = none,
             "A constant force and torque (global axes) at a body point (body axes from G).");
  module.def("PlaneContact", &plane_contact, "body"_a,
             element_doc("plane_contact",
                         "Penalty contact of a sphere (radius, centre at a body point) with the "
                         "plane plane_point, plane_normal (default z = 0, normal +z); "
                         "regularization 'linear' or 'smooth'; name=None."));
  module.def("SimpleTyre", &simple_tyre, "body"_a,
             element_doc("simple_tyre",
                         "The simple rigid-ring tyre on the plane plane_point, plane_normal; "
                         "name=None."));
  module.def("GimTyre", &gim_tyre, "body"_a,
             element_doc("gim_tyre",
                         "Gim's brush tyre on the plane plane_point, plane_normal; name=None."));
  module.def("Bushing", &bushing, "body_a"_a, "body_b"_a, "origin_a"_a = origin,
             "origin_b"_a = origin, "axes_a"_a = none, "axes_b"_a = none, "order"_a = "xyz",
             "name"_a = none,
             element_doc("bushing",
                         "Six-component linear bushing between two body frames (origin from G and "
                         "axes in body axes; None or 'ground' for the ground); constants by "
                         "keyword."));
}

// -------------------------------------------------------------------- system

// A model with its run-time parameters and force elements.
class System {
 public:
  System(ModelFactory make_model, const std::vector<Force>& forces)
      : system_(std::make_unique<MultibodySystem>(make_model())) {
    for (const auto& f : forces) add(f);
  }

  MultibodySystem& base() { return *system_; }
  const Model& model() const { return system_->model(); }
  void add(const Force& f) { system_->add(f.make(system_->model())); }

  // The system one call works on: this one, or with `extra` forces a copy
  // (same parameters and elements) that has them too.
  MultibodySystem& with(const std::vector<Force>& extra) {
    if (extra.empty()) return *system_;
    call_ = std::make_unique<MultibodySystem>(system_->model(), system_->source());
    for (const auto& e : system_->force_elements()) call_->add(e);
    for (const auto& f : extra) call_->add(f.make(call_->model()));
    return *call_;
  }

  py::dict parameters() const {
    py::dict d;
    for (int k = 0; k < model().nparam(); ++k)
      d[py::str(model().param_names()[k])] = model().parameters()[k];
    return d;
  }
  double parameter(const std::string& name) const {
    return model().parameters()[model().parameter_index(name)];
  }

  std::vector<std::string> force_names() const {
    std::vector<std::string> out;
    for (const auto& e : system_->force_elements()) out.push_back(e->name());
    return out;
  }

 private:
  std::unique_ptr<MultibodySystem> system_;
  std::unique_ptr<MultibodySystem> call_;  // the last call's system with extra forces
};

py::tuple positions(System& self, const py::object& q, double t) {
  const Model& m = self.model();
  // With closed loops, in the tree's coordinates x = (q, p), the loops closed.
  const State s = self.base().extended_state(state_arg(self.base(), t, q, py::none()));
  Kinematics k = m.make_kinematics();
  m.positions(t, s.q.data(), k);
  return py::make_tuple(body_array(k.R_data(), m.nbody(), true),
                        body_array(k.x_data(), m.nbody(), false));
}

py::tuple velocities(System& self, const py::object& q, const py::object& qd, double t) {
  const Model& m = self.model();
  const State s = self.base().extended_state(state_arg(self.base(), t, q, qd));
  Kinematics k = m.make_kinematics();
  m.velocities(t, s.q.data(), s.qd.data(), k);
  return py::make_tuple(body_array(k.v_data(), m.nbody(), false),
                        body_array(k.w_data(), m.nbody(), false));
}

// The tree's state and accelerations at (t, q, qd, qdd), qdd (n) in the independent
// coordinates: with closed loops, x = (q, p) closing them and xdd = T·qdd + c.
struct TreeState {
  State s;
  Vector qdd;
};
TreeState tree_state(System& self, const py::object& q, const py::object& qd, const py::object& qdd,
                     double t) {
  MultibodySystem& system = self.base();
  const State s = state_arg(system, t, q, qd);
  const int n = system.num_coordinates();
  const Vector a = qdd.is_none() ? Vector::Zero(n) : vector_arg(qdd, n, "qdd");
  check_finite(a, self.model(), "qdd");
  if (!self.model().has_loops()) return {s, a};
  return {system.extended_state(s), system.extended_accelerations(s, a)};
}

py::tuple body_accelerations(System& self, const py::object& q, const py::object& qd,
                             const py::object& qdd, double t) {
  const Model& m = self.model();
  const TreeState x = tree_state(self, q, qd, qdd, t);
  Kinematics k = m.make_kinematics();
  m.accelerations(t, x.s.q.data(), x.s.qd.data(), x.qdd.data(), k);
  return py::make_tuple(body_array(k.a_data(), m.nbody(), false),
                        body_array(k.dw_data(), m.nbody(), false));
}

py::tuple dependent_parameters(System& self, const py::object& q, const py::object& qd,
                               const py::object& qdd, double t) {
  const Model& m = self.model();
  const TreeState x = tree_state(self, q, qd, qdd, t);
  Kinematics k = m.make_kinematics();
  m.dependent_parameters(t, x.s.q.data(), x.s.qd.data(), x.qdd.data(), k);
  const auto first = [&](const std::vector<double>& v) {
    return std::vector<double>(v.begin(), v.begin() + m.ndep());
  };
  return py::make_tuple(py::array(py::cast(first(k.p()))), py::array(py::cast(first(k.pd()))),
                        py::array(py::cast(first(k.pdd()))));
}

// Closed loops: the implicit dependent parameters p, pd, pdd (ncon each) at
// the state and qdd (n; None: the state's accelerations).
py::tuple implicit_parameters(System& self, const py::object& q, const py::object& qd,
                              const py::object& qdd, double t) {
  MultibodySystem& system = self.base();
  const int m = self.model().ncon();
  const State s = state_arg(system, t, q, qd);
  Vector a(system.num_coordinates()), yd(system.num_extra_states());
  if (qdd.is_none()) {
    system.accelerations(s, a, yd);
  } else {
    a = vector_arg(qdd, system.num_coordinates(), "qdd");
    check_finite(a, self.model(), "qdd");
  }
  const State x = system.extended_state(s);
  const Vector xdd = system.extended_accelerations(s, a);
  return py::make_tuple(Vector(x.q.tail(m)), Vector(x.qd.tail(m)), Vector(xdd.tail(m)));
}

Matrix mass_matrix(System& self, const py::object& q, double t) {
  Matrix M(self.model().nq(), self.model().nq());
  self.base().mass_matrix(state_arg(self.base(), t, q, py::none()), M);
  return M;
}

Vector bias_forces(System& self, const py::object& q, const py::object& qd, double t) {
  MultibodySystem& system = self.base();
  Vector h(self.model().nq());
  const State s = state_arg(system, t, q, qd);
  if (system.source() == runtime::EquationsSource::emitted) {
    system.bias_forces_emitted(s, h);
  } else {
    system.bias_forces_assembled(s, h);
  }
  return h;
}

Vector applied_forces(System& self, const py::object& q, const py::object& qd, double t,
                      const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  Vector Q(self.model().nq());
  system.applied_forces(state_arg(system, t, q, qd), Q);
  return Q;
}

Vector accelerations(System& self, const py::object& q, const py::object& qd, double t,
                     const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  Vector qdd(self.model().nq()), yd(system.num_extra_states());
  system.accelerations(state_arg(system, t, q, qd), qdd, yd);
  return qdd;
}

// Row i: body i's joint reaction Fx, Fy, Fz, Mx, My, Mz (body axes, about its joint point).
runtime::Matrix joint_reactions(System& self, const py::object& q, const py::object& qd, double t,
                                const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  runtime::Matrix reaction;
  system.joint_reactions(state_arg(system, t, q, qd), reaction);
  return reaction.transpose();
}

// Each loop equation's reaction (ncon, named loop_reaction_names) at the state's accelerations.
Vector loop_reactions(System& self, const py::object& q, const py::object& qd, double t,
                      const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  Vector reaction;
  system.loop_reactions(state_arg(system, t, q, qd), reaction);
  return reaction;
}

py::dict energies(System& self, const py::object& q, const py::object& qd, double t,
                  const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  return energies_dict(system.energies(state_arg(system, t, q, qd)));
}

// ---------------------------------------------------------------- simulation

// What simulate() records at each output instant, row by row.
struct Recording {
  std::vector<double> t, q, qd, qdd, kinetic, gravitational, elastic;
};

py::object statistics_of(const runtime::Statistics& s) {
  py::dict d;
  d["steps"] = s.steps;
  d["rejected_steps"] = s.rejected_steps;
  d["rhs_evaluations"] = s.rhs_evaluations;
  d["residual_evaluations"] = s.residual_evaluations;
  d["jacobian_evaluations"] = s.jacobian_evaluations;
  d["newton_iterations"] = s.newton_iterations;
  // With global_tolerance: the runs made, the estimate of the result's error (NaN
  // without: none) and whether it is within the global tolerance.
  d["runs"] = s.runs;
  d["global_error_estimate"] = s.global_error_estimate;
  d["global_tolerance_met"] = s.global_tolerance_met;
  d["extrapolated"] = s.extrapolated;
  return namespace_of(d);
}

py::object result_of(const Recording& r, Eigen::Index nq, const Model& m,
                     std::string_view integrator, const runtime::Statistics& stats,
                     const std::vector<std::string>& warnings) {
  std::vector<double> total(r.kinetic.size());
  for (std::size_t i = 0; i < total.size(); ++i)
    total[i] = r.kinetic[i] + r.gravitational[i] + r.elastic[i];
  py::dict e;
  e["kinetic"] = column(r.kinetic);
  e["gravitational"] = column(r.gravitational);
  e["elastic"] = column(r.elastic);
  e["total"] = column(total);
  py::dict d;
  d["t"] = column(r.t);
  d["q"] = rows_array(r.q, nq);
  d["qd"] = rows_array(r.qd, nq);
  d["qdd"] = rows_array(r.qdd, nq);
  d["energies"] = namespace_of(e);
  d["q_names"] = m.q_names();
  d["integrator"] = std::string(integrator);
  d["statistics"] = statistics_of(stats);
  d["warnings"] = warnings;
  return namespace_of(d);
}

// The run's warnings (MultibodySystem::warnings) also as Python RuntimeWarnings,
// which a user sees without reading the result.
void warn_python(const std::vector<std::string>& warnings) {
  if (warnings.empty()) return;
  const py::object warn = py::module_::import("warnings").attr("warn");
  for (const auto& w : warnings) warn(w, py::handle(PyExc_RuntimeWarning));
}

py::object simulate(System& self, double t_end, const std::string& integrator, double rtol,
                    double atol, double interval, const py::object& times, const py::object& q0,
                    const py::object& qd0, double t0, double step, double max_step, bool fixed_step,
                    double global_tolerance, const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  const State initial = state_arg(system, t0, q0, qd0);
  runtime::IntegratorOptions o;
  o.relative_tolerance = rtol;
  o.absolute_tolerance = atol;
  o.output_interval = interval;
  if (!times.is_none()) o.output_times = times.cast<std::vector<double>>();
  o.initial_step = step;
  o.max_step = max_step;
  o.fixed_step = fixed_step;
  o.global_tolerance = global_tolerance;
  Recording r;
  o.on_output = [&](const State& s, const Vector& qdd, const Vector&) {
    r.t.push_back(s.t);
    r.q.insert(r.q.end(), s.q.begin(), s.q.end());
    r.qd.insert(r.qd.end(), s.qd.begin(), s.qd.end());
    r.qdd.insert(r.qdd.end(), qdd.begin(), qdd.end());
    const runtime::Energies e = system.energies(s);
    r.kinetic.push_back(e.kinetic);
    r.gravitational.push_back(e.gravitational);
    r.elastic.push_back(e.elastic);
  };
  auto integ = runtime::make_integrator(integrator, o);
  system.clear_warnings();
  integ->integrate(system, initial, t_end);
  warn_python(system.warnings());
  return result_of(r, system.num_coordinates(), system.model(), integ->name(), integ->statistics(),
                   system.warnings());
}

// ------------------------------------------------ statics and linearization

py::object solve_statics(System& self, const py::object& q, const py::iterable& locked,
                         double tolerance, double mass_weight, int max_iterations,
                         const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  runtime::StaticsOptions o;
  o.locked = coordinates_arg(system.model(), locked);
  o.tolerance = tolerance;
  o.mass_weight = mass_weight;
  o.max_iterations = max_iterations;
  State start = state_arg(system, 0.0, q, py::none());
  start.qd.setZero();
  const runtime::StaticsReport report = runtime::solve_statics(system, start, o);
  py::dict d;
  d["q"] = report.state.q;
  d["iterations"] = report.iterations;
  d["residual_norm"] = report.residual_norm;
  d["step_norm"] = report.step_norm;
  d["summary"] = report.summary();
  return namespace_of(d);
}

runtime::Linearization linearization(System& self, const py::object& q, const py::object& qd,
                                     double t, const py::iterable& locked,
                                     const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  runtime::LinearizationOptions o;
  o.locked = coordinates_arg(system.model(), locked);
  return runtime::linearize(system, state_arg(system, t, q, qd), o);
}

py::object linearize(System& self, const py::object& q, const py::object& qd, double t,
                     const py::iterable& locked, const std::vector<Force>& forces) {
  const runtime::Linearization lin = linearization(self, q, qd, t, locked, forces);
  py::dict d;
  d["coordinates"] = lin.coordinates;
  d["M"] = lin.M;
  d["C"] = lin.C;
  d["K"] = lin.K;
  d["A"] = lin.A;
  return namespace_of(d);
}

// xd = f(x, u), x = (q, qd), u generalized forces on the coordinates:
// A = df/dx (2n x 2n), B = df/du (2n x n), exact where the model was emitted
// with its derivatives.
py::object dynamics_derivatives(System& self, const py::object& q, const py::object& qd, double t,
                                const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  runtime::DynamicsDerivatives d;
  system.dynamics_derivatives(state_arg(system, t, q, qd), d, true);
  const Eigen::Index n = system.num_coordinates();
  runtime::Matrix A = runtime::Matrix::Zero(2 * n, 2 * n), B = runtime::Matrix::Zero(2 * n, n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = d.dqdd_dq;
  A.bottomRightCorner(n, n) = d.dqdd_dqd;
  B.bottomRows(n) = d.dqdd_dtau;
  py::dict out;
  out["qdd"] = d.qdd;
  out["dqdd_dq"] = d.dqdd_dq;
  out["dqdd_dqd"] = d.dqdd_dqd;
  out["dqdd_dtau"] = d.dqdd_dtau;
  out["A"] = A;
  out["B"] = B;
  out["method"] = system.jacobian_method();
  return namespace_of(out);
}

// One rk4 step of h from (q, qd) with generalized forces u (held over the
// step; default zero) and its exact derivatives A = dx1/dx0, B = dx1/du.
py::object step_derivatives(System& self, const py::object& q, const py::object& qd,
                            const py::object& u, double h, double t,
                            const std::vector<Force>& forces) {
  MultibodySystem& system = self.with(forces);
  const Eigen::Index n = system.num_coordinates();
  const Vector input = u.is_none() ? Vector::Zero(n) : u.cast<Vector>();
  runtime::StepDerivatives d;
  runtime::rk4_step_derivatives(system, state_arg(system, t, q, qd), input, h, d);
  py::dict out;
  out["q"] = d.next.q;
  out["qd"] = d.next.qd;
  out["t"] = d.next.t;
  out["A"] = d.A;
  out["B"] = d.B;
  out["method"] = system.jacobian_method();
  return namespace_of(out);
}

py::object modes(System& self, const py::object& q, const py::object& qd, double t,
                 const py::iterable& locked, const std::vector<Force>& forces) {
  const runtime::Linearization lin = linearization(self, q, qd, t, locked, forces);
  const std::vector<runtime::Mode> all = runtime::modes(lin);
  const auto count = static_cast<Eigen::Index>(all.size());
  Eigen::VectorXcd poles(count);
  Vector natural(count), damped(count), damping(count), modal_mass(count);
  Eigen::MatrixXcd shapes(static_cast<Eigen::Index>(lin.coordinates.size()), count);
  for (Eigen::Index i = 0; i < count; ++i) {
    const runtime::Mode& mode = all[static_cast<std::size_t>(i)];
    poles(i) = mode.pole;
    natural(i) = mode.natural_frequency_hz;
    damped(i) = mode.damped_frequency_hz;
    damping(i) = mode.damping_ratio;
    modal_mass(i) = mode.modal_mass;
    shapes.col(i) = mode.shape;
  }
  py::dict d;
  d["coordinates"] = lin.coordinates;
  d["poles"] = poles;
  d["natural_frequency_hz"] = natural;
  d["damped_frequency_hz"] = damped;
  d["damping_ratio"] = damping;
  d["modal_mass"] = modal_mass;
  d["shapes"] = shapes;
  return namespace_of(d);
}

// ------------------------------------------------------------------- module

// The model's names and sizes, on the module and on System.
template <class Target>
void define_constants(Target& target, const Model& m) {
  target.attr("model") = m.name();
  target.attr("variant") = m.variant();
  target.attr("nq") = m.nq();
  target.attr("nbody") = m.nbody();
  target.attr("ndep") = m.ndep();
  target.attr("nparam") = m.nparam();
  target.attr("q_names") = py::tuple(py::cast(m.q_names()));
  target.attr("body_names") = py::tuple(py::cast(m.body_names()));
  target.attr("param_names") = py::tuple(py::cast(m.param_names()));
  target.attr("nindependent") = m.nindependent();
  target.attr("loop_names") = py::tuple(py::cast(m.loop_names()));
  std::vector<std::string> reactions;
  for (int k = 0; k < m.ncon(); ++k) reactions.push_back(m.loop_reaction_name(k));
  target.attr("loop_reaction_names") = py::tuple(py::cast(reactions));
  const State s = m.initial_state();
  target.attr("q_initial") = Vector(s.q);
  target.attr("qd_initial") = Vector(s.qd);
  target.attr("gravity") = Vector(m.gravity());
}

void define_system(py::module_& module, ModelFactory make_model) {
  using namespace py::literals;
  const py::object none = py::none();
  const py::tuple empty;
  const std::vector<Force> no_forces;
  py::class_<System> system(module, "System",
                            "The model with its run-time parameters and force elements. Arrays "
                            "are NumPy, q and qd of nq values, bodies in body_names order.");
  system
      .def(py::init([make_model](const std::vector<Force>& forces) {
             return std::make_unique<System>(make_model, forces);
           }),
           "forces"_a = no_forces, "A system of this model with the given force elements.")
      .def("add", &System::add, "force"_a, "Adds a force element (a Force of this module).")
      .def_property_readonly("forces", &System::force_names,
                             "Names of the force elements, in order.")
      .def_property_readonly("parameters", &System::parameters,
                             "The run-time parameters, {name: value}.")
      .def("get_parameter", &System::parameter, "name"_a, "A run-time parameter's value.")
      .def(
          "set_parameter",
          [](System& self, const std::string& name, double value) {
            self.base().set_parameter(name, value);
          },
          "name"_a, "value"_a,
          "Sets a run-time parameter; the inertia is re-validated (ModelError naming the body "
          "or the parameter, the old values kept).")
      .def(
          "set_parameters",
          [](System& self, const py::dict& values) {
            for (const auto& [name, value] : values) {
              self.base().set_parameter(name.cast<std::string>(), value.cast<double>());
            }
          },
          "values"_a, "Sets several run-time parameters from {name: value}.")
      .def("positions", &positions, "q"_a = none, "t"_a = 0.0,
           "(R, x): every body's rotation body -> global (nbody x 3 x 3) and centre of "
           "gravity (nbody x 3).")
      .def("velocities", &velocities, "q"_a = none, "qd"_a = none, "t"_a = 0.0,
           "(v, w): every body's velocity of G and angular velocity (nbody x 3 each, global).")
      .def("body_accelerations", &body_accelerations, "q"_a, "qd"_a, "qdd"_a, "t"_a = 0.0,
           "(a, dw): every body's acceleration of G and angular acceleration (nbody x 3 each); "
           "with closed loops at qdd of the independent coordinates, the loops closed.")
      .def(
          "set_loop_guess",
          [](System& self, const py::object& p) {
            self.base().set_loop_guess(vector_arg(p, self.model().ncon(), "p"));
          },
          "p"_a,
          "Closed loops: the implicit dependent parameters' guesses (ncon) the next solve "
          "starts from, the assembly branch (later solves start from the last solution).")
      .def("implicit_parameters", &implicit_parameters, "q"_a = none, "qd"_a = none, "qdd"_a = none,
           "t"_a = 0.0,
           "Closed loops: (p, pd, pdd), the implicit dependent parameters solved at the state "
           "and qdd (None: the state's accelerations), ncon each.")
      .def("loop_reactions", &loop_reactions, "q"_a = none, "qd"_a = none, "t"_a = 0.0,
           "forces"_a = no_forces,
           "Closed loops: each loop equation's reaction at the state's accelerations (ncon, "
           "named by loop_reaction_names): a close_loop's force on its body b from its body a "
           "(N, global axes), a constraint's multiplier.")
      .def("dependent_parameters", &dependent_parameters, "q"_a = none, "qd"_a = none,
           "qdd"_a = none, "t"_a = 0.0,
           "(p, pd, pdd): the dependent parameters and their time derivatives (ndep each).")
      .def("mass_matrix", &mass_matrix, "q"_a = none, "t"_a = 0.0,
           "The mass matrix M(q) (nq x nq).")
      .def("bias_forces", &bias_forces, "q"_a = none, "qd"_a = none, "t"_a = 0.0,
           "h(q, qd): inertia and gravity terms, M qdd + h = Q (nq).")
      .def("applied_forces", &applied_forces, "q"_a = none, "qd"_a = none, "t"_a = 0.0,
           "forces"_a = no_forces, "Q: generalized forces of the force elements (nq).")
      .def("accelerations", &accelerations, "q"_a = none, "qd"_a = none, "t"_a = 0.0,
           "forces"_a = no_forces, "qdd solving M qdd = Q - h (nq).")
      .def("joint_reactions", &joint_reactions, "q"_a = none, "qd"_a = none, "t"_a = 0.0,
           "forces"_a = no_forces,
           "Each body's joint reaction (nbody x 6: Fx, Fy, Fz, Mx, My, Mz), onto the body from "
           "its reference, in its axes, the moment about its joint point, at the accelerations "
           "of the state.")
      .def("energies", &energies, "q"_a = none, "qd"_a = none, "t"_a = 0.0, "forces"_a = no_forces,
           "{kinetic, gravitational, elastic, total} at the state.")
      .def("simulate", &simulate, "t_end"_a, "integrator"_a = "dopri5", "rtol"_a = 1e-6,
           "atol"_a = 1e-8, "interval"_a = 0.0, "times"_a = none, "q0"_a = none, "qd0"_a = none,
           "t0"_a = 0.0, "step"_a = 0.0, "max_step"_a = std::numeric_limits<double>::infinity(),
           "fixed_step"_a = false, "global_tolerance"_a = 0.0, "forces"_a = no_forces,
           "Integrates from t0 to t_end. Outputs every `interval`, at `times`, or (both unset) "
           "every accepted step. Returns t (nt), q, qd, qdd (nt x nq), energies.kinetic, "
           ".gravitational, .elastic, .total (nt), q_names, integrator and statistics. "
           "Integrators: newmark, generalized-alpha, rk4, dopri5, dop853, midpoint, cvode, "
           "arkode (rk4 and midpoint need step). global_tolerance > 0: solved again (tighter "
           "tolerances, or halved fixed steps, the last two extrapolated) until the estimated "
           "error of the result is below it: statistics.global_error_estimate, "
           ".global_tolerance_met, .runs, .extrapolated.")
      .def("solve_statics", &solve_statics, "q"_a = none, "locked"_a = empty, "tolerance"_a = 1e-8,
           "mass_weight"_a = 100.0, "max_iterations"_a = 500, "forces"_a = no_forces,
           "Static equilibrium from q (qd = 0), locked coordinates held. Returns q, iterations, "
           "residual_norm, step_norm, summary; NumericError when it does not converge.")
      .def("linearize", &linearize, "q"_a = none, "qd"_a = none, "t"_a = 0.0, "locked"_a = empty,
           "forces"_a = no_forces,
           "M dqdd + C dqd + K dq = 0 about the state: coordinates, M, C, K (n x n) and the "
           "state matrix A (2n x 2n), locked coordinates removed.")
      .def("dynamics_derivatives", &dynamics_derivatives, "q"_a = none, "qd"_a = none, "t"_a = 0.0,
           "forces"_a = no_forces,
           "The forward dynamics' derivatives at (q, qd), generalized forces u on the coordinates: "
           "qdd, "
           "dqdd_dq, dqdd_dqd, dqdd_dtau (nq x nq each), the continuous-time A (2nq x 2nq) and B "
           "(2nq x nq) of "
           "xd = f(x, u), x = (q, qd), and method: exact where the model was emitted with its "
           "derivatives.")
      .def("step_derivatives", &step_derivatives, "q"_a = none, "qd"_a = none, "u"_a = none,
           "h"_a = 0.01, "t"_a = 0.0, "forces"_a = no_forces,
           "One step of h of the classical Runge-Kutta method (the rk4 integrator's) from (q, qd), "
           "with "
           "generalized forces u on the coordinates held over the step (default zero), and its "
           "exact "
           "derivatives: q, qd, t at the end, A = d(q1, qd1)/d(q0, qd0) (2nq x 2nq), B = d(q1, "
           "qd1)/du "
           "(2nq x nq), method.")
      .def("modes", &modes, "q"_a = none, "qd"_a = none, "t"_a = 0.0, "locked"_a = empty,
           "forces"_a = no_forces,
           "Modes of the linearization, sorted by |pole|: poles, natural_frequency_hz, "
           "damped_frequency_hz, damping_ratio, modal_mass (one per mode) and shapes "
           "(n x modes, complex).");
  define_constants(system, make_model());
}

}  // namespace

void define_model_module(py::module_& module, ModelFactory make_model) {
  define_exceptions(module);
  const Model model = make_model();
  module.doc() =
      fmt::format("symdyn model '{}' variant '{}': {} coordinates, {} bodies (docs/python.md).",
                  model.name(), model.variant(), model.nq(), model.nbody());
  define_constants(module, model);
  define_forces(module);
  define_system(module, make_model);
}

}  // namespace symdyn::python
