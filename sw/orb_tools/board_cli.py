# SPDX-License-Identifier: MIT
"""The CPU-side commands of `orb-accel` (docs/driver.md, docs/ros.md, docs/stream.md): `board info`,
`board stream`, `serve`, `ros`, `ros-env`, `sim-server` and `bag`. `board`, `serve` and `ros` take
one bus:

- `--uio [NAME]` (the default: UIO device "orb-accel" of the device-tree overlay), `--devmem BASE`:
  the board;
- `--connect HOST:PORT`: a simulator already serving (`orb-accel sim-server`);
- `--sim IMAGE_OR_VIDEO...`: start a simulator on those frames (streamed round and round) for the
  command's lifetime;

or `board stream --remote HOST:PORT`: the frames of an `orb-accel serve` on another machine.
`--ddr-memory SPEC` says where a DDR build's ring of frames lies (docs/driver.md, "Features from
DDR"; used only when the accelerator says CFG_DDR.ddr = 1): `udmabuf[:NAME]` (the default on the
board: u-dma-buf's udmabuf0), `array[:PHYS]` (in-process; the default on a simulator), `pynq`.

On the board these need numpy and Debian's packages only: OpenCV, cocotb and the simulator are
imported only for --sim, sim-server and bag.
"""

from __future__ import annotations

import argparse
import signal
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import ExitStack, contextmanager
from pathlib import Path

from golden_model import limits
from golden_model.config import MODES, NAMES, named, parse_step
from golden_model.frameparams import FrameParams
from orb_accel.bus import BOARD_TIMEOUT_S, SIM_TIMEOUT_FRAMES, Bus
from orb_accel.csvdir import CsvDir
from orb_accel.ddr import MemoryFactory, memory_factory
from orb_accel.driver import Frame, HwConfig, OrbAccel
from orb_accel.serve import DEFAULT_MAX_CLIENTS, DEFAULT_QUEUE
from orb_accel.stream import DEFAULT_PORT
from orb_sim.sim_server import DEFAULT_CONFIG, ENGINES, TOPLEVELS  # pure Python at import: fine on the board


def add_bus_options(p: argparse.ArgumentParser, remote: bool = False) -> None:
    g = p.add_mutually_exclusive_group()
    if remote:
        g.add_argument("--remote", metavar="HOST:PORT",
                       help="the frames of an `orb-accel serve` on HOST:PORT (docs/stream.md), not a bus")  # fmt: skip
    g.add_argument("--uio", metavar="NAME", nargs="?", const="orb-accel",
                   help="the board, through UIO device NAME (default when no bus is given: orb-accel)")  # fmt: skip
    g.add_argument("--devmem", metavar="BASE", type=lambda t: int(t, 0),
                   help="the board through /dev/mem at physical address BASE (0x43C00000; root; polls)")  # fmt: skip
    g.add_argument("--connect", metavar="HOST:PORT", help="a running simulator (orb-accel sim-server)")
    g.add_argument("--sim", metavar="IMAGE_OR_VIDEO", nargs="+", type=Path,
                   help="start a simulator streaming these images or videos (one size) round and round")  # fmt: skip
    p.add_argument("--sim-config", metavar="NAME", default=DEFAULT_CONFIG, choices=NAMES,
                   help=f"simulated bitstream: a named configuration (default {DEFAULT_CONFIG})")  # fmt: skip
    p.add_argument("--sim-scales", type=int, help="simulated bitstream: scales instead of the configuration's")
    p.add_argument("--sim-step", help="simulated bitstream: pyramid step NUM:DEN instead of the configuration's")
    p.add_argument("--sim-sectors", type=int, help="simulated bitstream: sectors instead of the configuration's")
    p.add_argument("--sim-mem-depth", type=int, help="simulated bitstream: slots per bank instead of the config's")
    p.add_argument("--sim-size", metavar="WxH",
                   help="resize the frames to WxH (default: the config's; native: the frames' own)")  # fmt: skip
    p.add_argument(
        "--sim-engine",
        choices=ENGINES,
        default="ghdl",
        help="ghdl: the RTL (default); fast: the synthesised netlist in Verilator (docs/fast-sim.md)",
    )
    p.add_argument("--sim-top", choices=TOPLEVELS, default=TOPLEVELS[0],
                   help="simulated top: the accelerator, or the board's Vivado wrapper (RBG video)")  # fmt: skip
    p.add_argument("--sim-max-frames", type=int, default=50, help="at most this many frames from a video (50)")
    p.add_argument("--sim-fault", metavar="SPEC", action="append", default=[],
                   help="a fault the simulator injects (repeatable): cut:EVERY:PERIODS (fast engine) or "
                        "buserr:OP:WHERE:FIRST[:EVERY[:RESP]] (docs/driver.md, Faults and recovery)")  # fmt: skip
    p.add_argument("--timeout", type=float, help=f"seconds to wait for a frame (board: {BOARD_TIMEOUT_S:g}; "
                   f"simulator: {SIM_TIMEOUT_FRAMES} frame periods of simulated time)")  # fmt: skip
    p.add_argument("--ddr-memory", metavar="SPEC",
                   help="a DDR build's frame memory (CFG_DDR.ddr = 1 only): udmabuf[:NAME] (default on the board: "
                        "udmabuf0), array[:PHYS] (default on a simulator), pynq (docs/driver.md)")  # fmt: skip


