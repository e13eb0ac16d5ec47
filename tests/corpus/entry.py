"""One corpus entry: the files it needs in its working folder and the invocations to run."""

from __future__ import annotations

import shlex
from dataclasses import dataclass


@dataclass(frozen=True)
class FileSpec:
    """A file an entry needs in its working folder (paths relative to it).

    ``kind``: ``text`` (``content`` with ``{CWD}`` and ``{RUNDIR}`` replaced),
    ``bytes`` (``content`` as latin-1), ``dir``, ``fifo``, ``sparse`` (``size``
    bytes, no disk used), ``symlink`` (to ``content``), ``chain`` (``size``
    files ``chain_<i>.toml``, each extending the next, the last the paper).
    """

    path: str
    kind: str = "text"
    content: str = ""
    size: int = 0


@dataclass(frozen=True)
class Entry:
    """A bad input: what was done (``description``) and what the command line must answer.

    ``expect``: ``reject`` (exit 2 and one ``error:`` line naming one of
    ``names``), ``ok`` (a still-valid input, exit 0) or ``either`` (ambiguous:
    only the safety checks apply).
    """

    id: str
    description: str
    runs: tuple[tuple[str, ...], ...]
    files: tuple[FileSpec, ...] = ()
    expect: str = "reject"  # reject | ok | either
    names: tuple[str, ...] = ()  # an exit-2 message must name one of these
    fast: bool = False
    forbid_stdout: tuple[str, ...] = ()  # on exit 0 (e.g. "null" thrusts)
    category: str = ""

    def commands(self) -> list[str]:
        return [shlex.join(["casadi-debris", *run]) for run in self.runs]
