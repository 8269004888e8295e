#include "common.hpp"

#include <algorithm>
#include <limits>

namespace dqpy {

namespace {
std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}
bool is_fixed(const char* d) { return d[0] >= '0' && d[0] <= '9'; }
}  // namespace

std::string shape_text(const std::vector<const char*>& dims) {
  std::string s = "(";
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i) s += ", ";
    s += dims[i];
  }
  return s + (dims.size() == 1 ? ",)" : ")");
}

template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> contiguous(py::handle obj, const char* what) {
  // Through NumPy itself rather than array_t::ensure, which returns null for any failure and
  // clears the reason: a MemoryError (a broadcast view of 10^11 rows) stays a MemoryError, and a
  // value that is not a number says which.
  try {
    py::object a = py::module_::import("numpy").attr("asarray")(obj, py::dtype::of<T>(), py::arg("order") = "C");
    return py::reinterpret_steal<py::array_t<T, py::array::c_style | py::array::forcecast>>(a.release());
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) throw;
    throw py::value_error(std::string(what) + ": expected numbers convertible to " +
                          (std::is_same_v<T, float> ? "float32" : "float64") + " (" + py::str(e.value()).cast<std::string>() + ")");
  }
}

py::array_t<double, py::array::c_style | py::array::forcecast> as_float64(py::handle obj, std::vector<py::ssize_t> shape,
                                                                           const char* what, std::vector<const char*> names) {
  auto a = contiguous<double>(obj, what);
  bool ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t i = 0; ok && i < shape.size(); ++i) ok = shape[i] < 0 || a.shape(static_cast<py::ssize_t>(i)) == shape[i];
  if (!ok) {
    std::vector<std::string> extents;
    std::size_t named = 0;
    for (const auto e : shape) extents.push_back(e >= 0 ? std::to_string(e) : named < names.size() ? names[named++] : "N");
    std::vector<const char*> dims;
    for (const auto& e : extents) dims.push_back(e.c_str());
    throw py::value_error(std::string(what) + ": expected shape " + shape_text(dims) + ", got " + shape_of(a));
  }
  return a;
}

py::array_t<std::int64_t, py::array::c_style> as_integers(py::handle obj, int ndim, const std::string& what, bool signed_only) {
  py::array any;
  try {
    any = py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) throw;
    throw py::value_error(what + " (" + py::str(e.value()).cast<std::string>() + ")");
  }
  if (any.ndim() != ndim) throw py::value_error(what + ", got shape " + shape_of(any));
  const std::string kind = any.attr("dtype").attr("kind").cast<std::string>();
  if (any.size() > 0 && kind != "i" && (signed_only || kind != "u")) throw py::value_error(what + ", got dtype " + py::str(any.dtype()).cast<std::string>());
  if (any.size() > 0 && kind == "u" && any.attr("max")().cast<unsigned long long>() > static_cast<unsigned long long>(INT64_MAX))
    throw py::value_error(what + ", got a value beyond 2**63 - 1");  // the int64 cast would wrap it
  return py::reinterpret_steal<py::array_t<std::int64_t, py::array::c_style>>(
      py::module_::import("numpy").attr("ascontiguousarray")(any, py::dtype::of<std::int64_t>()).release());
}

namespace {
py::object index_of(const IntegerArg& value) {  // the int that value's __index__ gives
  py::object n = py::reinterpret_steal<py::object>(PyNumber_Index(value.value.ptr()));
  if (!n) throw py::error_already_set();  // an __index__ that raised
  return n;
}
}  // namespace

unsigned thread_count(const IntegerArg& threads, unsigned most) {
  const py::object n = index_of(threads);
  int overflow = 0;
  const long long count = PyLong_AsLongLongAndOverflow(n.ptr(), &overflow);
  if (overflow != 0 || count < 0 || count > most)
    throw py::value_error("threads: expected 0 (every hardware thread) or a number of threads up to " + std::to_string(most) +
                          ", got " + std::string(py::str(n)));
  return static_cast<unsigned>(count);
}

std::size_t size_count(const IntegerArg& value, const char* name) {
  const py::object n = index_of(value);
  const unsigned long long count = PyLong_AsUnsignedLongLong(n.ptr());
  if (PyErr_Occurred() || count > std::numeric_limits<std::size_t>::max()) {
    PyErr_Clear();  // negative or too large: OverflowError, reported as the ValueError below
    throw py::value_error(std::string(name) + ": expected a count from 0 to " + std::to_string(std::numeric_limits<std::size_t>::max()) +
                          ", got " + std::string(py::str(n)));
  }
  return static_cast<std::size_t>(count);
}

void require_existing(const std::filesystem::path& path) {
  std::error_code ec;  // through symbolic links: a dangling one has nothing there
  if (std::filesystem::exists(std::filesystem::status(path, ec)) || (ec && ec != std::errc::no_such_file_or_directory)) return;
  PyObject* name = PyUnicode_DecodeFSDefault(path.c_str());
  if (!name) throw py::error_already_set();
  PyObject* args = Py_BuildValue("(isN)", ENOENT, std::strerror(ENOENT), name);
  if (!args) throw py::error_already_set();
  PyErr_SetObject(PyExc_FileNotFoundError, args);
  Py_DECREF(args);
  throw py::error_already_set();
}

