// Batch functions over NumPy arrays: one C++ loop per call, GIL released, float32 and float64,
// the caller's buffers read in place when they are C-contiguous. Shapes: (N, 8) dual quaternions
// (w, x, y, z real, then dual), (N, 4) quaternions, (N, 3) points, (N, 4, 4) / (N, 3, 3)
// matrices indexed [n, row, column]. Every input may also be a single value (shape without N),
// used for all N.
#include "batch.hpp"

#include <algorithm>
#include <array>
#include <utility>

#include "dq/simd/batch.hpp"

namespace dqpy {

std::vector<py::ssize_t> common_leading(std::initializer_list<std::pair<const BatchInput*, const char*>> inputs) {
  const auto text = [](const std::vector<py::ssize_t>& shape) {
    if (shape.size() == 1) return "N = " + std::to_string(shape[0]);
    std::string s = "leading shape (";
    for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
    return s + ")";
  };
  const std::vector<py::ssize_t>* shape = nullptr;  // of the first input with more than one row
  const char* from = nullptr;
  for (const auto& [in, name] : inputs) {
    if (in->single || in->count == 1) continue;  // used for every row
    if (!shape) {
      shape = &in->leading, from = name;
    } else if (in->leading != *shape) {
      throw py::value_error(std::string(name) + ": " + text(in->leading) + " does not match " + from + "'s " + text(*shape));
    }
  }
  if (shape) return *shape;
  // Every input single or of one row: the result has the longest of their leading shapes.
  std::vector<py::ssize_t> longest;
  for (const auto& [in, name] : inputs)
    if (in->leading.size() > longest.size()) longest = in->leading;
  return longest;
}

namespace {

template <class T>
using DQ = dq::DualQuaternion<T>;
template <class T>
using Q = dq::Quaternion<T>;
template <class T>
using V = dq::Vec3<T>;

/// A matrix as NumPy stores it: row-major, [row, column].
template <class T, int R, int C>
struct RowMajor {
  T v[static_cast<std::size_t>(R * C)];
};
template <class T, int R, int C>
RowMajor<T, R, C> row_major(const dq::Mat<T, R, C>& m) {
  RowMajor<T, R, C> out;
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) out.v[r * C + c] = m(r, c);
  return out;
}
template <class T, int R, int C>
dq::Mat<T, R, C> from_row_major(const RowMajor<T, R, C>& a) {
  dq::Mat<T, R, C> m;
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) m(r, c) = a.v[r * C + c];
  return m;
}

template <class T>
using RowMajor4 = RowMajor<T, 4, 4>;
template <class T>
using RowMajor3 = RowMajor<T, 3, 3>;
template <class T>
using RowMajor34 = RowMajor<T, 3, 4>;

const std::vector<const char*> dq_shape{"N", "8"}, q_shape{"N", "4"}, p_shape{"N", "3"}, t_shape{"N"};

