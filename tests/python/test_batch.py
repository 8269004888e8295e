"""Batch functions: against the scalar API (the same C++ formulas, so float64 results are equal
bit for bit), against NumPy formulas, float32 against float64, shapes, errors and threads."""
import threading
import time

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

import dqkit
from conftest import hamilton, random_rigid, random_unit_quaternions, rotation_matrix

EPS64 = np.finfo(np.float64).eps
# float32 against float64 on unit-size values: the float32 computation is a few dozen roundings
# of 6e-8 each; 256 ulps of float32 bounds it with room and is far below any formula error.
TOL32 = 256 * np.finfo(np.float32).eps


def dqs(q8):
    return [dqkit.DualQuaternion(q) for q in q8]


def test_compose_matches_scalar_and_numpy(rng):
    a, _, _ = random_rigid(rng, 100)
    b, _, _ = random_rigid(rng, 100)
    out = dqkit.compose(a, b)
    assert out.shape == (100, 8) and out.dtype == np.float64
    np.testing.assert_array_equal(out, [np.asarray(x * y) for x, y in zip(dqs(a), dqs(b))])
    real = hamilton(a[:, :4], b[:, :4])
    dual = hamilton(a[:, :4], b[:, 4:]) + hamilton(a[:, 4:], b[:, :4])
    np.testing.assert_allclose(out, np.concatenate([real, dual], 1), atol=64 * EPS64 * 4)
    np.testing.assert_array_equal(dqkit.quaternion_product(a[:, :4], b[:, :4]),
                                  [np.asarray(dqkit.Quaternion(x) * dqkit.Quaternion(y)) for x, y in zip(a[:, :4], b[:, :4])])


def test_transform_points_and_broadcasting(rng):
    q, r, t = random_rigid(rng, 50)
    p = rng.normal(size=(50, 3))
    out = dqkit.transform_points(q, p)
    np.testing.assert_array_equal(out, [x.transform_point(y) for x, y in zip(dqs(q), p)])
    np.testing.assert_allclose(out, np.einsum("nij,nj->ni", rotation_matrix(r), p) + t, atol=64 * EPS64 * 4)
    # One transform for every point, and one point for every transform.
    np.testing.assert_array_equal(dqkit.transform_points(q[0], p), [dqs(q)[0].transform_point(y) for y in p])
    np.testing.assert_array_equal(dqkit.transform_points(q, p[0]), [x.transform_point(p[0]) for x in dqs(q)])
    assert dqkit.transform_points(q[0], p[0]).shape == (3,)
    np.testing.assert_array_equal(dqkit.transform_directions(q, p), [x.transform_direction(y) for x, y in zip(dqs(q), p)])
    np.testing.assert_array_equal(dqkit.rotate(q[:, :4], p), [dqkit.Quaternion(x).rotate(y) for x, y in zip(q[:, :4], p)])


