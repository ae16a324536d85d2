# SPDX-License-Identifier: MIT
"""ROS 1 from Debian's packages, and the node's message classes generated from the .msg/.srv files
of orb_accel_msgs/ (this package's data) by Debian's genpy tools, without catkin.

`generate()` runs genpy's genmsg_py.py and gensrv_py.py once per version of the definitions into
a cache directory (ORB_ACCEL_MSGS_DIR, else ~/.cache/orb-accel/ros-msgs/<hash>) and returns the
directory to put on the Python path; `ros_env()` gives the environment (PYTHONPATH,
ROS_PACKAGE_PATH) under which rostopic, rosmsg and rosbag understand the messages. On the board's
Debian the system Python has rospy; on a machine where `python3` is another interpreter (a venv),
Debian's /usr/lib/python3/dist-packages is appended to sys.path, after the venv's own packages
(docs/ros.md). No OpenCV, no build tools.
"""

from __future__ import annotations

import hashlib
import importlib
import os
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

PACKAGE = "orb_accel_msgs"
MSG_PACKAGE_DIR = Path(__file__).resolve().parent / PACKAGE  # package.xml, msg/, srv/
PACKAGE_PATH = MSG_PACKAGE_DIR.parent  # a ROS_PACKAGE_PATH entry that holds orb_accel_msgs
DEBIAN_PYTHON = Path("/usr/bin/python3")
DEBIAN_SITE = Path("/usr/lib/python3/dist-packages")
GENPY_DIR = Path("/usr/lib/genpy")
STD_MSGS_DIR = Path("/usr/share/std_msgs/msg")
# the Debian 12 packages the node, its tests and the tools need (one list: also read by .ci/run and
# scripts/flow/check_tools.sh); all are architecture "all" or built for armhf
APT_PACKAGES = (Path(__file__).resolve().parent / "debian-packages.txt").read_text().strip()


class RosUnavailable(RuntimeError):
    """ROS 1 (or a part of it) is not installed; the message names the Debian packages."""


def _missing(what: str) -> RosUnavailable:
    return RosUnavailable(f"{what} is not installed: apt-get install {APT_PACKAGES} (Debian 12; docs/ros.md)")


def import_rospy() -> ModuleType:
    """rospy, from this interpreter's path or else from Debian's dist-packages (appended)."""
    try:
        return importlib.import_module("rospy")
    except ImportError:
        pass
    if (DEBIAN_SITE / "rospy").is_dir() and str(DEBIAN_SITE) not in sys.path:
        sys.path.append(str(DEBIAN_SITE))
        importlib.invalidate_caches()
        try:
            return importlib.import_module("rospy")
        except ImportError as exc:
            raise RosUnavailable(f"rospy from {DEBIAN_SITE} does not import here ({exc})") from None
    raise _missing("ROS 1 (rospy)")


def fields(name: str = "Features", kind: str = "msg") -> dict[str, str]:
    """A definition's fields, name -> type ("float32[]", "std_msgs/Header", ...), in order: the
    layout both nodes fill (orb_ros.loop.feature_arrays takes the arrays' types from here)."""
    out = {}
    for line in (MSG_PACKAGE_DIR / kind / f"{name}.{kind}").read_text().splitlines():
        words = line.split("#", 1)[0].split()
        if words == ["---"]:
            break
        if len(words) >= 2:
            out[words[1]] = words[0]
    return out


def definitions() -> list[Path]:
    """The .msg and .srv files, sorted."""
    return sorted([*MSG_PACKAGE_DIR.glob("msg/*.msg"), *MSG_PACKAGE_DIR.glob("srv/*.srv")])


def definitions_hash() -> str:
    h = hashlib.sha1()
    for path in definitions():
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:12]


def _genpy_python() -> str:
    """An interpreter that has Debian's genpy (its generator scripts import genpy and genmsg)."""
    for python in (sys.executable, str(DEBIAN_PYTHON)):
        ok = subprocess.run([python, "-c", "import genpy, genmsg"], capture_output=True).returncode == 0
        if ok:
            return python
    raise _missing("genpy (python3-genpy, python3-genmsg)")


