"""The PEP 517 backend of pyproject.toml: setuptools, with build_py extended to build the
extension module (and the import worker) with the project's CMake build and add them to the
package. The CMake build directory is build/pip-<python version> in the source tree, so a second
pip install only rebuilds what changed. CMAKE_BUILD_PARALLEL_LEVEL sets the jobs (default 2)."""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

from setuptools import build_meta as _setuptools
from setuptools.command.build_py import build_py
from setuptools.command.egg_info import egg_info
from wheel.bdist_wheel import bdist_wheel

# The PEP 517 hooks are setuptools' own.
build_wheel = _setuptools.build_wheel
build_sdist = _setuptools.build_sdist
get_requires_for_build_wheel = _setuptools.get_requires_for_build_wheel
get_requires_for_build_sdist = _setuptools.get_requires_for_build_sdist
prepare_metadata_for_build_wheel = _setuptools.prepare_metadata_for_build_wheel

SOURCE = pathlib.Path(__file__).resolve().parents[1]


class BuildWithCMake(build_py):
    """build_py, then the CMake target dqkit_python, installed (component python) into the wheel's tree."""

    def run(self):
        super().run()
        build = SOURCE / "build" / f"pip-py{sys.version_info.major}{sys.version_info.minor}"
        subprocess.run(["cmake", "-S", str(SOURCE), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython3_EXECUTABLE={sys.executable}", "-DDQKIT_BUILD_PYTHON=ON", "-DDQKIT_PYTHON_INSTALL_DIR:STRING=site",
                        "-DDQKIT_BUILD_TESTS=OFF", "-DDQKIT_BUILD_BENCHMARKS=OFF", "-DDQKIT_BUILD_EXAMPLES=OFF",
                        "-DDQKIT_BUILD_TOOLS=OFF"], check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "2")
        subprocess.run(["cmake", "--build", str(build), "--target", "dqkit_python", "-j", jobs], check=True)
        with tempfile.TemporaryDirectory() as stage:
            subprocess.run(["cmake", "--install", str(build), "--component", "python", "--prefix", stage], check=True)
            target = pathlib.Path(self.build_lib) / "dqkit"
            for item in (pathlib.Path(stage) / "site" / "dqkit").iterdir():
                if item.suffix == ".so":
                    shutil.copy2(item, target / item.name)
                elif item.name == "libexec":
                    shutil.copytree(item, target / "libexec", dirs_exist_ok=True)


class EggInfoInBuild(egg_info):
    """The metadata directory under build/ (ignored by git), not dqkit.egg-info in the source root."""

    def initialize_options(self):
        super().initialize_options()
        (SOURCE / "build").mkdir(exist_ok=True)
        self.egg_base = str(SOURCE / "build")


class PlatformWheel(bdist_wheel):
    """The wheel holds a compiled module: tagged for this Python and platform, not pure."""

    def finalize_options(self):
        super().finalize_options()
        self.root_is_pure = False
