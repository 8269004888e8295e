"""The examples in examples/python run, and write what they say they write."""
import os
import pathlib
import subprocess
import sys

import matplotlib.image
import numpy as np
import pytest

import dqkit
from conftest import CMU_BVH, SIMPLE_SKIN, need

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"


def run(name, *args, cwd):
    # The examples import the module under test (the one this process imported), from any directory.
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(dqkit.__file__).resolve().parents[1]))
    return subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)], check=True, capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=300).stdout


def test_cmu_trajectory_plots_a_png(tmp_path):
    out = run("cmu_trajectory.py", need(CMU_BVH), "--joint", "Head", "-o", tmp_path / "head.png", cwd=tmp_path)
    assert "2752 frames x 38 joints" in out
    image = matplotlib.image.imread(tmp_path / "head.png")
    assert image.shape[0] > 200 and image.shape[1] > 400 and image.std() > 0.05  # a picture, not a blank canvas
    with pytest.raises(subprocess.CalledProcessError) as e:
        run("cmu_trajectory.py", need(CMU_BVH), "--joint", "Tail", "-o", tmp_path / "x.png", cwd=tmp_path)
    assert "no joint named 'Tail'" in e.value.stderr


def test_blend_poses(tmp_path):
    out = run("blend_poses.py", need(CMU_BVH), "-o", tmp_path / "blend.png", cwd=tmp_path)
    assert "5 interpolated poses of 38 joints" in out
    assert matplotlib.image.imread(tmp_path / "blend.png").std() > 0.05


def test_skin_model_writes_obj_frames(tmp_path):
    if not dqkit.HAVE_IMPORT:
        pytest.skip("built without Assimp")
    scene = dqkit.import_scene(str(need(SIMPLE_SKIN)))
    out = run("skin_model.py", SIMPLE_SKIN, "-o", tmp_path, cwd=tmp_path)
    frames = sorted(tmp_path.glob("frame*.obj"))
    assert len(frames) == 4 and out.count("vertices") == 4
    vertices = [np.array([list(map(float, line.split()[1:4])) for line in f.read_text().splitlines() if line.startswith("v ")])
                for f in frames]
    assert all(len(v) == len(scene.meshes[0].positions) for v in vertices)
    # The first frame is the start of the animation; the middle ones are bent (simple_skin swings its top half).
    assert not np.allclose(vertices[1], vertices[0], atol=1e-3)


def test_readme_python_example_runs():
    readme = (EXAMPLES.parents[1] / "README.md").read_text()
    code = readme.split("```python\n", 1)[1].split("```", 1)[0]
    scope = {}
    exec(code.replace('"01_01.bvh"', repr(str(need(CMU_BVH)))), scope)  # noqa: S102  (the README's own code)
    assert scope["world"].shape == (2752, 38, 8) and scope["path"].shape == (2752, 3) and scope["mid"].shape == (38, 8)
