"""A seeded corpus of bad inputs for the ``casadi-debris`` command line (issue 11).

Two families of entries, each with a short id and a description of what was
done to the input:

* ``P…`` problem files: the shipped problems (``paper.toml``, and the
  ``[simulation]`` part of ``paper_slew.toml`` and ``paper_pointing.toml``)
  flattened, one mutation applied (deleted keys, zero, negative, NaN, inf,
  1e308, 10**18, numeric strings, bools, wrong lengths, wrong nesting, unknown
  keys, path-like ``name``), written back as TOML. ``C…`` are the children
  (``extends``) with one of their own keys mutated, ``X…`` broken ``extends``
  (missing, directory, circular, FIFO, devices, a huge file, deep chains), and
  ``S…`` broken TOML. Each is run as ``model FILE --json`` and
  ``budget FILE --json`` (and, for ``[simulation]`` keys and names, through
  ``simulate`` with a two-second run or ``margins`` with two samples);
* ``K…`` bad invocations of every command: option values out of range or of
  the wrong type, wrong arity, missing or unreadable files, a file where a
  folder is expected and vice versa, an existing ``--out``, unwritable places,
  junk ``--scheduler`` addresses, unknown options.

Every entry says what it expects: ``reject`` (exit 2 and one ``error:`` line
naming the key or option), ``ok`` (a still-valid input, exit 0) or ``either``
(ambiguous: only the safety checks apply).

Each run forks after the imports (no interpreter start-up per run), chdirs into
a fresh folder that is its HOME and TMPDIR, calls the click group in-process
as the console script would, and is killed after :data:`TIMEOUT_S`. The parent
checks: no traceback, exit status not 3 (nor anything but 0 and 2), no hang,
no signal, nothing written outside the run's folder (its three parent folders
are listed before and after) and no file present before the run changed, no
process left behind, and the expectation above.

Run the whole corpus and print the counts::

    python -m tests.bad_input_corpus --report [--fast] [--jobs 2] [--only ID,...]

Write one entry's files into a folder and print its commands (to reproduce)::

    python -m tests.bad_input_corpus --materialize P0123 /tmp/p0123
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import hashlib
import io
import json
import math
import os
import random
import re
import resource
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import tomllib
import traceback
from collections import defaultdict
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

SEED = 20250111
TIMEOUT_S = 20.0
FAST_FILES = 150
REPO = Path(__file__).resolve().parents[1]

# ---------------------------------------------------------------------------
# Corpus entries
# ---------------------------------------------------------------------------


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


def problems_dir() -> Path:
    from casadi_debris.config import default_problem_path

    return default_problem_path().parent


def _load(path: Path) -> dict[str, Any]:
    with path.open("rb") as handle:
        return tomllib.load(handle)


def _merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    merged = copy.deepcopy(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key] = _merge(merged[key], value)
        else:
            merged[key] = copy.deepcopy(value)
    return merged


# --- a small TOML writer (tomllib only reads) ------------------------------

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def _toml_key(key: str) -> str:
    return key if _BARE_KEY.fullmatch(key) else _toml_string(key)


def _toml_string(text: str) -> str:
    out = ['"']
    for ch in text:
        code = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\t":
            out.append("\\t")
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04x}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        inner = ", ".join(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items())
        return "{ " + inner + " }" if inner else "{}"
    raise TypeError(f"no TOML for {value!r}")


def _is_table_array(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def toml_dumps(data: dict[str, Any]) -> str:
    """TOML text for parsed TOML data (tables as headers, arrays of tables as [[...]])."""
    lines: list[str] = []

    def table(prefix: tuple[str, ...], body: dict[str, Any]) -> None:
        if prefix:
            lines.append("")
            lines.append("[" + ".".join(_toml_key(k) for k in prefix) + "]")
        for key, value in body.items():
            if not isinstance(value, dict) and not _is_table_array(value):
                lines.append(f"{_toml_key(key)} = {_toml_value(value)}")
        for key, value in body.items():
            if isinstance(value, dict):
                table((*prefix, key), value)
        for key, value in body.items():
            if _is_table_array(value):
                for item in value:
                    lines.append("")
                    lines.append("[[" + ".".join(_toml_key(k) for k in (*prefix, key)) + "]]")
                    for k, v in item.items():
                        lines.append(f"{_toml_key(k)} = {_toml_value(v)}")

    table((), data)
    return "\n".join(lines) + "\n"


# --- what a mutation should give ------------------------------------------

# Keys (indices dropped) where a zero is a legitimate value.
ZERO_OK = {
    "arrays.angle_deg",
    "arrays.damping_ratio",
    "cubesats.edge_margin_fraction",
    "cubesats.standoff_m",
    "disturbance.amplitude_mNm",
    "disturbance.phase_deg",
    "detumble.initial_rate_rad_s",
    "uncertainty.inertia_fraction",
    "uncertainty.mass_fraction",
    "uncertainty.array_angle_deg",
    "uncertainty.bending_frequency_fraction",
    "uncertainty.seed",
    "montecarlo.seed",
    "orbit.inclination_deg",
    "transfer.from_inclination_deg",
    "transfer.to_inclination_deg",
    "simulation.slew.start_s",
}
# Zero on the hub's boundary (centre of gravity, hinge at a hub edge): either way.
ZERO_EITHER = {"hub.cog_corner_m", "arrays.hinges_corner_m"}
# Signed quantities.
NEGATIVE_OK = {"arrays.angle_deg", "disturbance.phase_deg", "detumble.initial_rate_rad_s"}
# Seeds: any non-negative integer numpy takes.
HUGE_INT_EITHER = {"uncertainty.seed", "montecarlo.seed"}
# 1e-300 is "positive" but absurd here.
TINY_REJECT = {
    "hub.mass_kg",
    "arrays.mass_kg",
    "cubesats.mass_kg",
    "simulation.control_rate_hz",
    "constants.earth_mu_km3_s2",
    "constants.earth_radius_km",
    "constants.standard_gravity_m_s2",
}
# Keys and tables with defaults.
DELETE_OK = {
    "simulation",
    "simulation.duration_s",
    "simulation.control_rate_hz",
    "simulation.integrator_steps",
    "simulation.slew.method",
    "simulation.slew.start_s",
    "simulation.slew.duration_s",
    "simulation.slew.torque_fraction",
    "simulation.slew.feedforward",
    "simulation.slew.thrusters",
    "montecarlo",
    "montecarlo.corner_array_angles",
    "montecarlo.samples",
    "montecarlo.seed",
}
DELETE_EITHER = {"description"}
# Keys checked against each other: a message naming the partner is fine.
PARTNERS = {
    "hub.size_m": ("hub.cog_corner_m", "arrays.hinges_corner_m"),
    "arrays.hinges_corner_m": ("arrays.directions",),
    "arrays.directions": ("arrays.hinges_corner_m",),
    "cubesats.mass_kg": ("engine.",),
    "engine.thrust_per_stage_mN": ("cubesats.mass_kg",),
    "engine.isp_s": ("cubesats.mass_kg",),
    "engine.stage_life_h": ("cubesats.mass_kg",),
    "engine.stages": ("cubesats.mass_kg", "simulation."),
    "sensor.star_tracker_bandwidth_rad_s": ("simulation.",),
    "simulation.control_rate_hz": ("sensor.star_tracker_bandwidth_rad_s",),
    "simulation.integrator_steps": ("sensor.star_tracker_bandwidth_rad_s",),
    "constants.earth_radius_km": ("orbit.", "transfer."),
    "constants.earth_mu_km3_s2": ("orbit.", "transfer."),
    "orbit.altitude_km": ("constants.", "transfer."),
}

Path_ = tuple[str | int, ...]


def dotted(path: Path_) -> str:
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + part
    return out


def plain_key(path: Path_) -> str:
    """Dotted key without list indices: ``arrays.modes.omega_rad_s``."""
    return ".".join(p for p in path if isinstance(p, str))


def key_names(path: Path_) -> tuple[str, ...]:
    """Names an error about ``path`` may give: the key, its list, its table, partners."""
    names: list[str] = []
    strings = [p for p in path if isinstance(p, str)]
    # The key up to its last name (indices of a number list dropped).
    last_str = max(i for i, p in enumerate(path) if isinstance(p, str)) if strings else -1
    names.append(dotted(path[: last_str + 1]))
    if "modes" in strings and strings[0] == "arrays":
        names.append("arrays.modes")
    if len(strings) > 1:
        names.append(strings[0] + ".")  # another key of the same table
    names.extend(PARTNERS.get(plain_key(path), ()))
    return tuple(dict.fromkeys(n for n in names if n))


def _get(data: Any, path: Path_) -> Any:
    for part in path:
        data = data[part]
    return data


def _set(data: Any, path: Path_, value: Any) -> None:
    _get(data, path[:-1])[path[-1]] = value


def _delete(data: Any, path: Path_) -> None:
    del _get(data, path[:-1])[path[-1]]


def _leaves(data: Any, path: Path_ = ()) -> Iterator[tuple[Path_, Any]]:
    """Every node of the data: tables, lists and scalars, depth first."""
    yield path, data
    if isinstance(data, dict):
        for key, value in data.items():
            yield from _leaves(value, (*path, key))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from _leaves(value, (*path, i))


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _number_mutations(path: Path_, value: Any) -> Iterator[tuple[str, str, Any, str]]:
    """(op, description, new value, expectation) for a number."""
    key = plain_key(path)
    is_int = isinstance(value, int)

    def zero_expect() -> str:
        if key in ZERO_OK:
            return "ok"
        return "either" if key in ZERO_EITHER else "reject"

    yield "zero", "0", (0 if is_int else 0.0), zero_expect()
    negative = -abs(value) if value != 0 else (-1 if is_int else -1.0)
    neg_expect = "ok" if key in NEGATIVE_OK else "reject"
    yield "negative", repr(negative), negative, neg_expect
    yield "nan", "nan", math.nan, "reject"
    yield "inf", "inf", math.inf, "reject"
    yield "-inf", "-inf", -math.inf, "reject"
    yield "1e308", "1e308", 1e308, "reject"
    yield "huge-int", "10**18", 10**18, "either" if key in HUGE_INT_EITHER else "reject"
    yield "numeric-string", f'"{value}"', str(value), "reject"
    yield "bool", "true", True, "reject"
    yield "table-for-number", f"{{ value = {value} }}", {"value": value}, "reject"
    if not isinstance(path[-1], int):
        yield "list-for-number", f"[{value}]", [value], "reject"
    if is_int:
        yield "float-for-int", f"{value + 0.5}", value + 0.5, "reject"
    else:
        tiny_expect = "reject" if key in TINY_REJECT else "either"
        yield "tiny", "1e-300", 1e-300, tiny_expect
        if float(value).is_integer() and abs(value) < 1e15:
            yield "int-for-float", f"{int(value)} (integer)", int(value), "ok"


def _list_mutations(path: Path_, value: list[Any]) -> Iterator[tuple[str, str, Any, str]]:
    """Wrong lengths and nesting of a list of numbers or strings."""
    yield "empty-list", "[]", [], "reject"
    yield "drop-last", f"last of {len(value)} dropped", value[:-1], "reject"
    yield "append", "one more element", [*value, copy.deepcopy(value[-1])], "reject"
    yield "scalar-for-list", f"{value[0]!r} (no list)", copy.deepcopy(value[0]), "reject"
    yield "extra-nesting", "[[...]]", [copy.deepcopy(value)], "reject"
    if all(_is_number(v) for v in value):
        yield "string-list", "elements as strings", [str(v) for v in value], "reject"
    if isinstance(value[0], list):
        ragged = copy.deepcopy(value)
        ragged[0] = ragged[0][:-1]
        yield "ragged", "first row one short", ragged, "reject"


def _string_mutations(path: Path_, value: str) -> Iterator[tuple[str, str, Any, str]]:
    key = plain_key(path)
    if key == "name":
        for op, desc, new in (
            ("name-parent", '"../x"', "../x"),
            ("name-parent-deep", '"../../../../x"', "../../../../x"),
            ("name-parent-deeper", '"../../../../../../x"', "../../../../../../x"),
            ("name-slash", '"a/b"', "a/b"),
            ("name-empty", '""', ""),
            ("name-dot", '"."', "."),
            ("name-dotdot", '".."', ".."),
            ("name-long", "5000 characters", "n" * 5000),
            ("name-newline", '"a\\nb"', "a\nb"),
            ("name-nul", '"a\\u0000b"', "a\x00b"),
            ("name-absolute", "absolute path into the run folder", "{RUNDIR}/absolute"),
            ("name-backslash", '"a\\\\..\\\\b"', "a\\..\\b"),
        ):
            yield op, desc, new, "reject"
        yield "name-valid", '"paper-variant_2"', "paper-variant_2", "ok"
        return
    if key == "description":
        yield "description-newline", '"a\\nb"', "a\nb", "either"
        yield "description-empty", '""', "", "either"
        yield "description-long", "100000 characters", "d" * 100_000, "either"
        yield "number-for-string", "5", 5, "reject"
        return
    if key.endswith(".name"):  # a mode's name: a label
        yield "empty-string", '""', "", "either"
        yield "number-for-string", "5", 5, "reject"
        return
    yield "junk-string", '"junk"', "junk", "reject"
    yield "empty-string", '""', "", "reject"
    yield "number-for-string", "5", 5, "reject"
    yield "bool-for-string", "true", True, "reject"
    yield "upper-case", repr(value.upper()), value.upper(), "either"


def _table_mutations(path: Path_, value: dict[str, Any]) -> Iterator[tuple[str, str, Any, str]]:
    key = plain_key(path)
    yield "number-for-table", "1", 1, "reject"
    yield "string-for-table", '"x"', "x", "reject"
    yield "list-for-table", "[]", [], "reject"
    yield "empty-table", "{}", {}, "ok" if key in ("simulation", "montecarlo") else "reject"
    unknown = dict(value)
    unknown["bogus_key"] = 1.0
    yield "unknown-key", "bogus_key = 1.0 added", unknown, "reject"
    first = next((k for k, v in value.items() if not isinstance(v, dict | list)), None)
    if first is not None:
        renamed = {(k + "s" if k == first else k): v for k, v in value.items()}
        yield "misspelled-key", f"{first} -> {first}s", renamed, "reject"
        upper = {(k.upper() if k == first else k): v for k, v in value.items()}
        yield "upper-case-key", f"{first} -> {first.upper()}", upper, "reject"


def _delete_expect(path: Path_, data: dict[str, Any], base: str) -> str:
    key = plain_key(path)
    if key in DELETE_OK:
        return "ok"
    if key in DELETE_EITHER:
        return "either"
    if key == "simulation.reference":
        return "reject" if "slew" in data.get("simulation", {}) else "ok"
    if path[:2] == ("arrays", "modes") and len(path) == 3:
        mode = data["arrays"]["modes"][path[2]]
        return "reject" if (mode["kind"], mode["order"]) == ("bending", 1) else "ok"
    return "reject"


def _mutations(data: dict[str, Any], base: str) -> Iterator[tuple[str, Path_, str, Any, str]]:
    """(op, path, description, new value or DELETE, expectation) for every node."""
    for path, value in _leaves(data):
        if not path:
            continue
        key = dotted(path)
        deletable = isinstance(path[-1], str) or (
            path[:2] == ("arrays", "modes") and len(path) == 3
        )
        if deletable:
            yield "delete", path, f"{key} deleted", DELETE, _delete_expect(path, data, base)
        if _is_number(value):
            for op, desc, new, expect in _number_mutations(path, value):
                yield op, path, f"{key} = {desc}", new, expect
        elif isinstance(value, str):
            for op, desc, new, expect in _string_mutations(path, value):
                yield op, path, f"{key} = {desc}", new, expect
        elif isinstance(value, list) and value and not _is_table_array(value):
            for op, desc, new, expect in _list_mutations(path, value):
                yield op, path, f"{key}: {desc}", new, expect
        elif _is_table_array(value):
            yield "table-for-array", path, f"{key}: one table", copy.deepcopy(value[0]), "reject"
            yield "empty-array", path, f"{key} = []", [], "reject"
            dup = [*copy.deepcopy(value), copy.deepcopy(value[0])]
            yield "duplicate-item", path, f"{key}: first entry twice", dup, "reject"
        elif isinstance(value, dict):
            for op, desc, new, expect in _table_mutations(path, value):
                yield op, path, f"[{key}] {desc}", new, expect


DELETE = object()


def _apply(data: dict[str, Any], path: Path_, new: Any) -> dict[str, Any]:
    out = copy.deepcopy(data)
    if new is DELETE:
        _delete(out, path)
    else:
        _set(out, path, copy.deepcopy(new))
    return out


def _same(a: Any, b: Any) -> bool:
    return type(a) is type(b) and a == b


def _problem_runs(path: Path_ | None, op: str, name: str = "p.toml") -> tuple[tuple[str, ...], ...]:
    runs: list[tuple[str, ...]] = [("model", name, "--json"), ("budget", name, "--json")]
    key = plain_key(path) if path else ""
    if key.startswith("simulation"):
        runs.append(("simulate", name, "--duration-s", "2", "--no-plots", "--out", "out", "--json"))
    if op.startswith("name-"):
        # Commands whose default output folder comes from the name.
        runs.append(("simulate", name, "--duration-s", "1", "--no-plots", "--json"))
        runs.append(("margins", name, "--samples", "2", "--no-plots", "--json"))
    return tuple(runs)


def problem_entries() -> list[Entry]:
    """Mutated problem files: the paper flattened, the children's own keys."""
    folder = problems_dir()
    paper = _load(folder / "paper.toml")
    entries: list[Entry] = []

    def add(prefix: str, desc: str, text: str, path: Path_ | None, op: str, expect: str, **kw):
        entries.append(
            Entry(
                id=f"{prefix}{sum(e.id.startswith(prefix) for e in entries) + 1:04d}",
                description=desc,
                runs=_problem_runs(path, op),
                files=(FileSpec("p.toml", "text", text),),
                expect=expect,
                names=kw.pop("names", key_names(path) if path else ()),
                category=f"{op}",
                **kw,
            )
        )

    # The unchanged files, through the writer: must stay valid.
    for base in ("paper", "paper_slew", "paper_pointing"):
        data = _load(folder / f"{base}.toml")
        if "extends" in data:
            data = _merge(paper, {k: v for k, v in data.items() if k != "extends"})
        add(
            "P", f"{base}.toml flattened, unchanged (control)", toml_dumps(data), None, "none", "ok"
        )

    # The paper, every node.
    flattened = {"paper": paper}
    for base in ("paper_slew", "paper_pointing"):
        child = _load(folder / f"{base}.toml")
        flattened[base] = _merge(paper, {k: v for k, v in child.items() if k != "extends"})
    for base, data in flattened.items():
        for op, path, desc, new, expect in _mutations(data, base):
            if base != "paper" and path[0] != "simulation":
                continue  # the rest is the paper's, mutated above
            if new is not DELETE and _same(new, _get(data, path)):
                continue
            text = toml_dumps(_apply(data, path, new))
            add("P", f"{base}.toml: {desc}", text, path, op, expect)

    # Top level: unknown keys and tables, keys moved to the wrong table.
    top_extra = [
        ("unknown-top-key", "bogus_key = 1 at the top", {"bogus_key": 1}, ("bogus_key",)),
        ("unknown-table", "[bogus] table", {"bogus": {"x": 1.0}}, ("bogus",)),
        ("misplaced-key", "mass_kg at the top level", {"mass_kg": 500.0}, ("mass_kg",)),
        ("case-table", "[Hub] beside [hub]", {"Hub": {"mass_kg": 500.0}}, ("Hub",)),
    ]
    for op, desc, extra, path in top_extra:
        add("P", f"paper.toml: {desc}", toml_dumps({**paper, **extra}), path, op, "reject")
    moved = copy.deepcopy(paper)
    moved["cubesats"]["isp_s"] = moved["engine"].pop("isp_s")
    add(
        "P",
        "paper.toml: engine.isp_s moved into [cubesats]",
        toml_dumps(moved),
        ("cubesats", "isp_s"),
        "misplaced-key",
        "reject",
    )
    # Whole-file cases.
    for desc, text, op in (
        ("empty file", "", "empty-file"),
        ("only a name", 'name = "x"\n', "only-name"),
    ):
        add("P", desc, text, None, op, "reject", names=tuple(paper))
    return entries


