# SPDX-License-Identifier: MIT
"""The ROS 2 interface package `orb_accel_msgs`, generated from the ROS 1 node's definitions
(sw/orb_ros/orb_accel_msgs/msg/*.msg, srv/*.srv: the one source) by the ROS 2 generators from
PyPI, and compiled here (docs/ros2.md, "The message"). Nothing is written by hand.

`build()` runs, in the ROS 2 venv (`make setup` makes `.venv-ros2`): rosidl's translation to IDL
and the generators `rosidl_generator_c`, `rosidl_generator_py`, `rosidl_typesupport_c`,
`rosidl_typesupport_fastrtps_c` and `rosidl_typesupport_introspection_c` (the classes behind
`rosidl generate`, called directly: the CLI refuses the duplicate entry points the PyPI wheels
register); then it compiles the generated C and C++ with the system's compiler against the headers
and libraries the ROS 2 wheels install under the venv (`include/`, `lib/`) into five shared
libraries and the Python extension, as ament's CMake would. Once per version of the definitions
and of the ROS 2 wheels, into ORB_ACCEL_ROS2_MSGS_DIR, else
~/.cache/orb-accel/ros2-msgs/<hash>/ (`lib/`, `python/orb_accel_msgs/`).

`load()` makes them importable: the libraries are loaded by path (RTLD_GLOBAL, each with its
soname), so that rosidl's type-support dispatch, which dlopens `liborb_accel_msgs__rosidl_typesupport_*.so`
by name, finds them loaded without LD_LIBRARY_PATH; the Python package goes on sys.path.

    python -m orb_ros2.interfaces     # build (or find) them and print the directory
"""

from __future__ import annotations

import contextlib
import ctypes
import hashlib
import importlib
import io
import os
import shutil
import subprocess
import sys
import sysconfig
from importlib import metadata
from pathlib import Path
from types import ModuleType

from orb_ros.msgs import MSG_PACKAGE_DIR, PACKAGE, definitions

# the PyPI distributions of the ROS 2 venv (one list: the Makefile's setup-ros2 installs them, the
# docs name them); catkin-pkg: rosidl_adapter's .msg -> .idl translation imports it; rosbags: the
# test's bag recorder
ROS2_REQUIREMENTS = Path(__file__).resolve().parent / "requirements.txt"
# the shared libraries, in link order (each needs the ones before it)
LIBS = ("rosidl_generator_c", "rosidl_typesupport_introspection_c", "rosidl_typesupport_fastrtps_c",
        "rosidl_typesupport_c", "rosidl_generator_py")  # fmt: skip
DEPENDS = ("std_msgs", "builtin_interfaces", "service_msgs")  # the packages the definitions use (Header, services)


class Ros2Unavailable(RuntimeError):
    """ROS 2 (rclpy and the generators from PyPI) or a compiler is missing; the message says what to do."""


def _prefix() -> Path:
    """The ROS 2 venv: where the wheels put include/, lib/ and share/."""
    prefix = Path(sys.prefix)
    if not (prefix / "include" / "rosidl_runtime_c").is_dir() or not (prefix / "share" / "std_msgs").is_dir():
        raise Ros2Unavailable(f"this Python ({sys.executable}) has no ROS 2 from PyPI: `make setup` makes .venv-ros2 "
                              f"(pip install -r {ROS2_REQUIREMENTS}; docs/ros2.md)")  # fmt: skip
    return prefix


def key() -> str:
    """The version of the generated package: the definitions, the ROS 2 wheels it is compiled
    against and the Python ABI."""
    h = hashlib.sha1()
    for path in definitions():
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    for dist in ("ros-rclpy", "ros-rosidl-generator-py", "ros-rosidl-runtime-c", "ros-std-msgs", "ros-fastcdr"):
        try:
            h.update(f"{dist}={metadata.version(dist)}\0".encode())
        except metadata.PackageNotFoundError:
            h.update(f"{dist}=none\0".encode())
    h.update(sysconfig.get_config_var("EXT_SUFFIX").encode())
    return h.hexdigest()[:12]


def default_dir() -> Path:
    base = os.environ.get("ORB_ACCEL_ROS2_MSGS_DIR")
    return Path(base) if base else Path.home() / ".cache" / "orb-accel" / "ros2-msgs" / key()


