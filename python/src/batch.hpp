// The element-wise machinery of the batch functions (batch.cpp, and the skeleton batch in anim.cpp).
#pragma once

#include "common.hpp"

namespace dqpy {

/// Runs `f.template operator()<T>()` with T = float or double.
template <class F>
decltype(auto) with_dtype(Dtype d, F&& f) {
  if (d == Dtype::f32) return f.template operator()<float>();
  return f.template operator()<double>();
}

/// The leading extents of a call's result: those of its inputs that are not single values (or of
/// N = 1, which is used for every row too); ValueError when two differ.
std::vector<py::ssize_t> common_leading(std::initializer_list<std::pair<const BatchInput*, const char*>> inputs);
/// The number of rows of leading extents.
inline std::size_t row_count(const std::vector<py::ssize_t>& leading) {
  std::size_t n = 1;
  for (const py::ssize_t e : leading) n *= static_cast<std::size_t>(e);
  return n;
}

inline std::vector<py::ssize_t> out_shape(const std::vector<py::ssize_t>& leading, const std::vector<py::ssize_t>& tail) {
  std::vector<py::ssize_t> s = leading;
  s.insert(s.end(), tail.begin(), tail.end());
  return s;
}

/// Whether `rows`, a batch function's kernel over whole arrays of rows (a dq::simd kernel, bit for
/// bit its per-row function), takes arguments `A...` (rows of the call's dtype): nullptr for none.
template <class Rows, class... A>
constexpr bool kHasRows = !std::is_null_pointer_v<Rows> && std::is_invocable_v<Rows&, A...>;

/// out[i] = f(a[i]) over the rows of `a`, items reinterpreted as A<T> and R<T>. `rows`, where
/// given, computes the same in one call (`rows(x, o, n)`) for the dtypes it takes.
template <template <class> class A, template <class> class R, class F, class Rows = std::nullptr_t>
py::array map1(py::handle a, const char* name, const std::vector<const char*>& shape, const std::vector<py::ssize_t>& tail, F f,
               Rows rows = nullptr) {
  return with_dtype(call_dtype(a, name), [&]<class T>() -> py::array {
    const BatchInput in = batch_input(a, shape, dtype_of_v<T>, name, true);
    py::array_t<T> out(out_shape(in.leading, tail));
    const A<T>* x = as_values<A<T>>(data_of<T>(in));
    R<T>* o = as_values<R<T>>(out.mutable_data());
    py::gil_scoped_release release;
    if constexpr (kHasRows<Rows, const A<T>*, R<T>*, std::size_t>)
      rows(x, o, in.count);
    else
      for (std::size_t i = 0; i < in.count; ++i) o[i] = f(x[i]);
    return out;
  });
}

/// out[i] = f(a[i], b[i]); a single a or b is used for every row. `rows`, where given, computes
/// the same for rows of a and b in one call (`rows(x, y, o, n)`), unless a or b is single;
/// `one_by_rows`, where given, for one a and rows of b (`one_by_rows(x, y, o, n)`); each for the
/// dtypes it takes.
template <template <class> class A, template <class> class B, template <class> class R, class F, class Rows = std::nullptr_t,
          class OneByRows = std::nullptr_t>
py::array map2(py::handle a, py::handle b, const char* na, const char* nb, const std::vector<const char*>& sa,
               const std::vector<const char*>& sb, const std::vector<py::ssize_t>& tail, F f, Rows rows = nullptr,
               OneByRows one_by_rows = nullptr) {
  return with_dtype(call_dtype(a, na), [&]<class T>() -> py::array {
    const BatchInput ia = batch_input(a, sa, dtype_of_v<T>, na, true), ib = batch_input(b, sb, dtype_of_v<T>, nb, true);
    const std::vector<py::ssize_t> leading = common_leading({{&ia, na}, {&ib, nb}});
    const std::size_t n = row_count(leading);
    const std::size_t da = ia.count == 1 ? 0 : 1, db = ib.count == 1 ? 0 : 1;
    py::array_t<T> out(out_shape(leading, tail));
    const A<T>* x = as_values<A<T>>(data_of<T>(ia));
    const B<T>* y = as_values<B<T>>(data_of<T>(ib));
    R<T>* o = as_values<R<T>>(out.mutable_data());
    py::gil_scoped_release release;
    if constexpr (kHasRows<Rows, const A<T>*, const B<T>*, R<T>*, std::size_t>) {
      if (da == 1 && db == 1) {
        rows(x, y, o, n);
        return out;
      }
    }
    if constexpr (kHasRows<OneByRows, const A<T>&, const B<T>*, R<T>*, std::size_t>) {
      if (da == 0 && db == 1) {
        one_by_rows(x[0], y, o, n);
        return out;
      }
    }
    for (std::size_t i = 0; i < n; ++i) o[i] = f(x[i * da], y[i * db]);
    return out;
  });
}

/// The t of an interpolation as batch_input takes it: an ndarray of one or more dimensions (its
/// dtype must match the call's) or a list or tuple as given; a number (Python, NumPy, or a 0-d
/// array) as a 0-d array of the call's dtype; anything else a TypeError.
template <class T>
py::object interpolation_parameter(const py::object& t) {
  if ((py::isinstance<py::array>(t) && py::array(t).ndim() > 0) || PyList_Check(t.ptr()) || PyTuple_Check(t.ptr())) return t;
  // A number: Python's or NumPy's (a 0-d array or a scalar), real (a complex one would lose its
  // imaginary part with a mere warning).
  const std::string kind = py::hasattr(t, "dtype") ? t.attr("dtype").attr("kind").cast<std::string>() : std::string();
  const bool real = kind.empty() ? !PyComplex_Check(t.ptr()) : kind == "f" || kind == "i" || kind == "u" || kind == "b";
  if (py::isinstance<py::str>(t) || !real || (kind.empty() && !PyNumber_Check(t.ptr())))
    throw py::type_error("t: expected a real number or an (N,) array of numbers, got " + py::str(py::type::of(t).attr("__name__")).cast<std::string>());
  const T value = static_cast<T>(py::float_(t).cast<double>());
  return py::array_t<T>(std::vector<py::ssize_t>{}, &value);
}

/// out[i] = f(a[i], b[i], t[i]) with t a number or an (N,) array. `rows`, where given, computes
/// the same for rows of a and b and one t in one call (`rows(x, y, t, o, n)`) for the dtypes it takes.
template <template <class> class A, template <class> class B, template <class> class R, class F, class Rows = std::nullptr_t>
py::array map3(py::handle a, py::handle b, const py::object& t, const char* na, const char* nb,
               const std::vector<const char*>& sa, const std::vector<const char*>& sb, const std::vector<py::ssize_t>& tail, F f,
               Rows rows = nullptr) {
  return with_dtype(call_dtype(a, na), [&]<class T>() -> py::array {
    const BatchInput ia = batch_input(a, sa, dtype_of_v<T>, na, true), ib = batch_input(b, sb, dtype_of_v<T>, nb, true);
    const BatchInput it = batch_input(interpolation_parameter<T>(t), {"N"}, dtype_of_v<T>, "t", true);
    const std::vector<py::ssize_t> leading = common_leading({{&ia, na}, {&ib, nb}, {&it, "t"}});
    const std::size_t n = row_count(leading);
    const std::size_t da = ia.count == 1 ? 0 : 1, db = ib.count == 1 ? 0 : 1, dt = it.count == 1 ? 0 : 1;
    py::array_t<T> out(out_shape(leading, tail));
    const A<T>* x = as_values<A<T>>(data_of<T>(ia));
    const B<T>* y = as_values<B<T>>(data_of<T>(ib));
    const T* s = data_of<T>(it);
    R<T>* o = as_values<R<T>>(out.mutable_data());
    py::gil_scoped_release release;
    if constexpr (kHasRows<Rows, const A<T>*, const B<T>*, T, R<T>*, std::size_t>) {
      if (da == 1 && db == 1 && dt == 0) {
        rows(x, y, s[0], o, n);
        return out;
      }
    }
    for (std::size_t i = 0; i < n; ++i) o[i] = f(x[i * da], y[i * db], s[i * dt]);
    return out;
  });
}

/// (..., 8) unit dual quaternions of (..., 4, 4) or (..., 3, 4) rigid transforms (the batch form
/// of from_matrix, which dispatches on the number of dimensions).
py::array from_matrix_rows(const py::array& matrices);

}  // namespace dqpy