def add_parsers(sub: argparse._SubParsersAction) -> None:
    board = sub.add_parser("board", help="first look at the accelerator: identity, configuration, frames")
    bsub = board.add_subparsers(dest="board_command", required=True, parser_class=type(board))
    info = bsub.add_parser("info", help="identity, configuration, control registers and counters")
    add_bus_options(info)
    stream = bsub.add_parser("stream", help="read frames: frames per second, features per frame, counters")
    add_bus_options(stream, remote=True)
    stream.add_argument("--frames", type=int, default=10, help="frames to read (default 10; 0: until Ctrl-C)")
    stream.add_argument("--csv", type=Path, metavar="DIR", help="write each frame as DIR/frame_NNNNNN.csv")
    add_frame_options(stream)

    serve = sub.add_parser("serve", help="stream every frame's features to clients over TCP (docs/stream.md)")
    add_bus_options(serve)
    serve.add_argument(
        "--listen",
        metavar="HOST:PORT",
        default=f"0.0.0.0:{DEFAULT_PORT}",
        help=f"where clients connect (default 0.0.0.0:{DEFAULT_PORT}, every interface; port 0: any)",
    )
    serve.add_argument("--queue", type=int, default=DEFAULT_QUEUE,
                       help=f"frames queued per client before its oldest goes (default {DEFAULT_QUEUE})")  # fmt: skip
    serve.add_argument("--max-clients", type=int, default=DEFAULT_MAX_CLIENTS,
                       help=f"clients served at once (default {DEFAULT_MAX_CLIENTS})")  # fmt: skip
    serve.add_argument("--frames", type=int, default=0, help="stop after N frames (default 0: until Ctrl-C or SIGTERM)")
    add_frame_options(serve)

    ros = sub.add_parser("ros", help="the ROS 1 node: /orb_accel/features (docs/ros.md); NAME:=VALUE remaps")
    add_bus_options(ros)
    ros.add_argument("--threshold", type=int, default=20, help="start-up threshold (private parameter ~threshold wins)")
    ros.add_argument("--mode", choices=MODES, default="orb", help="start-up mode (~mode wins)")
    ros.add_argument("--roscore", action="store_true", help="start a roscore when none answers at ROS_MASTER_URI")
    sub.add_parser("ros-env", help="print shell exports under which rostopic/rosbag know orb_accel_msgs")

    ros2 = sub.add_parser("ros2", help="the ROS 2 node: /orb_accel/features (docs/ros2.md); --ros-args ... to the node")
    add_bus_options(ros2, remote=True)
    ros2.add_argument("--threshold", type=int, default=20, help="start-up threshold (parameter threshold wins)")
    ros2.add_argument("--mode", choices=MODES, default="orb", help="start-up mode (parameter mode wins)")
    ros2.add_argument("--ros2-python", metavar="PYTHON", type=Path,
                      help="the ROS 2 venv's python (default: $ORB_ACCEL_ROS2_PYTHON, else the checkout's "
                           ".venv-ros2/bin/python)")  # fmt: skip
    ros2.add_argument("--ros-args", nargs=argparse.REMAINDER, metavar="ARG",
                      help="the rest goes to the node as ROS arguments: -p NAME:=VALUE, -r FROM:=TO")  # fmt: skip

    srv = sub.add_parser("sim-server", help="serve a simulated accelerator on a local socket (docs/driver.md)")
    srv.add_argument("frames", nargs="+", type=Path, metavar="IMAGE_OR_VIDEO")
    srv.add_argument("--port", type=int, default=5555, help="TCP port on 127.0.0.1 (default 5555; 0: any)")
    srv.add_argument("--config", metavar="NAME", default=DEFAULT_CONFIG, choices=NAMES,
                     help=f"a named configuration (docs/configurations.md; default {DEFAULT_CONFIG})")  # fmt: skip
    srv.add_argument("--scales", type=int, help="instead of the configuration's")
    srv.add_argument("--step", help="pyramid step NUM:DEN instead of the configuration's")
    srv.add_argument("--sectors", type=int, help="instead of the configuration's")
    srv.add_argument("--mem-depth", type=int, help="instead of the configuration's")
    srv.add_argument("--size", metavar="WxH", help="resize the frames to WxH (default: the configuration's; 'native')")
    srv.add_argument("--top", choices=TOPLEVELS, default=TOPLEVELS[0])
    srv.add_argument("--engine", choices=ENGINES, default="ghdl", help="fast: the netlist in Verilator")
    srv.add_argument("--max-frames", type=int, default=50)
    srv.add_argument(
        "--fault",
        metavar="SPEC",
        action="append",
        default=[],
        help="a fault to inject (repeatable; docs/driver.md, Faults and recovery)",
    )

    bag = sub.add_parser("bag", help="convert a ROS 1 bag of /orb_accel/features (docs/ros-bags.md)")
    bsub2 = bag.add_subparsers(dest="bag_command", required=True, parser_class=type(bag))
    to_csv = bsub2.add_parser("csv", help="one CSV per frame plus index.csv")
    to_ros2 = bsub2.add_parser("ros2", help="a ROS 2 bag (sqlite3 or mcap)")
    for q in (to_csv, to_ros2):
        q.add_argument("bag", type=Path)
        q.add_argument("--out", type=Path, required=True)
        q.add_argument("--topic", default="/orb_accel/features")
    to_ros2.add_argument("--storage", choices=("sqlite3", "mcap"), default="mcap")