def _generate(prefix: Path, out: Path) -> None:
    """rosidl's generators into out/<generator>/ (each translates the .msg/.srv to IDL itself)."""
    os.environ.setdefault("AMENT_PREFIX_PATH", str(prefix))  # the generators find their templates there
    try:
        from rosidl_generator_c.cli import GenerateC
        from rosidl_generator_py.cli import GeneratePython
        from rosidl_typesupport_c.cli import GenerateCTypesupport
        from rosidl_typesupport_fastrtps_c.cli import GenerateFastRTPSCTypesupport
        from rosidl_typesupport_introspection_c.cli import GenerateIntrospectionCTypesupport
    except ImportError as exc:
        need = f"pip install -r {ROS2_REQUIREMENTS}"
        raise Ros2Unavailable(f"the ROS 2 generators do not import ({exc}): {need}") from None
    files = [f"{MSG_PACKAGE_DIR}:{p.relative_to(MSG_PACKAGE_DIR)}" for p in definitions()]
    generators = {"c": GenerateC, "py": GeneratePython, "typesupport_c": GenerateCTypesupport,
                  "fastrtps_c": GenerateFastRTPSCTypesupport,
                  "introspection_c": GenerateIntrospectionCTypesupport}  # fmt: skip
    for name, cls in generators.items():
        said = io.StringIO()
        try:
            with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
                cls(name).generate(PACKAGE, files, [str(prefix / "share")], output_path=out / name)
        except Exception as exc:
            raise Ros2Unavailable(f"rosidl generator {name} failed: {exc}\n{said.getvalue()[-2000:]}") from None


def _run(cmd: list[str]) -> None:
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise Ros2Unavailable(f"compiling orb_accel_msgs failed: {' '.join(cmd[:3])} ...:\n{r.stderr[-3000:]}")


