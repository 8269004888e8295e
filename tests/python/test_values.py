"""Value types against independent computations: NumPy formulas, scipy's Rotation, transforms3d."""
import math
import pickle

import numpy as np
import pytest
import transforms3d
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

import dqkit
from conftest import hamilton, random_rigid, random_unit_quaternions, rotation_matrix

EPS = np.finfo(np.float64).eps
TOL = 64 * EPS  # two independent double computations of unit-size values: a few ulps apart, never 64


def scipy_quat(q):
    """dqkit (w, x, y, z) from scipy's scalar-last (x, y, z, w)."""
    x, y, z, w = q
    return np.array([w, x, y, z])


def test_quaternion_product_is_hamilton(rng):
    a, b = random_unit_quaternions(rng, 2)
    p = dqkit.Quaternion(a) * dqkit.Quaternion(b)
    np.testing.assert_allclose(np.asarray(p), hamilton(a, b), rtol=0, atol=TOL)
    i, j, k = dqkit.Quaternion(0, 1, 0, 0), dqkit.Quaternion(0, 0, 1, 0), dqkit.Quaternion(0, 0, 0, 1)
    assert i * j == k and j * k == i and k * i == j and i * i == dqkit.Quaternion(-1, 0, 0, 0)


def test_axis_angle_and_rotation_vector_against_scipy(rng):
    for _ in range(50):
        axis = rng.normal(size=3)
        angle = rng.uniform(-2 * math.pi, 2 * math.pi)
        q = dqkit.Quaternion.from_axis_angle(axis, angle)
        ref = Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle)
        assert q.approx_equal(dqkit.Quaternion(scipy_quat(ref.as_quat())), TOL, dqkit.SignPolicy.same_rotation)
        np.testing.assert_allclose(q.to_matrix(), ref.as_matrix(), atol=TOL)
        np.testing.assert_allclose(q.to_matrix(), transforms3d.axangles.axangle2mat(axis, angle), atol=TOL)
        v = q.to_rotation_vector()
        assert np.linalg.norm(v) <= math.pi + TOL
        np.testing.assert_allclose(Rotation.from_rotvec(v).as_matrix(), ref.as_matrix(), atol=16 * TOL)
        aa = q.to_axis_angle()
        assert 0 <= aa.angle <= math.pi
        np.testing.assert_allclose(transforms3d.axangles.axangle2mat(aa.axis, aa.angle), ref.as_matrix(), atol=16 * TOL)


def test_rotate_and_matrix_follow_the_conventions(rng):
    q = random_unit_quaternions(rng, 1)[0]
    v = rng.normal(size=3)
    np.testing.assert_allclose(dqkit.Quaternion(q).rotate(v), rotation_matrix(q) @ v, atol=TOL * 4)
    np.testing.assert_allclose(dqkit.Quaternion(q).to_matrix(), transforms3d.quaternions.quat2mat(q), atol=TOL)
    back = dqkit.Quaternion.from_matrix(rotation_matrix(q))
    assert back.approx_equal(dqkit.Quaternion(q), TOL, dqkit.SignPolicy.same_rotation)


ORDERS = [o for o in dqkit.EulerOrder.__members__]


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("frame", ["intrinsic", "extrinsic"])
def test_euler_against_scipy(order, frame, rng):
    # scipy: upper-case sequences are intrinsic, lower-case extrinsic, with the same angle order.
    seq = order if frame == "intrinsic" else order.lower()
    o, f = dqkit.EulerOrder.__members__[order], dqkit.EulerFrame.__members__[frame]
    proper = order[0] == order[2]
    for _ in range(20):
        a, c = rng.uniform(-math.pi, math.pi, 2)
        b = rng.uniform(0.1, math.pi - 0.1) if proper else rng.uniform(-1.4, 1.4)
        ref = Rotation.from_euler(seq, [a, b, c])
        q = dqkit.from_euler(o, f, a, b, c)
        np.testing.assert_allclose(q.to_matrix(), ref.as_matrix(), atol=8 * TOL)
        np.testing.assert_allclose(dqkit.euler_to_matrix(o, f, a, b, c), ref.as_matrix(), atol=8 * TOL)
        e = dqkit.to_euler(q, o, f)
        assert not e.singular
        np.testing.assert_allclose(Rotation.from_euler(seq, list(e.angles)).as_matrix(), ref.as_matrix(), atol=64 * TOL)


def test_euler_against_transforms3d():
    # transforms3d 'sxyz' is static (extrinsic) x then y then z: R = Rz(c) Ry(b) Rx(a).
    a, b, c = 0.3, -0.7, 1.1
    q = dqkit.from_euler(dqkit.EulerOrder.XYZ, dqkit.EulerFrame.extrinsic, a, b, c)
    np.testing.assert_allclose(q.to_matrix(), transforms3d.euler.euler2mat(a, b, c, "sxyz"), atol=8 * TOL)
    e = dqkit.to_euler(q, dqkit.EulerOrder.XYZ, dqkit.EulerFrame.extrinsic).angles
    np.testing.assert_allclose(list(e), transforms3d.euler.mat2euler(q.to_matrix(), "sxyz"), atol=64 * TOL)