def add_frame_options(p: argparse.ArgumentParser) -> None:
    """The parameters a command that reads frames writes first (not with --remote: the server's)."""
    p.add_argument("--threshold", type=int, help=f"FAST threshold {limits.THRESHOLD.text} (default 20)")
    p.add_argument("--mode", choices=MODES, help="orb (default) or fast")
    p.add_argument("--budget", type=int, default=None,
                   help="at most N features a frame, the accelerator's grid selection (default: the recommended "
                        "one of the frame size, within a bank; 0: every feature)")  # fmt: skip


def _configure(accel: OrbAccel, args: argparse.Namespace, timeout: float) -> bool:
    """Write the frame options (defaults: threshold 20, orb, the recommended budget) and let the
    frame in flight pass; True when the grid selection is on."""
    if args.budget is not None and not 0 <= args.budget <= accel.hw.capacity:
        raise ValueError(f"--budget must be 0..{accel.hw.capacity} (a bank's capacity), got {args.budget}")
    grid = args.budget != 0
    accel.configure(args.threshold, args.mode, selection="grid" if grid else "all",
                    budget=args.budget if grid else None)  # fmt: skip
    accel.settle(timeout)  # the frame in flight may have started with the old values
    return grid


def _frame_options(args: argparse.Namespace) -> None:
    """Check the frame options and fill in their defaults (threshold 20, mode orb)."""
    if args.threshold is None:
        args.threshold = 20
    if args.mode is None:
        args.mode = "orb"
    if not limits.THRESHOLD.legal(args.threshold):
        raise ValueError(f"threshold must be {limits.THRESHOLD.text}, got {args.threshold}")
    if args.frames < 0:
        raise ValueError(f"--frames must be 0 or more, got {args.frames}")