def child_entries() -> list[Entry]:
    """The children (paper_slew, paper_pointing) with their own keys mutated, extends kept."""
    folder = problems_dir()
    paper_path = folder / "paper.toml"
    paper = _load(paper_path)
    entries: list[Entry] = []
    n = 0
    for base in ("paper_slew", "paper_pointing"):
        child = _load(folder / f"{base}.toml")
        child["extends"] = str(paper_path)
        for op, path, desc, new, expect in _mutations(child, base):
            if path == ("extends",):
                continue  # broken extends: extends_entries
            if new is not DELETE and _same(new, _get(child, path)):
                continue
            if new is DELETE:
                # A deleted key of the child falls back to the paper's.
                merged_base = copy.deepcopy(paper)
                try:
                    _get(merged_base, path)
                    inherited = True
                except (KeyError, IndexError, TypeError):
                    inherited = False
                if inherited and path != ("simulation", "reference"):
                    expect = "ok"
            mutated = _apply(child, path, new)
            n += 1
            entries.append(
                Entry(
                    id=f"C{n:04d}",
                    description=f"{base}.toml (extends the paper): {desc}",
                    runs=_problem_runs(path, op),
                    files=(FileSpec("p.toml", "text", toml_dumps(mutated)),),
                    expect=expect,
                    names=key_names(path),
                    category=op,
                )
            )
    # Overrides of the paper's keys in a child.
    for desc, body, names in (
        ("[hub] mass_kg = -1 in the child", {"hub": {"mass_kg": -1.0}}, ("hub.mass_kg",)),
        ("hub = 5 in the child", {"hub": 5}, ("hub",)),
        ("[engine] bogus = 1 in the child", {"engine": {"bogus": 1}}, ("engine.bogus",)),
        ('[cubesats] mass_kg = "3.5"', {"cubesats": {"mass_kg": "3.5"}}, ("cubesats.mass_kg",)),
        ("arrays.modes = [] in the child", {"arrays": {"modes": []}}, ("arrays.modes",)),
    ):
        n += 1
        text = toml_dumps({"extends": str(paper_path), "name": "child", **body})
        entries.append(
            Entry(
                id=f"C{n:04d}",
                description=f"child of the paper: {desc}",
                runs=_problem_runs(None, "override"),
                files=(FileSpec("p.toml", "text", text),),
                names=names,
                category="child-override",
            )
        )
    n += 1
    text = toml_dumps({"extends": str(paper_path), "name": "child", "hub": {"mass_kg": 450.0}})
    entries.append(
        Entry(
            id=f"C{n:04d}",
            description="child of the paper: hub.mass_kg = 450 (valid override, control)",
            runs=_problem_runs(None, "override"),
            files=(FileSpec("p.toml", "text", text),),
            expect="ok",
            category="child-override",
        )
    )
    return entries