def _compile(prefix: Path, gen: Path, out: Path) -> None:
    """The generated sources into out/lib/*.so and out/python/orb_accel_msgs/ (as ament would)."""
    cc, cxx = os.environ.get("CC", "gcc"), os.environ.get("CXX", "g++")
    for tool in (cc, cxx):
        if shutil.which(tool) is None:
            raise Ros2Unavailable(f"no C/C++ compiler ({tool}) to build orb_accel_msgs: apt-get install g++")
    inc = out / "include" / PACKAGE
    for name in ("c", "introspection_c", "fastrtps_c"):
        for header in (gen / name).rglob("*.h"):
            rel = header.relative_to(gen / name)
            if rel.parts[0] in ("msg", "srv"):
                (inc / rel).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(header, inc / rel)
    import numpy  # the ROS 2 venv's numpy (the wheels' own dependency)

    includes = [f"-I{out / 'include'}", f"-I{prefix / 'include'}"]
    includes += [f"-I{d}" for d in sorted((prefix / "include").iterdir()) if d.is_dir()]
    includes += [f"-I{sysconfig.get_paths()['include']}", f"-I{numpy.get_include()}"]
    lib = out / "lib"
    lib.mkdir(parents=True)
    flags = ["-O2", "-fPIC", "-shared", "-w", *includes, f"-L{prefix / 'lib'}", f"-L{lib}", "-Wl,-rpath,$ORIGIN"]
    ours = {name: f"{PACKAGE}__{name}" for name in LIBS}

    def deps(kind: str) -> list[str]:
        return [f"-l{p}__{kind}" for p in DEPENDS]

    def sources(name: str, pattern: str) -> list[str]:
        found = sorted(str(p) for p in (gen / name).rglob(pattern))
        if not found:
            raise Ros2Unavailable(f"generator {name} wrote no {pattern} under {gen / name}")
        return found

    def shared(name: str, compiler: str, srcs: list[str], libs: list[str], std: tuple[str, ...] = ()) -> None:
        target = f"lib{ours[name]}.so"
        _run([compiler, *std, *flags, *srcs, "-o", str(lib / target), f"-Wl,-soname,{target}", *libs])

    runtime = ["-lrosidl_runtime_c", "-lrcutils"]
    shared("rosidl_generator_c", cc, sources("c", "*.c"), [*deps("rosidl_generator_c"), *runtime])
    shared("rosidl_typesupport_introspection_c", cc, sources("introspection_c", "*.c"),
           [f"-l{ours['rosidl_generator_c']}", *deps("rosidl_typesupport_introspection_c"),
            "-lrosidl_typesupport_introspection_c", *runtime])  # fmt: skip
    shared("rosidl_typesupport_fastrtps_c", cxx, sources("fastrtps_c", "*.cpp"),
           [f"-l{ours['rosidl_generator_c']}", *deps("rosidl_typesupport_fastrtps_c"),
            *deps("rosidl_typesupport_fastrtps_cpp"), "-lrosidl_typesupport_fastrtps_c",
            "-lrosidl_typesupport_fastrtps_cpp", "-lfastcdr", "-lrmw", *runtime], ("-std=c++17",))  # fmt: skip
    shared("rosidl_typesupport_c", cxx, sources("typesupport_c", "*.cpp"),
           [f"-l{ours['rosidl_generator_c']}", "-lrosidl_typesupport_c", *runtime], ("-std=c++17",))  # fmt: skip
    py_sources = [s for s in sources("py", "*_s.c") if "/msg/" in s or "/srv/" in s]
    shared("rosidl_generator_py", cc, py_sources,
           [f"-l{ours['rosidl_generator_c']}", f"-l{ours['rosidl_typesupport_c']}", *deps("rosidl_generator_py"),
            *deps("rosidl_generator_c"), *runtime])  # fmt: skip
    pkg = out / "python" / PACKAGE
    pkg.mkdir(parents=True)
    ext = f"{PACKAGE}_s__rosidl_typesupport_c{sysconfig.get_config_var('EXT_SUFFIX')}"
    _run([cc, *flags, str(gen / "py" / f"_{PACKAGE}_s.ep.rosidl_typesupport_c.c"), "-o", str(pkg / ext),
          "-Wl,-rpath,$ORIGIN/../../lib", f"-l{ours['rosidl_generator_py']}", f"-l{ours['rosidl_generator_c']}",
          f"-l{ours['rosidl_typesupport_c']}", *runtime])  # fmt: skip
    for kind in ("msg", "srv"):
        if (gen / "py" / kind).is_dir():
            shutil.copytree(gen / "py" / kind, pkg / kind, ignore=shutil.ignore_patterns("*.c"))
    (pkg / "__init__.py").write_text("")


def build(out: Path | None = None) -> Path:
    """Generate and compile the package (once per key()) and return its directory."""
    out = default_dir() if out is None else out
    if (out / "python" / PACKAGE / "__init__.py").exists():
        return out
    prefix = _prefix()
    tmp = out.parent / f".{out.name}.{os.getpid()}"
    shutil.rmtree(tmp, ignore_errors=True)
    try:
        _generate(prefix, tmp / "gen")
        _compile(prefix, tmp / "gen", tmp / "build")
        out.parent.mkdir(parents=True, exist_ok=True)
        try:
            (tmp / "build").rename(out)  # atomic: a concurrent build may have won
        except OSError:
            if not (out / "python" / PACKAGE / "__init__.py").exists():
                raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out


_loaded: tuple[ModuleType, ModuleType] | None = None


def load(out: Path | None = None) -> tuple[ModuleType, ModuleType]:
    """(orb_accel_msgs.msg, orb_accel_msgs.srv) for rclpy, built if needed."""
    global _loaded
    if _loaded is None:
        root = build(out)
        for name in LIBS:
            ctypes.CDLL(str(root / "lib" / f"lib{PACKAGE}__{name}.so"), mode=ctypes.RTLD_GLOBAL)
        if str(root / "python") not in sys.path:
            sys.path.insert(0, str(root / "python"))
            importlib.invalidate_caches()
        _loaded = importlib.import_module(f"{PACKAGE}.msg"), importlib.import_module(f"{PACKAGE}.srv")
    return _loaded


def definition_text(name: str = "Features") -> str:
    """A message's definition as ROS 2 tools (rosbags, rosbag2's metadata) read it: the .msg file."""
    return (MSG_PACKAGE_DIR / "msg" / f"{name}.msg").read_text()


if __name__ == "__main__":
    print(build())
