# SPDX-License-Identifier: MIT
"""The digest of hdl/: which HDL a record measured (standard 8, docs/results/README.md).

A record of a simulation, a synthesis, a formal run or a campaign keeps `hdl_digest`, the digest of
the hdl/ tree it measured; the generated tables compare it with the checkout's own and say when the
HDL has changed since. A digest, not a commit count: it needs no git history (CI may clone
shallow), and a commit that does not touch hdl/ leaves it unchanged. The digest is SHA-256 over
each file's path and content's SHA-256, in path order, cut to 16 hex digits."""

from __future__ import annotations

import hashlib
import io
import subprocess
import tarfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TREE = "hdl"


def _digest(files: dict[str, bytes]) -> str:
    h = hashlib.sha256()
    for path in sorted(files):
        h.update(path.encode() + b"\0" + hashlib.sha256(files[path]).hexdigest().encode() + b"\n")
    return h.hexdigest()[:16]


def on_disk(root: Path = ROOT) -> str:
    """The digest of the checkout's hdl/: git's tracked files as they are on disk (every file under
    hdl/ where there is no git)."""
    base = root / TREE
    done = subprocess.run(["git", "ls-files", "-z", "--", TREE], cwd=root, capture_output=True)
    if done.returncode == 0 and done.stdout:
        paths = [p for p in done.stdout.decode().split("\0") if p]
        return _digest({p: (root / p).read_bytes() for p in paths if (root / p).is_file()})
    return _digest({str(p.relative_to(root)): p.read_bytes() for p in base.rglob("*")
                    if p.is_file() and "__pycache__" not in p.parts})  # fmt: skip


def at_commit(commit: str, root: Path = ROOT) -> str | None:
    """The digest of hdl/ at a commit, None when the checkout does not hold that commit."""
    done = subprocess.run(["git", "archive", "--format=tar", commit, "--", TREE], cwd=root, capture_output=True)
    if done.returncode != 0:
        return None
    files = {}
    with tarfile.open(fileobj=io.BytesIO(done.stdout)) as tar:
        for m in tar.getmembers():
            if m.isfile():
                f = tar.extractfile(m)
                if f is not None:
                    files[m.name] = f.read()
    return _digest(files)


def of_record(commit: str | None, root: Path = ROOT) -> str:
    """What a record made now keeps: the digest at its commit when one is given (a run measured on
    that commit's tree), else the checkout's."""
    if commit:
        got = at_commit(commit, root)
        if got is None:
            raise SystemExit(f"error: commit {commit} is not in this checkout: its hdl/ digest is unknown")
        return got
    return on_disk(root)