def extends_entries() -> list[Entry]:
    """Broken ``extends``: missing, directory, circular, FIFO, devices, huge, deep."""
    paper_path = problems_dir() / "paper.toml"
    paper_text = paper_path.read_text(encoding="utf-8")
    names = ("extends",)

    def child(target: str, full: bool = False) -> str:
        head = f"extends = {_toml_string(target)}\n"
        if full:  # a complete problem besides the extends
            return head + paper_text.replace('name = "paper"', 'name = "full"')
        return head + 'name = "child"\n'

    cases: list[tuple[str, tuple[FileSpec, ...], str, tuple[str, ...], bool]] = [
        (
            "missing file",
            (FileSpec("p.toml", content=child("nope.toml")),),
            "reject",
            (*names, "nope.toml"),
            True,
        ),
        (
            "a directory",
            (FileSpec("sub", "dir"), FileSpec("p.toml", content=child("sub"))),
            "reject",
            names,
            True,
        ),
        ('"" (the folder)', (FileSpec("p.toml", content=child("")),), "reject", names, True),
        ('"." (the folder)', (FileSpec("p.toml", content=child(".")),), "reject", names, False),
        ("itself", (FileSpec("p.toml", content=child("p.toml")),), "reject", names, True),
        (
            "circular a -> b -> a",
            (
                FileSpec("b.toml", content=child("p.toml")),
                FileSpec("p.toml", content=child("b.toml")),
            ),
            "reject",
            names,
            True,
        ),
        (
            "circular via a different spelling (./p.toml, sub/../p.toml)",
            (
                FileSpec("sub", "dir"),
                FileSpec("b.toml", content=child("sub/../p.toml")),
                FileSpec("p.toml", content=child("./b.toml")),
            ),
            "reject",
            names,
            False,
        ),
        (
            "a FIFO",
            (FileSpec("fifo", "fifo"), FileSpec("p.toml", content=child("fifo"))),
            "reject",
            names,
            True,
        ),
        ("/dev/zero", (FileSpec("p.toml", content=child("/dev/zero")),), "reject", names, True),
        (
            "/dev/null (full problem beside)",
            (FileSpec("p.toml", content=child("/dev/null", True)),),
            "reject",
            names,
            True,
        ),
        (
            "/dev/urandom",
            (FileSpec("p.toml", content=child("/dev/urandom")),),
            "reject",
            names,
            False,
        ),
        (
            "/dev/stdin (never ends)",
            (FileSpec("p.toml", content=child("/dev/stdin")),),
            "reject",
            names,
            True,
        ),
        (
            "a symlink to /dev/zero",
            (
                FileSpec("z.toml", "symlink", "/dev/zero"),
                FileSpec("p.toml", content=child("z.toml")),
            ),
            "reject",
            names,
            False,
        ),
        (
            "a dangling symlink",
            (
                FileSpec("d.toml", "symlink", "nowhere.toml"),
                FileSpec("p.toml", content=child("d.toml")),
            ),
            "reject",
            (*names, "d.toml"),
            False,
        ),
        (
            "a 1 GiB sparse file",
            (
                FileSpec("huge.toml", "sparse", size=1 << 30),
                FileSpec("p.toml", content=child("huge.toml")),
            ),
            "reject",
            names,
            False,
        ),
        (
            "a 40 MB file of comments",
            (
                FileSpec("big.toml", "text", ("# padding " * 8 + "\n") * 500_000 + paper_text),
                FileSpec("p.toml", content=child("big.toml")),
            ),
            "reject",
            names,
            False,
        ),
        (
            "a chain 2000 deep",
            (
                FileSpec("chain", "chain", size=2000),
                FileSpec("p.toml", content=child("chain_0.toml")),
            ),
            "reject",
            names,
            False,
        ),
        (
            "a chain 50 deep",
            (
                FileSpec("chain", "chain", size=50),
                FileSpec("p.toml", content=child("chain_0.toml")),
            ),
            "either",
            names,
            False,
        ),
        (
            "not valid TOML",
            (
                FileSpec("bad.toml", content="hub = [\n"),
                FileSpec("p.toml", content=child("bad.toml")),
            ),
            "reject",
            (*names, "bad.toml"),
            True,
        ),
        (
            "binary bytes",
            (
                FileSpec("bin.toml", "bytes", "\xff\xfe\x00\x01garbage"),
                FileSpec("p.toml", content=child("bin.toml")),
            ),
            "reject",
            (*names, "bin.toml"),
            False,
        ),
        (
            "a file with hub.mass_kg = -1",
            (
                FileSpec(
                    "base.toml", content=paper_text.replace("mass_kg = 500.0", "mass_kg = -1.0")
                ),
                FileSpec("p.toml", content=child("base.toml")),
            ),
            "reject",
            ("hub.mass_kg",),
            True,
        ),
        (
            "extends = 5",
            (FileSpec("p.toml", content='extends = 5\nname = "x"\n'),),
            "reject",
            names,
            True,
        ),
        (
            "extends = []",
            (FileSpec("p.toml", content='extends = []\nname = "x"\n'),),
            "reject",
            names,
            False,
        ),
        (
            "extends = { path = ... }",
            (
                FileSpec(
                    "p.toml",
                    content=f'extends = {{ path = {_toml_string(str(paper_path))} }}\nname = "x"\n',
                ),
            ),
            "reject",
            names,
            False,
        ),
        (
            "the paper by absolute path (control)",
            (FileSpec("p.toml", content=child(str(paper_path))),),
            "ok",
            (),
            True,
        ),
        (
            "a copy of the paper, relative (control)",
            (
                FileSpec("paper.toml", content=paper_text),
                FileSpec("p.toml", content=child("paper.toml")),
            ),
            "ok",
            (),
            False,
        ),
    ]
    entries = []
    for i, (desc, files, expect, entry_names, fast) in enumerate(cases, 1):
        entries.append(
            Entry(
                id=f"X{i:03d}",
                description=f"extends -> {desc}",
                runs=(("model", "p.toml", "--json"), ("budget", "p.toml", "--json")),
                files=files,
                expect=expect,
                names=entry_names,
                fast=fast,
                category="extends",
            )
        )
    return entries