def _size(text: str | None, config: str) -> tuple[int, int] | None:
    """The simulated frames' size: WxH, the named configuration's (None given), None for 'native'."""
    if text is None:
        nc = named(config)
        return nc.width, nc.height
    if text == "native":
        return None
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"size {text!r} is not WxH or native") from None
    return w, h


def _start_sim(stack: ExitStack, paths: list[Path], config: str, size: str | None, max_frames: int, top: str,
               engine: str = "ghdl", port: int = 0, scales: int | None = None, step: str | None = None,
               sectors: int | None = None, mem_depth: int | None = None,
               faults: Sequence[str] = ()) -> str:  # fmt: skip
    from orb_sim.sim_server import SimServer
    from orb_tools.images import load_frames

    frames = load_frames(paths, _size(size, config), max_frames)
    h, w = frames.shape[1:3]
    server = SimServer(frames, config, scales=scales, sectors=sectors, mem_depth=mem_depth, toplevel=top, port=port,
                       engine=engine, step=None if step is None else parse_step(step), faults=faults)  # fmt: skip
    g = server.generics
    print(f"starting the simulator ({engine}): {top} {w}x{h}, {config}: {g['SCALES_g']} scales of "
          f"{g['STEP_NUM_g']}:{g['STEP_DEN_g']}, {g['SECTORS_g']} sectors, {g['MEM_DEPTH_g']} slots per bank, "
          f"{len(frames)} frame(s) round and round"
          f"{', faults ' + ' '.join(server.config['faults']) if faults else ''} ...", flush=True)  # fmt: skip
    stack.enter_context(server)
    print(f"simulator listening on {server.address} (log: {server.log})", flush=True)
    return server.address


@contextmanager
def open_bus(args: argparse.Namespace) -> Iterator[tuple[Bus, str, float]]:
    """(bus, description, frame timeout in the bus's seconds) for the command's bus options."""
    from orb_accel.socket_bus import SocketBus

    with ExitStack() as stack:
        if args.sim or args.connect:
            address = args.connect or _start_sim(
                stack,
                args.sim,
                args.sim_config,
                args.sim_size,
                args.sim_max_frames,
                args.sim_top,
                args.sim_engine,
                scales=args.sim_scales,
                step=args.sim_step,
                sectors=args.sim_sectors,
                mem_depth=args.sim_mem_depth,
                faults=args.sim_fault,
            )
            bus = stack.enter_context(SocketBus(address))
            timeout = args.timeout or SIM_TIMEOUT_FRAMES * bus.frame_period_s()
            yield bus, f"simulator {address} ({bus.info['toplevel']})", timeout
        elif args.devmem is not None:
            from orb_accel.devmem import DevMemBus

            _traceback_on_sigbus()
            yield (
                stack.enter_context(DevMemBus(args.devmem)),
                f"/dev/mem at {args.devmem:#x}",
                args.timeout or BOARD_TIMEOUT_S,
            )
        else:
            from orb_accel.uio import UioBus

            _traceback_on_sigbus()
            name = args.uio or "orb-accel"
            bus = stack.enter_context(UioBus.open(name))
            yield bus, f"UIO device {name!r}", args.timeout or BOARD_TIMEOUT_S


def ddr_memory(args: argparse.Namespace, bus: object | None = None) -> MemoryFactory:
    """--ddr-memory as OrbAccel(memory=) takes it: opened only for a DDR build (orb_accel.ddr); on a
    simulator by default its simulated DDR, read over the socket (`bus`)."""
    return memory_factory(getattr(args, "ddr_memory", None), board=not (args.sim or args.connect), bus=bus)


def _traceback_on_sigbus() -> None:
    """On the board an error response to a load is a SIGBUS that ends the process (docs/driver.md,
    "Faults and recovery"): leave the Python stack of the access on stderr."""
    import faulthandler

    if not faulthandler.is_enabled():
        faulthandler.enable()


def _counters_line(counters: dict[str, int]) -> str:
    return ", ".join(f"{k} {v}" for k, v in counters.items())


