"""dqkit: dual quaternions and the 3D character hierarchies built from them.

The C++ library's names, with NumPy arrays for vectors, matrices and batches. Value types
(Dual, HyperDual, Quaternion, DualQuaternion) are double precision; the batch functions take
float32 or float64 arrays: (N, 8) dual quaternions (w, x, y, z real, then dual), (N, 4)
quaternions, (N, 3) points, (N, 4, 4) matrices [n, row, column], (F, J, 8) poses.
See docs/python.md.
"""
import os as _os

# Model import runs Assimp in the helper executable dqkit-import-worker (spawned, never a fork of
# the interpreter). The package carries a copy; a worker the user names keeps precedence.
_worker = _os.path.join(_os.path.dirname(__file__), "libexec", "dqkit-import-worker")
if _os.path.exists(_worker):
    _os.environ.setdefault("DQKIT_IMPORT_WORKER", _worker)

from ._dqkit import *  # noqa: E402,F401,F403
from ._dqkit import __doc__ as _module_doc  # noqa: E402,F401

__version__ = "0.1.0"
