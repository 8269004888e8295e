// Shared pieces of the Python bindings: NumPy conversions of the small value types, checked views
// of the arrays the batch functions take, and errors as Python exceptions.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "dq/dq.hpp"
#include "dq/util/expected.hpp"

namespace py = pybind11;

namespace dqpy {

/// Raised by the file readers and builders: the library's message ("file:line: ..."). A subclass
/// of ValueError, registered in module.cpp.
struct ReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class T>
T unwrap(dq::Expected<T>&& e) {
  if (!e) throw ReadError(e.error().message);
  return std::move(*e);
}
inline void check(const dq::Status& s) {
  if (!s) throw ReadError(s.error().message);
}

/// Raised when a file cannot be written (it exists and overwrite is False, a directory or device
/// is in the way, the disk is full): the library's message naming the file. A subclass of OSError,
/// registered in module.cpp.
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
inline void check_written(const dq::Status& s) {
  if (!s) throw WriteError(s.error().message);
}
/// FileNotFoundError (errno ENOENT, the path as its filename) when nothing is at `path`, as
/// Python's open() raises: readers are caught with `except OSError` like any file function. Other
/// problems with the file are the library's ReadError, with its message.
void require_existing(const std::filesystem::path& path);

/// A value for a writer, or ValueError with the reason it cannot be written.
template <class T>
T writable(dq::Expected<T>&& e) {
  if (!e) throw py::value_error(e.error().message);
  return std::move(*e);
}

/// A count as passed: an int or any other integer (an object with __index__, such as NumPy's
/// int64), not a bool (the caster below; int in signatures).
struct IntegerArg {
  py::object value;
};
/// A `threads` argument: 0 (every hardware thread) or a number of threads up to `most`, else
/// ValueError naming it.
unsigned thread_count(const IntegerArg& threads, unsigned most);
/// A count from 0 to SIZE_MAX, else ValueError naming the argument.
std::size_t size_count(const IntegerArg& value, const char* name);

/// The text of operator<< (the C++ printing, w, x, y, z order).
template <class X>
std::string str_of(const X& x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

// ---- fixed-size values <-> NumPy ----------------------------------------------------------------
inline py::array_t<double> vec_to_numpy(const dq::Vec3<double>& v) {
  py::array_t<double> a(3);
  auto m = a.mutable_unchecked<1>();
  m(0) = v.x, m(1) = v.y, m(2) = v.z;
  return a;
}
/// A (R, C) array indexed [row, column] from the column-major matrix.
template <int R, int C>
py::array_t<double> mat_to_numpy(const dq::Mat<double, R, C>& m) {
  py::array_t<double> a({R, C});
  auto o = a.template mutable_unchecked<2>();
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) o(r, c) = m(r, c);
  return a;
}

/// A dense float64 copy of `obj` with exactly `shape` (−1: any extent, named in the error by
/// `names`, in order, else "N"), else ValueError naming the expected shape. A MemoryError stays one.
py::array_t<double, py::array::c_style | py::array::forcecast> as_float64(py::handle obj, std::vector<py::ssize_t> shape,
                                                                           const char* what, std::vector<const char*> names = {});
/// A dense int64 copy of an array of integers (booleans and floats refused: never a silent
/// truncation of 0.7 to 0; unsigned ones too where `signed_only`), of `ndim` dimensions, else
/// ValueError saying what `what` expects.
py::array_t<std::int64_t, py::array::c_style> as_integers(py::handle obj, int ndim, const std::string& what, bool signed_only = false);

/// `a`, made read-only: a property that returns a copy says so by refusing element assignment
/// (anim.locals[0, 0, 0] = 1 would change the copy alone, silently).
inline py::array read_only(py::array a) {
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

/// py::enum_ whose constructor refuses an integer that names no member: pybind11's takes any
/// (EulerOrder(99) would reach the library as a value outside the enumeration).
/// Unpickling (__setstate__) is checked the same way.
template <class E>
class Enum : public py::enum_<E> {
 public:
  template <class... Extra>
  Enum(const py::handle& scope, const char* name, const Extra&... extra) : py::enum_<E>(scope, name, extra...) {
    py::delattr(*this, "__init__");
    this->def(py::init([](typename py::enum_<E>::Scalar value) { return member(value); }), py::arg("value"));
    // As pybind11's own __setstate__ of an enum, with the check.
    this->attr("__setstate__") = py::cpp_function(
        [](py::detail::value_and_holder& v_h, typename py::enum_<E>::Scalar state) {
          py::detail::initimpl::setstate<py::class_<E>>(v_h, member(state), Py_TYPE(v_h.inst) != v_h.type->type);
        },
        py::detail::is_new_style_constructor(), py::name("__setstate__"), py::is_method(*this), py::arg("state"));
  }

 private:
  static E member(typename py::enum_<E>::Scalar value) {
    const py::object enum_type = py::type::of<E>();
    for (const auto& m : enum_type.attr("__members__").template cast<py::dict>())
      if (m.second.template cast<E>() == static_cast<E>(value)) return static_cast<E>(value);
    throw py::value_error(std::to_string(value) + " is not a " + enum_type.attr("__name__").template cast<std::string>() + " (its members: " +
                          py::str(py::list(enum_type.attr("__members__").attr("keys")())).template cast<std::string>() + ")");
  }
};

template <int R, int C>
dq::Mat<double, R, C> mat_from_numpy(py::handle obj) {
  const auto a = as_float64(obj, {R, C}, "matrix");
  auto v = a.template unchecked<2>();
  dq::Mat<double, R, C> m;
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) m(r, c) = v(r, c);
  return m;
}

// ---- batch arrays -------------------------------------------------------------------------------
/// "(N, 8)", "(F, J, 8)", ...: the shape as the error messages and the documentation write it.
std::string shape_text(const std::vector<const char*>& dims);

/// An input array of the batch API: float32 or float64, C-contiguous (a copy only when the
/// caller's array is not), with a trailing shape checked; leading dimensions are named in `dims`.
struct BatchInput {
  py::array array;  ///< the contiguous array (the caller's own when the layout allowed)
  std::size_t count = 0;  ///< product of the leading (named) dimensions
  bool single = false;    ///< given without its leading dimension: one value for every row
  std::vector<py::ssize_t> leading;  ///< the leading extents ((N,), or (F, J) for an (F, J, 8) array)
};

/// The dtype of a batch call: float32 or float64, else ValueError.
enum class Dtype { f32, f64 };
Dtype dtype_of(const py::array& a, const char* name);
template <class T>
inline constexpr Dtype dtype_of_v = std::is_same_v<T, float> ? Dtype::f32 : Dtype::f64;
/// The dtype of a call, from its first array argument (float64 for lists and tuples).
Dtype call_dtype(py::handle first, const char* name);

/// Checks `obj` against the shape `dims` (names for leading extents, digits for fixed ones, e.g.
/// {"N", "8"}); `optional_leading` accepts the shape without its first dimension too (one value
/// broadcast over N). A lone leading "N" stands for any number of leading dimensions, as NumPy's
/// (..., 8): an (F, J, 8) array is F × J rows. Converts to `dtype` (same as the other inputs:
/// mixing is an error).
BatchInput batch_input(py::handle obj, const std::vector<const char*>& dims, Dtype dtype, const char* name,
                       bool optional_leading = false);

/// A batch argument: an ndarray, or (when pybind11 converts arguments, its second pass over the
/// overloads) a list or tuple. dqkit's value types are not accepted, so a call with values picks
/// the scalar overload of the same name (sclerp(a, b, 1) with an int t included).
struct ArrayLike {
  py::object value;
  operator py::handle() const { return value; }  // NOLINT: implicit, to pass to the helpers below
};

template <class T>
const T* data_of(const BatchInput& in) {
  return static_cast<const T*>(in.array.data());
}


/// Dual quaternions stored as 8 consecutive scalars (w, x, y, z real, then dual) are exactly the
/// memory of DualQuaternion<T> (two Quaternion<T> of four fields, w first): the batch functions
/// reinterpret the NumPy buffers, without copying.
static_assert(sizeof(dq::Quaternion<float>) == 4 * sizeof(float) && sizeof(dq::Quaternion<double>) == 4 * sizeof(double));
static_assert(sizeof(dq::DualQuaternion<float>) == 8 * sizeof(float) && sizeof(dq::DualQuaternion<double>) == 8 * sizeof(double));
static_assert(sizeof(dq::Vec3<double>) == 3 * sizeof(double) && sizeof(dq::Vec3<float>) == 3 * sizeof(float));
static_assert(std::is_standard_layout_v<dq::DualQuaternion<double>> && std::is_standard_layout_v<dq::Vec3<double>>);

template <class X, class T>
const X* as_values(const T* p) {
  return reinterpret_cast<const X*>(p);
}
template <class X, class T>
X* as_values(T* p) {
  return reinterpret_cast<X*>(p);
}

/// (N, 8) float64 array of dual quaternions from a list of them, and back.
py::array_t<double> dual_quaternions_to_numpy(std::span<const dq::DualQuaternion<double>> qs, std::vector<py::ssize_t> shape);
std::vector<dq::DualQuaternion<double>> dual_quaternions_from_numpy(py::handle obj, const char* name);

void bind_values(py::module_& m);
void bind_batch(py::module_& m);
void bind_anim(py::module_& m);
void bind_io(py::module_& m);
void bind_ik(py::module_& m);
void bind_skin(py::module_& m);

}  // namespace dqpy

