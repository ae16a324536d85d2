# SPDX-License-Identifier: MIT
"""The interface of the house's VHDL entities as data: the header paragraph, the generics and ports
(with their comments and the source's groups) and the entity instances of the architecture.

A reader of the house style (docs/conventions.md), not of VHDL in general: one declaration per
line (`name : [mode] type [:= default]; -- comment`), a comment line of its own before a group of
declarations heads that group, and instances written `label : entity work.orb_x`. Anything else
inside a generic or port clause is refused with the file and line, so a new style cannot be
silently dropped from the generated pages."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

# the one line each entity's header carries that points at its generated page (docs/entities/)
PAGE_LINE = "-- Ports and generics: docs/entities/{name}.md"

_DECL = re.compile(
    r"^(?P<names>[A-Za-z]\w*(?:\s*,\s*[A-Za-z]\w*)*)\s*:\s*"
    r"(?:(?P<mode>in|out|inout|buffer)\s+)?"
    r"(?P<type>[^:;]+?)\s*(?::=\s*(?P<default>[^;]+?))?\s*;?$"
)
_INSTANCE = re.compile(r"^\s*(\w+)\s*:\s*entity\s+work\.(\w+)", re.IGNORECASE | re.MULTILINE)
_PRAGMA = re.compile(r"^(vsg_(on|off)|synthesis|pragma)\b")


@dataclass(frozen=True)
class Decl:
    """One generic or port: its name, mode (ports only), type, default (generics) and comment."""

    name: str
    mode: str
    type: str
    default: str
    comment: str


@dataclass(frozen=True)
class Group:
    """Declarations under one comment line of the source ("" for those before any)."""

    heading: str
    decls: tuple[Decl, ...]


@dataclass(frozen=True)
class Entity:
    name: str
    header: tuple[str, ...]  # the header's paragraphs, SPDX line and the page line left out
    generics: tuple[Group, ...]
    ports: tuple[Group, ...]
    instances: tuple[tuple[str, str], ...] = field(default=())  # (label, entity), in source order


def _split_comment(line: str) -> tuple[str, str]:
    """Code and comment of a line ("--" outside a string literal starts the comment)."""
    quoted = False
    for i, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif not quoted and line.startswith("--", i):
            return line[:i].rstrip(), line[i + 2 :].strip()
    return line.rstrip(), ""


def _header(lines: list[str], name: str) -> tuple[str, ...]:
    """The comment block at the top of the file, as paragraphs."""
    page = PAGE_LINE.format(name=name)
    paras: list[list[str]] = [[]]
    for line in lines[1:]:
        if not line.startswith("--"):
            break
        if line.strip() == page:
            continue
        text = line[2:].strip()
        if text and paras[-1] and re.search(r"[A-Za-z]-$", paras[-1][-1]):
            paras[-1][-1] += text  # a word hyphenated at the line's end
        elif text:
            paras[-1].append(text)
        elif paras[-1]:
            paras.append([])
    return tuple(" ".join(p) for p in paras if p)


def _clause(lines: list[str], start: int, path: Path) -> tuple[tuple[Group, ...], int]:
    """The generic or port clause opened on line `start`: its groups, and the line after it."""
    groups: list[Group] = []
    heading: list[str] = []
    decls: list[Decl] = []
    depth = 0
    i = start
    first = True
    while i < len(lines):
        code, comment = _split_comment(lines[i].strip())
        if first:
            # "generic (" or "port (": the clause's own opening parenthesis
            code = code.split("(", 1)[1] if "(" in code else ""
            depth = 1
            first = False
        i += 1
        if code == "" and comment:
            if _PRAGMA.match(comment):
                continue
            if decls:
                groups.append(Group(" ".join(heading), tuple(decls)))
                heading, decls = [], []
            heading.append(comment)
            continue
        if code == "":
            continue
        opened = code.count("(") - code.count(")")
        if depth + opened <= 0:  # the clause's closing ");" (possibly after the last declaration)
            body = code[: code.rfind(")")].strip()
            if body:
                decls.extend(_decls(body, comment, path, i))
            break
        depth += opened
        decls.extend(_decls(code, comment, path, i))
    else:
        raise ValueError(f"{path}:{start + 1}: clause not closed")
    if decls or heading:
        groups.append(Group(" ".join(heading), tuple(decls)))
    return _attach_single(groups), i


def _attach_single(groups: list[Group]) -> tuple[Group, ...]:
    """A comment line above a single uncommented declaration that follows ungrouped ones describes
    that declaration: it becomes its comment, not a group heading."""
    out: list[Group] = []
    for g in groups:
        if g.heading and len(g.decls) == 1 and not g.decls[0].comment and out and not out[-1].heading:
            d = g.decls[0]
            out[-1] = Group("", (*out[-1].decls, Decl(d.name, d.mode, d.type, d.default, g.heading)))
        else:
            out.append(g)
    return tuple(out)


def _decls(code: str, comment: str, path: Path, line: int) -> list[Decl]:
    m = _DECL.match(code.strip())
    if not m:
        raise ValueError(f"{path}:{line}: not a declaration of the house style: {code.strip()!r}")
    names = [n.strip() for n in m["names"].split(",")]
    typ = " ".join(m["type"].split())
    default = " ".join((m["default"] or "").split())
    return [Decl(n, m["mode"] or "", typ, default, comment) for n in names]


def parse_entity(path: Path) -> Entity:
    """The entity of one house-style VHDL file (named after the file)."""
    text = path.read_text()
    lines = text.splitlines()
    name = path.stem
    start = next((i for i, s in enumerate(lines) if re.match(rf"^entity\s+{name}\s+is\b", s)), None)
    if start is None:
        raise ValueError(f"{path}: no `entity {name} is`")
    generics: tuple[Group, ...] = ()
    ports: tuple[Group, ...] = ()
    i = start + 1
    while i < len(lines) and not re.match(rf"^end\s+entity\b|^end\s+{name}\b", lines[i].strip()):
        s = lines[i].strip().lower()
        if re.match(r"^generic\s*\(", s):
            generics, i = _clause(lines, i, path)
        elif re.match(r"^port\s*\(", s):
            ports, i = _clause(lines, i, path)
        else:
            i += 1
    instances = tuple((m[1], m[2]) for m in _INSTANCE.finditer(text))
    return Entity(name, _header(lines, name), generics, ports, instances)
