# SPDX-License-Identifier: MIT
"""Generate docs/img/architecture.svg: the data flow through orb_accel_top, one box per entity
instance, drawn from the HDL.

The boxes come from the instance hierarchy of hdl/top/orb_accel_top.vhd and below (`label : entity
work.orb_x`, read by orb_flow.vhdl): each box shows the entity's name, and its colour is the
entity's area in hdl/manifest.txt. What the HDL does not say in a form worth parsing is written
here: where each box sits (LAYOUT, keyed by the instance path), a few words on its role, and the
arrows of the data flow (EDGES). The generator refuses a picture that has drifted from the HDL:
an instance of the hierarchy without a place in LAYOUT, or a place of no instance, stops it. The
memory primitives (PRIMITIVES) are not drawn; the picture's caption names where they are used.

Plain SVG 1.1 text, written by this module alone (no dependency), deterministic; committed and
byte-checked by tb/house/test_docs_gen.py. Usage: python -m orb_flow.gen.architecture [--out ROOT]
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape

from orb_flow.gen.codegen import views_main
from orb_flow.vhdl import parse_entity
from orb_sim.hdl import ROOT, read_manifest

VIEW = Path("docs/img/architecture.svg")
GENERATOR = "sw/orb_flow/gen/architecture.py"
TOP = "orb_accel_top"
WRAPPER = "orb_accel_zynq"
PRIMITIVES = ("orb_line_buffer", "orb_sdp_ram")  # memories: not drawn, named in the caption

WIDTH, HEIGHT = 1500, 760
CHAR_W = 6.4  # the width of a character at FONT_SIZE, generously (checked against each box)
FONT_SIZE = 11

# instance path below orb_accel_top ("" is the top itself) -> (x, y, w, h, role)
LAYOUT: dict[str, tuple[int, int, int, int, str]] = {
    "": (145, 60, 1195, 610, ""),
    "luma": (160, 100, 120, 50, "RGB to luma"),
    "gate": (300, 100, 120, 50, "frame gate (enable)"),
    "check": (440, 100, 130, 50, "protocol check"),
    "detect": (160, 185, 965, 380, "the streaming core"),
    "detect/scaler": (175, 270, 125, 50, "2:1 box"),
    "detect/resampler": (175, 345, 125, 50, "NUM:DEN bilinear"),
    "detect/path": (320, 215, 545, 335, "one per pyramid level"),
    "detect/path/detect": (335, 245, 400, 140, "detection"),
    "detect/path/detect/window": (345, 285, 90, 50, "7x7 window"),
    "detect/path/detect/score": (455, 270, 110, 50, "FAST-9, SAD score"),
    "detect/path/detect/harris": (455, 328, 110, 50, "response code"),
    "detect/path/detect/nms": (585, 270, 140, 105, "3x3 NMS"),
    "detect/path/detect/nms/scores": (595, 315, 120, 50, "3x3 of scores"),
    "detect/path/smooth": (345, 430, 95, 50, "7x7 smoothing"),
    "detect/path/desc": (460, 400, 275, 140, "description"),
    "detect/path/desc/moments": (470, 440, 125, 50, "circular moments"),
    "detect/path/desc/sector": (603, 440, 125, 50, "sector"),
    "detect/path/selection": (750, 340, 105, 60, "grid selection"),
    "detect/merge": (885, 255, 150, 105, "levels merged"),
    "detect/merge/fifo": (895, 298, 130, 50, "per level"),
    "detect/rotate": (900, 420, 120, 55, "orbit rotation"),
    "mem": (1155, 420, 170, 55, "two banks of slots"),
    "dma": (1155, 490, 170, 95, "or: a ring in DDR"),
    "dma/fifo": (1165, 528, 150, 45, "burst FIFO"),
    "regs": (1155, 100, 170, 50, "registers, interrupt"),
    "overlay": (890, 600, 170, 55, "feature marks"),
}

# the outside world: name -> (x, y, w, h, title, role)
EXTERNAL: dict[str, tuple[int, int, int, int, str, str]] = {
    "video_in": (10, 100, 120, 50, "s_axis_video", "RGB, RBG or luma"),
    "cpu": (1355, 100, 135, 50, "s_axil: the CPU", "AXI4-Lite, irq"),
    "video_out": (1355, 600, 135, 55, "m_axis_video", "HDMI out"),
    "ddr": (1355, 510, 135, 55, "m_axi_feat", "AXI4 to DDR"),
}

# arrows: (from, side, to, side, label, dashed, points between); sides r, l, t, b (+ offset px)
EDGES: tuple[tuple[str, str, str, str, str, bool, tuple[tuple[int, int], ...]], ...] = (
    ("video_in", "r", "luma", "l", "", False, ()),
    ("luma", "r", "gate", "l", "", False, ()),
    ("gate", "r", "check", "l", "", False, ()),
    ("check", "b", "detect/path", "t-87.5", "level 0", False, ()),
    ("check", "b", "detect/scaler", "t", "", False, ((505, 172), (237.5, 172))),
    ("check", "b", "detect/resampler", "l", "", False, ((505, 172), (168, 172), (168, 370))),
    ("detect/scaler", "r", "detect/path", "l", "", False, ()),
    ("detect/resampler", "r", "detect/path", "l", "", False, ()),
    ("detect/path/detect/window", "r", "detect/path/detect/score", "l", "", False, ()),
    ("detect/path/detect/window", "r", "detect/path/detect/harris", "l", "", False, ()),
    ("detect/path/detect/score", "r", "detect/path/detect/nms", "l", "", False, ()),
    ("detect/path/detect/harris", "r", "detect/path/detect/nms", "l+45", "", False, ()),
    ("detect/path/detect/window", "b", "detect/path/smooth", "t", "", False, ()),
    ("detect/path/smooth", "r", "detect/path/desc", "l", "", False, ()),
    ("detect/path/detect/nms", "b", "detect/path/desc", "t+85", "survivors", False, ()),
    ("detect/path/detect/nms", "r", "detect/path/selection", "l-10", "", False, ()),
    ("detect/path/desc", "r", "detect/path/selection", "l+15", "", False, ()),
    ("detect/path/selection", "r", "detect/merge", "l", "", False, ()),
    ("detect/merge", "b", "detect/rotate", "t", "", False, ()),
    ("detect/rotate", "r", "mem", "l", "", False, ()),
    ("detect/rotate", "r", "dma", "l", "", False, ((1140, 447.5), (1140, 537.5))),
    ("dma", "r", "ddr", "l", "", False, ()),
    ("detect/rotate", "b", "overlay", "t", "", False, ()),
    ("video_in", "b", "overlay", "l", "the input video", False, ((70, 627.5),)),
    ("overlay", "r", "video_out", "l", "", False, ()),
    ("mem", "t", "regs", "b", "read port", False, ()),
    ("regs", "r", "cpu", "l", "", False, ()),
    ("regs", "t", "gate", "t", "enable", True, ((1240, 78), (360, 78))),
    ("regs", "l", "detect", "t+57.5", "thresholds, mode, selection, budget", True, ()),
)

# notes inside the picture: (x, y, text)
NOTES: tuple[tuple[int, int, str], ...] = (
    (175, 412, "one per level s > 0,"),
    (175, 425, "from level s - 1"),
)

AREA_FILL = {
    "input": "#dbeafe",
    "detect": "#fde68a",
    "describe": "#fbcfe8",
    "core": "#ddd6fe",
    "host": "#bbf7d0",
    "output": "#fed7aa",
    "top": "#f3f4f6",
    "common": "#e5e7eb",
}


@dataclass(frozen=True)
class Inst:
    path: str  # below orb_accel_top, "/"-separated labels
    entity: str


def hierarchy(root: Path) -> tuple[list[Inst], dict[str, str], dict[str, list[str]]]:
    """The drawn instances below TOP, each entity's area, and where each primitive is used."""
    sources = {s.name: s for s in read_manifest(root / "hdl" / "manifest.txt")}
    parsed = {name: parse_entity(s.path) for name, s in sources.items() if not s.is_package}
    out = [Inst("", TOP)]
    used: dict[str, list[str]] = {p: [] for p in PRIMITIVES}

    def walk(path: str, entity: str) -> None:
        for label, child in parsed[entity].instances:
            if child in PRIMITIVES:
                if entity not in used[child]:
                    used[child].append(entity)
                continue
            sub = f"{path}/{label}" if path else label
            out.append(Inst(sub, child))
            walk(sub, child)

    walk("", TOP)
    wraps = [label for label, child in parsed[WRAPPER].instances if child == TOP]
    if not wraps:
        raise ValueError(f"{WRAPPER} no longer instantiates {TOP}: the picture's frame is wrong")
    return out, {name: s.area for name, s in sources.items()}, used


