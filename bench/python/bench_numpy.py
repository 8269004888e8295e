"""Throughput of dqkit's batch functions from Python against the same math written in pure NumPy
and against scipy's Rotation where it applies, measured in the same run (a benchmark, not a test).

    PYTHONPATH=build/<dir>/python /usr/bin/python3 bench/python/bench_numpy.py [--quick]

Each figure is the best of several repeats (items per second: interpolations, points, joints);
every NumPy/scipy result is checked against dqkit's before it is timed, so the comparison is of
the same computation. docs/python.md has the numbers of a run.
"""
import argparse
import platform
import time

import numpy as np
from scipy.spatial.transform import Rotation

import dqkit

parser = argparse.ArgumentParser()
parser.add_argument("--quick", action="store_true", help="smaller inputs and fewer repeats (a smoke run)")
parser.add_argument("--bvh", default="/usr/share/assimp/models/BVH/01_01.bvh")
args = parser.parse_args()
N = 20_000 if args.quick else 200_000
REPEATS = 3 if args.quick else 7


def best(f, repeats=REPEATS):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


# ---- NumPy implementations of the same math (w, x, y, z; real then dual) ----------------------
def hamilton(a, b):
    aw, ax, ay, az = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    bw, bx, by, bz = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return np.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def conj(q):
    return q * np.array([1, -1, -1, -1], q.dtype)


def dq_product(a, b):
    return np.concatenate([hamilton(a[..., :4], b[..., :4]),
                           hamilton(a[..., :4], b[..., 4:]) + hamilton(a[..., 4:], b[..., :4])], axis=-1)


def translation(q):
    return 2 * hamilton(q[..., 4:], conj(q[..., :4]))[..., 1:]


def numpy_sclerp(a, b, t):
    """a (a⁻¹ b)^t through the screw parameters of a⁻¹ b (Kavan et al.), shortest path."""
    d = dq_product(np.concatenate([conj(a[:, :4]), conj(a[:, 4:])], 1), b)
    d = np.where(d[:, :1] < 0, -d, d)
    r, v = d[:, :4], d[:, 1:4]
    s = np.linalg.norm(v, axis=1)
    half = np.arctan2(s, r[:, 0])                       # θ/2
    l = v / s[:, None]                                  # axis (the inputs here are never pure translations)
    tr = translation(d)
    slide = np.einsum("ij,ij->i", tr, l)
    m = 0.5 * (np.cross(tr, l) + (tr - slide[:, None] * l) / np.tan(half)[:, None])
    ht, hd = t * half, 0.5 * t * slide
    sn, cs = np.sin(ht), np.cos(ht)
    p = np.concatenate([cs[:, None], l * sn[:, None], (-hd * sn)[:, None], m * sn[:, None] + l * (hd * cs)[:, None]], 1)
    return dq_product(a, p)


def numpy_transform_points(q, p):
    r, u = q[:, :4], q[:, 1:4]
    c = np.cross(u, p)
    return p + 2 * (r[:, :1] * c + np.cross(u, c)) + translation(q)


def numpy_dqs(positions, bones, weights, q):
    """Dual quaternion skinning vectorized over the vertices: the bones' q (bone world · inverse
    bind) blended with signs aligned to the largest weight's, normalized, applied."""
    qs = q[bones]                                                        # (V, K, 8)
    pivot = qs[np.arange(len(bones)), np.argmax(weights, 1), :4]
    signs = np.where(np.einsum("vkc,vc->vk", qs[..., :4], pivot) < 0, -1.0, 1.0)
    b = np.einsum("vk,vkc->vc", weights * signs, qs)
    b /= np.linalg.norm(b[:, :4], axis=1, keepdims=True)
    return numpy_transform_points(b, positions)


def numpy_fk(parents, local):
    model = np.empty_like(local)
    for j, pj in enumerate(parents):
        model[:, j] = local[:, j] if pj < 0 else dq_product(model[:, pj], local[:, j])
    return model


def scipy_fk(parents, rot, trans):
    wr, wt = [None] * len(parents), [None] * len(parents)
    for j, pj in enumerate(parents):
        if pj < 0:
            wr[j], wt[j] = rot[j], trans[j]
        else:
            wr[j], wt[j] = wr[pj] * rot[j], wr[pj].apply(trans[j]) + wt[pj]
    return wr, wt


