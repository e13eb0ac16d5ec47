"""``K…`` entries, the common part: base arguments of every command and the entry builder.

A bad value replaces one option of a command's base arguments, which keep an
accepted run short. Every entry's folder also holds a file and a non-empty
folder of the user's (``existing.txt``, ``full/keep.txt``) that must be left alone.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from .entry import Entry, FileSpec
from .shipped import problems_dir
from .toml_writer import toml_dumps

SHORT_TOML = "short.toml"

# Base arguments that keep an accepted run short (a bad value replaces one of them).
BASE: dict[str, list[str]] = {
    "model": [],
    "budget": [],
    "allocate": ["--torque-mNm", "1", "0", "0", "--json"],
    "slew": ["--sample-s", "10", "--out", "out", "--json"],
    "simulate": [SHORT_TOML, "--no-plots", "--out", "out", "--json"],
    "margins": ["--samples", "2", "--no-plots", "--out", "out", "--json"],
    "montecarlo": [
        SHORT_TOML,
        *("--samples", "1", "--max-cases", "1", "--workers", "1", "--no-jit"),
        *("--out", "out", "--json"),
    ],
    "synthesize": [
        *("--mu-points", "10", "--max-iterations", "1", "--d-orders", "1", "--samples", "5"),
        *("--out", "ctrl.json", "--json"),
    ],
    "reproduce": ["--quick", "--out", "out", "--json"],
    "compare": [SHORT_TOML, "--out", "out", "--json"],
}
NEEDS_SHORT = {"simulate", "montecarlo", "compare"}
# Commands that take long when a bad value is accepted: never in the fast subset.
HEAVY = {"synthesize", "reproduce", "montecarlo", "margins", "simulate", "compare"}
ARITY = {"--torque-mNm": 3, "--force-mN": 3}

INT_COUNT = ["-1", "0", "nan", "inf", "1e9", "1000000000", str(10**18), "", "abc", "2.5"]
SEED_VALUES = [
    ("-1", "reject"),
    ("nan", "reject"),
    ("abc", "reject"),
    ("1.5", "reject"),
    (str(2**70), "either"),
]
DURATION = ["0", "-1", "nan", "inf", "-inf", "1e12", "1e308", "abc"]


def short_problem() -> FileSpec:
    """``short.toml``: the paper with 2 s runs."""
    paper = problems_dir() / "paper.toml"
    text = toml_dumps(
        {
            "extends": str(paper),
            "name": "short",
            "description": "the paper, 2 s runs",
            "simulation": {"duration_s": 2.0},
        }
    )
    return FileSpec(SHORT_TOML, "text", text)


def replace_option(base: list[str], option: str, values: list[str]) -> list[str]:
    """``base`` without ``option`` (and its values), then ``option values``."""
    out: list[str] = []
    skip = 0
    arity = ARITY.get(option, 1)
    for arg in base:
        if skip:
            skip -= 1
            continue
        if arg == option:
            skip = arity
            continue
        out.append(arg)
    return [*out, option, *values]


class Invocations:
    """The ``K…`` entries in the making, numbered in the order they are added."""

    def __init__(self) -> None:
        self.entries: list[Entry] = []

    def add(
        self,
        command: str,
        args: list[str],
        desc: str,
        names: tuple[str, ...],
        expect: str = "reject",
        files: Iterable[FileSpec] = (),
        fast: bool = False,
        forbid: tuple[str, ...] = (),
        category: str = "",
    ) -> None:
        """``casadi-debris command args`` (``command`` empty: the group's own arguments)."""
        specs = list(files)
        if command in NEEDS_SHORT or SHORT_TOML in args:
            specs.append(short_problem())
        specs.append(FileSpec("existing.txt", content="a file the user had\n"))
        specs.append(FileSpec("full", "dir"))
        specs.append(FileSpec("full/keep.txt", content="keep me\n"))
        self.entries.append(
            Entry(
                id=f"K{len(self.entries) + 1:03d}",
                description=f"{command}: {desc}",
                runs=((command, *args),) if command else (tuple(args),),
                files=tuple(specs),
                expect=expect,
                names=names,
                fast=fast,
                forbid_stdout=forbid,
                category=category or command or "group",
            )
        )

    def option(self, command: str, opt: str, values: list[str], desc: str, **kw: Any) -> None:
        """The command's base arguments with ``opt`` given ``values``."""
        kw.setdefault("category", f"{command} {opt}")
        names = (opt,)
        if kw.get("files") or values[0].startswith("/dev/") or values[0].endswith(".json"):
            names = (opt, values[0])  # a message about a file's content may name the file
        names = kw.pop("names", names)
        self.add(command, replace_option(BASE[command], opt, values), desc, names, **kw)

    def file_options(
        self, command: str, opt: str, values: Iterable[str], category: str = ""
    ) -> None:
        """``opt`` naming something that is no readable file (see :data:`NOT_FILES`)."""
        for value in values:
            desc, files = NOT_FILES[value]
            kw: dict[str, Any] = {"category": category} if category else {}
            self.option(command, opt, [value], f"{opt} {desc}", files=files, **kw)


# Paths given where a file to read is expected: (description, files in the folder).
NOT_FILES: dict[str, tuple[str, tuple[FileSpec, ...]]] = {
    "nope.json": ("missing", ()),
    "adir": ("a directory", (FileSpec("adir", "dir"),)),
    "/dev/null": ("/dev/null", ()),
    "fifo": ("a FIFO", (FileSpec("fifo", "fifo"),)),
    "/dev/zero": ("/dev/zero", ()),
}