def _anchor(box: tuple[int, int, int, int], side: str) -> tuple[float, float]:
    x, y, w, h = box
    where, off = side[0], float(side[1:] or 0)
    if where == "r":
        return x + w, y + h / 2 + off
    if where == "l":
        return x, y + h / 2 + off
    if where == "t":
        return x + w / 2 + off, y
    return x + w / 2 + off, y + h


def _route(a: tuple[float, float], b: tuple[float, float], sa: str, sb: str) -> list[tuple[float, float]]:
    """Right-angled path from a to b leaving and entering along the sides' normals."""
    if a[0] == b[0] or a[1] == b[1]:
        return [a, b]
    if sa[0] in "lr" and sb[0] in "lr":
        mx = (a[0] + b[0]) / 2
        return [a, (mx, a[1]), (mx, b[1]), b]
    if sa[0] in "tb" and sb[0] in "tb":
        my = (a[1] + b[1]) / 2
        return [a, (a[0], my), (b[0], my), b]
    if sa[0] in "lr":
        return [a, (b[0], a[1]), b]
    return [a, (a[0], b[1]), b]


def _num(v: float) -> str:
    return f"{v:g}"


def _text(x: float, y: float, s: str, size: int = FONT_SIZE, weight: str = "normal", anchor: str = "middle") -> str:
    return (
        f'<text x="{_num(x)}" y="{_num(y)}" font-size="{size}" font-weight="{weight}" '
        f'text-anchor="{anchor}">{escape(s)}</text>'
    )