// Rows through the dq::simd kernels, which compute the scalar functions bit for bit
// (tests/test_simd.cpp) on the widest instruction set the CPU has. compose, conjugate and the
// transforms of points and directions, float32 and float64: the kernels over arrays of structures,
// which read NumPy's rows in place (transposed in registers). normalized and dlb, float32: the
// kernels over component arrays, the rows converted on the stack and back (dq::simd::to_rows,
// from_rows), kChunk rows at a time, so that nothing is allocated.
constexpr std::size_t kChunk = 256;
/// Eight component arrays of kChunk floats.
struct Chunk {
  alignas(64) std::array<std::array<float, kChunk>, 8> c;
  dq::simd::Rows rows() { return dq::detail::row_of<float>(c, 0); }
  dq::simd::ConstRows rows() const { return dq::detail::row_of<const float>(c, 0); }
};
/// chunk(first, count) over [0, n) in pieces of at most kChunk rows.
template <class F>
void in_chunks(std::size_t n, F chunk) {
  for (std::size_t i = 0; i < n; i += kChunk) chunk(i, std::min(kChunk, n - i));
}
template <class T>
using Rows = std::span<const DQ<T>>;
constexpr auto compose_rows = []<class T>(const DQ<T>* a, const DQ<T>* b, DQ<T>* out, std::size_t n) {
  dq::simd::compose(Rows<T>(a, n), Rows<T>(b, n), std::span<DQ<T>>(out, n));
};
constexpr auto conjugate_rows = []<class T>(const DQ<T>* q, DQ<T>* out, std::size_t n) {
  dq::simd::inverse(Rows<T>(q, n), std::span<DQ<T>>(out, n));  // Q*, bit for bit
};
/// out[i] = q[i] applied to p[i]: the point (Rigid) or the direction.
template <bool Rigid>
auto transform_rows() {
  return []<class T>(const DQ<T>* q, const V<T>* p, V<T>* out, std::size_t n) {
    if constexpr (Rigid)
      dq::simd::transform_points(Rows<T>(q, n), std::span<const V<T>>(p, n), std::span<V<T>>(out, n));
    else
      dq::simd::transform_directions(Rows<T>(q, n), std::span<const V<T>>(p, n), std::span<V<T>>(out, n));
  };
}
/// out[i] = q applied to p[i] for one q and rows of points, which the kernel reads and writes directly.
template <bool Rigid>
auto transform_cloud() {
  return []<class T>(const DQ<T>& q, const V<T>* p, V<T>* out, std::size_t n) {
    if constexpr (Rigid)
      dq::simd::transform_points(q, std::span<const V<T>>(p, n), std::span<V<T>>(out, n));
    else
      dq::simd::transform_directions(q, std::span<const V<T>>(p, n), std::span<V<T>>(out, n));
  };
}
void normalize32(const DQ<float>* q, DQ<float>* out, std::size_t n) {
  Chunk c;
  in_chunks(n, [&](std::size_t i, std::size_t m) {
    dq::simd::to_rows({q + i, m}, c.rows());
    dq::simd::normalize(std::as_const(c).rows(), c.rows(), m);
    dq::simd::from_rows(std::as_const(c).rows(), {out + i, m});
  });
}
void dlb32(const DQ<float>* a, const DQ<float>* b, float t, DQ<float>* out, std::size_t n) {
  Chunk ca, cb;
  in_chunks(n, [&](std::size_t i, std::size_t m) {
    dq::simd::to_rows({a + i, m}, ca.rows());
    dq::simd::to_rows({b + i, m}, cb.rows());
    dq::simd::dlb(std::as_const(ca).rows(), std::as_const(cb).rows(), t, ca.rows(), m);
    dq::simd::from_rows(std::as_const(ca).rows(), {out + i, m});
  });
}

void bind_products(py::module_& m) {
  m.def("compose", [](ArrayLike a, ArrayLike b) {
    return map2<DQ, DQ, DQ>(a, b, "a", "b", dq_shape, dq_shape, {8}, [](const auto& x, const auto& y) { return x * y; }, compose_rows);
  }, py::arg("a"), py::arg("b"), "Row-wise products a[i] b[i] of (N, 8) dual quaternions (b applied first).");
  m.def("quaternion_product", [](ArrayLike a, ArrayLike b) {
    return map2<Q, Q, Q>(a, b, "a", "b", q_shape, q_shape, {4}, [](const auto& x, const auto& y) { return x * y; });
  }, py::arg("a"), py::arg("b"), "Row-wise Hamilton products of (N, 4) quaternions.");
  m.def("transform_points", [](ArrayLike q, ArrayLike p) {
    return map2<DQ, V, V>(q, p, "q", "p", dq_shape, p_shape, {3}, [](const auto& x, const auto& y) { return x.transform_point(y); },
                          transform_rows<true>(), transform_cloud<true>());
  }, py::arg("q"), py::arg("p"), "R p + t for (N, 8) unit dual quaternions and (N, 3) points.");
  m.def("transform_directions", [](ArrayLike q, ArrayLike v) {
    return map2<DQ, V, V>(q, v, "q", "v", dq_shape, p_shape, {3}, [](const auto& x, const auto& y) { return x.transform_direction(y); },
                          transform_rows<false>(), transform_cloud<false>());
  }, py::arg("q"), py::arg("v"), "R v for (N, 8) unit dual quaternions and (N, 3) directions.");
  m.def("rotate", [](ArrayLike q, ArrayLike v) {
    return map2<Q, V, V>(q, v, "q", "v", q_shape, p_shape, {3}, [](const auto& x, const auto& y) { return x.rotate(y); });
  }, py::arg("q"), py::arg("v"), "q v q* for (N, 4) unit quaternions and (N, 3) vectors.");
  m.def("normalized", [](ArrayLike q) {
    return map1<DQ, DQ>(q, "q", dq_shape, {8}, [](const auto& x) { return x.normalized(); }, normalize32);
  }, py::arg("q"), "Each (N, 8) dual quaternion made unit (DualQuaternion.normalized).");
  m.def("conjugate", [](ArrayLike q) {
    return map1<DQ, DQ>(q, "q", dq_shape, {8}, [](const auto& x) { return x.conjugate(); }, conjugate_rows);
  }, py::arg("q"), "Q* of each (N, 8) dual quaternion: the inverse of a unit one.");
}