def cmd_info(args: argparse.Namespace) -> int:
    from golden_model import regs

    with open_bus(args) as (bus, what, _):
        accel = OrbAccel(bus, release_stale=False)  # it only looks: another program may be reading a bank
        major, minor = accel.version()
        hw = accel.hw
        status = accel.read(regs.STATUS)
        print(f"accelerator on {what}: ID {accel.read(regs.ID):#010x} ('ORB1'), register map {major}.{minor}")
        print(f"configuration: {hw.width}x{hw.height}, {hw.scales} scales of {hw.step_num}:{hw.step_den}, "
              f"{hw.sectors} sectors, "
              f"{hw.mem_depth} slots per bank ({hw.mem_depth - 1} features per frame at most)")  # fmt: skip
        sel = accel.selection
        cells = f"{sel.cells[0]} x {sel.cells[1]} cells"
        how = (f"grid selection, budget {sel.budget}, {cells}, low threshold {sel.threshold_lo}"
               if sel.mode == "grid" else "every feature (selection all)")  # fmt: skip
        print(f"control: {'enabled' if accel.enabled else 'disabled'}, mode {accel.mode}, threshold {accel.threshold}, "
              f"{how}; STATUS {status:#x}, IRQ_STATUS {accel.read(regs.IRQ_STATUS):#x}")  # fmt: skip
        print(f"counters: {_counters_line(accel.counters())}")
        if accel.ddr:
            assert accel.window is not None
            ring = {n.lower(): accel.read(getattr(regs, n)) for n in ("RING_BASE", "RING_STRIDE", "RING_COUNT",
                                                                      "RING_STATUS")}  # fmt: skip
            print(f"features to DDR: window {accel.window.text()}; "
                  + ", ".join(f"{k} {v:#x}" for k, v in ring.items())
                  + f"; {_counters_line(accel.dma_counters())}")  # fmt: skip
    return 0


def _frame_line(frame: Frame, hw: HwConfig, made_with: FrameParams | None, n: int, t0: float, extra: str = "") -> str:
    per_scale = "/".join(str(int((frame.scale == s).sum())) for s in range(hw.scales))
    how = made_with.text() if made_with is not None else "parameters not recorded"
    return (f"frame {frame.number}: {len(frame)} features (per scale {per_scale}), dropped {frame.dropped}, "
            f"truncated {frame.truncated}; {how}; {n / (time.monotonic() - t0):.2f} frames/s{extra}")  # fmt: skip


def _write_csv(csv: CsvDir | None, frame: Frame, hw: HwConfig, made_with: FrameParams, stamp: float) -> None:
    if csv is not None:
        csv.write(frame.features, frame=frame.number, stamp=stamp, params=made_with, width=hw.width,
                  height=hw.height, dropped=frame.dropped, truncated=frame.truncated)  # fmt: skip


def cmd_stream(args: argparse.Namespace) -> int:
    if args.remote:
        return _stream_remote(args)
    _frame_options(args)
    with open_bus(args) as (bus, what, timeout), ExitStack() as stack:
        accel = OrbAccel(bus, memory=ddr_memory(args, bus))
        stack.callback(accel.close)
        grid = _configure(accel, args, timeout)
        csv = stack.enter_context(CsvDir(args.csv)) if args.csv is not None else None
        hw = accel.hw
        print(f"streaming from {what}: {hw.width}x{hw.height}, {hw.scales} scales, threshold {args.threshold}, "
              f"budget {accel.selection.budget if grid else 'none (every feature)'}, "
              f"mode {args.mode} (frame timeout {timeout:g} s of the bus's time)", flush=True)  # fmt: skip
        t0 = time.monotonic()
        n = total = 0
        frame = None
        for frame in accel.frames(args.frames or None, timeout):
            n += 1
            total += len(frame)
            # the frame's own parameters (its record); an accelerator before map 3.1: those written
            made_with = frame.params or accel.written()
            print(_frame_line(frame, hw, made_with, n, t0), flush=True)
            _write_csv(csv, frame, hw, made_with, time.time())
        wall = time.monotonic() - t0
        print(f"{n} frames in {wall:.2f} s: {n / wall if wall else 0:.2f} frames/s, "
              f"{total / max(n, 1):.1f} features per frame, {bus.reads} bus reads")  # fmt: skip
        if frame is not None:
            print(f"counters: {_counters_line(frame.counters)}")
        if csv is not None:
            print(f"CSV -> {args.csv}/")
    return 0