def test_gimbal_lock_is_reported_and_reproduces_the_rotation():
    q = dqkit.from_euler(dqkit.EulerOrder.ZYX, dqkit.EulerFrame.intrinsic, 0.4, math.pi / 2, 0.3)
    e = dqkit.to_euler(q, dqkit.EulerOrder.ZYX, dqkit.EulerFrame.intrinsic)
    assert e.singular and e.angles.c == 0
    back = dqkit.from_euler(dqkit.EulerOrder.ZYX, dqkit.EulerFrame.intrinsic, *e.angles)
    assert back.approx_equal(q, 64 * TOL, dqkit.SignPolicy.same_rotation)


def test_dual_quaternion_transform_and_matrix(rng):
    qs, r, t = random_rigid(rng, 20)
    for q8, ri, ti in zip(qs, r, t):
        q = dqkit.DualQuaternion(q8)
        np.testing.assert_allclose(q.translation(), ti, atol=32 * TOL)
        p = rng.normal(size=3)
        np.testing.assert_allclose(q.transform_point(p), rotation_matrix(ri) @ p + ti, atol=32 * TOL)
        np.testing.assert_allclose(q.transform_direction(p), rotation_matrix(ri) @ p, atol=32 * TOL)
        m = dqkit.to_mat4(q)
        np.testing.assert_allclose(m[:3, :3], Rotation.from_quat(np.r_[ri[1:], ri[0]]).as_matrix(), atol=TOL)
        np.testing.assert_allclose(m[:3, 3], ti, atol=32 * TOL)
        np.testing.assert_array_equal(m[3], [0, 0, 0, 1])
        np.testing.assert_array_equal(dqkit.to_mat34(q), m[:3])
        assert dqkit.from_matrix(m).approx_equal(q, 32 * TOL, dqkit.SignPolicy.same_rotation)
        assert dqkit.from_matrix(m[:3]).approx_equal(q, 32 * TOL, dqkit.SignPolicy.same_rotation)


def test_composition_follows_matrices(rng):
    qs, _, _ = random_rigid(rng, 2)
    a, b = dqkit.DualQuaternion(qs[0]), dqkit.DualQuaternion(qs[1])
    np.testing.assert_allclose(dqkit.to_mat4(a * b), dqkit.to_mat4(a) @ dqkit.to_mat4(b), atol=64 * TOL)
    np.testing.assert_allclose(dqkit.to_mat4(a.inverse_unit()), np.linalg.inv(dqkit.to_mat4(a)), atol=64 * TOL)


def test_sclerp_is_the_screw_motion(rng):
    qs, _, _ = random_rigid(rng, 2)
    a, b = dqkit.DualQuaternion(qs[0]), dqkit.DualQuaternion(qs[1])
    assert dqkit.sclerp(a, b, 0).approx_equal(a, 64 * TOL, dqkit.SignPolicy.same_rotation)
    assert dqkit.sclerp(a, b, 1).approx_equal(b, 64 * TOL, dqkit.SignPolicy.same_rotation)
    # The midpoint m satisfies (a⁻¹ m)² = a⁻¹ b: half the screw, checked through matrices.
    m = dqkit.sclerp(a, b, 0.5)
    half = np.linalg.inv(dqkit.to_mat4(a)) @ dqkit.to_mat4(m)
    np.testing.assert_allclose(half @ half, np.linalg.inv(dqkit.to_mat4(a)) @ dqkit.to_mat4(b), atol=1e3 * TOL)
    # Same screw as exp/log: a exp(½ log(a⁻¹ b)).
    ref = a * dqkit.exp(dqkit.log(a.conjugate() * b) * 0.5)
    assert m.approx_equal(ref, 256 * TOL, dqkit.SignPolicy.same_rotation)


def test_slerp_against_scipy_slerp(rng):
    from scipy.spatial.transform import Slerp
    a, b = random_unit_quaternions(rng, 2)
    ts = np.linspace(0, 1, 7)
    ref = Slerp([0, 1], Rotation.from_quat([np.r_[a[1:], a[0]], np.r_[b[1:], b[0]]]))(ts).as_matrix()
    for t, mat in zip(ts, ref):
        np.testing.assert_allclose(dqkit.slerp(dqkit.Quaternion(a), dqkit.Quaternion(b), t).to_matrix(), mat, atol=64 * TOL)


