# SPDX-License-Identifier: MIT
"""ROS bags of the accelerator's node to the project's CSV directory and to ROS 2 bags (docs/ros-bags.md).

The node publishes one ``orb_accel_msgs/Features`` message per frame (sw/orb_ros/orb_accel_msgs/msg/
Features.msg). ``features_from_msg`` turns one message, from rosbags or from rospy (genpy), into the
project's feature columns (golden_model.features.Features), checking that it is consistent.
``bag_to_csv`` and ``bag_to_ros2`` convert a ROS 1 bag (as Debian's ``rosbag record`` writes it) with
PyPI ``rosbags``; only the features topic is converted.
"""

from __future__ import annotations

import dataclasses
import shutil
from collections.abc import Iterator
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
from rosbags.rosbag1 import Reader as Reader1
from rosbags.rosbag1 import ReaderError as ReaderError1
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Writer2
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from golden_model.brief import DESCRIPTOR_BYTES
from golden_model.config import MODES, check_step
from golden_model.features import NO_SECTOR, Features
from golden_model.frameparams import FrameParams
from orb_accel.csvdir import CsvDir

TOPIC = "/orb_accel/features"
PACKAGE = "orb_accel_msgs"
MSGTYPE = f"{PACKAGE}/msg/Features"  # rosbags' (ROS 2 style) name; ROS 1 says orb_accel_msgs/Features
MSG_DIR = Path(__file__).resolve().parents[1] / "orb_ros" / PACKAGE / "msg"
STORAGES = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}
ROS2_BAG_VERSION = 8  # rosbags 0.11.9 writes rosbag2 metadata version 8 or 9; 8 is the older one


def _register(store: Stores) -> Typestore:
    if not MSG_DIR.is_dir():
        raise FileNotFoundError(f"{MSG_DIR}: message definitions of {PACKAGE} missing (broken installation?)")
    typestore = get_typestore(store)
    for msg in sorted(MSG_DIR.glob("*.msg")):
        typestore.register(get_types_from_msg(msg.read_text(), f"{PACKAGE}/msg/{msg.stem}"))
    return typestore


@cache
def typestore_ros1() -> Typestore:
    """ROS 1 Noetic types plus orb_accel_msgs (for reading ROS 1 bags)."""
    return _register(Stores.ROS1_NOETIC)


@cache
def typestore_ros2() -> Typestore:
    """ROS 2 Humble types plus orb_accel_msgs (std_msgs/Header without seq; for writing ROS 2 bags)."""
    return _register(Stores.ROS2_HUMBLE)


def md5sum() -> str:
    """The ROS 1 md5sum of orb_accel_msgs/Features (the same as genmsg's)."""
    return typestore_ros1().generate_msgdef(MSGTYPE)[1]


def _array(value: Any, dtype: type) -> np.ndarray:
    if isinstance(value, bytes | bytearray | memoryview):  # genpy's uint8[]
        return np.frombuffer(bytes(value), dtype=np.uint8).astype(dtype)
    return np.asarray(value, dtype=dtype).reshape(-1)


