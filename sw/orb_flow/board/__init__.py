"""The Zybo Z7-20 board build: Vivado run, dry run, report summary, .bit.bin (docs/board.md)."""

from __future__ import annotations

from typing import Any


def config_key(board: dict[str, Any], name: str) -> str:
    """The board configuration of `name` in vivado/board.json: its key (640x480) or the named
    configuration it builds (board-vga; docs/configurations.md). ValueError naming both otherwise."""
    if name in board["configs"]:
        return name
    for key, cfg in board["configs"].items():
        if cfg.get("config") == name:
            return key
    known = ", ".join(f"{k} ({c.get('config')})" for k, c in board["configs"].items())
    raise ValueError(f"no board configuration {name!r}; known: {known}")