def _fits(what: str, s: str, w: int, size: int = FONT_SIZE) -> None:
    if len(s) * CHAR_W * size / FONT_SIZE > w - 6:
        raise ValueError(f"architecture: {what}'s text {s!r} is wider than its box ({w} px)")


def render(root: Path) -> dict[Path, str]:
    insts, areas, used = hierarchy(root)
    have = {i.path for i in insts}
    missing = sorted(have - set(LAYOUT))
    extra = sorted(set(LAYOUT) - have)
    if missing or extra:
        raise ValueError(
            f"architecture: instances without a place in LAYOUT: {missing}; places of no instance: {extra}"
        )
    boxes = {p: LAYOUT[p][:4] for p in LAYOUT} | {n: e[:4] for n, e in EXTERNAL.items()}
    parents = {p.rsplit("/", 1)[0] if "/" in p else "" for p in have if p}  # the drawn composites
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
        f'viewBox="0 0 {WIDTH} {HEIGHT}" font-family="DejaVu Sans, Verdana, Arial, sans-serif">',
        f"<!-- Generated by {GENERATOR} from hdl/top/{TOP}.vhd and the entities below it: do not edit;"
        " run `.venv/bin/python -m orb_flow.gen.architecture`. -->",
        "<defs>",
        '<marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" markerHeight="7" '
        'orient="auto-start-reverse"><path d="M 0 0 L 10 5 L 0 10 z" fill="#374151"/></marker>',
        "</defs>",
        f'<rect x="0" y="0" width="{WIDTH}" height="{HEIGHT}" fill="#ffffff"/>',
        _text(
            10, 24, f"{TOP}: the data flow (one box per entity instance; colour = area of hdl/)", 15, "bold", "start"
        ),
        _text(
            10,
            44,
            f"{WRAPPER} wraps it for Vivado. Boxes from the HDL's instance hierarchy, generated by {GENERATOR}.",
            11,
            anchor="start",
        ),
    ]
    # the scale path is one per level: two shadows behind it
    sx, sy, sw, sh = LAYOUT["detect/path"][:4]
    for k in (2, 1):
        out.append(
            f'<rect x="{sx + 6 * k}" y="{sy + 6 * k}" width="{sw}" height="{sh}" rx="5" '
            f'fill="{AREA_FILL[areas["orb_scale_path"]]}" fill-opacity="0.5" stroke="#6b7280"/>'
        )
    for inst in insts:
        x, y, w, h, role = LAYOUT[inst.path]
        fill = AREA_FILL[areas[inst.entity]]
        title = f"{TOP}/{inst.path}: {inst.entity}" if inst.path else TOP
        composite = inst.path in parents
        label = inst.path.rsplit("/", 1)[-1] if inst.path else f"{WRAPPER}/{hierarchy_label(root)}"
        name = f"{inst.entity} ({label})"
        out.append(f"<g><title>{escape(title)}</title>")
        out.append(
            f'<rect x="{x}" y="{y}" width="{w}" height="{h}" rx="5" fill="{fill}" '
            f'fill-opacity="{0.45 if composite else 1}" stroke="#374151" stroke-width="{1.5 if composite else 1}"/>'
        )
        if composite:
            head = f"{name}: {role}" if role else name
            if len(head) * CHAR_W > w - 6:  # the role on a line of its own
                _fits(inst.path, name, w)
                _fits(inst.path, role, w, FONT_SIZE - 1)
                out.append(_text(x + 6, y + 15, name, FONT_SIZE, "bold", "start"))
                out.append(_text(x + 6, y + 28, role, FONT_SIZE - 1, anchor="start"))
            else:
                out.append(_text(x + 6, y + 15, head, FONT_SIZE, "bold", "start"))
        else:
            _fits(inst.path, inst.entity, w)
            _fits(inst.path, role, w, FONT_SIZE - 1)
            out.append(_text(x + w / 2, y + h / 2 - 3, inst.entity, FONT_SIZE, "bold"))
            out.append(_text(x + w / 2, y + h / 2 + 12, role, FONT_SIZE - 1))
        out.append("</g>")
    out.extend(_text(x, y, text, 10, anchor="start") for x, y, text in NOTES)
    out.append(_text(sx + sw - 6, sy + sh - 6, "x SCALES_g (one per level)", 10, anchor="end"))
    for name, (x, y, w, h, title, role) in EXTERNAL.items():
        _fits(name, title, w)
        _fits(name, role, w, FONT_SIZE - 1)
        out.append(
            f'<rect x="{x}" y="{y}" width="{w}" height="{h}" rx="12" fill="#ffffff" stroke="#374151" '
            'stroke-dasharray="4 3"/>'
        )
        out.append(_text(x + w / 2, y + h / 2 - 3, title, FONT_SIZE, "bold"))
        out.append(_text(x + w / 2, y + h / 2 + 12, role, FONT_SIZE - 1))
    for src, s_side, dst, d_side, label, dashed, via in EDGES:
        a, b = _anchor(boxes[src], s_side), _anchor(boxes[dst], d_side)
        if via:
            pts: list[tuple[float, float]] = [a, *via, b]
        else:
            pts = _route(a, b, s_side, d_side)
        d = " ".join(f"{_num(px)},{_num(py)}" for px, py in pts)
        dash = ' stroke-dasharray="5 4"' if dashed else ""
        out.append(
            f'<polyline points="{d}" fill="none" stroke="#374151" stroke-width="1.3"{dash} marker-end="url(#arrow)"/>'
        )
        if label:  # beside the middle of the longest segment
            (x0, y0), (x1, y1) = max(
                itertools.pairwise(pts), key=lambda s: abs(s[1][0] - s[0][0]) + abs(s[1][1] - s[0][1])
            )
            if y0 == y1:  # centred above a horizontal segment
                out.append(_text((x0 + x1) / 2, y0 - 4, label, 10))
            else:
                out.append(_text(x0 + 4, (y0 + y1) / 2, label, 10, anchor="start"))
    legend_y = HEIGHT - 62
    out.append(_text(10, legend_y, "areas (hdl/<area>/):", 11, "bold", "start"))
    x = 140
    for area in ("input", "detect", "describe", "core", "host", "output", "top"):
        out.append(
            f'<rect x="{x}" y="{legend_y - 11}" width="14" height="14" fill="{AREA_FILL[area]}" stroke="#374151"/>'
        )
        out.append(_text(x + 20, legend_y, area, 11, anchor="start"))
        x += 100
    prims = "; ".join(f"{p} in {', '.join(sorted(used[p]))}" for p in PRIMITIVES if used[p])
    out.append(_text(10, legend_y + 22, f"Memories not drawn: {prims}.", 11, anchor="start"))
    out.append(
        _text(
            10,
            legend_y + 42,
            "Solid arrows: data; dashed: configuration. Each box: entity (instance label); "
            "its page is docs/entities/<entity>.md.",
            11,
            anchor="start",
        )
    )
    out.append("</svg>")
    return {VIEW: "\n".join(out) + "\n"}


def hierarchy_label(root: Path) -> str:
    """The label of orb_accel_top's instance in the Vivado wrapper."""
    src = next(s for s in read_manifest(root / "hdl" / "manifest.txt") if s.name == WRAPPER)
    return next(label for label, child in parse_entity(src.path).instances if child == TOP)


def main(argv: list[str] | None = None) -> None:
    views_main(__doc__, render, ROOT, argv)


if __name__ == "__main__":
    main()