def test_conversions_match_scalar_and_scipy(rng):
    q, r, t = random_rigid(rng, 40)
    m = dqkit.to_mat4(q)
    assert m.shape == (40, 4, 4)
    np.testing.assert_array_equal(m, [dqkit.to_mat4(x) for x in dqs(q)])
    np.testing.assert_allclose(m[:, :3, :3], Rotation.from_quat(np.c_[r[:, 1:], r[:, :1]]).as_matrix(), atol=64 * EPS64)
    np.testing.assert_allclose(m[:, :3, 3], t, atol=64 * EPS64 * 4)
    back = dqkit.from_matrix(m)
    np.testing.assert_array_equal(back, [np.asarray(dqkit.from_matrix(x)) for x in m])
    np.testing.assert_array_equal(dqkit.quaternion_to_matrix(r), [dqkit.Quaternion(x).to_matrix() for x in r])
    np.testing.assert_array_equal(dqkit.quaternion_from_matrix(rotation_matrix(r)),
                                  [np.asarray(dqkit.Quaternion.from_matrix(x)) for x in rotation_matrix(r)])
    np.testing.assert_array_equal(dqkit.from_rotation_translation(r, t),
                                  [np.asarray(dqkit.DualQuaternion.from_rotation_translation(dqkit.Quaternion(x), y)) for x, y in zip(r, t)])
    np.testing.assert_array_equal(dqkit.translation(q), [x.translation() for x in dqs(q)])
    np.testing.assert_array_equal(dqkit.rotation(q), r)
    v = dqkit.to_rotation_vector(r)
    np.testing.assert_allclose(Rotation.from_rotvec(v).as_matrix(), rotation_matrix(r), atol=64 * EPS64)
    np.testing.assert_array_equal(dqkit.from_rotation_vector(v), [np.asarray(dqkit.Quaternion.from_rotation_vector(x)) for x in v])
    angles = rng.uniform(-1.2, 1.2, size=(40, 3))
    e = dqkit.from_euler(dqkit.EulerOrder.ZXY, dqkit.EulerFrame.intrinsic, angles)
    np.testing.assert_allclose(dqkit.quaternion_to_matrix(e), Rotation.from_euler("ZXY", angles).as_matrix(), atol=64 * EPS64)
    back_angles, singular = dqkit.to_euler(e, dqkit.EulerOrder.ZXY, dqkit.EulerFrame.intrinsic)
    assert singular.shape == (40,) and not singular.any()
    np.testing.assert_allclose(back_angles, angles, atol=1e3 * EPS64)


def test_interpolation_matches_scalar(rng):
    a, _, _ = random_rigid(rng, 30)
    b, _, _ = random_rigid(rng, 30)
    t = rng.uniform(0, 1, 30)
    np.testing.assert_array_equal(dqkit.sclerp(a, b, t), [np.asarray(dqkit.sclerp(x, y, s)) for x, y, s in zip(dqs(a), dqs(b), t)])
    np.testing.assert_array_equal(dqkit.sclerp(a, b, 0.25), [np.asarray(dqkit.sclerp(x, y, 0.25)) for x, y in zip(dqs(a), dqs(b))])
    np.testing.assert_array_equal(dqkit.dlb(a, b, t), [np.asarray(dqkit.dlb(x, y, s)) for x, y, s in zip(dqs(a), dqs(b), t)])
    qa, qb = a[:, :4], b[:, :4]
    np.testing.assert_array_equal(dqkit.slerp(qa, qb, t),
                                  [np.asarray(dqkit.slerp(dqkit.Quaternion(x), dqkit.Quaternion(y), s)) for x, y, s in zip(qa, qb, t)])
    # One key interpolated towards many, over a time axis.
    assert dqkit.sclerp(a[0], b, 0.5).shape == (30, 8)
    assert dqkit.sclerp(a[0], b[0], np.linspace(0, 1, 11)).shape == (11, 8)


