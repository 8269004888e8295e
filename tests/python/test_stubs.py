"""The type stubs match the compiled module, and help() explains."""
import ast
import pathlib
import pydoc
import subprocess
import sys

import pytest

import dqkit

ROOT = pathlib.Path(__file__).resolve().parents[2]
STUB = ROOT / "python" / "dqkit" / "__init__.pyi"


def test_committed_stub_is_generated_from_this_module():
    if not dqkit.HAVE_IMPORT:
        pytest.skip("the committed stub describes the module built with Assimp (import_scene, SceneSkin, ...)")
    env_path = str(pathlib.Path(dqkit.__file__).resolve().parents[1])
    fresh = subprocess.run([sys.executable, str(ROOT / "python" / "generate_stubs.py")], check=True, capture_output=True,
                           text=True, env={"PYTHONPATH": env_path}).stdout
    assert fresh == STUB.read_text(), "python/dqkit/__init__.pyi is stale: regenerate it (python/generate_stubs.py)"


def test_stub_is_valid_python_and_names_every_public_name():
    tree = ast.parse(STUB.read_text())
    declared = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    declared |= {n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)}
    public = {n for n in dir(dqkit) if not n.startswith("_")}
    assert public <= declared, sorted(public - declared)


def test_help_explains():
    text = pydoc.render_doc(dqkit.sclerp, renderer=pydoc.plaintext)
    assert "sclerp(a: dqkit._dqkit.DualQuaternion" in text and "(N, 8)" in text
    assert "rotate by r, then translate by t" in pydoc.render_doc(dqkit.DualQuaternion, renderer=pydoc.plaintext).lower()