def semantic_entries() -> list[Entry]:
    """Each value well typed and in its own range, the problem still wrong (or, controls, right)."""
    folder = problems_dir()
    paper = _load(folder / "paper.toml")
    slew = _merge(
        paper, {k: v for k, v in _load(folder / "paper_slew.toml").items() if k != "extends"}
    )
    failure = {"cubesat": 1, "time_s": 10.0}
    cases: list[tuple[str, dict[str, Any], dict[Path_, Any], str, tuple[str, ...], bool]] = [
        # (description, base, {path: value}, expect, names, fast)
        (
            "a stage's propellant heavier than its CubeSat (stage_life_h = 50000)",
            paper,
            {("engine", "stage_life_h"): 50000.0},
            "reject",
            ("engine.", "cubesats.mass_kg"),
            True,
        ),
        (
            "CubeSat of 0.1 kg, lighter than its propellant",
            paper,
            {("cubesats", "mass_kg"): 0.1},
            "reject",
            ("engine.", "cubesats.mass_kg"),
            False,
        ),
        (
            "hub inertia breaks the triangle inequality (75, 40, 200)",
            paper,
            {("hub", "inertia_kgm2"): [[75.0, 0.0, 0.0], [0.0, 40.0, 0.0], [0.0, 0.0, 200.0]]},
            "reject",
            ("hub.inertia_kgm2",),
            True,
        ),
        (
            "hub inertia symmetric but not positive definite",
            paper,
            {("hub", "inertia_kgm2"): [[75.0, 80.0, 2.0], [80.0, 40.0, -1.0], [2.0, -1.0, 80.0]]},
            "reject",
            ("hub.inertia_kgm2",),
            True,
        ),
        (
            "array inertia breaks the triangle inequality (17, 62, 100)",
            paper,
            {("arrays", "inertia_kgm2"): [17.0, 62.0, 100.0]},
            "reject",
            ("arrays.inertia_kgm2",),
            False,
        ),
        (
            "a hinge off every hub face",
            paper,
            {("arrays", "hinges_corner_m"): [[0.4, 1.4, 0.5], [0.4, 1.4, 1.0]]},
            "reject",
            ("arrays.hinges_corner_m", "arrays.directions"),
            False,
        ),
        (
            "both arrays towards -z (the second through the hub)",
            paper,
            {("arrays", "directions"): ["-z", "-z"]},
            "reject",
            ("arrays.directions", "arrays.hinges_corner_m"),
            False,
        ),
        (
            "orbit inclination 200 deg",
            paper,
            {("orbit", "inclination_deg"): 200.0},
            "reject",
            ("orbit.inclination_deg",),
            False,
        ),
        (
            "orbit altitude 1e6 km",
            paper,
            {("orbit", "altitude_km"): 1e6},
            "either",
            ("orbit.altitude_km",),
            False,
        ),
        (
            "control_rate_hz = 1e-9",
            paper,
            {("simulation", "control_rate_hz"): 1e-9},
            "reject",
            ("simulation.control_rate_hz",),
            True,
        ),
        (
            "control_rate_hz = 1e6",
            paper,
            {("simulation", "control_rate_hz"): 1e6},
            "reject",
            ("simulation.control_rate_hz", "simulation."),
            False,
        ),
        (
            "integrator_steps = 1000000000",
            paper,
            {("simulation", "integrator_steps"): 10**9},
            "reject",
            ("simulation.integrator_steps", "simulation."),
            True,
        ),
        (
            "simulation.duration_s = 1e12",
            paper,
            {("simulation", "duration_s"): 1e12},
            "reject",
            ("simulation.duration_s",),
            False,
        ),
        (
            "uncertainty.samples = 1000000000",
            paper,
            {("uncertainty", "samples"): 10**9},
            "reject",
            ("uncertainty.samples",),
            True,
        ),
        (
            "montecarlo.samples = 1000000000",
            paper,
            {("montecarlo", "samples"): 10**9},
            "reject",
            ("montecarlo.samples",),
            False,
        ),
        (
            "montecarlo.corner_array_angles = 1000000",
            paper,
            {("montecarlo", "corner_array_angles"): 10**6},
            "reject",
            ("montecarlo.corner_array_angles",),
            False,
        ),
        (
            "engine.stages = 1000",
            paper,
            {("engine", "stages"): 1000},
            "reject",
            ("engine.stages", "engine.", "cubesats.mass_kg"),
            False,
        ),
        (
            "first bending mode at 1e6 rad/s",
            paper,
            {("arrays", "modes", 0, "omega_rad_s"): 1e6},
            "either",
            ("arrays.modes",),
            False,
        ),
        (
            "two modes named alike",
            paper,
            {("arrays", "modes", 1, "name"): "bending1"},
            "reject",
            ("arrays.modes",),
            False,
        ),
        (
            "mode order 0",
            paper,
            {("arrays", "modes", 2, "order"): 0},
            "reject",
            ("arrays.modes",),
            False,
        ),
        (
            "failure of CubeSat 25 (there are 24)",
            paper,
            {("simulation", "failures"): [{"cubesat": 25, "time_s": 10.0}]},
            "reject",
            ("simulation.failures",),
            True,
        ),
        (
            "failure of CubeSat 0 (numbered from 1)",
            paper,
            {("simulation", "failures"): [{"cubesat": 0, "time_s": 10.0}]},
            "reject",
            ("simulation.failures",),
            False,
        ),
        (
            "failure of stage 4 (there are 3)",
            paper,
            {("simulation", "failures"): [{"cubesat": 1, "stage": 4, "time_s": 10.0}]},
            "reject",
            ("simulation.failures",),
            False,
        ),
        (
            "failure at t = -5 s",
            paper,
            {("simulation", "failures"): [{"cubesat": 1, "time_s": -5.0}]},
            "reject",
            ("simulation.failures",),
            False,
        ),
        (
            "failure at t = nan",
            paper,
            {("simulation", "failures"): [{"cubesat": 1, "time_s": math.nan}]},
            "reject",
            ("simulation.failures",),
            False,
        ),
        (
            "failure with an unknown key",
            paper,
            {("simulation", "failures"): [{**failure, "severity": 1}]},
            "reject",
            ("simulation.failures",),
            False,
        ),
        (
            "failures = a table, not an array",
            paper,
            {("simulation", "failures"): failure},
            "reject",
            ("simulation.failures",),
            False,
        ),
        (
            "failure of CubeSat 1 at 10 s (control)",
            paper,
            {("simulation", "failures"): [failure]},
            "ok",
            (),
            True,
        ),
        (
            "slew torque_fraction = 1.5",
            slew,
            {("simulation", "slew", "torque_fraction"): 1.5},
            "reject",
            ("simulation.slew.torque_fraction",),
            False,
        ),
        (
            "bang-bang slew with thrusters = true",
            slew,
            {("simulation", "slew", "thrusters"): True},
            "reject",
            ("simulation.slew.thrusters",),
            False,
        ),
        (
            "fuel-optimal slew without a duration",
            slew,
            {("simulation", "slew", "method"): "fuel-optimal", ("simulation", "slew"): None},
            "reject",
            ("simulation.slew.duration_s", "simulation.slew"),
            False,
        ),
        (
            "slew start_s = -1",
            slew,
            {("simulation", "slew", "start_s"): -1.0},
            "reject",
            ("simulation.slew.start_s",),
            False,
        ),
        (
            'slew feedforward = "yes"',
            slew,
            {("simulation", "slew", "feedforward"): "yes"},
            "reject",
            ("simulation.slew.feedforward",),
            False,
        ),
        (
            "slew angle 181 deg",
            slew,
            {("simulation", "slew", "angle_deg"): 181.0},
            "reject",
            ("simulation.slew.angle_deg",),
            True,
        ),
        (
            "slew duration 1 s (below the minimum time)",
            slew,
            {("simulation", "slew", "duration_s"): 1.0},
            "either",
            ("simulation.slew.duration_s", "simulation.slew"),
            False,
        ),
        (
            'slew axis "-z"',
            slew,
            {("simulation", "slew", "axis"): "-z"},
            "either",
            ("simulation.slew.axis",),
            False,
        ),
        (
            "slew start_s 10 (control)",
            slew,
            {("simulation", "slew", "start_s"): 10.0},
            "ok",
            (),
            False,
        ),
    ]
    entries = []
    for i, (desc, base, changes, expect, names, fast) in enumerate(cases, 1):
        data = copy.deepcopy(base)
        for path, value in changes.items():
            if value is None:  # the marker for "delete duration_s" in that table
                _get(data, path).pop("duration_s", None)
            else:
                _set(data, path, value)
        runs = _problem_runs(("simulation",), "semantic")
        entries.append(
            Entry(
                id=f"M{i:03d}",
                description=f"{'paper_slew' if base is slew else 'paper'}.toml: {desc}",
                runs=runs,
                files=(FileSpec("p.toml", "text", toml_dumps(data)),),
                expect=expect,
                names=names,
                fast=fast,
                category="semantic",
            )
        )
    return entries


def syntax_entries(rng: random.Random) -> list[Entry]:
    """Broken TOML: truncated at seeded positions, duplicate keys, bad UTF-8."""
    text = (problems_dir() / "paper.toml").read_text(encoding="utf-8")
    cases: list[tuple[str, FileSpec, str, tuple[str, ...]]] = []
    positions = sorted(rng.sample(range(20, len(text) - 20), 12))
    for pos in positions:
        cut = text[:pos]
        try:
            tomllib.loads(cut)
        except tomllib.TOMLDecodeError:
            cases.append(
                (
                    f"truncated at character {pos}",
                    FileSpec("p.toml", content=cut),
                    "reject",
                    ("line", "TOML"),
                )
            )
        else:
            cases.append(
                (
                    f"truncated at character {pos} (still TOML)",
                    FileSpec("p.toml", content=cut),
                    "either",
                    (),
                )
            )
    cases.append(
        (
            "hub.mass_kg twice",
            FileSpec(
                "p.toml", content=text.replace("mass_kg = 500.0", "mass_kg = 500.0\nmass_kg = 1.0")
            ),
            "reject",
            ("line", "mass_kg"),
        )
    )
    cases.append(
        ("invalid UTF-8", FileSpec("p.toml", "bytes", 'name = "\xff\xfe"\n'), "reject", ())
    )
    cases.append(("a NUL byte", FileSpec("p.toml", "bytes", "\x00" + text), "reject", ()))
    cases.append(
        ("UTF-8 BOM in front", FileSpec("p.toml", "bytes", "\xef\xbb\xbf" + text), "either", ())
    )
    return [
        Entry(
            id=f"S{i:03d}",
            description=f"paper.toml: {desc}",
            runs=(("model", "p.toml", "--json"), ("budget", "p.toml", "--json")),
            files=(spec,),
            expect=expect,
            names=names,
            fast=i <= 4,
            category="syntax",
        )
        for i, (desc, spec, expect, names) in enumerate(cases, 1)
    ]


# --- command-line entries --------------------------------------------------

SHORT_TOML = "short.toml"


def _short_problem() -> FileSpec:
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


