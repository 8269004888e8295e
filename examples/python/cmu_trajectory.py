"""Load a CMU motion capture clip, compute the world transforms of every joint in every frame with
one call, and plot a joint's trajectory to a PNG.

    /usr/bin/python3 examples/python/cmu_trajectory.py [file.bvh] [--joint LeftHand] [-o out.png]
"""
import argparse
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import dqkit  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("bvh", nargs="?", default="/usr/share/assimp/models/BVH/01_01.bvh")
parser.add_argument("--joint", default="LeftHand")
parser.add_argument("-o", "--output", default="trajectory.png")
args = parser.parse_args()

bvh = dqkit.read_bvh_file(args.bvh)                 # raises dqkit.ReadError with file:line
skeleton = dqkit.bvh_skeleton(bvh)
local = dqkit.bvh_animation(bvh, skeleton).locals   # (F, J, 8) local transforms
start = time.perf_counter()
world = dqkit.local_to_model(skeleton, local)        # (F, J, 8) world transforms, one call
elapsed = time.perf_counter() - start
j = skeleton.find(args.joint)
if j < 0:
    raise SystemExit(f"{args.bvh}: no joint named {args.joint!r}; joints: {', '.join(skeleton.names)}")
path = dqkit.translation(world[:, j])                # (F, 3)
t = np.arange(bvh.frame_count) * bvh.frame_time

fig, (top, side) = plt.subplots(1, 2, figsize=(11, 4.5))
top.plot(path[:, 0], path[:, 2], lw=1)
top.plot(*path[0, [0, 2]], "go", label="first frame")
top.plot(*path[-1, [0, 2]], "rs", label="last frame")
top.set(xlabel="x", ylabel="z", title=f"{args.joint}: seen from above", aspect="equal")
top.legend(loc="upper left", fontsize=8, framealpha=0.6)
side.plot(t, path[:, 1], lw=1)
side.set(xlabel="time (s)", ylabel="height y", title=f"{args.joint}: height")
fig.suptitle(f"{args.bvh.rsplit('/', 1)[-1]}: {bvh.frame_count} frames, {len(skeleton)} joints")
fig.tight_layout()
fig.savefig(args.output, dpi=100)
print(f"{bvh.frame_count} frames x {len(skeleton)} joints in {elapsed * 1e3:.2f} ms; "
      f"{args.joint} travelled {np.linalg.norm(np.diff(path, axis=0), axis=1).sum():.1f} units; wrote {args.output}")
