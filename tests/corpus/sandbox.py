"""A run's folder: the entry's files written into it, and what is there before and after.

Each run has a folder ``<run>/w1/w2/w3/w4/w5/cwd``: the command runs in ``cwd``
(its HOME and TMPDIR too); a path that climbs out of it (a problem named
``../../x``) lands in one of the guard folders between, where it is seen and can
harm nothing.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Any

from .entry import Entry, FileSpec
from .shipped import problems_dir
from .toml_writer import toml_string

GUARDS = ("w1", "w2", "w3", "w4", "w5")


def working_folder(rundir: Path) -> Path:
    """Where a run in ``rundir`` runs, below the guard folders."""
    return rundir.joinpath(*GUARDS, "cwd")


def _write_chain(cwd: Path, size: int) -> None:
    """``chain_0.toml`` … each extending the next, the last the paper."""
    paper = problems_dir() / "paper.toml"
    for i in range(size):
        target = f"chain_{i + 1}.toml" if i + 1 < size else str(paper)
        (cwd / f"chain_{i}.toml").write_text(f"extends = {toml_string(target)}\n", encoding="utf-8")


def _write(spec: FileSpec, cwd: Path, rundir: Path) -> None:
    path = cwd / spec.path
    path.parent.mkdir(parents=True, exist_ok=True)
    content = spec.content.replace("{CWD}", str(cwd)).replace("{RUNDIR}", str(rundir))
    if spec.kind == "text":
        path.write_text(content, encoding="utf-8")
    elif spec.kind == "bytes":
        path.write_bytes(content.encode("latin-1"))
    elif spec.kind == "dir":
        path.mkdir(exist_ok=True)
    elif spec.kind == "fifo":
        os.mkfifo(path)
    elif spec.kind == "sparse":
        with path.open("wb") as handle:
            handle.truncate(spec.size)
    elif spec.kind == "symlink":
        path.symlink_to(content)
    elif spec.kind == "chain":
        _write_chain(cwd, spec.size)
    else:
        raise ValueError(spec.kind)


def write_files(entry: Entry, cwd: Path, rundir: Path) -> None:
    """Create ``cwd`` and the entry's files in it."""
    cwd.mkdir(parents=True)
    for spec in entry.files:
        _write(spec, cwd, rundir)


def snapshot_files(folder: Path) -> dict[str, tuple[Any, ...]]:
    """Relative path -> (kind, size, sha256 of files under 1 MiB) of everything below."""
    out: dict[str, tuple[Any, ...]] = {}
    for dirpath, dirnames, filenames in os.walk(folder):
        for name in dirnames + filenames:
            path = Path(dirpath) / name
            st = path.lstat()
            digest = ""
            if path.is_file() and not path.is_symlink() and st.st_size < (1 << 20):
                digest = hashlib.sha256(path.read_bytes()).hexdigest()
            kind = st.st_mode >> 12
            size = st.st_size if kind != 0o04 else 0
            out[str(path.relative_to(folder))] = (kind, size, digest)
    return out


def listing(folder: Path) -> set[str]:
    try:
        return set(os.listdir(folder))
    except OSError:
        return set()