def _controller_files() -> dict[str, FileSpec]:
    from casadi_debris.config import default_controller_path

    shipped = json.loads(default_controller_path().read_text(encoding="utf-8"))
    nan_a = copy.deepcopy(shipped)
    nan_a["A"][0][0] = math.nan
    short_b = copy.deepcopy(shipped)
    short_b["B"] = short_b["B"][:-1]
    no_c = copy.deepcopy(shipped)
    del no_c["C"]
    string_d = copy.deepcopy(shipped)
    string_d["D"] = "zero"
    version = copy.deepcopy(shipped)
    version["format_version"] = 99
    huge = copy.deepcopy(shipped)
    huge["C"][0][0] = 1e308
    return {
        "NaN in A": FileSpec("ctl.json", content=json.dumps(nan_a)),
        "B one row short": FileSpec("ctl.json", content=json.dumps(short_b)),
        "C missing": FileSpec("ctl.json", content=json.dumps(no_c)),
        'D = "zero"': FileSpec("ctl.json", content=json.dumps(string_d)),
        "format_version 99": FileSpec("ctl.json", content=json.dumps(version)),
        "1e308 in C": FileSpec("ctl.json", content=json.dumps(huge)),
        "{}": FileSpec("ctl.json", content="{}"),
        "[]": FileSpec("ctl.json", content="[]"),
        "not JSON": FileSpec("ctl.json", content="controller, please\n"),
        "empty": FileSpec("ctl.json", content=""),
    }


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
        "--samples",
        "1",
        "--max-cases",
        "1",
        "--workers",
        "1",
        "--no-jit",
        "--out",
        "out",
        "--json",
    ],
    "synthesize": [
        "--mu-points",
        "10",
        "--max-iterations",
        "1",
        "--d-orders",
        "1",
        "--samples",
        "5",
        "--out",
        "ctrl.json",
        "--json",
    ],
    "reproduce": ["--quick", "--out", "out", "--json"],
    "compare": [SHORT_TOML, "--out", "out", "--json"],
}
NEEDS_SHORT = {"simulate", "montecarlo", "compare"}
# Commands that take long when a bad value is accepted: never in the fast subset.
HEAVY = {"synthesize", "reproduce", "montecarlo", "margins", "simulate", "compare"}
ARITY = {"--torque-mNm": 3, "--force-mN": 3}


def _replace_option(base: list[str], option: str, values: list[str]) -> list[str]:
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


INT_COUNT = ["-1", "0", "nan", "inf", "1e9", "1000000000", str(10**18), "", "abc", "2.5"]
SEED_VALUES = [
    ("-1", "reject"),
    ("nan", "reject"),
    ("abc", "reject"),
    ("1.5", "reject"),
    (str(2**70), "either"),
]
DURATION = ["0", "-1", "nan", "inf", "-inf", "1e12", "1e308", "abc"]
DIR_OUT = [
    ("existing.txt", "an existing file"),
    ("existing.txt/sub", "a folder under a file"),
    ("/proc/casadi-debris-corpus", "an unwritable place (/proc)"),
    (".", "the working folder (not empty)"),
    ("full", "an existing non-empty folder"),
    ("", "empty string"),
]


STAGE_STATE_KEYS = ("propellant_kg", "firing_time_s", "failed_cubesats", "failed_stages")


