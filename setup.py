"""Builds the Python module with the project's CMake (python/CMakeLists.txt) for
`pip install --no-build-isolation .`; the metadata is in pyproject.toml.

The CMake build folder is `build/` (the README's), or $VANTAGE_BUILD_DIR: a configured one is
reused, so only the module is compiled after `make build`. setuptools' own files go to
build/setuptools/ (setup.cfg)."""

import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    """Configures and builds the `vantage_python` target, then copies the module and its stub."""

    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("VANTAGE_BUILD_DIR", ROOT / "build")).resolve()
        jobs = os.environ.get("JOBS", "2")
        module = build / "python" / ("vantage" + sysconfig.get_config_var("EXT_SUFFIX"))
        configure = ["cmake", "-S", str(ROOT), "-B", str(build)]
        # A configured build folder keeps its interpreter unless it builds for another ABI.
        if not (build / "CMakeCache.txt").exists() or not module.exists():
            configure.append(f"-DPython_EXECUTABLE={sys.executable}")
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "vantage_python",
                        f"-j{jobs}"], check=True)
        if not module.exists():
            raise RuntimeError(f"no {module.name} in {module.parent}: is pybind11-dev installed "
                               "(scripts/install-deps.sh)?")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(module, target)
        shutil.copyfile(ROOT / "python" / "vantage.pyi", target.parent / "vantage.pyi")


setup(ext_modules=[Extension("vantage", sources=[])], cmdclass={"build_ext": CMakeBuild},
      py_modules=[])