def random_rigid(rng, n):
    r = rng.normal(size=(n, 4))
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    t = rng.uniform(-3, 3, size=(n, 3))
    return dqkit.from_rotation_translation(r, t), r, t


def line(what, unit, rows):
    print(f"\n{what} ({unit} per second; speed-up of the first row over each)")
    ref = rows[0][1]
    for name, rate in rows:
        print(f"  {name:34s} {rate / 1e6:10.2f} M   {ref / rate:8.1f}x" if rate != ref else f"  {name:34s} {rate / 1e6:10.2f} M")


rng = np.random.default_rng(1)
print(f"dqkit batch throughput, N = {N}, best of {REPEATS}; {platform.processor() or platform.machine()}, "
      f"NumPy {np.__version__}, Python {platform.python_version()}")

# ---- sclerp ------------------------------------------------------------------------------------
a, ra, ta = random_rigid(rng, N)
b, rb, tb = random_rigid(rng, N)
t = rng.uniform(0, 1, N)
assert np.allclose(numpy_sclerp(a, b, t), dqkit.sclerp(a, b, t), atol=1e-9)
a32, b32, t32 = a.astype(np.float32), b.astype(np.float32), t.astype(np.float32)
qa, qb = Rotation.from_quat(np.c_[ra[:, 1:], ra[:, :1]]), Rotation.from_quat(np.c_[rb[:, 1:], rb[:, :1]])


def scipy_slerp():
    return qa * Rotation.from_rotvec((qa.inv() * qb).as_rotvec() * t[:, None])


assert np.allclose(scipy_slerp().as_matrix(), dqkit.quaternion_to_matrix(dqkit.slerp(ra, rb, t)), atol=1e-9)
line("sclerp of (N, 8) dual quaternions", "interpolations", [
    ("dqkit.sclerp float64", N / best(lambda: dqkit.sclerp(a, b, t))),
    ("dqkit.sclerp float32", N / best(lambda: dqkit.sclerp(a32, b32, t32))),
    ("NumPy sclerp (screw parameters)", N / best(lambda: numpy_sclerp(a, b, t))),
    ("dqkit.slerp, rotations only", N / best(lambda: dqkit.slerp(ra, rb, t))),
    ("scipy Rotation slerp, rotations only", N / best(scipy_slerp)),
])

# ---- point transforms --------------------------------------------------------------------------
P = 4 * N
q, r, tt = random_rigid(rng, P)
p = rng.normal(size=(P, 3))
rot = Rotation.from_quat(np.c_[r[:, 1:], r[:, :1]])
assert np.allclose(numpy_transform_points(q, p), dqkit.transform_points(q, p), atol=1e-12)
assert np.allclose(rot.apply(p) + tt, dqkit.transform_points(q, p), atol=1e-12)
q32, p32 = q.astype(np.float32), p.astype(np.float32)
line("transform_points, (N, 8) with (N, 3)", "points", [
    ("dqkit.transform_points float64", P / best(lambda: dqkit.transform_points(q, p))),
    ("dqkit.transform_points float32", P / best(lambda: dqkit.transform_points(q32, p32))),
    ("NumPy (rotation formula + t)", P / best(lambda: numpy_transform_points(q, p))),
    ("scipy Rotation.apply + t", P / best(lambda: rot.apply(p) + tt)),
])

