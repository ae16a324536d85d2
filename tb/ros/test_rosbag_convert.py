# SPDX-License-Identifier: MIT
"""ROS bags of orb_accel_msgs/Features to CSV directories and ROS 2 bags (orb_tools.rosbag_convert,
orb_accel.csvdir; docs/ros-bags.md), with messages made from the model's features on photographs.
The ROS 1 bag is written with rosbags and read back by Debian's rosbag (system Python)."""

from __future__ import annotations

import dataclasses
import json
import subprocess
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import Reader as Reader2
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from golden_model.config import Config
from golden_model.features import Features, first_difference
from golden_model.frameparams import FrameParams
from golden_model.pipeline import extract
from orb_accel.csvdir import INDEX_COLUMNS, CsvDir, read_csv_dir
from orb_tools.rosbag_convert import (
    MSG_DIR,
    MSGTYPE,
    TOPIC,
    bag_to_csv,
    bag_to_ros2,
    features_from_msg,
    main_csv,
    main_ros2,
    md5sum,
    typestore_ros1,
)
from orbtb.images import flat, photo

ORB = Config(128, 96, scales=2, sectors=32, threshold=20, mode="orb")
# the per-feature arrays but the descriptors (uint8[] arrays, genpy's bytes, read as ints here)
ARRAYS = ("x", "y", "size", "angle", "response", "octave", "scale_x", "scale_y", "corner_response", "low")
COUNTERS = ("frames_total", "dropped_total", "overflow_total", "overrun_total", "protocol_errors_total",
            "desc_lost_total", "discarded_total")  # fmt: skip
T0 = 1_700_000_000_123_456_789  # ns
GRID54 = dataclasses.replace(ORB, threshold=30, scales=4, step_num=5, step_den=4, selection="grid", budget=50, cols=5,
                             rows=4, threshold_lo=9)  # fmt: skip


@dataclasses.dataclass(frozen=True)
class Frame:
    cfg: Config
    features: Features
    frame: int
    stamp_ns: int
    dropped: int = 0
    truncated: int = 0


@pytest.fixture(scope="module")
def frames() -> list[Frame]:
    """Two photographs in orb mode (2:1 x 2 and 5:4 x 4), one in fast mode, one frame without features;
    frame numbers wrap."""
    cases = [
        (ORB, photo("astronaut", 128, 96)),
        (GRID54, photo("coffee", 128, 96)),
        (dataclasses.replace(ORB, mode="fast"), photo("astronaut", 128, 96)),
        (ORB, flat(128, 96)),
    ]
    out = []
    for i, (cfg, img) in enumerate(cases):
        feats = extract(img, cfg)
        out.append(Frame(cfg, feats, (65534 + i) % 65536, T0 + i * 33_333_333, dropped=i, truncated=2 * i))
    assert [len(f.features) > 0 for f in out] == [True, True, True, False]
    assert out[2].features.descriptor.shape[1] == 0
    return out


