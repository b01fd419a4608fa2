"""Builds the Python package fss (distribution "fssim") with the project's CMake.

pip runs this file through pyproject.toml's backend (setuptools.build_meta);
docs/python.md#installing gives the commands. build_ext configures the project
in build-python-pip/ beside this file (Release, static libfss, the module only:
FSS_BUILD_PYTHON on, tests and benchmarks off, the interpreter running this
file), builds the target fss_python and puts its fss/_fss*.so into the wheel
beside the files of python/fss/ (__init__.py, the .pyi stub, py.typed).
build-python-pip/ is kept, so that a second install compiles only what
changed; it is ignored by git, like build/, and removed by hand at will.

Environment (none is needed):
  CMAKE_ARGS                   more arguments for the configure step, split as
                               a shell splits words, after the ones above (so
                               they override them), e.g.
                               CMAKE_ARGS="-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"
  CMAKE_CXX_COMPILER_LAUNCHER  read by CMake itself at the first configure of
                               build-python-pip/: a compiler launcher (ccache)
  CMAKE_BUILD_PARALLEL_LEVEL   compile jobs (default: the number of processors)
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = Path(__file__).resolve().parent
# One level below the source, as build/: the compiler sees the same relative
# paths (../src/...), so ccache with a base_dir shares build/'s compiles.
CMAKE_BUILD = SOURCE / "build-python-pip"


def project_version():
    """The VERSION of CMakeLists.txt's project() command."""
    text = (SOURCE / "CMakeLists.txt").read_text(encoding="utf-8")
    match = re.search(r"project\(\s*fssim\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", text)
    if match is None:
        sys.exit("setup.py: no 'project(fssim VERSION x.y.z' in CMakeLists.txt")
    return match.group(1)


def configure_key():
    """What a kept build directory must match to be reused: the source it
    was configured for and the interpreter's ABI."""
    return f"{SOURCE}\n{sys.version}\n{sysconfig.get_config_var('EXT_SUFFIX')}\n"


class CMakeBuild(build_ext):
    """build_ext for the one extension fss._fss: built by CMake, copied."""

    def build_extension(self, ext):
        if shutil.which("cmake") is None:
            sys.exit("setup.py: cmake not found: install CMake >= 3.20 and the C++ "
                     "dependencies (Debian: scripts/install-deps.sh)")
        configure = [
            "cmake", "-S", str(SOURCE), "-B", str(CMAKE_BUILD),
            "-DCMAKE_BUILD_TYPE=Release", "-DBUILD_SHARED_LIBS=OFF",
            "-DFSS_BUILD_PYTHON=ON", "-DFSS_BUILD_TESTS=OFF", "-DFSS_BUILD_BENCH=OFF",
            f"-DPython3_EXECUTABLE={sys.executable}",
            *shlex.split(os.environ.get("CMAKE_ARGS", "")),
        ]
        # The stamp: the key, then the configure command. Another key: a
        # fresh configure (no CMakeCache.txt, no CMakeFiles/ with the
        # objects); the same command: no configure step (the build step
        # configures again by itself when a CMake file changed).
        stamp = CMAKE_BUILD / "setup-py-configured-for.txt"
        key = configure_key()
        done = stamp.read_text(encoding="utf-8") if stamp.exists() else ""
        if done and not done.startswith(key):
            (CMAKE_BUILD / "CMakeCache.txt").unlink(missing_ok=True)
            shutil.rmtree(CMAKE_BUILD / "CMakeFiles", ignore_errors=True)
        command = "\n".join(configure) + "\n"
        if done != key + command or not (CMAKE_BUILD / "CMakeCache.txt").exists():
            stamp.unlink(missing_ok=True)
            subprocess.run(configure, check=True)
            stamp.write_text(key + command, encoding="utf-8")
        build = ["cmake", "--build", str(CMAKE_BUILD), "--target", "fss_python"]
        if self.parallel:
            build += ["-j", str(self.parallel)]
        elif "CMAKE_BUILD_PARALLEL_LEVEL" not in os.environ:
            build += ["-j", str(os.cpu_count() or 1)]
        subprocess.run(build, check=True)
        built = CMAKE_BUILD / "python" / "fss" / ("_fss" + sysconfig.get_config_var("EXT_SUFFIX"))
        if not built.exists():
            sys.exit(f"setup.py: the build made no {built}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


# setuptools' own build files and the egg-info go under build-python-pip/ too,
# not into the source tree.
CMAKE_BUILD.mkdir(exist_ok=True)
setup(
    name="fssim",
    version=project_version(),
    description="Flutter shutter camera simulator: the module fss on numpy arrays",
    long_description=(SOURCE / "README.md").read_text(encoding="utf-8"),
    long_description_content_type="text/markdown",
    license="BSD-3-Clause",
    license_files=["LICENSE"],
    python_requires=">=3.9",
    install_requires=["numpy"],
    packages=["fss"],
    package_dir={"fss": "python/fss"},
    package_data={"fss": ["*.pyi", "py.typed"]},
    ext_modules=[Extension("fss._fss", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={
        "build": {"build_base": str(CMAKE_BUILD / "setuptools")},
        "egg_info": {"egg_base": str(CMAKE_BUILD)},
    },
    zip_safe=False,
)
