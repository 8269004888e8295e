"""Shared fixtures of the Python tests: the module under test (from PYTHONPATH, as scripts/test.sh
sets it), random rigid transforms, and the sample files of Debian's assimp-testmodels."""
import os
import pathlib

import numpy as np
import pytest

import dqkit  # noqa: F401  (fails the whole run at collection if the module is not importable)

MODELS = pathlib.Path(os.environ.get("DQKIT_ASSIMP_MODELS", "/usr/share/assimp/models"))
CMU_BVH = MODELS / "BVH" / "01_01.bvh"
SIMPLE_SKIN = MODELS / "glTF2" / "simple_skin" / "simple_skin.gltf"


@pytest.fixture
def rng():
    return np.random.default_rng(20261201)


def random_unit_quaternions(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def random_rigid(rng, n, scale=3.0):
    """(N, 8) unit dual quaternions r + ε ½ t r, built with NumPy (independently of dqkit)."""
    r = random_unit_quaternions(rng, n)
    t = rng.uniform(-scale, scale, size=(n, 3))
    tq = np.concatenate([np.zeros((n, 1)), t], axis=1)
    return np.concatenate([r, 0.5 * hamilton(tq, r)], axis=1), r, t


def hamilton(a, b):
    """Row-wise Hamilton products (w, x, y, z), written out from the definition i² = j² = k² = ijk = −1."""
    aw, ax, ay, az = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    bw, bx, by, bz = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return np.stack([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def rotation_matrix(q):
    """The rotation matrix of unit quaternions (w, x, y, z), from the conventions' formula."""
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def need(path):
    if not path.exists():
        pytest.skip(f"{path} is missing (Debian assimp-testmodels)")
    return path