def cli_entries() -> list[Entry]:
    """Bad invocations of every command."""
    controllers = _controller_files()
    entries: list[Entry] = []

    def add(
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
        specs = list(files)
        if command in NEEDS_SHORT or SHORT_TOML in args:
            specs.append(_short_problem())
        specs.append(FileSpec("existing.txt", content="a file the user had\n"))
        specs.append(FileSpec("full", "dir"))
        specs.append(FileSpec("full/keep.txt", content="keep me\n"))
        entries.append(
            Entry(
                id=f"K{len(entries) + 1:03d}",
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

    def option(command: str, opt: str, values: list[str], desc: str, **kw: Any) -> None:
        kw.setdefault("category", f"{command} {opt}")
        names = (opt,)
        if kw.get("files") or values[0].startswith("/dev/") or values[0].endswith(".json"):
            names = (opt, values[0])  # a message about a file's content may name the file
        names = kw.pop("names", names)
        add(command, _replace_option(BASE[command], opt, values), desc, names, **kw)

    # Every command: an unknown option, a flag given a value, an option missing its value.
    for command, base in BASE.items():
        add(
            command,
            [*base, "--bogus"],
            "unknown option --bogus",
            ("--bogus",),
            fast=True,
            category="unknown-option",
        )
        add(
            command,
            [*base, "--json=1"],
            "--json=1 (a flag with a value)",
            ("--json",),
            fast=command not in HEAVY or command in ("simulate", "margins"),
            category="flag-value",
        )
        with_values = [
            a
            for a in base
            if a.startswith("--") and a not in ("--json", "--no-plots", "--no-jit", "--quick")
        ]
        if with_values:
            opt = with_values[0]
            add(
                command,
                _replace_option(base, opt, []),
                f"{opt} without its value",
                (opt,),
                fast=True,
                category="missing-value",
            )
    # Problem-file argument.
    for command in ("model", "budget", "allocate", "slew", "simulate", "margins"):
        base = [a for a in BASE[command] if a != SHORT_TOML]
        fast = command in ("model", "budget", "allocate")
        for arg, desc, files in (
            ("nope.toml", "a missing problem file", ()),
            ("adir", "a directory as the problem file", (FileSpec("adir", "dir"),)),
            ("/dev/null", "/dev/null as the problem file", ()),
            ("fifo", "a FIFO as the problem file", (FileSpec("fifo", "fifo"),)),
        ):
            names = ("PROBLEM", arg, "problem")
            add(
                command,
                [arg, *base],
                desc,
                names,
                files=files,
                fast=fast and arg != "fifo",
                category="problem-argument",
            )
    add(
        "model",
        ["a.toml", "b.toml"],
        "two problem files",
        ("b.toml",),
        files=(FileSpec("a.toml", content=""),),
        fast=True,
    )
    add("", ["bogus-command"], "an unknown command", ("bogus-command",), fast=True)
    add("", ["--bogus"], "an unknown global option", ("--bogus",), fast=True)
    add("", ["--version"], "--version (control)", (), expect="ok", fast=True)
    add("model", ["--help"], "model --help (control)", (), expect="ok", fast=True)

    # synthesize
    for opt in ("--mu-points", "--max-iterations", "--samples"):
        for value in INT_COUNT:
            # No D-K step (the H-inf design alone) is a valid request, and a long one.
            if (opt, value) != ("--max-iterations", "0"):
                option("synthesize", opt, [value], f"{opt} {value!r}")
    for value, expect in SEED_VALUES:
        option("synthesize", "--seed", [value], f"--seed {value}", expect=expect)
    for value in ["1000", "-1", "", "a", "1,,2", "nan", "1.5", "1e9", "1,2,4,8,16,32,64,128"]:
        option("synthesize", "--d-orders", [value], f"--d-orders {value!r}")
    for value, desc, files, expect in (
        ("adir", "a directory as the controller file", (FileSpec("adir", "dir"),), "reject"),
        ("existing.txt", "an existing file without --overwrite", (), "reject"),
        ("/proc/casadi-debris-corpus.json", "an unwritable place", (), "reject"),
        ("existing.txt/c.json", "a file under a file", (), "reject"),
        ("", "empty string", (), "reject"),
    ):
        option("synthesize", "--out", [value], f"--out {desc}", files=files, expect=expect)

    # margins
    for value in INT_COUNT:
        option("margins", "--samples", [value], f"--samples {value!r}")
    for value, expect in SEED_VALUES:
        option("margins", "--seed", [value], f"--seed {value}", expect=expect)
    for value, desc in DIR_OUT:
        option("margins", "--out", [value], f"--out {desc}")
    for desc, spec in controllers.items():
        option(
            "margins",
            "--controller",
            ["ctl.json"],
            f"--controller: {desc}",
            files=(spec,),
            category="controller",
        )
    for value, desc, files in (
        ("nope.json", "missing", ()),
        ("adir", "a directory", (FileSpec("adir", "dir"),)),
        ("/dev/null", "/dev/null", ()),
        ("fifo", "a FIFO", (FileSpec("fifo", "fifo"),)),
        ("/dev/zero", "/dev/zero", ()),
    ):
        option(
            "margins",
            "--controller",
            [value],
            f"--controller {desc}",
            files=files,
            category="controller",
        )

    # allocate (fast: no long computation whatever it does)
    torque = [
        (["1", "2"], "two values", "reject"),
        (["nan", "0", "0"], "nan", "reject"),
        (["inf", "0", "0"], "inf", "reject"),
        (["-inf", "0", "0"], "-inf", "reject"),
        (["1.7e308", "1.7e308", "1.7e308"], "1.7e308 on every axis", "reject"),
        (["1e300", "0", "0"], "1e300", "reject"),
        (["a", "b", "c"], "letters", "reject"),
        (["", "0", "0"], "an empty value", "reject"),
    ]
    for values, desc, expect in torque:
        option("allocate", "--torque-mNm", values, f"--torque-mNm {desc}", expect=expect, fast=True)
    add(
        "allocate",
        ["--torque-mNm", "1", "2", "3", "4", "--json"],
        "--torque-mNm with four values (the fourth is taken as the problem file)",
        ("4", "--torque-mNm", "PROBLEM"),
        fast=True,
    )
    for values, desc in (
        (["5e-321", "0", "0"], "5e-321 (subnormal)"),
        (["1e-15", "0", "0"], "1e-15"),
        (["0", "0", "0"], "zero"),
    ):
        option(
            "allocate",
            "--torque-mNm",
            values,
            f"--torque-mNm {desc}: a valid demand, thrust must be a number",
            expect="ok",
            fast=True,
            forbid=("null", "NaN", "Infinity"),
        )
    add("allocate", ["--json"], "--torque-mNm missing", ("--torque-mNm",), fast=True)
    for values, desc in (
        (["nan", "0", "0"], "nan"),
        (["1e308", "0", "0"], "1e308"),
        (["1", "2"], "two values"),
    ):
        option("allocate", "--force-mN", values, f"--force-mN {desc}", fast=True)
    for value, expect in (
        ("0", "reject"),
        ("25", "reject"),
        ("-1", "reject"),
        ("a", "reject"),
        ("1,,2", "reject"),
        ("", "reject"),
        ("1.5", "reject"),
        ("1,1", "either"),
        (",".join(str(i) for i in range(1, 25)), "either"),
    ):
        option(
            "allocate",
            "--failed",
            [value],
            f"--failed {value!r}",
            expect=expect,
            fast=value in ("0", "25", "a"),
        )
    for value in ("junk", "", "nan"):
        option("allocate", "--solver", [value], f"--solver {value!r}", fast=value == "junk")
    option("allocate", "--saturation", ["junk"], "--saturation junk", fast=True)
    for desc, content in (
        ("not JSON", "state\n"),
        ("a list", "[]"),
        ("propellant_kg a string", '{"propellant_kg": "a"}'),
        ("propellant_kg NaN", '{"propellant_kg": ' + json.dumps([[math.nan] * 3] * 24) + "}"),
        ("negative propellant", '{"propellant_kg": ' + json.dumps([[-1.0] * 3] * 24) + "}"),
        (
            "propellant_kg one CubeSat short",
            '{"propellant_kg": ' + json.dumps([[0.1] * 3] * 23) + "}",
        ),
        ("failed CubeSat 99", '{"failed_cubesats": [99]}'),
        ("unknown key", '{"bogus": 1}'),
    ):
        option(
            "allocate",
            "--stage-state",
            ["state.json"],
            f"--stage-state {desc}",
            files=(FileSpec("state.json", content=content),),
            category="stage-state",
            names=("--stage-state", "state.json", *STAGE_STATE_KEYS),
        )
    for value, desc, files in (
        ("nope.json", "missing", ()),
        ("adir", "a directory", (FileSpec("adir", "dir"),)),
        ("fifo", "a FIFO", (FileSpec("fifo", "fifo"),)),
        ("/dev/zero", "/dev/zero", ()),
    ):
        option(
            "allocate",
            "--stage-state",
            [value],
            f"--stage-state {desc}",
            files=files,
            category="stage-state",
        )

    # slew
    for value in ("w", "", "xy", "+q", "nan", "0"):
        option("slew", "--axis", [value], f"--axis {value!r}", fast=True)
    option("slew", "--axis", ["-x"], "--axis -x (control)", expect="ok")
    for value in ("0", "-10", "181", "nan", "inf", "1e308", "abc"):
        option("slew", "--angle-deg", [value], f"--angle-deg {value}", fast=value in ("nan", "abc"))
    option("slew", "--method", ["junk"], "--method junk", fast=True)
    option("slew", "--flexible-method", ["junk"], "--flexible-method junk", fast=True)
    for value in DURATION:
        option("slew", "--duration-s", [value], f"--duration-s {value}")
    for value in ("0", "-0.5", "1.5", "nan", "inf"):
        option("slew", "--torque-fraction", [value], f"--torque-fraction {value}")
    for value in ("0", "-1", "nan", "inf", "abc"):
        option("slew", "--rate-limit-deg-s", [value], f"--rate-limit-deg-s {value}")
    for value in ("-1", "nan", "inf", "1e12"):
        option("slew", "--smoothing-s", [value], f"--smoothing-s {value}")
    for value in ("0", "-1", "nan", "inf", "1e-12", "abc"):
        option("slew", "--sample-s", [value], f"--sample-s {value}")
    for value, desc in DIR_OUT:
        option("slew", "--out", [value], f"--out {desc}")

    # simulate
    for opt, values in (
        ("--corner", ["-1", "256", "1000000000", "nan", "abc"]),
        ("--sample", ["-1", "1000000000", "nan"]),
    ):
        for value in values:
            option("simulate", opt, [value], f"{opt} {value}")
    for value, expect in SEED_VALUES:
        option("simulate", "--seed", [value], f"--seed {value}", expect=expect)
    for value in DURATION:
        option("simulate", "--duration-s", [value], f"--duration-s {value}")
    for value, desc in DIR_OUT:
        option("simulate", "--out", [value], f"--out {desc}")
    for desc, spec in list(controllers.items())[:6]:
        option(
            "simulate",
            "--controller",
            ["ctl.json"],
            f"--controller: {desc}",
            files=(spec,),
            category="controller",
        )
    for value, desc, files in (
        ("nope.json", "missing", ()),
        ("adir", "a directory", (FileSpec("adir", "dir"),)),
        ("fifo", "a FIFO", (FileSpec("fifo", "fifo"),)),
    ):
        option(
            "simulate",
            "--controller",
            [value],
            f"--controller {desc}",
            files=files,
            category="controller",
        )
    open_loop = {
        "not CSV": "torque please\n",
        "empty": "",
        "header only": "t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n",
        "NaN torque": "t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n0,nan,0,0\n1,0,0,0\n",
        "times going back": "t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n0,1,0,0\n-5,0,0,0\n",
        "two columns": "t_s,tau_x_mNm\n0,1\n1,0\n",
        "1e308 torque": "t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n0,1e308,0,0\n1,0,0,0\n",
    }
    for desc, content in open_loop.items():
        add(
            "simulate",
            [
                SHORT_TOML,
                "--rigid",
                "--open-loop",
                "ol.csv",
                "--no-plots",
                "--out",
                "out",
                "--json",
            ],
            f"--open-loop {desc}",
            ("--open-loop", "ol.csv"),
            files=(FileSpec("ol.csv", content=content),),
            category="open-loop",
        )
    add(
        "simulate",
        [SHORT_TOML, "--open-loop", "ol.csv", "--no-plots", "--out", "out", "--json"],
        "--open-loop without --rigid",
        ("--open-loop", "--rigid"),
        files=(FileSpec("ol.csv", content="t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n0,1,0,0\n"),),
        category="open-loop",
    )
    add(
        "simulate",
        [SHORT_TOML, "--rigid", "--open-loop", "adir", "--no-plots", "--out", "out", "--json"],
        "--open-loop a directory",
        ("--open-loop", "adir"),
        files=(FileSpec("adir", "dir"),),
        category="open-loop",
    )

    # montecarlo
    for opt in ("--samples", "--max-cases"):
        for value in INT_COUNT:
            option("montecarlo", opt, [value], f"{opt} {value!r}")
    for value, expect in SEED_VALUES:
        option("montecarlo", "--seed", [value], f"--seed {value}", expect=expect)
    for value, expect in (
        ("0", "reject"),
        ("-1", "reject"),
        ("nan", "reject"),
        ("abc", "reject"),
        ("1000000", "either"),
    ):
        option("montecarlo", "--workers", [value], f"--workers {value}", expect=expect)
    for value in ("junk", "", "tcp://", "file:///etc/passwd", "inproc://x", "tcp://127.0.0.1:9"):
        option("montecarlo", "--scheduler", [value], f"--scheduler {value!r}", category="scheduler")
    for value, desc in DIR_OUT:
        option("montecarlo", "--out", [value], f"--out {desc}")
    for desc in ("NaN in A", "not JSON"):
        option(
            "montecarlo",
            "--controller",
            ["ctl.json"],
            f"--controller: {desc}",
            files=(controllers[desc],),
            category="controller",
        )

    # reproduce
    for value, desc in DIR_OUT:
        option("reproduce", "--out", [value], f"--out {desc}")
    for value in ("0", "-1", "nan", "abc"):
        option("reproduce", "--workers", [value], f"--workers {value}")

    # compare
    add(
        "compare",
        ["--out", "out", "--json"],
        "no problem file",
        ("PROBLEM_FILES", "problem"),
        fast=True,
    )
    for arg, desc, files in (
        ("nope.toml", "a missing problem file", ()),
        ("adir", "a directory", (FileSpec("adir", "dir"),)),
        ("fifo", "a FIFO", (FileSpec("fifo", "fifo"),)),
    ):
        add(
            "compare",
            [SHORT_TOML, arg, "--out", "out", "--json"],
            desc,
            (arg, "PROBLEM_FILES", "problem"),
            files=files,
        )
    for value in ("junk", "", ",", "bang-bang,junk"):
        option("compare", "--methods", [value], f"--methods {value!r}")
    for value, desc in DIR_OUT:
        option("compare", "--out", [value], f"--out {desc}")
    option(
        "compare",
        "--controller",
        ["ctl.json"],
        "--controller: not JSON",
        files=(controllers["not JSON"],),
        category="controller",
    )

    # --overwrite on a folder casadi-debris did not write: refused, its file kept.
    for command in ("slew", "simulate", "margins", "compare"):
        add(
            command,
            [*_replace_option(BASE[command], "--out", ["full"]), "--overwrite"],
            "--out an existing folder of the user's with --overwrite",
            ("--out", "--overwrite", "full"),
            category="overwrite-foreign",
        )
    # An unwritable --out with the full default work: refused before the work starts.
    for command, args in (
        ("margins", ["--no-plots", "--out", "/proc/casadi-debris-corpus"]),
        ("montecarlo", ["--out", "/proc/casadi-debris-corpus"]),
        ("synthesize", ["--out", "/proc/casadi-debris-corpus.json"]),
        ("simulate", ["--out", "/proc/casadi-debris-corpus"]),
    ):
        add(
            command,
            args,
            "an unwritable --out with the full default work (checked before it starts)",
            ("--out",),
            category="out-checked-late",
        )
    return entries


def corpus(seed: int = SEED) -> list[Entry]:
    """The whole corpus, with the fast subset marked (seeded, reproducible)."""
    rng = random.Random(seed)
    files = problem_entries() + child_entries()
    # Fast subset: a seeded pick spread over the kinds of mutation.
    by_category: dict[str, list[int]] = defaultdict(list)
    for i, entry in enumerate(files):
        by_category[entry.category].append(i)
    chosen: set[int] = set()
    categories = sorted(by_category)
    while len(chosen) < FAST_FILES and any(by_category.values()):
        for category in categories:
            pool = by_category[category]
            if pool and len(chosen) < FAST_FILES:
                chosen.add(pool.pop(rng.randrange(len(pool))))
    files = [replace(e, fast=i in chosen or e.category == "none") for i, e in enumerate(files)]
    extra = extends_entries() + semantic_entries() + syntax_entries(rng)
    return files + extra + cli_entries()


# ---------------------------------------------------------------------------
# Running
# ---------------------------------------------------------------------------


@dataclass
class RunResult:
    args: tuple[str, ...]
    code: int | None = None  # exit status; None: killed (hang) or signal
    signal: int | None = None
    timed_out: bool = False
    stdout: str = ""
    stderr: str = ""
    seconds: float = 0.0
    outside: list[str] = field(default_factory=list)  # written outside its folder
    changed: list[str] = field(default_factory=list)  # files there before, changed or gone
    leftover: bool = False  # processes still in its group after it ended


@dataclass
class EntryResult:
    entry: Entry
    runs: list[RunResult]
    problems: list[str]

    @property
    def ok(self) -> bool:
        return not self.problems


def _snapshot_files(folder: Path) -> dict[str, tuple[Any, ...]]:
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


def _listing(folder: Path) -> set[str]:
    try:
        return set(os.listdir(folder))
    except OSError:
        return set()


def _materialize(entry: Entry, cwd: Path, rundir: Path) -> None:
    cwd.mkdir(parents=True)
    paper = problems_dir() / "paper.toml"
    for spec in entry.files:
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
            for i in range(spec.size):
                target = f"chain_{i + 1}.toml" if i + 1 < spec.size else str(paper)
                (cwd / f"chain_{i}.toml").write_text(
                    f"extends = {_toml_string(target)}\n", encoding="utf-8"
                )
        else:
            raise ValueError(spec.kind)


def _vm_size_bytes() -> int:
    with open("/proc/self/status", encoding="ascii") as handle:
        for line in handle:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0


def _child(args: tuple[str, ...], cwd: Path, rundir: Path) -> None:
    """In the forked child: run one invocation as the console script would; never return."""
    code = 98
    try:
        os.setpgid(0, 0)
        out = os.open(rundir / "stdout", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        err = os.open(rundir / "stderr", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.dup2(out, 1)
        os.dup2(err, 2)
        read_end, _write_end = os.pipe()  # a stdin that never ends, like a terminal
        os.dup2(read_end, 0)
        sys.stdin = io.TextIOWrapper(open(0, "rb", closefd=False), encoding="utf-8")  # noqa: SIM115
        sys.stdout = io.TextIOWrapper(
            open(1, "wb", closefd=False),  # noqa: SIM115
            encoding="utf-8",
            errors="backslashreplace",
            line_buffering=True,
        )
        sys.stderr = io.TextIOWrapper(
            open(2, "wb", closefd=False),  # noqa: SIM115
            encoding="utf-8",
            errors="backslashreplace",
            line_buffering=True,
        )
        limit = _vm_size_bytes() + (3 << 30)
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        resource.setrlimit(resource.RLIMIT_FSIZE, (1 << 30, 1 << 30))
        os.chdir(cwd)
        tmp = cwd / ".tmp"
        tmp.mkdir(exist_ok=True)
        os.environ.update(HOME=str(cwd), TMPDIR=str(tmp), PWD=str(cwd))
        os.environ.pop("CASADI_DEBRIS_DEBUG", None)
        tempfile.tempdir = None
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        from casadi_debris.cli import main

        sys.argv = ["casadi-debris", *args]
        try:
            main.main(args=list(args), prog_name="casadi-debris", standalone_mode=True)
            code = 0
        except SystemExit as exc:
            if exc.code is None:
                code = 0
            elif isinstance(exc.code, int):
                code = exc.code
            else:
                print(exc.code, file=sys.stderr)
                code = 1
        except BaseException:  # what Python prints for an uncaught exception
            traceback.print_exc()
            code = 1
        with contextlib.suppress(Exception):
            sys.stdout.flush()
            sys.stderr.flush()
    except BaseException:
        with contextlib.suppress(Exception):
            traceback.print_exc()
            sys.stderr.flush()
        code = 97
    os._exit(code)


# Folders between a run's folder and its working folder: a path that climbs out
# of the working folder (a problem named "../../x") lands in one of them, where
# it is seen and can harm nothing.
GUARDS = ("w1", "w2", "w3", "w4", "w5")


@dataclass
class _Pending:
    entry: Entry
    index: int
    args: tuple[str, ...]
    pid: int
    rundir: Path
    cwd: Path
    started: float
    before: dict[str, tuple[Any, ...]]
    listings: dict[Path, set[str]]


def _prepare_parent() -> list[str]:
    """Imports done once, before any fork (children only run the command)."""
    import matplotlib

    matplotlib.use("Agg")
    import importlib
    import pkgutil

    import matplotlib.font_manager
    import matplotlib.pyplot

    import casadi_debris

    # The commands import their modules when run: import every module once here,
    # or each forked run pays for it (seconds).
    failed: list[str] = []
    for module in pkgutil.walk_packages(casadi_debris.__path__, "casadi_debris."):
        if module.name.endswith("__main__"):
            continue  # runs the command line when imported
        try:
            importlib.import_module(module.name)
        except Exception as exc:
            failed.append(f"{module.name}: {type(exc).__name__}: {exc}")
    return failed


PR_SET_CHILD_SUBREAPER = 36


def _set_subreaper(on: bool) -> bool:
    """Orphans of the runs become this process's children (Linux), so that none is missed."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(PR_SET_CHILD_SUBREAPER, int(on), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _processes() -> dict[int, tuple[int, str]]:
    """pid -> (parent pid, state) of every process."""
    out: dict[int, tuple[int, str]] = {}
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat", encoding="ascii", errors="replace") as handle:
                stat = handle.read()
        except OSError:
            continue
        fields = stat[stat.rfind(")") + 2 :].split()
        out[int(name)] = (int(fields[1]), fields[0])
    return out


def _kill_tree(pid: int) -> None:
    """SIGKILL a process, its process group and every descendant."""
    procs = _processes()
    tree, frontier = set(), [pid]
    while frontier:
        parent = frontier.pop()
        children = [p for p, (pp, _) in procs.items() if pp == parent and p not in tree]
        tree.update(children)
        frontier.extend(children)
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pid, signal.SIGKILL)
    for p in (pid, *tree):
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(p, signal.SIGKILL)


def _reap_orphans(keep: set[int]) -> bool:
    """Kill and reap processes handed to us as orphans; True if any was still running."""
    me = os.getpid()
    running = False
    for pid, (ppid, state) in _processes().items():
        if ppid != me or pid in keep:
            continue
        if state not in ("Z", "X"):
            running = True
            _kill_tree(pid)
        with contextlib.suppress(ChildProcessError):
            os.waitpid(pid, 0)
    return running


def run_corpus(
    entries: list[Entry],
    jobs: int = 1,
    timeout: float = TIMEOUT_S,
    progress: bool = False,
    keep: bool = False,
) -> list[EntryResult]:
    """Run every entry's invocations, each in a forked child; return checked results."""
    for failure in _prepare_parent():  # a tree half-way through an edit: results will show it
        print(f"warning: cannot import {failure}", file=sys.stderr, flush=True)
    root = Path(tempfile.mkdtemp(prefix="casadi-debris-corpus-"))
    units_dir = root / "units"
    units_dir.mkdir()
    subreaper = _set_subreaper(True)
    known_children = {pid for pid, (ppid, _) in _processes().items() if ppid == os.getpid()}
    queue = [(e, i, run) for e in entries for i, run in enumerate(e.runs)]
    queue.reverse()
    results: dict[str, list[RunResult | None]] = {e.id: [None] * len(e.runs) for e in entries}
    pending: list[_Pending] = []
    done = 0
    total = len(queue)
    try:
        while queue or pending:
            while queue and len(pending) < jobs:
                entry, index, args = queue.pop()
                rundir = units_dir / f"{entry.id}-{index}"
                cwd = rundir.joinpath(*GUARDS, "cwd")
                _materialize(entry, cwd, rundir)
                before = _snapshot_files(cwd)
                guards = [rundir.joinpath(*GUARDS[:i]) for i in range(len(GUARDS) + 1)]
                listings = {folder: _listing(folder) for folder in (root, units_dir, *guards)}
                sys.stdout.flush()
                sys.stderr.flush()
                pid = os.fork()
                if pid == 0:
                    _child(args, cwd, rundir)
                with contextlib.suppress(OSError):
                    os.setpgid(pid, pid)
                pending.append(
                    _Pending(
                        entry, index, args, pid, rundir, cwd, time.monotonic(), before, listings
                    )
                )
            time.sleep(0.01)
            for item in list(pending):
                finished, status = os.waitpid(item.pid, os.WNOHANG)
                elapsed = time.monotonic() - item.started
                result = RunResult(item.args, seconds=elapsed)
                if finished == 0:
                    if elapsed < timeout:
                        continue
                    _kill_tree(item.pid)
                    os.waitpid(item.pid, 0)
                    result.timed_out = True
                elif os.WIFSIGNALED(status):
                    result.signal = os.WTERMSIG(status)
                else:
                    result.code = os.WEXITSTATUS(status)
                pending.remove(item)
                try:
                    os.killpg(item.pid, signal.SIGKILL)
                    result.leftover = not result.timed_out
                except (ProcessLookupError, PermissionError):
                    pass
                if subreaper:
                    keep_pids = known_children | {p.pid for p in pending}
                    orphans = _reap_orphans(keep_pids)
                    result.leftover = result.leftover or (orphans and not result.timed_out)
                _collect(item, result, units_dir)
                results[item.entry.id][item.index] = result
                done += 1
                if progress and done % 50 == 0:
                    print(f"  {done}/{total} runs", file=sys.stderr, flush=True)
                if not keep:
                    shutil.rmtree(item.rundir, ignore_errors=True)
    finally:
        for item in pending:
            _kill_tree(item.pid)
            with contextlib.suppress(ChildProcessError):
                os.waitpid(item.pid, 0)
        if subreaper:
            _reap_orphans(known_children)
            _set_subreaper(False)
        if not keep:
            shutil.rmtree(root, ignore_errors=True)
    return [check(e, [r for r in results[e.id] if r is not None]) for e in entries]


def _collect(item: _Pending, result: RunResult, units_dir: Path) -> None:
    for name, attr in (("stdout", "stdout"), ("stderr", "stderr")):
        with contextlib.suppress(OSError):
            data = (item.rundir / name).read_bytes()
            setattr(result, attr, data.decode("utf-8", "backslashreplace"))
    for folder, names in item.listings.items():
        now = _listing(folder)
        if folder == item.rundir:
            new = now - names - {"stdout", "stderr"}
        elif folder == units_dir:
            new = {n for n in now - names if not re.fullmatch(r"[A-Z]\d+-\d+", n)}
        else:
            new = now - names
        result.outside.extend(str(folder / n) for n in sorted(new))
        gone = names - now
        if folder != units_dir:
            result.outside.extend(f"{folder / n} (deleted)" for n in sorted(gone))
    after = _snapshot_files(item.cwd) if item.cwd.exists() else {}
    for path, state in item.before.items():
        if path.startswith(".tmp"):
            continue
        if path not in after:
            result.changed.append(f"{path} (deleted)")
        elif after[path] != state:
            result.changed.append(f"{path} (changed)")


_TRACEBACK = "Traceback (most recent call last)"


def _error_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if re.match(r"(?i)^(internal )?error\b", line)]


def names_match(message: str, names: Iterable[str]) -> bool:
    """Does the message name one of these keys, table prefixes (``hub.``) or options?"""
    for name in names:
        if name.endswith("."):
            pattern = rf"(?<![\w.]){re.escape(name)}\w"
        elif name.startswith("-"):
            pattern = rf"{re.escape(name)}(?![\w-])"
        else:
            pattern = rf"(?<![\w.]){re.escape(name)}(?![\w])"
        if re.search(pattern, message):
            return True
    return False


def check(entry: Entry, runs: list[RunResult]) -> EntryResult:
    """The problems of one entry's runs (empty: it passed)."""
    problems: list[str] = []
    for run in runs:
        where = shlex.join(run.args)
        output = run.stdout + run.stderr
        errors = _error_lines(run.stderr)
        line = errors[-1] if errors else (run.stderr.strip().splitlines() or [""])[-1]
        if run.timed_out:
            problems.append(f"hang: no answer in {TIMEOUT_S:.0f} s [{where}]")
        elif run.signal is not None:
            problems.append(f"killed by signal {run.signal} [{where}]")
        if _TRACEBACK in output:
            last = [ln for ln in output.splitlines() if ln.strip()][-1:]
            problems.append(f"traceback: {last[0] if last else ''} [{where}]")
        if run.code == 3:
            problems.append(f"exit 3: {line} [{where}]")
        elif run.code not in (None, 0, 2, 3):
            problems.append(f"exit {run.code}: {line} [{where}]")
        if run.code == 0 and entry.expect == "reject":
            problems.append(f"silent: bad input accepted (exit 0) [{where}]")
        if run.code == 2 and entry.expect == "ok":
            problems.append(f"valid input rejected: {line} [{where}]")
        if run.code == 2:
            if len(errors) != 1:
                problems.append(f"exit 2 without exactly one error line ({len(errors)}) [{where}]")
            elif entry.names and not names_match(errors[0], entry.names):
                problems.append(
                    f"exit 2 names none of {list(entry.names)}: {errors[0][:300]} [{where}]"
                )
        if run.code == 0:
            found = [s for s in entry.forbid_stdout if s in run.stdout]
            if found:
                problems.append(f"output contains {found} [{where}]")
        if run.outside:
            problems.append(f"wrote outside its folder: {run.outside[:5]} [{where}]")
        if run.changed:
            problems.append(f"changed files it did not create: {run.changed[:5]} [{where}]")
        if run.leftover:
            problems.append(f"left processes running [{where}]")
    return EntryResult(entry, runs, problems)


# ---------------------------------------------------------------------------
# Repository check and report
# ---------------------------------------------------------------------------


def git_status() -> set[str]:
    """``git status --porcelain`` lines of the repository (untracked files listed one by one)."""
    try:
        out = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=all"],
            cwd=REPO,
            capture_output=True,
            text=True,
            check=True,
            timeout=60,
        ).stdout
    except (OSError, subprocess.SubprocessError):
        return set()
    return set(out.splitlines())


def new_repo_files(before: set[str], after: set[str]) -> list[str]:
    """Status lines that appeared, less source edits and tool caches (others work in this tree)."""
    caches = re.compile(r"(^|/)(__pycache__|\.\w*cache|\.venv[\w-]*|\.hypothesis)/")
    new = sorted(after - before)
    return [
        line
        for line in new
        if not caches.search(line[3:])
        and (
            not re.search(r"\.(py|md|toml|cfg|txt|json|yml|yaml)$", line)
            or "runs/" in line
            or line.strip().endswith(("summary.json", "controller.json"))
        )
    ]


def counts(results: list[EntryResult]) -> dict[str, int]:
    runs = [r for res in results for r in res.runs]
    problems = [p for res in results for p in res.problems]
    return {
        "inputs tried (entries)": len(results),
        "invocations": len(runs),
        "exit 0": sum(r.code == 0 for r in runs),
        "exit 2": sum(r.code == 2 for r in runs),
        "exit 3": sum(r.code == 3 for r in runs),
        "other exit": sum(r.code not in (None, 0, 2, 3) for r in runs),
        "hangs": sum(r.timed_out for r in runs),
        "signals": sum(r.signal is not None for r in runs),
        "silent (bad input accepted)": sum(p.startswith("silent") for p in problems),
        "tracebacks": sum(p.startswith("traceback") for p in problems),
        "files written outside / changed": sum(bool(r.outside or r.changed) for r in runs),
        "valid input rejected": sum(p.startswith("valid input rejected") for p in problems),
        "exit 2 not naming the key/option": sum(
            p.startswith("exit 2 names none") for p in problems
        ),
        "exit 2 without one error line": sum(p.startswith("exit 2 without") for p in problems),
        "processes left": sum(r.leftover for r in runs),
        "entries failing": sum(not res.ok for res in results),
    }


def _kind(problem: str) -> str:
    for prefix in (
        "hang",
        "killed by signal",
        "traceback",
        "exit 3",
        "silent",
        "valid input rejected",
        "exit 2 names none",
        "exit 2 without",
        "wrote outside",
        "changed files",
        "left processes",
        "output contains",
        "exit",
    ):
        if problem.startswith(prefix):
            return prefix
    return problem.split(":")[0]


def failure_table(results: list[EntryResult], limit: int | None = None) -> str:
    lines = []
    for res in results:
        if res.ok:
            continue
        e = res.entry
        lines.append(f"{e.id} [{e.expect}] {e.description}")
        for problem in res.problems:
            lines.append(f"    {problem}")
    if limit is not None and len(lines) > limit:
        lines = [*lines[:limit], f"... ({len(lines) - limit} more lines)"]
    return "\n".join(lines)


def grouped(results: list[EntryResult]) -> str:
    """Failures grouped by kind of problem, then by command and mutation."""
    groups: dict[tuple[str, str], list[tuple[EntryResult, str]]] = defaultdict(list)
    for res in results:
        for problem in res.problems:
            command = problem.rsplit("[", 1)[-1].split()[0] if "[" in problem else "?"
            groups[(_kind(problem), f"{command} / {res.entry.category}")].append((res, problem))
    lines = []
    for (kind, sub), items in sorted(groups.items(), key=lambda kv: (kv[0][0], -len(kv[1]))):
        res, problem = items[0]
        lines.append(f"{kind} — {sub}: {len(items)}; e.g. {res.entry.id}: {res.entry.description}")
        lines.append(f"      {problem[:240]}")
    return "\n".join(lines)


def materialize(entry_id: str, folder: Path, seed: int = SEED) -> Entry:
    entry = next(e for e in corpus(seed) if e.id == entry_id)
    folder = folder.resolve()
    _materialize(entry, folder.joinpath(*GUARDS, "cwd"), folder)
    return entry


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawTextHelpFormatter
    )
    parser.add_argument("--report", action="store_true", help="run the corpus and print counts")
    parser.add_argument("--fast", action="store_true", help="only the fast subset")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--only", default="", help="comma-separated entry ids or id prefixes")
    parser.add_argument("--seed", type=int, default=SEED)
    parser.add_argument("--json", type=Path, help="write every result to this JSON file")
    parser.add_argument("--list", action="store_true", help="list the entries")
    parser.add_argument("--materialize", nargs=2, metavar=("ID", "FOLDER"))
    args = parser.parse_args(argv)
    if args.materialize:
        entry = materialize(args.materialize[0], Path(args.materialize[1]), args.seed)
        print(f"{entry.id}: {entry.description} (expect {entry.expect})")
        cwd = Path(args.materialize[1]).resolve().joinpath(*GUARDS, "cwd")
        print(f"cd {shlex.quote(str(cwd))}")
        for command in entry.commands():
            print(command)
        return 0
    entries = corpus(args.seed)
    if args.fast:
        entries = [e for e in entries if e.fast]
    if args.only:
        wanted = [w for w in args.only.split(",") if w]
        entries = [e for e in entries if any(e.id == w or e.id.startswith(w) for w in wanted)]
    if args.list or not args.report:
        for e in entries:
            flag = "fast" if e.fast else "slow"
            commands = " ; ".join(e.commands())[:160]
            print(f"{e.id} {flag} {e.expect:6} {e.description[:100]} :: {commands}")
        print(f"{len(entries)} entries", file=sys.stderr)
        return 0

    def stop(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt  # so that the runs are killed and the folders removed

    signal.signal(signal.SIGTERM, stop)
    started = time.monotonic()
    repo_before = git_status()
    results = run_corpus(entries, jobs=args.jobs, progress=True)
    repo_new = new_repo_files(repo_before, git_status())
    import casadi_debris

    print(f"# casadi_debris from {Path(casadi_debris.__file__).parent}")
    print(
        f"# bad-input corpus: seed {args.seed}, {len(entries)} entries, "
        f"{time.monotonic() - started:.0f} s, {args.jobs} jobs"
    )
    for name, value in counts(results).items():
        print(f"{name:40} {value}")
    print(f"{'new files in the repository':40} {len(repo_new)} {repo_new[:10]}")
    print("\n# failures grouped\n" + grouped(results))
    print("\n# failures\n" + failure_table(results))
    if args.json:
        payload = [
            {
                "id": r.entry.id,
                "description": r.entry.description,
                "expect": r.entry.expect,
                "commands": r.entry.commands(),
                "problems": r.problems,
                "codes": [run.code for run in r.runs],
                "stderr": [run.stderr[-2000:] for run in r.runs],
            }
            for r in results
        ]
        args.json.write_text(json.dumps(payload, indent=1), encoding="utf-8")
    return 0 if all(r.ok for r in results) and not repo_new else 1


if __name__ == "__main__":
    sys.exit(main())