def features_from_msg(msg: Any) -> Features:
    """One Features message (rosbags or genpy object: attribute access only) to feature columns.

    Raises ValueError when the message is inconsistent: parallel arrays of different lengths, a
    descriptor length other than 32 N (orb mode) or 0 (fast mode), x/y that are not the
    full-resolution centres of scale_x/scale_y, an angle off the sector grid, a non-integral response.
    """
    mode, sectors = str(msg.mode), int(msg.sectors)
    if mode not in MODES:
        raise ValueError(f"mode {mode!r} not one of {MODES}")
    cols = {
        name: _array(getattr(msg, name), np.float64)
        for name in ("x", "y", "size", "angle", "response", "octave", "scale_x", "scale_y")
    }
    lengths = {name: len(col) for name, col in cols.items()}
    n = lengths["x"]
    if len(set(lengths.values())) != 1:
        raise ValueError(f"feature arrays of different lengths: {lengths}")
    desc = _array(msg.descriptors, np.uint8)
    code, low = _array(msg.corner_response, np.uint8), _array(msg.low, np.uint8)
    if len(code) != n or len(low) != n:
        raise ValueError(f"{len(code)} corner responses and {len(low)} low flags for {n} features")
    if n and (code.max() >= 64 or low.max() > 1):
        raise ValueError("a corner response above 63 or a low flag other than 0 and 1")
    want = n * DESCRIPTOR_BYTES if mode == "orb" else 0
    if len(desc) != want:
        raise ValueError(f"{len(desc)} descriptor bytes for {n} features in {mode} mode (expected {want})")
    octave, sx, sy = cols["octave"], cols["scale_x"], cols["scale_y"]
    if n and (octave.min() < 0 or octave.max() >= int(msg.scales)):
        raise ValueError(f"octave outside 0 .. scales - 1 = {int(msg.scales) - 1}")
    num, den = int(msg.step_num), int(msg.step_den)
    check_step(num, den)  # ConfigError, a ValueError
    want_x, want_y = Features(
        octave.astype(np.int64), sx.astype(np.int64), sy.astype(np.int64), step=(num, den)
    ).full_res()
    for name, pos, want in (("x", sx, want_x), ("y", sy, want_y)):
        bad = np.flatnonzero(np.float32(want) != np.float32(cols[name]))
        if len(bad):
            i = bad[0]
            raise ValueError(
                f"feature {i}: {name} = {cols[name][i]:g} is not (scale_{name} + 0.5) * r^octave - 0.5 "
                f"with scale_{name} = {pos[i]:g}, octave = {octave[i]:g}, r = {num}/{den}"
            )
    score = cols["response"]
    if not np.all(np.isfinite(score) & (score == np.round(score))):
        raise ValueError("a response is not an integer (FAST scores are)")
    angle = cols["angle"]
    if mode == "fast":
        if not np.all(angle == -1):
            raise ValueError("an angle other than -1 in fast mode")
        sector = np.full(n, NO_SECTOR, dtype=np.int64)
    else:
        exact = angle * sectors / 360.0 if sectors > 0 else np.full(n, np.nan)
        bad = np.flatnonzero(~(np.isfinite(exact) & (exact == np.round(exact)) & (exact >= 0) & (exact < sectors)))
        if len(bad):
            raise ValueError(f"feature {bad[0]}: angle {angle[bad[0]]:g} is not on a sector of {sectors}")
        sector = exact.astype(np.int64)
    return Features(
        octave.astype(np.int64), sx.astype(np.int64), sy.astype(np.int64), score.astype(np.int64), sector,
        desc.reshape(n, DESCRIPTOR_BYTES if mode == "orb" else 0), sectors, (num, den), code.astype(np.int64),
        low.astype(bool),
    )  # fmt: skip


def _stamp_seconds(stamp: Any) -> float:
    """A header stamp in seconds: rosbags' Time (sec, nanosec) or rospy's (secs, nsecs)."""
    if hasattr(stamp, "nanosec"):
        return stamp.sec + stamp.nanosec * 1e-9
    return stamp.secs + stamp.nsecs * 1e-9


def _open_topic(bag: Path, topic: str) -> tuple[Reader1, list]:
    """Open a ROS 1 bag and find the topic's connections, checking their type and md5sum.

    The caller closes the reader (it is open: do not use it as a context manager again).
    """
    bag = Path(bag)
    if not bag.is_file():
        raise FileNotFoundError(f"{bag}: no such bag file")
    reader = Reader1(bag)
    try:
        reader.open()
    except ReaderError1 as err:
        raise ValueError(f"{bag}: not a readable ROS 1 bag ({err})") from None
    try:
        conns = [c for c in reader.connections if c.topic == topic]
        if not conns:
            have = sorted({c.topic for c in reader.connections})
            raise ValueError(f"{bag}: no topic {topic} (topics: {', '.join(have) or 'none'})")
        ours = md5sum()
        for c in conns:
            if c.msgtype != MSGTYPE:
                raise ValueError(f"{bag}: topic {topic} has type {c.msgtype}, not {MSGTYPE}")
            if c.digest != ours:
                raise ValueError(
                    f"{bag}: {topic} was recorded with another version of {PACKAGE}/Features "
                    f"(md5sum {c.digest}, this version's is {ours})"
                )
    except BaseException:
        reader.close()
        raise
    return reader, conns


def _messages(reader: Reader1, conns: list) -> Iterator[tuple[int, Any]]:
    """(record time in ns, message) in record-time order."""
    ts = typestore_ros1()
    try:
        for _, timestamp, raw in reader.messages(connections=conns):
            yield timestamp, ts.deserialize_ros1(raw, MSGTYPE)
    except ReaderError1 as err:
        raise ValueError(f"{reader.path}: damaged ROS 1 bag ({err})") from None