def _stream_remote(args: argparse.Namespace) -> int:
    """`board stream --remote`: the frames of an `orb-accel serve`, as they come (the server
    configures the accelerator)."""
    from orb_accel.remote import RemoteAccel
    from orb_accel.stream import StreamClosed

    given = [f"--{k}" for k in ("threshold", "mode", "budget") if getattr(args, k) is not None]
    if given:
        raise ValueError(f"{', '.join(given)}: with --remote the server sets the accelerator's parameters "
                         "(orb-accel serve --threshold ...)")  # fmt: skip
    if args.frames < 0:
        raise ValueError(f"--frames must be 0 or more, got {args.frames}")
    with RemoteAccel(args.remote, name="orb-accel board stream") as accel, ExitStack() as stack:
        if args.csv is not None and not accel.info.get("records_params", True):
            raise ValueError("--csv: this accelerator's records carry no parameters (register map before 3.1)")
        csv = stack.enter_context(CsvDir(args.csv)) if args.csv is not None else None
        hw = accel.hw
        timeout = args.timeout or accel.frame_wait_s
        print(f"streaming from orb-accel serve at {args.remote} ({accel.info.get('source', '?')}): "
              f"{hw.width}x{hw.height}, {hw.scales} scales of {hw.step_num}:{hw.step_den}, {hw.sectors} sectors; "
              f"the server queues {accel.info.get('queue_depth')} frames for this client, then drops the oldest "
              f"(frame timeout {timeout:g} s)", flush=True)  # fmt: skip
        t0 = time.monotonic()
        n = total = 0
        frame = None
        missed = 0
        try:
            while not args.frames or n < args.frames:
                frame, meta = accel.receive(timeout)
                n += 1
                total += len(frame)
                extra = f"; {meta.dropped - missed} dropped before it by the server" if meta.dropped > missed else ""
                missed = meta.dropped
                print(_frame_line(frame, hw, frame.params, n, t0, extra), flush=True)
                _write_csv(csv, frame, hw, frame.params or frame.record.params, meta.t_ready_ns * 1e-9)
        except StreamClosed as exc:
            print(exc, flush=True)
            if args.frames:
                raise
        wall = time.monotonic() - t0
        print(f"{n} frames in {wall:.2f} s: {n / wall if wall else 0:.2f} frames/s, "
              f"{total / max(n, 1):.1f} features per frame, {accel.bytes_received:,} bytes received, "
              f"{accel.dropped} frame(s) dropped by the server for this client")  # fmt: skip
        if frame is not None:
            print(f"counters: {_counters_line(frame.counters)}")
        if csv is not None:
            print(f"CSV -> {args.csv}/")
    return 0


def cmd_serve(args: argparse.Namespace) -> int:
    """`orb-accel serve`: the frame loop of orb_accel.serve until --frames, Ctrl-C or SIGTERM."""
    from orb_accel.serve import StreamServer, hello_info, serve
    from orb_accel.socket_bus import SocketBus
    from orb_accel.stream import NAME, VERSION

    _frame_options(args)
    if args.queue < 1 or args.max_clients < 1:
        raise ValueError(f"--queue and --max-clients must be 1 or more, got {args.queue} and {args.max_clients}")
    signal.signal(signal.SIGTERM, _raise_interrupt)  # a clean stop: BYE to every client
    with open_bus(args) as (bus, what, timeout):
        accel = OrbAccel(bus, memory=ddr_memory(args, bus))
        grid = _configure(accel, args, timeout)
        # a client's wait for a frame in wall seconds: the simulator's can take minutes
        wait_s = bus.op_timeout_s if isinstance(bus, SocketBus) else max(2.0, 2 * timeout)
        server = StreamServer(hello_info(accel, what, wait_s), args.listen, args.queue, args.max_clients).start()
        reason = "the server stopped"
        try:
            sel = f"budget {accel.selection.budget}" if grid else "every feature"
            print(f"serving the frames of {what} ({accel.hw.width}x{accel.hw.height}, threshold {args.threshold}, "
                  f"{sel}, mode {args.mode}) on {server.address}: {NAME} version {VERSION}, {args.queue} frame(s) "
                  f"queued per client, the oldest dropped; until "
                  f"{f'{args.frames} frames, ' if args.frames else ''}Ctrl-C or SIGTERM", flush=True)  # fmt: skip
            stats = serve(accel, server, timeout, args.frames or None)
            reason = f"the server stopped after {stats.frames} frames"
        except KeyboardInterrupt:
            reason = "the server was stopped (Ctrl-C or SIGTERM)"
        finally:
            server.close(reason)
        clients = server.clients()
        print(f"stopped: {reason}; frames read {server.seq}, clients {len(clients)}, "
              f"{server.bytes_encoded:,} bytes encoded", flush=True)  # fmt: skip
        for c in clients:
            print(f"  client {c.number} ({c.peer}, {c.name or 'unnamed'}): {c.sent} frame(s) sent, {c.dropped} "
                  f"dropped; {c.why}")  # fmt: skip
    return 0