# ---- forward kinematics of a CMU clip ----------------------------------------------------------
bvh = dqkit.read_bvh_file(args.bvh)
skeleton = dqkit.bvh_skeleton(bvh)
local = dqkit.bvh_animation(bvh, skeleton).locals
reps = max(1, N // bvh.frame_count // 4)
local = np.concatenate([local] * reps)              # several passes over the clip: (F, J, 8)
F, J = local.shape[:2]
parents = list(skeleton.parents)
model = dqkit.local_to_model(skeleton, local)
assert np.allclose(numpy_fk(parents, local), model, atol=1e-9)
rots = [Rotation.from_quat(np.c_[local[:, j, 1:4], local[:, j, :1]]) for j in range(J)]
trans = [translation(local[:, j]) for j in range(J)]
_, wt = scipy_fk(parents, rots, trans)
assert np.allclose(np.stack(wt, 1), dqkit.translation(model.reshape(-1, 8)).reshape(F, J, 3), atol=1e-9)
local32 = local.astype(np.float32)
line(f"forward kinematics of (F, J, 8) = ({F}, {J}, 8) CMU poses", "joints", [
    ("dqkit.local_to_model float64", F * J / best(lambda: dqkit.local_to_model(skeleton, local))),
    ("dqkit.local_to_model float32", F * J / best(lambda: dqkit.local_to_model(skeleton, local32))),
    ("dqkit.local_to_model float64, 2 thr.", F * J / best(lambda: dqkit.local_to_model(skeleton, local, threads=2))),
    ("dqkit.local_to_model float32, 2 thr.", F * J / best(lambda: dqkit.local_to_model(skeleton, local32, threads=2))),
    ("NumPy (loop over joints)", F * J / best(lambda: numpy_fk(parents, local))),
    ("scipy Rotation (loop over joints)", F * J / best(lambda: scipy_fk(parents, rots, trans))),
])

# ---- skinning ----------------------------------------------------------------------------------
# DQS of N vertices with 4 influences each among 64 bones: dqkit (float32, the vector kernels) on
# the calling thread and on a pool of two, against the same blend vectorized with NumPy.
B = 64
positions = rng.uniform(-1, 1, size=(N, 3))
bones = np.stack([rng.choice(B, 4, replace=False) for _ in range(N)])
weights = rng.uniform(0.1, 1, size=(N, 4))
weights /= weights.sum(1, keepdims=True)
inverse_bind = np.stack([np.eye(4)] * B)
inverse_bind[:, :3, 3] = rng.uniform(-1, 1, size=(B, 3))
skin = dqkit.build_skin(positions, bones, weights, inverse_bind)
bone_world = random_rigid(rng, B)[0]
pool = dqkit.SkinningThreads(2)
q = dqkit.compose(bone_world, dqkit.from_matrix(inverse_bind))
assert np.allclose(numpy_dqs(positions, bones, weights, q), dqkit.skin_vertices(skin, bone_world), atol=1e-4)
line(f"DQS skinning, {N} vertices x 4 influences", "vertices", [
    ("dqkit.skin_vertices", N / best(lambda: dqkit.skin_vertices(skin, bone_world))),
    ("dqkit.skin_vertices, 2 threads", N / best(lambda: dqkit.skin_vertices(skin, bone_world, pool=pool))),
    ("NumPy (vectorized blend)", N / best(lambda: numpy_dqs(positions, bones, weights, q))),
])

# ---- rows in cache ---------------------------------------------------------------------------
# compose, transform_points and local_to_model run dq::simd's kernels on the CPU's widest
# instruction set in both dtypes, normalized in float32 (the rows converted to component arrays in
# chunks; FK's frames transposed in place); float64 normalized runs the scalar function. 65,536
# rows (2 MB per (N, 8) float32 array) and 1024 frames of the clip: in the last-level cache, where
# NumPy's allocation of the result (first touches of fresh pages) does not set the rate.
M = 1 << 16
qa, qb = random_rigid(rng, M)[0], random_rigid(rng, M)[0]
pm = rng.normal(size=(M, 3))
qa32, qb32, pm32 = qa.astype(np.float32), qb.astype(np.float32), pm.astype(np.float32)
scaled = qa * rng.uniform(0.5, 2.0, size=(M, 1))
scaled32 = scaled.astype(np.float32)
assert np.allclose(dqkit.compose(qa32, qb32), dq_product(qa, qb), atol=1e-5)
for what, f64, f32 in (("compose", lambda: dqkit.compose(qa, qb), lambda: dqkit.compose(qa32, qb32)),
                       ("normalized", lambda: dqkit.normalized(scaled), lambda: dqkit.normalized(scaled32)),
                       ("transform_points", lambda: dqkit.transform_points(qa, pm), lambda: dqkit.transform_points(qa32, pm32))):
    # Calls of under a millisecond: the best of more repeats (of 7, runs on a shared machine differed by half).
    line(f"{what}, N = {M} rows in cache", "rows", [(f"dqkit.{what} float64", M / best(f64, 8 * REPEATS)),
                                                    (f"dqkit.{what} float32", M / best(f32, 8 * REPEATS))])
few = local[:1024]
few32 = few.astype(np.float32)
line(f"forward kinematics of (F, J, 8) = ({len(few)}, {J}, 8) CMU poses, in cache", "joints", [
    ("dqkit.local_to_model float64", few.shape[0] * J / best(lambda: dqkit.local_to_model(skeleton, few))),
    ("dqkit.local_to_model float32", few.shape[0] * J / best(lambda: dqkit.local_to_model(skeleton, few32))),
])