def generate(out: Path | None = None) -> Path:
    """Generate the Python classes (once per version of the definitions) and return the directory
    that holds the `orb_accel_msgs` package."""
    if out is None:
        base = os.environ.get("ORB_ACCEL_MSGS_DIR")
        out = Path(base) if base else Path.home() / ".cache" / "orb-accel" / "ros-msgs" / definitions_hash()
    pkg = out / PACKAGE
    if (pkg / "__init__.py").exists():
        return out
    for tool in ("genmsg_py.py", "gensrv_py.py"):
        if not (GENPY_DIR / tool).exists():
            raise _missing(f"genpy's {tool}")
    if not STD_MSGS_DIR.is_dir():
        raise _missing(f"std_msgs' message files ({STD_MSGS_DIR}: ros-std-msgs)")
    python = _genpy_python()
    tmp = out / f".{PACKAGE}.{os.getpid()}"
    includes = [f"-I{PACKAGE}:{MSG_PACKAGE_DIR / 'msg'}", f"-Istd_msgs:{STD_MSGS_DIR}"]
    for kind, tool in (("msg", "genmsg_py.py"), ("srv", "gensrv_py.py")):
        files = [str(p) for p in definitions() if p.parent.name == kind]
        dest = tmp / PACKAGE / kind
        gen = [python, str(GENPY_DIR / tool), "-p", PACKAGE]
        for cmd in ([*gen, *includes, "-o", str(dest), *files], [*gen, "--initpy", "-o", str(dest)]):
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                raise RosUnavailable(f"{tool} failed: {r.stderr.strip() or r.stdout.strip()}")
    (tmp / PACKAGE / "__init__.py").write_text("")
    pkg.parent.mkdir(parents=True, exist_ok=True)
    try:
        (tmp / PACKAGE).rename(pkg)  # atomic: a concurrent generator may have won
    except OSError:
        if not (pkg / "__init__.py").exists():
            raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out


def std_msgs_shim(out: Path) -> Path | None:
    """Debian's ros-std-msgs installs /usr/share/std_msgs/msg without a package.xml, so rospack (and
    with it `rosmsg show` of a message that uses std_msgs/Header) cannot find the package. This
    makes `out/packages/std_msgs` (a package.xml and a link to the message folder) and returns
    `out/packages` for ROS_PACKAGE_PATH; None when the installed package has its own."""
    if (STD_MSGS_DIR.parent / "package.xml").exists() or not STD_MSGS_DIR.is_dir():
        return None
    pkg = out / "packages" / "std_msgs"
    if not (pkg / "package.xml").exists():
        pkg.mkdir(parents=True, exist_ok=True)
        link = pkg / "msg"
        if not link.exists():
            link.symlink_to(STD_MSGS_DIR)
        tmp = pkg / f".package.xml.{os.getpid()}"
        tmp.write_text(
            '<?xml version="1.0"?>\n<package format="2"><name>std_msgs</name><version>0.0.0</version>'
            "<description>Debian's std_msgs messages (a shim made by orb_ros.msgs)</description>"
            '<maintainer email="none@example.org">none</maintainer><license>BSD</license></package>\n'
        )
        tmp.replace(pkg / "package.xml")
    return pkg.parent


def load() -> tuple[ModuleType, ModuleType]:
    """(orb_accel_msgs.msg, orb_accel_msgs.srv), generated if needed (they import genpy and
    std_msgs: Debian's ROS must be importable, see import_rospy)."""
    import_rospy()
    root = str(generate())
    if root not in sys.path:
        sys.path.insert(0, root)
        importlib.invalidate_caches()
    return importlib.import_module(f"{PACKAGE}.msg"), importlib.import_module(f"{PACKAGE}.srv")


def ros_env(base: dict[str, str] | None = None) -> dict[str, str]:
    """Environment variables under which Debian's ROS tools (rostopic, rosbag, rosmsg) and the
    system Python see the generated messages: PYTHONPATH and ROS_PACKAGE_PATH prepended."""
    env = dict(os.environ if base is None else base)
    root = str(generate())

    def prepend(name: str, value: str) -> None:
        parts = [p for p in env.get(name, "").split(os.pathsep) if p]
        env[name] = os.pathsep.join([value, *[p for p in parts if p != value]])

    prepend("PYTHONPATH", root)
    shim = std_msgs_shim(Path(root))
    if shim is not None:
        prepend("ROS_PACKAGE_PATH", str(shim))
    prepend("ROS_PACKAGE_PATH", str(PACKAGE_PATH))
    return env