def _raise_interrupt(_sig: int, _frame: object) -> None:
    raise KeyboardInterrupt


def _master_answers(uri: str) -> bool:
    import socket
    import xmlrpc.client

    old = socket.getdefaulttimeout()
    socket.setdefaulttimeout(2.0)
    try:
        return xmlrpc.client.ServerProxy(uri).getSystemState("/orb_accel_probe")[0] == 1
    except (OSError, xmlrpc.client.Error):
        return False
    finally:
        socket.setdefaulttimeout(old)


def _start_roscore(stack: ExitStack, uri: str) -> None:
    """A roscore on ROS_MASTER_URI's port for the command's lifetime (its own process group)."""
    import os
    import shutil
    import subprocess
    from urllib.parse import urlparse

    from orb_ros.msgs import APT_PACKAGES, RosUnavailable

    roscore = shutil.which("roscore")
    if roscore is None:
        raise RosUnavailable(f"roscore is not installed: apt-get install {APT_PACKAGES}")
    port = urlparse(uri).port or 11311
    proc = subprocess.Popen([roscore, "-p", str(port)], stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT,
                            start_new_session=True)  # fmt: skip

    def stop() -> None:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGINT)
            try:
                proc.wait(20)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)

    stack.callback(stop)
    deadline = time.monotonic() + 60
    while not _master_answers(uri):
        if proc.poll() is not None or time.monotonic() > deadline:
            raise RosUnavailable(f"roscore -p {port} did not start (exit {proc.poll()})")
        time.sleep(0.3)
    print(f"started roscore at {uri} (stops with this command)", flush=True)


def cmd_ros(args: argparse.Namespace, ros_args: list[str]) -> int:
    import os

    from orb_ros import msgs as rosmsgs
    from orb_ros.node import Params, init_node, run_node

    rospy = rosmsgs.import_rospy()
    msg_mod, srv_mod = rosmsgs.load()
    with ExitStack() as stack:
        uri = os.environ.get("ROS_MASTER_URI", "http://localhost:11311")
        if args.roscore and not _master_answers(uri):
            _start_roscore(stack, uri)
        settings = init_node(rospy, Params(args.threshold, args.mode, True), argv=[sys.argv[0], *ros_args])
        signal.signal(signal.SIGTERM, _raise_interrupt)  # rospy's handlers are off: stop the loop at once
        # SIGINT too, whatever was inherited: a shell without job control starts background jobs
        # with SIGINT ignored, and Python then installs no KeyboardInterrupt handler (roslaunch and
        # the tests stop nodes with SIGINT)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        with open_bus(args) as (bus, what, timeout):
            return run_node(rospy, msg_mod, srv_mod, bus, settings, timeout, what, memory=ddr_memory(args, bus))