def make_msg(fr: Frame) -> object:
    """The node's message for one frame (rosbags' ROS 1 classes), as docs of Features.msg say."""
    types = typestore_ros1().types
    f, cfg = fr.features, fr.cfg
    p = FrameParams.of(cfg)
    mult = (cfg.step_num / cfg.step_den) ** f.scale.astype(np.float64)
    stamp = types["builtin_interfaces/msg/Time"](sec=fr.stamp_ns // 10**9, nanosec=fr.stamp_ns % 10**9)
    return types[MSGTYPE](
        header=types["std_msgs/msg/Header"](seq=fr.frame, stamp=stamp, frame_id="orb_accel"),
        width=cfg.width, height=cfg.height, frame=fr.frame, threshold=cfg.threshold, mode=cfg.mode,
        scales=cfg.scales, sectors=cfg.sectors, step_num=cfg.step_num, step_den=cfg.step_den,
        budget=p.budget if p.selection == "grid" else 0, selection=p.selection, threshold_lo=p.threshold_lo,
        cols=p.cols, rows=p.rows,
        x=((f.x + 0.5) * mult - 0.5).astype(np.float32), y=((f.y + 0.5) * mult - 0.5).astype(np.float32),
        size=(31 * mult).astype(np.float32),
        angle=np.where(f.sector >= 0, f.sector * (360.0 / cfg.sectors), -1.0).astype(np.float32),
        response=f.score.astype(np.float32), octave=f.scale.astype(np.int32),
        scale_x=f.x.astype(np.uint16), scale_y=f.y.astype(np.uint16),
        descriptors=np.ascontiguousarray(f.descriptor, dtype=np.uint8).reshape(-1),
        corner_response=f.response.astype(np.uint8), low=f.low.astype(np.uint8),
        dropped=fr.dropped, truncated=fr.truncated,
        **{name: 100 + k for k, name in enumerate(COUNTERS)},
    )  # fmt: skip


def write_bag(path: Path, msgs: list[object] | None, *, md5: str | None = None) -> Path:
    """A ROS 1 bag with a std_msgs/String topic and the messages on TOPIC (None: no TOPIC at all);
    record time = header stamp + 1 ms. ``md5``: the md5sum the TOPIC connection claims."""
    ts = typestore_ros1()
    with Writer1(path) as w:
        chat = w.add_connection("/chatter", "std_msgs/msg/String", typestore=ts)
        w.write(chat, T0, ts.serialize_ros1(ts.types["std_msgs/msg/String"](data="hello"), "std_msgs/msg/String"))
        if msgs is None:
            return path
        if md5 is None:
            conn = w.add_connection(TOPIC, MSGTYPE, typestore=ts)
        else:
            conn = w.add_connection(TOPIC, MSGTYPE, msgdef=ts.generate_msgdef(MSGTYPE)[0], md5sum=md5)
        for m in msgs:
            t = m.header.stamp.sec * 10**9 + m.header.stamp.nanosec + 1_000_000
            w.write(conn, t, ts.serialize_ros1(m, MSGTYPE))
    return path


@pytest.fixture(scope="module")
def bag(frames: list[Frame], tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_bag(tmp_path_factory.mktemp("bag") / "features.bag", [make_msg(fr) for fr in frames])


def assert_same(want: Features, got: Features, what: str) -> None:
    diff = first_difference(want, got)
    assert diff is None, f"{what}: {diff}"
    assert got.sectors_total == want.sectors_total, what
    assert got.descriptor.shape == want.descriptor.shape, what


# --- CSV directory -----------------------------------------------------------------------------


def write_frame(d: CsvDir, fr: Frame) -> Path:
    return d.write(
        fr.features, frame=fr.frame, stamp=fr.stamp_ns / 1e9, params=FrameParams.of(fr.cfg), width=fr.cfg.width,
        height=fr.cfg.height, dropped=fr.dropped, truncated=fr.truncated,
    )  # fmt: skip


def test_csv_dir_round_trip(frames: list[Frame], tmp_path: Path) -> None:
    out = tmp_path / "new" / "csv"
    with CsvDir(out) as d:
        paths = [write_frame(d, fr) for fr in frames]
    assert [p.name for p in paths] == [f"frame_{i:06d}.csv" for i in range(len(frames))]
    assert (out / "index.csv").read_text().splitlines()[0] == ",".join(INDEX_COLUMNS)
    back = read_csv_dir(out)
    assert len(back) == len(frames)
    for i, (fr, (row, feats)) in enumerate(zip(frames, back, strict=True)):
        assert row == {
            "index": i, "file": paths[i].name, "frame": fr.frame, "stamp": fr.stamp_ns / 1e9,
            "threshold": fr.cfg.threshold, "mode": fr.cfg.mode, "sectors": fr.cfg.sectors, "width": 128,
            "height": 96, "features": len(fr.features), "dropped": fr.dropped, "truncated": fr.truncated,
            "threshold_lo": fr.cfg.threshold_lo, "selection": fr.cfg.selection, "budget": fr.cfg.budget,
            "cols": fr.cfg.cols, "rows": fr.cfg.rows,
        }  # fmt: skip
        assert_same(fr.features, feats, f"frame {i}")


def test_csv_dir_refuses_non_empty_dir(tmp_path: Path) -> None:
    CsvDir(tmp_path / "empty").close()  # an empty directory is fine, and so is a new one
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / "notes.txt").write_text("mine")
    with pytest.raises(FileExistsError, match="not an empty directory"):
        CsvDir(tmp_path / "x")
    with pytest.raises(FileExistsError):
        CsvDir(tmp_path / "empty")  # now it holds index.csv
    assert (tmp_path / "x" / "notes.txt").read_text() == "mine"


# --- features_from_msg ---------------------------------------------------------------------------


def test_features_from_msg(frames: list[Frame]) -> None:
    for fr in frames:
        assert_same(fr.features, features_from_msg(make_msg(fr)), f"frame {fr.frame}")


def genpy_like(msg: object) -> SimpleNamespace:
    """What rospy hands a callback: numeric arrays as tuples, uint8[] as bytes."""
    fields = {name: getattr(msg, name) for name in ("mode", "sectors", "scales", "step_num", "step_den", "frame")}
    arrays = {name: tuple(getattr(msg, name).tolist()) for name in ARRAYS}
    return SimpleNamespace(**fields, **arrays, descriptors=bytes(msg.descriptors))


def test_features_from_genpy_shaped_msg(frames: list[Frame]) -> None:
    for fr in frames:
        assert_same(fr.features, features_from_msg(genpy_like(make_msg(fr))), f"frame {fr.frame}")


def _cut(name: str, n: int = 1):
    return lambda m: dataclasses.replace(m, **{name: getattr(m, name)[:-n]})


def _set(name: str, i: int, value: float):
    def change(m):
        a = getattr(m, name).copy()
        a[i] = value
        return dataclasses.replace(m, **{name: a})

    return change


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (_cut("y"), "different lengths"),
        (_cut("octave"), "different lengths"),
        (_cut("descriptors"), "descriptor bytes"),
        (_cut("descriptors", 32), "descriptor bytes"),
        (_cut("corner_response"), "corner responses"),
        (_cut("low"), "low flags"),
        (_set("corner_response", 0, 64), "above 63"),
        (_set("low", 0, 2), "low flag other than"),
        (_set("x", 3, 10.25), "x = 10.25 is not"),
        (_set("y", 0, -3.0), "y = -3 is not"),
        (_set("angle", 2, 5.0), "not on a sector"),
        (_set("angle", 2, 360.0), "not on a sector"),
        (_set("angle", 2, float("nan")), "not on a sector"),
        (_set("response", 1, 20.5), "not an integer"),
        (_set("octave", 1, 2), "octave outside"),
        (lambda m: dataclasses.replace(m, step_den=3), "step_den must be"),
        (lambda m: dataclasses.replace(m, mode="brief"), "mode 'brief'"),
        (lambda m: dataclasses.replace(m, mode="fast"), "in fast mode"),
    ],
)
def test_features_from_msg_rejects(frames: list[Frame], change, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        features_from_msg(change(make_msg(frames[0])))


def test_fast_mode_needs_no_angles(frames: list[Frame]) -> None:
    msg = make_msg(frames[2])
    with pytest.raises(ValueError, match="angle other than -1"):
        features_from_msg(_set("angle", 0, 0.0)(msg))


# --- bag to CSV ------------------------------------------------------------------------------------


def test_bag_to_csv(frames: list[Frame], bag: Path, tmp_path: Path) -> None:
    out = tmp_path / "csv"
    line = main_csv(bag, out, TOPIC)
    assert line == f"{bag}: 4 frames of {TOPIC} -> {out}/ (frame_000000.csv .. frame_000003.csv, index.csv)"
    back = read_csv_dir(out)
    assert [row["frame"] for row, _ in back] == [65534, 65535, 0, 1]
    for fr, (row, feats) in zip(frames, back, strict=True):
        assert (row["threshold"], row["mode"], row["sectors"], row["width"], row["height"]) == (
            fr.cfg.threshold, fr.cfg.mode, fr.cfg.sectors, fr.cfg.width, fr.cfg.height,
        )  # fmt: skip
        assert (row["dropped"], row["truncated"], row["features"]) == (fr.dropped, fr.truncated, len(fr.features))
        p = FrameParams.of(fr.cfg)
        budget = p.budget if p.selection == "grid" else 0
        assert (row["threshold_lo"], row["selection"], row["budget"], row["cols"], row["rows"]) == (
            p.threshold_lo, p.selection, budget, p.cols, p.rows)  # fmt: skip
        assert row["stamp"] == pytest.approx(fr.stamp_ns / 1e9, abs=1e-6)
        assert_same(fr.features, feats, f"frame {fr.frame}")


def test_topic_without_messages(tmp_path: Path) -> None:
    empty = write_bag(tmp_path / "empty.bag", [])
    assert main_csv(empty, tmp_path / "csv", TOPIC).endswith(f"0 frames of {TOPIC} -> {tmp_path / 'csv'}/ (index.csv)")
    assert read_csv_dir(tmp_path / "csv") == []
    assert bag_to_ros2(empty, tmp_path / "ros2") == 0


def test_bad_message_leaves_no_csv(frames: list[Frame], tmp_path: Path) -> None:
    bad = write_bag(tmp_path / "bad.bag", [make_msg(frames[0]), _cut("descriptors")(make_msg(frames[1]))])
    with pytest.raises(ValueError, match="descriptor bytes"):
        bag_to_csv(bad, tmp_path / "csv")
    assert not (tmp_path / "csv").exists()
    (tmp_path / "empty").mkdir()
    with pytest.raises(ValueError, match="descriptor bytes"):
        bag_to_csv(bad, tmp_path / "empty")
    assert list((tmp_path / "empty").iterdir()) == []


# --- bag to ROS 2 --------------------------------------------------------------------------------


def ros2_typestore():
    """An independent ROS 2 typestore with the repository's message (as a ROS 2 user would build it)."""
    ts = get_typestore(Stores.ROS2_JAZZY)
    ts.register(get_types_from_msg((MSG_DIR / "Features.msg").read_text(), MSGTYPE))
    return ts


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_bag_to_ros2(frames: list[Frame], bag: Path, tmp_path: Path, storage: str) -> None:
    out = tmp_path / "ros2"
    assert main_ros2(bag, out, storage, TOPIC) == f"{bag}: 4 frames of {TOPIC} -> {out}/ (ROS 2 bag, {storage})"
    ts = ros2_typestore()
    assert f"storage_identifier: {storage}" in (out / "metadata.yaml").read_text()
    with Reader2(out) as reader:
        assert [(c.topic, c.msgtype, c.msgcount) for c in reader.connections] == [(TOPIC, MSGTYPE, 4)]
        assert reader.connections[0].digest == ts.hash_rihs01(MSGTYPE)
        got = [(t, ts.deserialize_cdr(raw, MSGTYPE)) for _, t, raw in reader.messages()]
    assert len(got) == len(frames)
    for fr, (t, msg) in zip(frames, got, strict=True):
        assert t == fr.stamp_ns + 1_000_000  # the ROS 1 bag's record time
        assert not hasattr(msg.header, "seq")
        assert msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec == fr.stamp_ns
        assert msg.header.frame_id == "orb_accel"
        assert (msg.frame, msg.mode, msg.threshold) == (fr.frame, fr.cfg.mode, fr.cfg.threshold)
        assert [getattr(msg, name) for name in COUNTERS] == list(range(100, 107))
        assert_same(fr.features, features_from_msg(msg), f"{storage} frame {fr.frame}")


# --- errors ----------------------------------------------------------------------------------------


def test_missing_bag(tmp_path: Path) -> None:
    missing = tmp_path / "none.bag"
    with pytest.raises(FileNotFoundError, match=r"none\.bag"):
        bag_to_csv(missing, tmp_path / "csv")
    with pytest.raises(FileNotFoundError, match=r"none\.bag"):
        bag_to_ros2(missing, tmp_path / "ros2")
    assert not (tmp_path / "csv").exists() and not (tmp_path / "ros2").exists()


def test_text_file_is_no_bag(bag: Path, tmp_path: Path) -> None:
    text = tmp_path / "notes.bag"
    text.write_text("not a bag\n")
    with pytest.raises(ValueError, match=r"notes\.bag: not a readable ROS 1 bag"):
        bag_to_csv(text, tmp_path / "csv")
    with pytest.raises(ValueError, match=r"notes\.bag: not a readable ROS 1 bag"):
        bag_to_ros2(text, tmp_path / "ros2", "mcap")
    cut = tmp_path / "cut.bag"
    cut.write_bytes(bag.read_bytes()[: bag.stat().st_size // 2])  # e.g. a copy cut short: no index
    with pytest.raises(ValueError, match=r"cut\.bag: not a readable ROS 1 bag"):
        bag_to_csv(cut, tmp_path / "csv")
    assert not (tmp_path / "csv").exists() and not (tmp_path / "ros2").exists()


def test_bag_without_topic(tmp_path: Path) -> None:
    other = write_bag(tmp_path / "other.bag", None)
    with pytest.raises(ValueError, match=f"other.bag: no topic {TOPIC} \\(topics: /chatter"):
        bag_to_csv(other, tmp_path / "csv")
    with pytest.raises(ValueError, match="no topic /elsewhere"):
        bag_to_ros2(other, tmp_path / "ros2", topic="/elsewhere")
    assert not (tmp_path / "csv").exists() and not (tmp_path / "ros2").exists()


def test_existing_outputs_refused(bag: Path, tmp_path: Path) -> None:
    (tmp_path / "ros2").mkdir()
    with pytest.raises(FileExistsError, match="ros2: exists already"):
        bag_to_ros2(bag, tmp_path / "ros2")
    (tmp_path / "csv").mkdir()
    (tmp_path / "csv" / "index.csv").write_text("earlier run\n")
    with pytest.raises(FileExistsError, match="not an empty directory"):
        bag_to_csv(bag, tmp_path / "csv")
    assert (tmp_path / "csv" / "index.csv").read_text() == "earlier run\n"
    with pytest.raises(ValueError, match="storage 'zip'"):
        bag_to_ros2(bag, tmp_path / "new", "zip")


def test_md5_mismatch_refused(frames: list[Frame], tmp_path: Path) -> None:
    old = write_bag(tmp_path / "old.bag", [make_msg(frames[0])], md5="0123456789abcdef0123456789abcdef")
    with pytest.raises(ValueError, match="recorded with another version of orb_accel_msgs/Features"):
        bag_to_csv(old, tmp_path / "csv")
    with pytest.raises(ValueError, match="another version"):
        bag_to_ros2(old, tmp_path / "ros2")
    assert not (tmp_path / "csv").exists() and not (tmp_path / "ros2").exists()


# --- Debian's ROS 1 reads the bag --------------------------------------------------------------------

DEBIAN_READ = """
import json, sys
import rosbag
path, topic = sys.argv[1:3]
with rosbag.Bag(path) as bag:
    info = bag.get_type_and_topic_info()
    out = {"types": info.msg_types, "count": info.topics[topic].message_count, "msgs": []}
    for _, m, _ in bag.read_messages(topics=[topic]):
        d = {k: list(getattr(m, k)) for k in %r}
        d.update(md5=m._md5sum, type=m._type, mode=m.mode, frame=m.frame, sectors=m.sectors, scales=m.scales,
                 step_num=m.step_num, step_den=m.step_den,
                 seq=m.header.seq, stamp=[m.header.stamp.secs, m.header.stamp.nsecs],
                 descriptors=m.descriptors.hex(), shapes=[type(m.x).__name__, type(m.descriptors).__name__])
        out["msgs"].append(d)
print(json.dumps(out))
""" % (ARRAYS,)  # noqa: UP031


def debian_python(script: str, *args: str, stdin: str = "") -> str:
    """Run a script in the system Python, which has Debian's python3-rosbag (the venv has not)."""
    if not Path("/usr/bin/rosbag").exists():
        pytest.fail("Debian's ROS 1 bag tools are missing: apt-get install python3-rosbag")
    run = subprocess.run(
        ["/usr/bin/python3", "-c", script, *args], input=stdin, capture_output=True, text=True, timeout=60
    )
    assert run.returncode == 0, run.stderr
    return run.stdout


def test_debian_rosbag_reads_the_bag(frames: list[Frame], bag: Path) -> None:
    out = json.loads(debian_python(DEBIAN_READ, str(bag), TOPIC))
    assert out["types"] == {"orb_accel_msgs/Features": md5sum(), "std_msgs/String": out["types"]["std_msgs/String"]}
    assert out["count"] == len(frames)
    for fr, m in zip(frames, out["msgs"], strict=True):
        # genpy computed this md5 from the definition stored in the bag, independently of rosbags
        assert (m["md5"], m["type"]) == (md5sum(), "orb_accel_msgs/Features")
        assert (m["frame"], m["seq"], m["mode"]) == (fr.frame, fr.frame, fr.cfg.mode)
        assert m["stamp"] == [fr.stamp_ns // 10**9, fr.stamp_ns % 10**9]
        assert m["shapes"] == ["tuple", "bytes"]
        msg = SimpleNamespace(
            **{k: tuple(m[k]) for k in ARRAYS}, mode=m["mode"], sectors=m["sectors"], scales=m["scales"],
            step_num=m["step_num"], step_den=m["step_den"], descriptors=bytes.fromhex(m["descriptors"]),
        )  # fmt: skip
        assert_same(fr.features, features_from_msg(msg), f"genpy frame {fr.frame}")


DEBIAN_WRITE = """
import json, sys
import genpy, genpy.dynamic, rosbag
path, topic, msg_file = sys.argv[1:4]
# the full text a publisher's genpy class carries (genmsg: the .msg, then each dependency)
header = "MSG: std_msgs/Header\\nuint32 seq\\ntime stamp\\nstring frame_id\\n"
text = open(msg_file).read() + "\\n" + "=" * 80 + "\\n" + header
types = genpy.dynamic.generate_dynamic("orb_accel_msgs/Features", text)
with rosbag.Bag(path, "w") as bag:
    for d in json.load(sys.stdin):
        m = types["orb_accel_msgs/Features"]()
        sec, nsec = d.pop("stamp")
        m.header = types["std_msgs/Header"](seq=d.pop("seq"), stamp=genpy.Time(sec, nsec), frame_id="orb_accel")
        m.descriptors = bytes.fromhex(d.pop("descriptors"))
        for k, v in d.items():
            setattr(m, k, v)
        bag.write(topic, m, genpy.Time(sec, nsec) + genpy.Duration(0, 1000000))
"""


def test_bag_written_by_debian_rosbag(frames: list[Frame], tmp_path: Path) -> None:
    """A bag as `rosbag record` writes it (Debian's rosbag.Bag, a genpy class made from the .msg
    text): accepted (same md5sum) and converted to the same features."""
    scalars = ("width", "height", "frame", "threshold", "mode", "scales", "sectors", "step_num", "step_den", "budget",
               "selection", "threshold_lo", "cols", "rows", "dropped", "truncated", *COUNTERS)  # fmt: skip
    data = []
    for fr in frames:
        m = make_msg(fr)
        d = {k: getattr(m, k) for k in scalars} | {k: getattr(m, k).tolist() for k in ARRAYS}
        d |= {
            "seq": fr.frame,
            "stamp": [fr.stamp_ns // 10**9, fr.stamp_ns % 10**9],
            "descriptors": m.descriptors.tobytes().hex(),
        }
        data.append(d)
    path = tmp_path / "recorded.bag"
    debian_python(DEBIAN_WRITE, str(path), TOPIC, str(MSG_DIR / "Features.msg"), stdin=json.dumps(data))
    assert bag_to_csv(path, tmp_path / "csv") == len(frames)
    back = read_csv_dir(tmp_path / "csv")
    for fr, (row, feats) in zip(frames, back, strict=True):
        assert (row["frame"], row["mode"], row["threshold"]) == (fr.frame, fr.cfg.mode, fr.cfg.threshold)
        assert row["stamp"] == pytest.approx(fr.stamp_ns / 1e9, abs=1e-6)
        assert_same(fr.features, feats, f"frame {fr.frame}")
    assert bag_to_ros2(path, tmp_path / "ros2", "mcap") == len(frames)