@pytest.mark.parametrize("name", ["compose", "sclerp", "dlb", "transform_points", "to_mat4", "normalized"])
def test_float32_matches_float64(name, rng):
    a, _, _ = random_rigid(rng, 64, scale=1.0)
    b, _, _ = random_rigid(rng, 64, scale=1.0)
    p = rng.normal(size=(64, 3))
    args = {"compose": (a, b), "sclerp": (a, b, 0.3), "dlb": (a, b, 0.3), "transform_points": (a, p),
            "to_mat4": (a,), "normalized": (a,)}[name]
    f = getattr(dqkit, name)
    r64 = f(*args)
    r32 = f(*(x.astype(np.float32) if isinstance(x, np.ndarray) else x for x in args))
    assert r32.dtype == np.float32 and r64.dtype == np.float64 and r32.shape == r64.shape
    np.testing.assert_allclose(r32, r64, atol=TOL32 * 4)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_rows_take_the_vector_kernels_bit_for_bit(rng, dtype):
    """Rows of compose, transform_points, transform_directions and conjugate, in float32 and float64
    (dq::simd's kernels over arrays of structures, on the rows in place), and float32 rows of
    normalized and dlb (one t; its kernels over component arrays, in chunks of 256 rows converted on
    the stack): each row's result is, bit for bit, the one computed for that row alone (a single row
    runs the scalar function). float64 normalized and dlb run the scalar function on both sides."""
    n = 1003  # three whole chunks and a tail that is no multiple of any vector width
    bits = np.uint32 if dtype == np.float32 else np.uint64
    a = random_rigid(rng, n)[0].astype(dtype)
    b = random_rigid(rng, n)[0].astype(dtype)
    p = rng.normal(size=(n, 3)).astype(dtype)
    scaled = a * rng.uniform(0.5, 2.0, size=(n, 1)).astype(dtype)
    scaled[7, :4] = 0  # normalize's other branches: a zero real part, a NaN, a dual part along the real one
    scaled[300, 5] = np.nan
    scaled[700, 4:] = 3 * scaled[700, :4]
    for f, args in ((dqkit.compose, (a, b)), (dqkit.transform_points, (a, p)), (dqkit.transform_directions, (a, p)),
                    (dqkit.normalized, (scaled,)), (dqkit.conjugate, (scaled,))):
        whole = f(*args)
        assert whole.dtype == dtype
        alone = np.array([f(*(x[i] for x in args)) for i in range(n)])
        np.testing.assert_array_equal(whole.view(bits), alone.view(bits), err_msg=f.__name__)
    # One transform for every point (a cloud: dq::simd's one-transform kernels, the rows read and
    # written in place): each point bit for bit the point moved alone.
    for f in (dqkit.transform_points, dqkit.transform_directions):
        whole = f(a[5], p)
        assert whole.dtype == dtype and whole.shape == (n, 3)
        alone = np.array([f(a[5], p[i]) for i in range(n)])
        np.testing.assert_array_equal(whole.view(bits), alone.view(bits), err_msg=f.__name__ + ", one transform")
        # Other shapes of the same call: leading dimensions with q as (1, 8), rows backwards, no rows.
        grid = f(a[5:6], p[:1000].reshape(10, 100, 3))
        np.testing.assert_array_equal(grid.view(bits), alone[:1000].reshape(10, 100, 3).view(bits))
        np.testing.assert_array_equal(f(a[5], p[::-1]).view(bits), alone[::-1].view(bits))
        assert f(a[5], p[:0]).shape == (0, 3)
    for t in (0.3, -0.5, 1.7):  # dlb takes any t (extrapolation too)
        whole = dqkit.dlb(a, scaled, t)
        assert whole.dtype == dtype
        alone = np.array([dqkit.dlb(a[i], scaled[i], t) for i in range(n)])
        np.testing.assert_array_equal(whole.view(bits), alone.view(bits), err_msg=f"dlb, t = {t}")


def test_non_contiguous_inputs_are_read_correctly(rng):
    a, _, _ = random_rigid(rng, 20)
    wide = np.zeros((20, 16))
    wide[:, ::2] = a  # every other column: a strided view
    np.testing.assert_array_equal(dqkit.compose(wide[:, ::2], a), dqkit.compose(a, a))
    fortran = np.asfortranarray(a)
    np.testing.assert_array_equal(dqkit.to_mat4(fortran), dqkit.to_mat4(a))
    np.testing.assert_array_equal(dqkit.to_mat4(a[::-1]), dqkit.to_mat4(a)[::-1])