// Vec3<double> converts from any sequence of three numbers (tuple, list, NumPy array) and to a
// float64 array of shape (3,).
namespace pybind11::detail {
template <>
struct type_caster<dq::Vec3<double>> {
  PYBIND11_TYPE_CASTER(dq::Vec3<double>, const_name("numpy.ndarray"));
  bool load(handle src, bool convert) {
    if (!convert && !isinstance<array>(src)) return false;
    if (isinstance<str>(src) || !(isinstance<sequence>(src) || isinstance<array>(src))) return false;
    const auto a = dqpy::as_float64(src, {3}, "vector");
    value = {a.at(0), a.at(1), a.at(2)};
    return true;
  }
  // A field read through a property (def_readwrite, def_readonly: a reference policy) comes back
  // read-only, so that task.point[0] = 1 fails instead of changing a copy; results are writable.
  static handle cast(const dq::Vec3<double>& v, return_value_policy policy, handle) {
    py::array a = dqpy::vec_to_numpy(v);
    if (policy == return_value_policy::reference_internal || policy == return_value_policy::reference) dqpy::read_only(a);
    return a.release();
  }
};
}  // namespace pybind11::detail

namespace pybind11::detail {
template <>
struct type_caster<dqpy::ArrayLike> {
  PYBIND11_TYPE_CASTER(dqpy::ArrayLike, const_name("numpy.typing.ArrayLike"));
  bool load(handle src, bool convert) {
    if (!isinstance<array>(src) && !(convert && (PyList_Check(src.ptr()) || PyTuple_Check(src.ptr())))) return false;
    value.value = reinterpret_borrow<object>(src);
    return true;
  }
  static handle cast(const dqpy::ArrayLike& a, return_value_policy, handle) { return a.value.inc_ref(); }
};
}  // namespace pybind11::detail

namespace pybind11::detail {
template <>
struct type_caster<dqpy::IntegerArg> {
  PYBIND11_TYPE_CASTER(dqpy::IntegerArg, const_name("int"));
  bool load(handle src, bool) {  // a bool is an int to Python (and NumPy's bool_ has a deprecated __index__), but not a count
    if (!src || PyBool_Check(src.ptr()) || !PyIndex_Check(src.ptr())) return false;
    if (!PyLong_Check(src.ptr()) && isinstance(src, module_::import("numpy").attr("bool_"))) return false;
    value.value = reinterpret_borrow<object>(src);
    return true;
  }
  static handle cast(const dqpy::IntegerArg& a, return_value_policy, handle) { return a.value.inc_ref(); }  // defaults
};
}  // namespace pybind11::detail