Dtype call_dtype(py::handle first, const char* name) {
  return py::isinstance<py::array>(first) ? dtype_of(py::reinterpret_borrow<py::array>(first), name) : Dtype::f64;
}

Dtype dtype_of(const py::array& a, const char* name) {
  if (a.dtype().is(py::dtype::of<float>())) return Dtype::f32;
  if (a.dtype().is(py::dtype::of<double>())) return Dtype::f64;
  throw py::value_error(std::string(name) + ": expected dtype float32 or float64, got " + py::str(a.dtype()).cast<std::string>());
}

BatchInput batch_input(py::handle obj, const std::vector<const char*>& dims, Dtype dtype, const char* name, bool optional_leading) {
  py::array a = py::array::ensure(obj);
  if (!a) {
    throw py::value_error(std::string(name) + ": expected an array of shape " + shape_text(dims));
  }
  // An ndarray keeps its dtype (float32 or float64, the same for every input of a call); lists,
  // tuples and objects with __array__ take the call's.
  if (py::isinstance<py::array>(obj) && dtype_of(a, name) != dtype)
    throw py::value_error(std::string(name) + ": dtype " + py::str(a.dtype()).cast<std::string>() +
                          " does not match the other inputs' " + (dtype == Dtype::f32 ? "float32" : "float64"));
  py::array c = dtype == Dtype::f32 ? py::array(contiguous<float>(a, name)) : py::array(contiguous<double>(a, name));
  // Rows are read as dq::DualQuaternion<T> etc.: an unaligned buffer (np.frombuffer at an odd
  // offset) is copied into an aligned one first.
  if (!(py::detail::array_proxy(c.ptr())->flags & py::detail::npy_api::NPY_ARRAY_ALIGNED_)) c = c.attr("copy")();
  const std::size_t want = dims.size();
  if (optional_leading && want >= 1 && std::string_view(dims[0]) == "N" && std::all_of(dims.begin() + 1, dims.end(), is_fixed)) {
    const std::size_t tail = want - 1, ndim = static_cast<std::size_t>(c.ndim());
    bool ok = ndim >= tail;
    for (std::size_t i = 0; ok && i < tail; ++i) ok = c.shape(static_cast<py::ssize_t>(ndim - tail + i)) == std::stol(dims[1 + i]);
    if (!ok)
    {  // NumPy's notation: "..." for any leading dimensions, none included
      std::vector<const char*> any(dims.begin(), dims.end());
      any[0] = "...";
      throw py::value_error(std::string(name) + ": expected shape " + shape_text(any) + ", got " + shape_of(a));
    }
    std::vector<py::ssize_t> leading(c.shape(), c.shape() + (ndim - tail));
    std::size_t count = 1;
    for (const py::ssize_t e : leading) count *= static_cast<std::size_t>(e);
    const bool single = leading.empty();
    return {std::move(c), count, single, std::move(leading)};
  }
  const bool full = static_cast<std::size_t>(c.ndim()) == want;
  const bool short_form = optional_leading && static_cast<std::size_t>(c.ndim()) + 1 == want;
  bool ok = full || short_form;
  const std::size_t skip = full ? 0 : 1;
  std::size_t count = 1;
  std::vector<py::ssize_t> leading;
  for (std::size_t i = skip; ok && i < want; ++i) {
    const auto extent = c.shape(static_cast<py::ssize_t>(i - skip));
    if (is_fixed(dims[i])) {
      ok = extent == std::stol(dims[i]);
    } else {
      count *= static_cast<std::size_t>(extent);
      leading.push_back(extent);
    }
  }
  if (!ok) {
    std::string expected = shape_text(dims);
    if (optional_leading) expected += " or " + shape_text(std::vector<const char*>(dims.begin() + 1, dims.end()));
    throw py::value_error(std::string(name) + ": expected shape " + expected + ", got " + shape_of(a));
  }
  return {std::move(c), count, short_form, std::move(leading)};
}

py::array_t<double> dual_quaternions_to_numpy(std::span<const dq::DualQuaternion<double>> qs, std::vector<py::ssize_t> shape) {
  py::array_t<double> a(std::move(shape));
  std::memcpy(a.mutable_data(), qs.data(), qs.size() * sizeof(dq::DualQuaternion<double>));
  return a;
}

std::vector<dq::DualQuaternion<double>> dual_quaternions_from_numpy(py::handle obj, const char* name) {
  const auto a = as_float64(obj, {-1, 8}, name);
  std::vector<dq::DualQuaternion<double>> out(static_cast<std::size_t>(a.shape(0)));
  std::memcpy(static_cast<void*>(out.data()), a.data(), out.size() * sizeof(dq::DualQuaternion<double>));
  return out;
}

}  // namespace dqpy