def test_dlb_and_dib(rng):
    qs, _, _ = random_rigid(rng, 3)
    a, b, c = (dqkit.DualQuaternion(q) for q in qs)
    # dlb: the weighted sum with b's sign aligned to a's, normalized (Kavan et al.).
    sb = 1.0 if np.dot(qs[0][:4], qs[1][:4]) >= 0 else -1.0
    blend = dqkit.DualQuaternion(0.7 * qs[0] + 0.3 * sb * qs[1]).normalized()
    assert dqkit.dlb(a, b, 0.3).approx_equal(blend, 16 * TOL)
    assert dqkit.dlb([a, b], [0.7, 0.3]).approx_equal(blend, 16 * TOL)
    # dib of two inputs lies on their sclerp.
    r = dqkit.dib([a, b], [0.75, 0.25])
    assert r.converged and r.value.approx_equal(dqkit.sclerp(a, b, 0.25), 1e3 * TOL, dqkit.SignPolicy.same_rotation)
    with pytest.raises(ValueError, match="one weight per"):
        dqkit.dlb([a, b, c], [1.0, 2.0])


def test_screw_and_vrml_round_trip(rng):
    qs, r, t = random_rigid(rng, 10)
    for q8 in qs:
        q = dqkit.DualQuaternion(q8)
        s = dqkit.to_screw(q)
        assert 0 <= s.angle <= math.pi
        np.testing.assert_allclose(np.linalg.norm(s.axis.direction), 1, atol=TOL)
        assert dqkit.from_screw(s).approx_equal(q, 256 * TOL, dqkit.SignPolicy.same_rotation)
        v = dqkit.to_vrml(q, center=[1, 2, 3])
        assert dqkit.from_vrml(v).approx_equal(q, 256 * TOL, dqkit.SignPolicy.same_rotation)
    # A pure translation is a screw with angle 0 and the translation along the axis, exactly.
    s = dqkit.to_screw(dqkit.DualQuaternion.from_translation([0, 0, 2]))
    assert s.angle == 0 and s.translation == 2


def test_dual_numbers_differentiate():
    x = 0.3
    y = dqkit.sin(dqkit.Dual.variable(x)) * dqkit.exp(dqkit.Dual.variable(x))
    assert y.real == pytest.approx(math.sin(x) * math.exp(x), abs=4 * EPS)
    assert y.dual == pytest.approx((math.cos(x) + math.sin(x)) * math.exp(x), abs=4 * EPS)
    h = dqkit.sin(dqkit.HyperDual.variable(x))
    assert h.e1 == pytest.approx(math.cos(x), abs=2 * EPS) and h.e12 == pytest.approx(-math.sin(x), abs=2 * EPS)


@pytest.mark.parametrize("value", [
    dqkit.Dual(1.5, -2.25), dqkit.HyperDual(1, 2, 3, 4), dqkit.Quaternion(0.1, 0.2, 0.3, 0.4),
    dqkit.DualQuaternion(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 1 / 3)])
def test_repr_pickle_and_exact_equality(value):
    assert eval(repr(value), {name: getattr(dqkit, name) for name in dir(dqkit)}) == value
    assert pickle.loads(pickle.dumps(value)) == value
    assert type(value).__name__ in repr(value)


def test_exact_and_approximate_comparison():
    q = dqkit.Quaternion.from_axis_angle([0, 1, 0], 1.0)
    assert q != -q and q.approx_equal(-q, 0, dqkit.SignPolicy.same_rotation)
    assert not q.approx_equal(-q, 0.5)
    nudged = dqkit.Quaternion(q.w + 1e-9, q.x, q.y, q.z)
    assert nudged != q and nudged.approx_equal(q, 2e-9) and not nudged.approx_equal(q, 5e-10)
    d = dqkit.DualQuaternion.from_translation([1, 2, 3])
    assert dqkit.approx_equal(d, -d, 0, dqkit.SignPolicy.same_rotation) and d != -d


def test_numpy_round_trip():
    q = dqkit.DualQuaternion.from_rotation_translation(dqkit.Quaternion.from_axis_angle([1, 0, 0], 0.5), [1, 2, 3])
    a = np.asarray(q)
    assert a.shape == (8,) and a.dtype == np.float64
    assert dqkit.DualQuaternion(a) == q
    assert np.asarray(q, dtype=np.float32).dtype == np.float32
    assert list(q) == list(a)
    with pytest.raises(ValueError, match=r"expected shape \(8,\)"):
        dqkit.DualQuaternion(np.zeros(7))
    with pytest.raises(ValueError, match=r"expected shape \(4,\)"):
        dqkit.Quaternion([1, 2, 3])


unit = st.floats(-1, 1, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(st.lists(unit, min_size=4, max_size=4).filter(lambda v: np.linalg.norm(v) > 0.1),
       st.lists(st.floats(-10, 10), min_size=3, max_size=3), st.lists(st.floats(-10, 10), min_size=3, max_size=3))
def test_property_transform_is_rotation_then_translation(r, t, p):
    r = np.array(r) / np.linalg.norm(r)
    q = dqkit.DualQuaternion.from_rotation_translation(dqkit.Quaternion(r), t)
    scale = 1 + np.abs(t).max() + np.abs(p).max()
    np.testing.assert_allclose(q.transform_point(p), rotation_matrix(r) @ p + t, atol=64 * EPS * scale)
    np.testing.assert_allclose(q.inverse_unit().transform_point(q.transform_point(p)), p, atol=256 * EPS * scale)
    assert q.is_unit(64 * EPS)
