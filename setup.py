"""The native part of `pip install .` (pyproject.toml holds the rest): CMake builds the module
dacrt._dacrt and the library it links, libdacrt.so, which goes into the package beside it (the
module looks in its own folder first).

The CMake build directory is build-pip/ (configured on the first install, built again on the
next ones), or DACRT_BUILD_DIR: a build tree configured already (`make`'s build/), whose library
and module are reused as they are built.
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
OWN_BUILD = ROOT / "build-pip"


class CMakeBuild(build_ext):
    @staticmethod
    def has_stub(build):
        """Whether the build writes the type stub (not a sanitizer build)."""
        cache = (build / "CMakeCache.txt").read_text()
        return "DACRT_SANITIZE:BOOL=ON" not in cache

    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("DACRT_BUILD_DIR") or OWN_BUILD / "cmake").resolve()
        if not (build / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                            "-DDACRT_TESTS=OFF", "-DPython_EXECUTABLE=" + sys.executable],
                           check=True)
        stub = build / "python" / "dacrt" / "__init__.pyi"
        targets = ["dacrt_python"] + (["dacrt_python_stub"] if self.has_stub(build) else [])
        subprocess.run(["cmake", "--build", str(build), "--target", *targets, "-j",
                        str(os.cpu_count() or 1)], check=True)
        built = sorted((build / "python" / "dacrt").glob("_dacrt.*.so"))
        if not built:
            sys.exit("setup.py: CMake built no module in %s/python/dacrt" % build)
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        # setuptools keeps its build folder between installs: no native file of an earlier one.
        for stale in [*target.parent.glob("_dacrt.*.so"), *target.parent.glob("libdacrt.so*"),
                      target.parent / "__init__.pyi"]:
            stale.unlink(missing_ok=True)
        shutil.copy2(built[-1], target)
        if stub.exists():
            shutil.copy2(stub, target.parent / stub.name)
        for library in build.glob("libdacrt.so*"):  # the name the module asks for, and others
            shutil.copy2(library, target.parent / library.name, follow_symlinks=True)


OWN_BUILD.mkdir(exist_ok=True)
setup(ext_modules=[Extension("dacrt._dacrt", sources=[])],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": str(OWN_BUILD / "setuptools")},
               "egg_info": {"egg_base": str(OWN_BUILD)}})