void bind_conversions(py::module_& m) {
  m.def("to_mat4", [](ArrayLike q) {
    return map1<DQ, RowMajor4>(q, "q", dq_shape, {4, 4}, [](const auto& x) { return row_major(dq::to_mat4(x)); });
  }, py::arg("q"), "(N, 4, 4) matrices [n, row, column] of (N, 8) unit dual quaternions.");
  m.def("quaternion_to_matrix", [](ArrayLike q) {
    return map1<Q, RowMajor3>(q, "q", q_shape, {3, 3}, [](const auto& x) { return row_major(x.to_matrix()); });
  }, py::arg("q"), "(N, 3, 3) rotation matrices of (N, 4) unit quaternions (Quaternion.to_matrix).");
  m.def("quaternion_from_matrix", [](ArrayLike mat) {
    return map1<RowMajor3, Q>(mat, "matrix", {"N", "3", "3"}, {4}, [](const auto& x) {
      using T = std::remove_cvref_t<decltype(x.v[0])>;
      return Q<T>::from_matrix(from_row_major(x));
    });
  }, py::arg("matrix"), "(N, 4) unit quaternions of (N, 3, 3) rotation matrices (Quaternion.from_matrix).");
  m.def("from_rotation_translation", [](ArrayLike r, ArrayLike t) {
    return map2<Q, V, DQ>(r, t, "r", "t", q_shape, p_shape, {8}, [](const auto& x, const auto& y) {
      return std::remove_cvref_t<decltype(dq::DualQuaternion(x, x))>::from_rotation_translation(x, y);
    });
  }, py::arg("r"), py::arg("t"), "(N, 8) transforms: rotate by r[i], then translate by t[i].");
  m.def("translation", [](ArrayLike q) {
    return map1<DQ, V>(q, "q", dq_shape, {3}, [](const auto& x) { return x.translation(); });
  }, py::arg("q"), "(N, 3) translations 2 q_d q_r* of (N, 8) unit dual quaternions.");
  m.def("rotation", [](ArrayLike q) {
    return map1<DQ, Q>(q, "q", dq_shape, {4}, [](const auto& x) { return x.real; });
  }, py::arg("q"), "(N, 4) rotations (the real parts) of (N, 8) dual quaternions.");
  m.def("from_rotation_vector", [](ArrayLike v) {
    return map1<V, Q>(v, "v", p_shape, {4}, [](const auto& x) {
      using T = std::remove_cvref_t<decltype(x.x)>;
      return Q<T>::from_rotation_vector(x);
    });
  }, py::arg("v"), "(N, 4) rotations of (N, 3) rotation vectors.");
  m.def("to_rotation_vector", [](ArrayLike q) {
    return map1<Q, V>(q, "q", q_shape, {3}, [](const auto& x) { return x.to_rotation_vector(); });
  }, py::arg("q"), "(N, 3) rotation vectors (angle in [0, π]) of (N, 4) unit quaternions.");
  m.def("from_euler", [](dq::EulerOrder order, dq::EulerFrame frame, ArrayLike angles) {
    return map1<V, Q>(angles, "angles", p_shape, {4}, [&](const auto& x) { return dq::from_euler(order, frame, x.x, x.y, x.z); });
  }, py::arg("order"), py::arg("frame"), py::arg("angles"), "(N, 4) rotations of (N, 3) Euler triples (a, b, c).");
  m.def("to_euler", [](ArrayLike q, dq::EulerOrder order, dq::EulerFrame frame) {
    return with_dtype(call_dtype(q, "q"), [&]<class T>() -> py::tuple {
      const BatchInput in = batch_input(q, q_shape, dtype_of_v<T>, "q", true);
      py::array_t<T> angles(out_shape(in.leading, {3}));
      py::array_t<bool> singular(out_shape(in.leading, {}));
      const Q<T>* x = as_values<Q<T>>(data_of<T>(in));
      T* a = angles.mutable_data();
      bool* flags = singular.mutable_data();
      {
        py::gil_scoped_release release;
        for (std::size_t i = 0; i < in.count; ++i) {
          const dq::EulerExtraction<T> e = dq::to_euler(x[i], order, frame);
          a[3 * i] = e.angles.a, a[3 * i + 1] = e.angles.b, a[3 * i + 2] = e.angles.c;
          flags[i] = e.singular;
        }
      }
      return py::make_tuple(angles, singular);
    });
  }, py::arg("q"), py::arg("order"), py::arg("frame"),
     "Euler triples (N, 3) and gimbal-lock flags (N,) of (N, 4) unit quaternions.");
}