def _clean_up(out: Path, existed: bool) -> None:
    """Remove what a failed conversion wrote: out itself, or its contents when it existed (empty) before."""
    shutil.rmtree(out, ignore_errors=True)
    if existed:
        out.mkdir(exist_ok=True)


def params_from_msg(msg: object) -> FrameParams:
    """The parameters a message says its frame was processed with (docs/ros.md)."""
    return FrameParams(threshold=int(msg.threshold), threshold_lo=int(msg.threshold_lo), mode=str(msg.mode),
                       selection=str(msg.selection), budget=int(msg.budget), cols=int(msg.cols),
                       rows=int(msg.rows))  # fmt: skip


def bag_to_csv(bag: Path, out: Path, topic: str = TOPIC) -> int:
    """Convert the topic of a ROS 1 bag to a CSV directory (orb_accel.csvdir); returns the frame count.

    The stamp column is the header stamp in seconds. ``out`` must be new or empty; on an error
    (a malformed message, a damaged bag) it is left as it was.
    """
    out = Path(out)
    reader, conns = _open_topic(bag, topic)
    try:
        existed = out.exists()
        with CsvDir(out) as csv_dir:
            try:
                for _, msg in _messages(reader, conns):
                    csv_dir.write(
                        features_from_msg(msg), frame=msg.frame, stamp=_stamp_seconds(msg.header.stamp),
                        params=params_from_msg(msg), width=msg.width, height=msg.height,
                        dropped=msg.dropped, truncated=msg.truncated,
                    )  # fmt: skip
            except BaseException:
                csv_dir.close()
                _clean_up(out, existed)
                raise
            return csv_dir.count
    finally:
        reader.close()


def _to_ros2(msg: Any) -> Any:
    """A ROS 1 Features message (rosbags) as the ROS 2 one: the same fields, Header without seq."""
    types = typestore_ros2().types
    stamp = types["builtin_interfaces/msg/Time"](sec=msg.header.stamp.sec, nanosec=msg.header.stamp.nanosec)
    header = types["std_msgs/msg/Header"](stamp=stamp, frame_id=msg.header.frame_id)
    cls = types[MSGTYPE]
    return cls(**{f.name: header if f.name == "header" else getattr(msg, f.name) for f in dataclasses.fields(cls)})


def bag_to_ros2(bag: Path, out: Path, storage: str = "sqlite3", topic: str = TOPIC) -> int:
    """Convert the topic of a ROS 1 bag to a new ROS 2 bag directory; returns the message count.

    ``storage`` is "sqlite3" or "mcap". The messages keep the ROS 1 bag's record times; they become
    the ROS 2 definition of orb_accel_msgs/msg/Features (std_msgs/Header without seq). Other topics
    are not copied. ``out`` must not exist; on an error it is removed again.
    """
    out = Path(out)
    if storage not in STORAGES:
        raise ValueError(f"storage {storage!r} not one of {tuple(STORAGES)}")
    if out.exists():
        raise FileExistsError(f"{out}: exists already (not overwriting)")
    reader, conns = _open_topic(bag, topic)
    ts = typestore_ros2()
    count = 0
    try:
        with Writer2(out, version=ROS2_BAG_VERSION, storage_plugin=STORAGES[storage]) as writer:
            conn = writer.add_connection(topic, MSGTYPE, typestore=ts)
            for timestamp, msg in _messages(reader, conns):
                writer.write(conn, timestamp, ts.serialize_cdr(_to_ros2(msg), MSGTYPE))
                count += 1
    except BaseException:
        shutil.rmtree(out, ignore_errors=True)
        raise
    finally:
        reader.close()
    return count


def _files(n: int) -> str:
    if n == 0:
        return "index.csv"
    return f"frame_000000.csv .. frame_{n - 1:06d}.csv, index.csv" if n > 1 else "frame_000000.csv, index.csv"


def main_csv(bag: Path, out: Path, topic: str) -> str:
    """`orb-accel bag csv`: convert, and return a one-line summary (errors: see bag_to_csv)."""
    n = bag_to_csv(bag, out, topic)
    return f"{bag}: {n} frames of {topic} -> {out}/ ({_files(n)})"


def main_ros2(bag: Path, out: Path, storage: str, topic: str) -> str:
    """`orb-accel bag ros2`: convert, and return a one-line summary (errors: see bag_to_ros2)."""
    n = bag_to_ros2(bag, out, storage, topic)
    return f"{bag}: {n} frames of {topic} -> {out}/ (ROS 2 bag, {storage})"