@pytest.mark.parametrize("call, message", [
    (lambda: dqkit.compose(np.zeros((5, 7)), np.zeros((5, 8))), r"a: expected shape \(\.\.\., 8\), got \(5, 7\)"),
    (lambda: dqkit.transform_points(np.zeros((5, 8)), np.zeros((5, 4))), r"p: expected shape \(\.\.\., 3\), got \(5, 4\)"),
    (lambda: dqkit.to_mat4(np.zeros((2, 3, 7))), r"q: expected shape \(\.\.\., 8\), got \(2, 3, 7\)"),
    (lambda: dqkit.from_matrix(np.zeros((5, 2, 4))), r"matrix: expected shape \(\.\.\., 4, 4\)"),
    (lambda: dqkit.from_matrix(np.zeros((2, 2))), r"matrix: expected shape \(\.\.\., 4, 4\) or \(\.\.\., 3, 4\)"),
    (lambda: dqkit.slerp(np.zeros((5, 8)), np.zeros((5, 4)), 0.5), r"a: expected shape \(\.\.\., 4\)"),
    (lambda: dqkit.compose(np.zeros((5, 8), np.int64), np.zeros((5, 8))), "expected dtype float32 or float64, got int64"),
    (lambda: dqkit.compose(np.zeros((5, 8), np.float16), np.zeros((5, 8))), "expected dtype float32 or float64, got float16"),
    (lambda: dqkit.compose(np.zeros((5, 8), np.float32), np.zeros((5, 8))), "b: dtype float64 does not match the other inputs' float32"),
    (lambda: dqkit.compose(np.zeros((5, 8)), np.zeros((4, 8))), "b: N = 4 does not match a's N = 5"),
    (lambda: dqkit.sclerp(np.zeros((5, 8)), np.zeros((5, 8)), np.zeros(3)), "t: N = 3 does not match"),
    (lambda: dqkit.local_to_model([-1, 0], np.zeros((4, 3, 8))), r"local: expected shape \(F, 2, 8\) or \(2, 8\)"),
    (lambda: dqkit.local_to_model([-1, 1], np.zeros((2, 8))), "joint 1 has parent 1"),
])
def test_wrong_shapes_and_dtypes_raise_value_error(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_empty_batches():
    assert dqkit.compose(np.zeros((0, 8)), np.zeros((0, 8))).shape == (0, 8)
    assert dqkit.to_mat4(np.zeros((0, 8), np.float32)).shape == (0, 4, 4)


def test_batch_from_several_threads(rng):
    a, _, _ = random_rigid(rng, 20000)
    b, _, _ = random_rigid(rng, 20000)
    expected = dqkit.sclerp(a, b, 0.3)
    results = [None] * 6
    errors = []

    def work(i):
        try:
            for _ in range(3):
                results[i] = dqkit.sclerp(a, b, 0.3)
        except Exception as e:  # noqa: BLE001  (reported below)
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for r in results:
        np.testing.assert_array_equal(r, expected)


def test_long_batches_release_the_gil(rng):
    a, _, _ = random_rigid(rng, 500_000)
    b = a[::-1].copy()
    ready, go, duration = threading.Event(), threading.Event(), []

    def work():
        ready.set()
        go.wait()
        t0 = time.perf_counter()
        dqkit.sclerp(a, b, 0.5)
        duration.append(time.perf_counter() - t0)

    t = threading.Thread(target=work)
    t.start()
    ready.wait()
    # The main thread keeps running while the batch runs: holding the GIL would stop it for the
    # whole call, a gap as long as the call itself.
    last, gap = time.perf_counter(), 0.0
    go.set()
    while True:
        now = time.perf_counter()
        gap, last = max(gap, now - last), now
        if not t.is_alive():
            break
    t.join()
    assert gap < 0.5 * duration[0], f"the main thread stopped for {gap:.3f} s of a {duration[0]:.3f} s batch: the GIL was held"


def test_normalized_and_conjugate(rng):
    a, _, _ = random_rigid(rng, 10)
    scaled = a * rng.uniform(0.5, 2, size=(10, 1))
    np.testing.assert_array_equal(dqkit.normalized(scaled), [np.asarray(dqkit.DualQuaternion(x).normalized()) for x in scaled])
    np.testing.assert_array_equal(dqkit.conjugate(a), [np.asarray(dqkit.DualQuaternion(x).conjugate()) for x in a])


def test_unaligned_buffers_are_read_correctly(rng):
    a, _, _ = random_rigid(rng, 5)
    raw = bytearray(a.nbytes + 1)
    unaligned = np.frombuffer(raw, dtype=np.float64, count=a.size, offset=1).reshape(5, 8)
    assert not unaligned.flags.aligned
    unaligned[...] = a
    np.testing.assert_array_equal(dqkit.to_mat4(unaligned), dqkit.to_mat4(a))


@settings(max_examples=100, deadline=None)
@given(arrays(np.float64, (6, 4), elements=st.floats(-1, 1)).filter(lambda r: (np.linalg.norm(r, axis=1) > 0.1).all()),
       arrays(np.float64, (6, 3), elements=st.floats(-5, 5)), arrays(np.float64, (6, 3), elements=st.floats(-5, 5)))
def test_property_batch_compose_then_transform(r, t, p):
    r = r / np.linalg.norm(r, axis=1, keepdims=True)
    q = dqkit.from_rotation_translation(r, t)
    ab = dqkit.compose(q, q[::-1])
    # (a b) p = a (b p), and the matrices agree with the dual quaternions.
    scale = 1 + 2 * np.abs(t).max() + np.abs(p).max()
    np.testing.assert_allclose(dqkit.transform_points(ab, p), dqkit.transform_points(q, dqkit.transform_points(q[::-1], p)),
                               atol=256 * EPS64 * scale)
    m = dqkit.to_mat4(ab)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", m[:, :3, :3], p) + m[:, :3, 3], dqkit.transform_points(ab, p),
                               atol=256 * EPS64 * scale)


