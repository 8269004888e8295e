"""Import a skinned model (through Assimp, in dqkit's isolated worker), pose it at a few times of
its animation, skin it with dual quaternions, and save each frame as OBJ.

    /usr/bin/python3 examples/python/skin_model.py [model.gltf] [-o outdir]
"""
import argparse
import os

import numpy as np

import dqkit

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("model", nargs="?", default="/usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf")
parser.add_argument("-o", "--output", default=".")
args = parser.parse_args()

scene = dqkit.import_scene(args.model)       # a dqkit.ReadError says what went wrong, and where
skin = dqkit.SceneSkin.build(scene)
anim = scene.animations[0].animation if scene.animations else None
duration = anim.duration() if anim else 0.0
os.makedirs(args.output, exist_ok=True)
for k, time in enumerate(np.linspace(0, duration, 4)):
    world = dqkit.pose_at(scene, 0, time) if anim else dqkit.local_to_model(scene.skeleton, scene.skeleton.rest_pose)
    frame = skin.skin(world, dqkit.SkinningMethod.dqs)
    path = os.path.join(args.output, f"frame{k}.obj")
    with open(path, "w") as f:
        f.write(dqkit.format_frame(frame, dqkit.MeshFormat.obj))
    lo, hi = frame.positions.min(0), frame.positions.max(0)
    print(f"t = {time:.2f} s: {skin.vertex_count} vertices, bounds {np.round(lo, 3)} .. {np.round(hi, 3)} -> {path}")