def ros2_python(given: Path | None = None) -> tuple[Path, dict[str, str]]:
    """The ROS 2 venv's python (rclpy from PyPI lives only there: docs/ros2.md) and the environment
    that lets it import this project: from a source checkout, the checkout's package folders on
    PYTHONPATH (as orb_sim.hdl finds the checkout); an installed orb-accel must be installed in
    that venv too."""
    import os

    root = Path(__file__).resolve().parents[2]
    checkout = (root / "hdl" / "manifest.txt").is_file() and (root / "sw" / "orb_ros2").is_dir()
    python = given or (Path(os.environ["ORB_ACCEL_ROS2_PYTHON"]) if os.environ.get("ORB_ACCEL_ROS2_PYTHON") else None)
    if python is None and checkout:
        python = root / ".venv-ros2" / "bin" / "python"
    if python is None or not python.exists():
        from orb_ros.msgs import RosUnavailable

        raise RosUnavailable(f"no ROS 2 venv ({python or 'give --ros2-python or ORB_ACCEL_ROS2_PYTHON'}): `make setup` "
                             "makes .venv-ros2 (docs/ros2.md)")  # fmt: skip
    env = dict(os.environ)
    if checkout:
        parts = [str(root), str(root / "sw"), *[p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]]
        env["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(parts))
    return python, env


def cmd_ros2(args: argparse.Namespace, ros_args: list[str]) -> int:
    """Start the ROS 2 node (orb_ros2.node) in the ROS 2 venv, on a simulator of its own with --sim.
    SIGINT reaches the node through the process group; SIGTERM is handed on. The node's status."""
    import subprocess

    python, env = ros2_python(args.ros2_python)
    node_args = ["--threshold", str(args.threshold), "--mode", args.mode]
    if args.timeout is not None:
        ros_args = [*(ros_args or ["--ros-args"]), "-p", f"timeout:={float(args.timeout)}"]
    with ExitStack() as stack:
        if args.sim:
            address = _start_sim(stack, args.sim, args.sim_config, args.sim_size, args.sim_max_frames, args.sim_top,
                                 args.sim_engine, scales=args.sim_scales, step=args.sim_step, sectors=args.sim_sectors,
                                 mem_depth=args.sim_mem_depth, faults=args.sim_fault)  # fmt: skip
            bus = ["--connect", address]
        elif args.connect:
            bus = ["--connect", args.connect]
        elif args.remote:
            bus = ["--remote", args.remote]
        elif args.devmem is not None:
            bus = ["--devmem", hex(args.devmem)]
        else:
            bus = ["--uio", args.uio or "orb-accel"]
        if args.ddr_memory is not None and not args.remote:
            bus += ["--ddr-memory", args.ddr_memory]
        proc = subprocess.Popen([str(python), "-m", "orb_ros2.node", *bus, *node_args, *ros_args], env=env)
        signal.signal(signal.SIGTERM, lambda *_: proc.send_signal(signal.SIGTERM))
        try:
            return proc.wait()
        except KeyboardInterrupt:  # the node, in this process group, has it too
            try:
                return proc.wait(20)
            except subprocess.TimeoutExpired:
                proc.terminate()
                return proc.wait()


def cmd_ros_env(_args: argparse.Namespace) -> int:
    import shlex

    from orb_ros.msgs import ros_env

    env = ros_env({})
    for name in ("PYTHONPATH", "ROS_PACKAGE_PATH"):
        print(f"export {name}={shlex.quote(env[name])}${{{name}:+:${name}}}")
    return 0


def cmd_sim_server(args: argparse.Namespace) -> int:
    with ExitStack() as stack:
        _start_sim(stack, args.frames, args.config, args.size, args.max_frames, args.top, args.engine, args.port,
                   scales=args.scales, step=args.step, sectors=args.sectors, mem_depth=args.mem_depth,
                   faults=args.fault)  # fmt: skip
        print("serving until Ctrl-C", flush=True)
        while True:
            time.sleep(3600)


def cmd_bag(args: argparse.Namespace) -> int:
    from orb_tools import rosbag_convert

    if args.bag_command == "csv":
        print(rosbag_convert.main_csv(args.bag, args.out, args.topic))
    else:
        print(rosbag_convert.main_ros2(args.bag, args.out, args.storage, args.topic))
    return 0


def split_ros_args(argv: list[str]) -> tuple[list[str], list[str]]:
    """(our arguments, ROS remappings and private parameters: NAME:=VALUE, _param:=value)."""
    ours = [a for a in argv if ":=" not in a]
    return ours, [a for a in argv if ":=" in a]