def test_lists_take_the_call_dtype_and_values_pick_the_scalar_overload(rng):
    q, _, _ = random_rigid(rng, 4)
    np.testing.assert_array_equal(dqkit.transform_points(q, [1, 2, 3]), dqkit.transform_points(q, np.array([1.0, 2.0, 3.0])))
    out = dqkit.transform_points(q.astype(np.float32), [[1, 2, 3]] * 4)
    assert out.dtype == np.float32 and out.shape == (4, 3)
    np.testing.assert_array_equal(dqkit.compose(q.tolist(), q.tolist()), dqkit.compose(q, q))
    a, b = dqkit.DualQuaternion(q[0]), dqkit.DualQuaternion(q[1])
    assert isinstance(dqkit.sclerp(a, b, 1), dqkit.DualQuaternion)  # int t: still the scalar function
    with pytest.raises(TypeError):
        dqkit.compose(object(), q)


def test_leading_dimensions_as_numpy(rng):
    """(..., 8): an (F, J, 8) array, such as local_to_model's result, is F × J rows, and the result
    keeps the leading shape; row by row the same as the flattened call."""
    q, _, _ = random_rigid(rng, 6)
    p, _, _ = random_rigid(rng, 6)
    world = q.reshape(2, 3, 8)
    np.testing.assert_array_equal(dqkit.translation(world), dqkit.translation(q).reshape(2, 3, 3))
    np.testing.assert_array_equal(dqkit.compose(world, p.reshape(2, 3, 8)), dqkit.compose(q, p).reshape(2, 3, 8))
    np.testing.assert_array_equal(dqkit.compose(world, p[0]), dqkit.compose(q, p[0]).reshape(2, 3, 8))  # one value for every row
    t = np.linspace(0, 1, 6)
    np.testing.assert_array_equal(dqkit.sclerp(world, p.reshape(2, 3, 8), t.reshape(2, 3)), dqkit.sclerp(q, p, t).reshape(2, 3, 8))
    angles, singular = dqkit.to_euler(q[:, :4].reshape(3, 2, 4) / np.linalg.norm(q[:, :4], axis=1).reshape(3, 2, 1),
                                      dqkit.EulerOrder.ZYX, dqkit.EulerFrame.intrinsic)
    assert angles.shape == (3, 2, 3) and singular.shape == (3, 2)
    matrices = dqkit.to_mat4(world)
    assert matrices.shape == (2, 3, 4, 4)
    np.testing.assert_array_equal(dqkit.from_matrix(matrices), dqkit.from_matrix(matrices.reshape(6, 4, 4)).reshape(2, 3, 8))
    with pytest.raises(ValueError, match=r"b: N = 6 does not match a's leading shape \(2, 3\)"):
        dqkit.compose(world, p)