void bind_interpolation(py::module_& m) {
  m.def("slerp", [](ArrayLike a, ArrayLike b, py::object t, dq::Path path) {
    return map3<Q, Q, Q>(a, b, t, "a", "b", q_shape, q_shape, {4},
                         [path](const auto& x, const auto& y, auto s) { return dq::slerp(x, y, s, path); });
  }, py::arg("a"), py::arg("b"), py::arg("t"), py::arg("path") = dq::Path::shortest,
     "Row-wise slerp of (N, 4) quaternions; t a number or (N,).");
  m.def("sclerp", [](ArrayLike a, ArrayLike b, py::object t, dq::Path path) {
    return map3<DQ, DQ, DQ>(a, b, t, "a", "b", dq_shape, dq_shape, {8},
                            [path](const auto& x, const auto& y, auto s) { return dq::sclerp(x, y, s, path); });
  }, py::arg("a"), py::arg("b"), py::arg("t"), py::arg("path") = dq::Path::shortest,
     "Row-wise screw interpolation of (N, 8) unit dual quaternions; t a number or (N,).");
  m.def("dlb", [](ArrayLike a, ArrayLike b, py::object t) {
    return map3<DQ, DQ, DQ>(a, b, t, "a", "b", dq_shape, dq_shape, {8},
                            [](const auto& x, const auto& y, auto s) { return dq::dlb(x, y, s); }, dlb32);
  }, py::arg("a"), py::arg("b"), py::arg("t"), "Row-wise dual quaternion linear blending of (N, 8) keys; t a number or (N,).");
}

}  // namespace

py::array from_matrix_rows(const py::array& matrices) {
  if (matrices.ndim() >= 2 && matrices.shape(matrices.ndim() - 2) == 3)
    return map1<RowMajor34, DQ>(matrices, "matrix", {"N", "3", "4"}, {8}, [](const auto& x) { return dq::from_matrix(from_row_major(x)); });
  return map1<RowMajor4, DQ>(matrices, "matrix", {"N", "4", "4"}, {8}, [](const auto& x) { return dq::from_matrix(from_row_major(x)); });
}

void bind_batch(py::module_& m) {
  bind_products(m);
  bind_conversions(m);
  bind_interpolation(m);
}

}  // namespace dqpy
