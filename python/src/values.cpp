// The value types (Dual, HyperDual, Quaternion, DualQuaternion and the conversion records) and
// the scalar functions over them, in double precision, with the C++ names.
#include <pybind11/operators.h>

#include "batch.hpp"

namespace dqpy {
namespace {

using D = dq::Dual<double>;
using HD = dq::HyperDual<double>;
using Q = dq::Quaternion<double>;
using DQ = dq::DualQuaternion<double>;
using V = dq::Vec3<double>;

std::array<double, 4> components(const Q& q) { return {q.w, q.x, q.y, q.z}; }
std::array<double, 8> components(const DQ& q) {
  return {q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z};
}
Q quaternion_from(py::handle obj) {
  const auto a = as_float64(obj, {4}, "quaternion (w, x, y, z)");
  return {a.at(0), a.at(1), a.at(2), a.at(3)};
}
DQ dual_quaternion_from(py::handle obj) {
  const auto a = as_float64(obj, {8}, "dual quaternion (w, x, y, z real, then dual)");
  return {a.at(0), a.at(1), a.at(2), a.at(3), a.at(4), a.at(5), a.at(6), a.at(7)};
}
template <std::size_t N>
py::array_t<double> to_numpy(const std::array<double, N>& c) {
  return py::array_t<double>(static_cast<py::ssize_t>(N), c.data());
}

/// x[i] of the components, Python style (−1 the last); IndexError outside.
template <std::size_t N>
double component(const std::array<double, N>& c, py::ssize_t i) {
  const auto n = static_cast<py::ssize_t>(N);
  if (i < -n || i >= n) throw py::index_error("component " + std::to_string(i) + " of " + std::to_string(N));
  return c[static_cast<std::size_t>(i < 0 ? i + n : i)];
}

/// np.asarray(x) and np.asarray(x, dtype): the components, float64 unless a dtype is asked for.
template <class X>
py::object as_array(const X& x, py::object dtype) {
  py::array a = to_numpy(components(x));
  return dtype.is_none() ? py::object(a) : a.attr("astype")(dtype);
}

/// repr: the type name and the components, round-trippable (17 digits).
template <class... X>
std::string repr_of(const char* name, const X&... values) {
  std::ostringstream os;
  os.precision(17);
  os << name << '(';
  const char* sep = "";
  ((os << sep << values, sep = ", "), ...);
  os << ')';
  return os.str();
}

void bind_scalars(py::module_& m) {
  py::class_<D>(m, "Dual", "Dual number a + εb (ε² = 0): f(a + ε) = f(a) + ε f'(a).")
      .def(py::init<>())
      .def(py::init<double, double>(), py::arg("real"), py::arg("dual") = 0.0)
      .def_readwrite("real", &D::real)
      .def_readwrite("dual", &D::dual)
      .def_static("variable", &D::variable, py::arg("x"), "x + ε: f(variable(x)).dual is f'(x).")
      .def(py::self + py::self).def(py::self - py::self).def(py::self * py::self).def(py::self / py::self)
      .def(py::self + double()).def(double() + py::self).def(py::self * double()).def(double() * py::self)
      .def(py::self - double()).def(double() - py::self).def(py::self / double()).def(double() / py::self)
      .def(-py::self)
      .def(py::self == py::self)
      .def("approx_equal", [](const D& a, const D& b, double tol) { return std::abs(a.real - b.real) <= tol && std::abs(a.dual - b.dual) <= tol; },
           py::arg("other"), py::arg("tolerance"), "Both parts within `tolerance` (absolute).")
      .def("__repr__", [](const D& x) { return repr_of("Dual", x.real, x.dual); })
      .def("__str__", [](const D& x) { return str_of(x); })
      .def(py::pickle([](const D& x) { return py::make_tuple(x.real, x.dual); },
                      [](py::tuple t) { return D(t[0].cast<double>(), t[1].cast<double>()); }));
  // Hyper-dual numbers take their C++ constructor order: real, e1, e2, e12.
  py::class_<HD>(m, "HyperDual", "Hyper-dual number a + b ε1 + c ε2 + d ε1ε2: exact first and second derivatives.")
      .def(py::init<>())
      .def(py::init<double, double, double, double>(), py::arg("real"), py::arg("e1") = 0.0, py::arg("e2") = 0.0,
           py::arg("e12") = 0.0)
      .def_readwrite("real", &HD::real).def_readwrite("e1", &HD::e1).def_readwrite("e2", &HD::e2).def_readwrite("e12", &HD::e12)
      .def_static("variable", &HD::variable, py::arg("x"), "x + ε1 + ε2: f(variable(x)) holds f'(x) in e1 and f''(x) in e12.")
      .def(py::self + py::self).def(py::self - py::self).def(py::self * py::self).def(py::self / py::self)
      .def(py::self * double()).def(double() * py::self).def(py::self + double()).def(double() + py::self)
      .def(-py::self)
      .def(py::self == py::self)
      .def("approx_equal",
           [](const HD& a, const HD& b, double tol) {
             return std::abs(a.real - b.real) <= tol && std::abs(a.e1 - b.e1) <= tol && std::abs(a.e2 - b.e2) <= tol &&
                    std::abs(a.e12 - b.e12) <= tol;
           },
           py::arg("other"), py::arg("tolerance"), "All four parts within `tolerance` (absolute).")
      .def("__repr__", [](const HD& x) { return repr_of("HyperDual", x.real, x.e1, x.e2, x.e12); })
      .def(py::pickle([](const HD& x) { return py::make_tuple(x.real, x.e1, x.e2, x.e12); },
                      [](py::tuple t) { return HD(t[0].cast<double>(), t[1].cast<double>(), t[2].cast<double>(), t[3].cast<double>()); }));
  // The elementary functions, generic in C++, for both derivative types.
#define DQPY_FUNCTION(name)                                           \
  m.def(#name, [](const D& x) { return dq::name(x); }, py::arg("x")); \
  m.def(#name, [](const HD& x) { return dq::name(x); }, py::arg("x"));
  DQPY_FUNCTION(sin)
  DQPY_FUNCTION(cos)
  DQPY_FUNCTION(exp)
  DQPY_FUNCTION(log)
  DQPY_FUNCTION(sqrt)
#undef DQPY_FUNCTION
}

void bind_quaternion(py::module_& m) {
  Enum<dq::SignPolicy>(m, "SignPolicy", "Whether approx_equal treats q and −q as the same rotation.")
      .value("exact", dq::SignPolicy::exact)
      .value("same_rotation", dq::SignPolicy::same_rotation);
  Enum<dq::Path>(m, "Path", "Which arc slerp and sclerp follow.")
      .value("shortest", dq::Path::shortest)
      .value("longest", dq::Path::longest);
  py::class_<dq::AxisAngle<double>>(m, "AxisAngle", "Unit axis and angle (radians).")
      .def(py::init([](const V& axis, double angle) { return dq::AxisAngle<double>{axis, angle}; }), py::arg("axis"), py::arg("angle"))
      .def_readwrite("axis", &dq::AxisAngle<double>::axis)
      .def_readwrite("angle", &dq::AxisAngle<double>::angle)
      .def("__repr__", [](const dq::AxisAngle<double>& a) { return repr_of("AxisAngle", str_of(a.axis), a.angle); });

  py::class_<Q>(m, "Quaternion", "w + x i + y j + z k (Hamilton product; rotation by θ about n is (cos θ/2, n sin θ/2)).")
      .def(py::init<>(), "The identity.")
      .def(py::init<double, double, double, double>(), py::arg("w"), py::arg("x"), py::arg("y"), py::arg("z"))
      .def(py::init(&quaternion_from), py::arg("wxyz"), "From a sequence or array of four numbers (w, x, y, z).")
      .def_readwrite("w", &Q::w).def_readwrite("x", &Q::x).def_readwrite("y", &Q::y).def_readwrite("z", &Q::z)
      .def_static("identity", &Q::identity)
      .def_static("pure", &Q::pure, py::arg("v"), "(0, v).")
      .def_static("from_axis_angle", py::overload_cast<const V&, const double&>(&Q::from_axis_angle), py::arg("axis"), py::arg("angle"),
                  "Rotation by `angle` radians about `axis` (normalized; a zero axis gives the identity).")
      .def_static("from_axis_angle", py::overload_cast<const dq::AxisAngle<double>&>(&Q::from_axis_angle), py::arg("axis_angle"))
      .def("to_axis_angle", &Q::to_axis_angle, "Axis and angle in [0, π]; the identity has axis (1, 0, 0).")
      .def_static("from_rotation_vector", &Q::from_rotation_vector, py::arg("v"), "exp of v/2: rotation by |v| about v.")
      .def("to_rotation_vector", &Q::to_rotation_vector, "Axis times angle, angle in [0, π].")
      .def_static("from_two_vectors", &Q::from_two_vectors, py::arg("a"), py::arg("b"), "The shortest rotation taking a's direction to b's.")
      .def_static("from_matrix", [](py::handle mat) { return Q::from_matrix(mat_from_numpy<3, 3>(mat)); }, py::arg("matrix"),
                  "From a (3, 3) rotation matrix (column vectors).")
      .def("to_matrix", [](const Q& q) { return mat_to_numpy(q.to_matrix()); }, "The (3, 3) rotation matrix of a unit quaternion.")
      .def("vec", &Q::vec)
      .def("conjugate", &Q::conjugate)
      .def("squared_norm", &Q::squared_norm)
      .def("norm", &Q::norm)
      .def("normalized", &Q::normalized, "Unit length; the zero quaternion gives the identity.")
      .def("inverse", &Q::inverse)
      .def("canonical", &Q::canonical, "±q with w ≥ 0 (w = 0: first non-zero of x, y, z positive).")
      .def("rotate", &Q::rotate, py::arg("v"), "q v q* for a unit quaternion.")
      .def(py::self + py::self).def(py::self - py::self).def(py::self * py::self)
      .def(py::self * double()).def(double() * py::self).def(py::self / double()).def(-py::self)
      .def(py::self == py::self)
      .def("approx_equal", [](const Q& a, const Q& b, double tol, dq::SignPolicy p) { return dq::approx_equal(a, b, tol, p); },
           py::arg("other"), py::arg("tolerance"), py::arg("policy") = dq::SignPolicy::exact,
           "Every component within `tolerance` (absolute); with SignPolicy.same_rotation, −other counts too.")
      .def("to_numpy", [](const Q& q) { return to_numpy(components(q)); }, "float64 array (w, x, y, z).")
      .def("__array__", &as_array<Q>, py::arg("dtype") = py::none())
      .def("__iter__", [](const Q& q) { return py::iter(py::make_tuple(q.w, q.x, q.y, q.z)); })
      .def("__len__", [](const Q&) { return 4; })
      .def("__getitem__", [](const Q& q, py::ssize_t i) { return component(components(q), i); }, py::arg("i"))
      .def("__repr__", [](const Q& q) { return repr_of("Quaternion", q.w, q.x, q.y, q.z); })
      .def(py::pickle([](const Q& q) { return py::make_tuple(q.w, q.x, q.y, q.z); }, [](py::tuple t) { return quaternion_from(t); }));

  m.def("dot", [](const Q& a, const Q& b) { return dq::dot(a, b); }, py::arg("a"), py::arg("b"), "Four-component dot product.");
  m.def("exp", [](const Q& q) { return dq::exp(q); }, py::arg("q"));
  m.def("log", [](const Q& q) { return dq::log(q); }, py::arg("q"));
  m.def("pow", [](const Q& q, double t) { return dq::pow(q, t); }, py::arg("q"), py::arg("t"));
  m.def("angular_distance", [](const Q& a, const Q& b) { return dq::angular_distance(a, b); }, py::arg("a"), py::arg("b"),
        "The angle of the rotation between a and b, in [0, π].");
  m.def("approx_equal", [](const Q& a, const Q& b, double tol, dq::SignPolicy p) { return dq::approx_equal(a, b, tol, p); },
        py::arg("a"), py::arg("b"), py::arg("tolerance"), py::arg("policy") = dq::SignPolicy::exact);
  m.def("slerp", [](const Q& a, const Q& b, double t, dq::Path path) { return dq::slerp(a, b, t, path); }, py::arg("a"), py::arg("b"),
        py::arg("t"), py::arg("path") = dq::Path::shortest, "Spherical linear interpolation (constant angular speed, never fails).");
  m.def("nlerp", [](const Q& a, const Q& b, double t, dq::Path path) { return dq::nlerp(a, b, t, path); }, py::arg("a"), py::arg("b"),
        py::arg("t"), py::arg("path") = dq::Path::shortest,
        "Normalized linear interpolation: the straight line between the keys, made unit (slerp's path, not its speed).");
  m.def("average", [](const std::vector<Q>& qs, const std::vector<double>& w) {
          if (w.empty()) return dq::average<double>(std::span<const Q>(qs));
          if (w.size() != qs.size()) throw py::value_error("average needs one weight per rotation");
          return dq::average<double>(std::span<const Q>(qs), std::span<const double>(w));
        },
        py::arg("rotations"), py::arg("weights") = std::vector<double>{}, "Weighted rotation average (Markley's eigenvector).");
}

void bind_dual_quaternion(py::module_& m) {
  py::class_<dq::PluckerLine<double>>(m, "PluckerLine", "Line with unit direction l and moment m = p × l.")
      .def(py::init([](const V& l, const V& mo) { return dq::PluckerLine<double>{l, mo}; }), py::arg("direction"), py::arg("moment"))
      .def_readwrite("direction", &dq::PluckerLine<double>::direction)
      .def_readwrite("moment", &dq::PluckerLine<double>::moment)
      .def("closest_point_to_origin", &dq::PluckerLine<double>::closest_point_to_origin)
      .def("__repr__", [](const dq::PluckerLine<double>& l) { return repr_of("PluckerLine", str_of(l.direction), str_of(l.moment)); });

  py::class_<DQ>(m, "DualQuaternion", "Q = q_r + ε q_d; the rigid transform 'rotate by r, then translate by t' is r + ε ½ t r.")
      .def(py::init<>(), "The identity.")
      .def(py::init<const Q&, const Q&>(), py::arg("real"), py::arg("dual"))
      .def(py::init<double, double, double, double, double, double, double, double>(), py::arg("rw"), py::arg("rx"), py::arg("ry"),
           py::arg("rz"), py::arg("dw"), py::arg("dx"), py::arg("dy"), py::arg("dz"))
      .def(py::init(&dual_quaternion_from), py::arg("components"), "From eight numbers: (w, x, y, z) real, then dual.")
      .def_readwrite("real", &DQ::real)
      .def_readwrite("dual", &DQ::dual)
      .def_static("identity", &DQ::identity)
      .def_static("from_rotation", &DQ::from_rotation, py::arg("r"))
      .def_static("from_translation", &DQ::from_translation, py::arg("t"))
      .def_static("from_rotation_translation", &DQ::from_rotation_translation, py::arg("r"), py::arg("t"),
                  "Rotate by the unit quaternion r, then translate by t.")
      .def("conjugate", &DQ::conjugate, "Q* = q_r* + ε q_d* (the inverse of a unit dual quaternion).")
      .def("dual_conjugate", &DQ::dual_conjugate, "q_r − ε q_d.")
      .def("combined_conjugate", &DQ::combined_conjugate, "q_r* − ε q_d*.")
      .def("squared_norm", &DQ::squared_norm)
      .def("norm", &DQ::norm, "The dual-number norm.")
      .def("normalized", &DQ::normalized, "The nearest unit dual quaternion (unit real part, dual part orthogonal to it).")
      .def("is_unit", &DQ::is_unit, py::arg("tolerance"))
      .def("inverse", &DQ::inverse)
      .def("inverse_unit", &DQ::inverse_unit)
      .def("rotation", &DQ::rotation)
      .def("translation", &DQ::translation, "t = 2 q_d q_r*.")
      .def("transform_point", &DQ::transform_point, py::arg("p"), "R p + t.")
      .def("transform_direction", &DQ::transform_direction, py::arg("v"), "R v.")
      .def("transform_line", &DQ::transform_line, py::arg("line"))
      .def(py::self + py::self).def(py::self - py::self).def(py::self * py::self)
      .def(py::self * double()).def(double() * py::self).def(py::self / double()).def(-py::self)
      .def(D() * py::self)
      .def(py::self == py::self)
      .def("approx_equal", [](const DQ& a, const DQ& b, double tol, dq::SignPolicy p) { return dq::approx_equal(a, b, tol, p); },
           py::arg("other"), py::arg("tolerance"), py::arg("policy") = dq::SignPolicy::exact,
           "All eight components within `tolerance` (absolute); with SignPolicy.same_rotation, −other counts too.")
      .def("to_numpy", [](const DQ& q) { return to_numpy(components(q)); }, "float64 array (w, x, y, z real, then dual).")
      .def("__array__", &as_array<DQ>, py::arg("dtype") = py::none())
      .def("__iter__", [](const DQ& q) { return py::iter(py::cast(components(q))); })
      .def("__len__", [](const DQ&) { return 8; })
      .def("__getitem__", [](const DQ& q, py::ssize_t i) { return component(components(q), i); }, py::arg("i"))
      .def("__repr__", [](const DQ& q) {
        return repr_of("DualQuaternion", q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z);
      })
      .def(py::pickle([](const DQ& q) { return py::tuple(py::cast(components(q))); }, [](py::tuple t) { return dual_quaternion_from(t); }));

  m.def("approx_equal", [](const DQ& a, const DQ& b, double tol, dq::SignPolicy p) { return dq::approx_equal(a, b, tol, p); },
        py::arg("a"), py::arg("b"), py::arg("tolerance"), py::arg("policy") = dq::SignPolicy::exact);
  m.def("exp", [](const DQ& x) { return dq::exp(x); }, py::arg("xi"), "The screw exponential of a pure dual quaternion.");
  m.def("log", [](const DQ& q) { return dq::log(q); }, py::arg("q"), "The screw logarithm of a unit dual quaternion.");
  m.def("pow", [](const DQ& q, double t) { return dq::pow(q, t); }, py::arg("q"), py::arg("t"));
  m.def("sqrt", [](const DQ& q) { return dq::sqrt(q); }, py::arg("q"));
  m.def("sclerp", [](const DQ& a, const DQ& b, double t, dq::Path path) { return dq::sclerp(a, b, t, path); }, py::arg("a"), py::arg("b"),
        py::arg("t"), py::arg("path") = dq::Path::shortest, "Screw linear interpolation a (a⁻¹ b)^t (constant speed along the screw).");
  m.def("dlb", [](const DQ& a, const DQ& b, double t) { return dq::dlb(a, b, t); }, py::arg("a"), py::arg("b"), py::arg("t"),
        "Dual quaternion linear blending of two keys.");
  Enum<dq::BlendPivot>(m, "BlendPivot")
      .value("largest_weight", dq::BlendPivot::largest_weight)
      .value("first", dq::BlendPivot::first);
  m.def("dlb", [](const std::vector<DQ>& qs, const std::vector<double>& w, dq::BlendPivot pivot) {
          if (w.size() != qs.size()) throw py::value_error("dlb needs one weight per dual quaternion");
          return dq::dlb(std::span<const DQ>(qs), std::span<const double>(w), pivot);
        },
        py::arg("qs"), py::arg("weights"), py::arg("pivot") = dq::BlendPivot::largest_weight, "Weighted dual quaternion linear blending.");
  py::class_<dq::IterativeBlend<double>>(m, "IterativeBlend")
      .def_readonly("value", &dq::IterativeBlend<double>::value)
      .def_readonly("iterations", &dq::IterativeBlend<double>::iterations)
      .def_readonly("converged", &dq::IterativeBlend<double>::converged)
      .def_readonly("residual", &dq::IterativeBlend<double>::residual);
  m.def("dib", [](const std::vector<DQ>& qs, const std::vector<double>& w, int iterations) {
          if (w.size() != qs.size() || qs.empty()) throw py::value_error("dib needs one or more dual quaternions and one weight per dual quaternion");
          if (iterations < 1) throw py::value_error("max_iterations: expected 1 or more, got " + std::to_string(iterations));
          return dq::dib(std::span<const DQ>(qs), std::span<const double>(w), iterations);
        },
        py::arg("qs"), py::arg("weights"), py::arg("max_iterations") = 20, "Dual quaternion iterative blending (Kavan's DIB).");
  m.def("decoupled_interpolate", [](const DQ& a, const DQ& b, double t) { return dq::decoupled_interpolate(a, b, t); },
        py::arg("a"), py::arg("b"), py::arg("t"), "slerp of the rotation, straight line for the translation.");
}

void bind_conversions(py::module_& m) {
  m.def("to_mat4", [](const DQ& q) { return mat_to_numpy(dq::to_mat4(q)); }, py::arg("q"), "The (4, 4) homogeneous matrix (column vectors).");
  m.def("to_mat34", [](const DQ& q) { return mat_to_numpy(dq::to_mat34(q)); }, py::arg("q"), "The top three rows of to_mat4.");
  m.def("from_matrix", [](py::handle mat) -> py::object {
          const auto a = py::array::ensure(mat);
          if (a && a.ndim() >= 3)  // lists take float64, as in every batch call
            return from_matrix_rows(py::isinstance<py::array>(mat) ? a : py::array(as_float64(mat, std::vector<py::ssize_t>(static_cast<std::size_t>(a.ndim()), -1), "matrix")));
          if (a && a.ndim() == 2 && a.shape(0) == 3 && a.shape(1) == 4) return py::cast(dq::from_matrix(mat_from_numpy<3, 4>(mat)));
          if (a && a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4) return py::cast(dq::from_matrix(mat_from_numpy<4, 4>(mat)));
          throw py::value_error("matrix: expected shape (..., 4, 4) or (..., 3, 4)");
        },
        py::arg("matrix"),
        "The unit dual quaternion of a (4, 4) or (3, 4) rigid transform matrix; (..., 4, 4) or (..., 3, 4) matrices give (..., 8) dual quaternions.");
  Enum<dq::EulerOrder> order(m, "EulerOrder", "The twelve axis sequences.");
  for (auto o : {dq::EulerOrder::XYZ, dq::EulerOrder::XZY, dq::EulerOrder::YXZ, dq::EulerOrder::YZX, dq::EulerOrder::ZXY, dq::EulerOrder::ZYX,
                 dq::EulerOrder::XYX, dq::EulerOrder::XZX, dq::EulerOrder::YXY, dq::EulerOrder::YZY, dq::EulerOrder::ZXZ, dq::EulerOrder::ZYZ})
    order.value(std::string(dq::to_string(o)).c_str(), o);
  Enum<dq::EulerFrame>(m, "EulerFrame", "intrinsic XYZ(a, b, c) = Rx(a) Ry(b) Rz(c); extrinsic = Rz(c) Ry(b) Rx(a).")
      .value("intrinsic", dq::EulerFrame::intrinsic)
      .value("extrinsic", dq::EulerFrame::extrinsic);
  py::class_<dq::EulerAngles<double>>(m, "EulerAngles", "The first, middle and third angle of a sequence (radians).")
      .def(py::init([](double a, double b, double c) { return dq::EulerAngles<double>{a, b, c}; }), py::arg("a"), py::arg("b"), py::arg("c"))
      .def_readwrite("a", &dq::EulerAngles<double>::a).def_readwrite("b", &dq::EulerAngles<double>::b).def_readwrite("c", &dq::EulerAngles<double>::c)
      .def("__iter__", [](const dq::EulerAngles<double>& e) { return py::iter(py::make_tuple(e.a, e.b, e.c)); })
      .def("__repr__", [](const dq::EulerAngles<double>& e) { return repr_of("EulerAngles", e.a, e.b, e.c); });
  py::class_<dq::EulerExtraction<double>>(m, "EulerExtraction")
      .def_readonly("angles", &dq::EulerExtraction<double>::angles)
      .def_readonly("singular", &dq::EulerExtraction<double>::singular, "Gimbal lock: the third angle was set to 0.")
      .def("__repr__", [](const dq::EulerExtraction<double>& e) {
        return repr_of("EulerExtraction", repr_of("EulerAngles", e.angles.a, e.angles.b, e.angles.c), e.singular ? "singular" : "regular");
      });
  m.def("from_euler", [](dq::EulerOrder o, dq::EulerFrame f, double a, double b, double c) { return dq::from_euler(o, f, a, b, c); },
        py::arg("order"), py::arg("frame"), py::arg("a"), py::arg("b"), py::arg("c"), "The rotation of an Euler triple.");
  m.def("to_euler", [](const Q& q, dq::EulerOrder o, dq::EulerFrame f) { return dq::to_euler(q, o, f); }, py::arg("q"), py::arg("order"),
        py::arg("frame"), "Euler angles of a rotation; at gimbal lock the third angle is 0 and `singular` is set.");
  m.def("euler_to_matrix", [](dq::EulerOrder o, dq::EulerFrame f, double a, double b, double c) { return mat_to_numpy(dq::euler_to_matrix(o, f, a, b, c)); },
        py::arg("order"), py::arg("frame"), py::arg("a"), py::arg("b"), py::arg("c"),
        "The (3, 3) rotation matrix of an Euler sequence, as the product of its three axis rotations.");

  py::class_<dq::Screw<double>>(m, "Screw", "Unit axis line, angle θ about it and translation d along it.")
      .def(py::init([](const dq::PluckerLine<double>& axis, double angle, double d) { return dq::Screw<double>{axis, angle, d}; }),
           py::arg("axis"), py::arg("angle"), py::arg("translation"))
      .def_readwrite("axis", &dq::Screw<double>::axis)
      .def_readwrite("angle", &dq::Screw<double>::angle)
      .def_readwrite("translation", &dq::Screw<double>::translation)
      .def("dual_angle", &dq::Screw<double>::dual_angle)
      .def("__repr__", [](const dq::Screw<double>& s) {
        return repr_of("Screw", str_of(s.axis.direction), str_of(s.axis.moment), s.angle, s.translation);
      });
  m.def("from_screw", &dq::from_screw<double>, py::arg("screw"), "The unit dual quaternion of a screw motion (to_screw's inverse).");
  m.def("to_screw", &dq::to_screw<double>, py::arg("q"), "θ in [0, π]; a pure translation has its axis through the origin.");

  py::class_<dq::VrmlTransform<double>>(m, "VrmlTransform", "VRML Transform: rotation (axis, angle) about center, then translation.")
      .def(py::init([](const V& axis, double angle, const V& t, const V& c) { return dq::VrmlTransform<double>{axis, angle, t, c}; }),
           py::arg("axis") = V{0, 0, 1}, py::arg("angle") = 0.0, py::arg("translation") = V{}, py::arg("center") = V{})
      .def_readwrite("axis", &dq::VrmlTransform<double>::axis)
      .def_readwrite("angle", &dq::VrmlTransform<double>::angle)
      .def_readwrite("translation", &dq::VrmlTransform<double>::translation)
      .def_readwrite("center", &dq::VrmlTransform<double>::center)
      .def("__repr__", [](const dq::VrmlTransform<double>& v) {
        return repr_of("VrmlTransform", str_of(v.axis), v.angle, str_of(v.translation), str_of(v.center));
      });
  m.def("from_vrml", &dq::from_vrml<double>, py::arg("transform"), "The unit dual quaternion of a VRML Transform.");
  m.def("to_vrml", &dq::to_vrml<double>, py::arg("q"), py::arg("center") = V{},
        "A VRML Transform with the given center whose rotation and translation give q (from_vrml's inverse).");
}

}  // namespace

void bind_values(py::module_& m) {
  bind_scalars(m);
  bind_quaternion(m);
  bind_dual_quaternion(m);
  bind_conversions(m);
  // NumPy would take np.float64(2) * q through q.__array__ and answer an ndarray: a higher
  // __array_priority__ makes its scalars' and arrays' operators defer to the value's own
  // (q.__rmul__ here), while ufuncs (np.abs(q)) still read the components through __array__.
  for (const char* name : {"Quaternion", "DualQuaternion"}) m.attr(name).attr("__array_priority__") = 1000;
}

}  // namespace dqpy
