"""``P…`` and ``C…`` entries: the shipped problem files with one field mutated.

``P…``: the paper flattened (and the ``[simulation]`` part of ``paper_slew`` and
``paper_pointing`` flattened onto it), one node changed or deleted, written back
as TOML; unknown and misplaced keys; empty files; then the paper with its
``[cubesat_layout]`` written out as a ``[[cubesats]]`` list, every node of the
list and of its first CubeSat and engine mutated. ``C…``: the children, which
``extends`` the paper, with one of their own keys mutated, and overrides of the
paper's keys in a child (the CubeSats and arrays a child replaces whole).
"""

from __future__ import annotations

import copy
from typing import Any

from .entry import Entry, FileSpec
from .expectations import Path_, key_names, plain_key
from .mutations import DELETE, apply_mutation, get_path, mutations, same_value
from .shipped import CHILDREN, flattened, load_shipped, paper_cubesat_list, problems_dir
from .toml_writer import toml_dumps


def problem_runs(path: Path_ | None, op: str, name: str = "p.toml") -> tuple[tuple[str, ...], ...]:
    """``model`` and ``budget`` of the file; ``simulate`` and ``margins`` where the key matters."""
    runs: list[tuple[str, ...]] = [("model", name, "--json"), ("budget", name, "--json")]
    key = plain_key(path) if path else ""
    if key.startswith("simulation"):
        runs.append(("simulate", name, "--duration-s", "2", "--no-plots", "--out", "out", "--json"))
    if op.startswith("name-"):
        # Commands whose default output folder comes from the name.
        runs.append(("simulate", name, "--duration-s", "1", "--no-plots", "--json"))
        runs.append(("margins", name, "--samples", "2", "--no-plots", "--json"))
    return tuple(runs)


class _Files:
    """Numbered entries of one problem file ``p.toml`` each (ids ``<prefix>0001`` on)."""

    def __init__(self, prefix: str) -> None:
        self.prefix = prefix
        self.entries: list[Entry] = []

    def add(
        self, desc: str, text: str, path: Path_ | None, op: str, expect: str = "reject", **kw: Any
    ) -> None:
        kw.setdefault("names", key_names(path) if path else ())
        kw.setdefault("category", op)
        self.entries.append(
            Entry(
                id=f"{self.prefix}{len(self.entries) + 1:04d}",
                description=desc,
                runs=problem_runs(path, op),
                files=(FileSpec("p.toml", "text", text),),
                expect=expect,
                **kw,
            )
        )


def _paper_node_entries(files: _Files) -> None:
    """The unchanged files through the writer (controls), then every node of each."""
    flat = {base: flattened(base) for base in ("paper", *CHILDREN)}
    for base, data in flat.items():
        desc = f"{base}.toml flattened, unchanged (control)"
        files.add(desc, toml_dumps(data), None, "none", "ok")
    for base, data in flat.items():
        for op, path, desc, new, expect in mutations(data):
            if base != "paper" and path[0] != "simulation":
                continue  # the rest is the paper's, mutated above
            if new is not DELETE and same_value(new, get_path(data, path)):
                continue
            text = toml_dumps(apply_mutation(data, path, new))
            files.add(f"{base}.toml: {desc}", text, path, op, expect)


def _paper_whole_file_entries(files: _Files) -> None:
    """Unknown keys and tables at the top, keys in the wrong table, empty files."""
    paper = load_shipped("paper")
    top_extra = [
        ("unknown-top-key", "bogus_key = 1 at the top", {"bogus_key": 1}, ("bogus_key",)),
        ("unknown-table", "[bogus] table", {"bogus": {"x": 1.0}}, ("bogus",)),
        ("misplaced-key", "mass_kg at the top level", {"mass_kg": 500.0}, ("mass_kg",)),
        ("case-table", "[Hub] beside [hub]", {"Hub": {"mass_kg": 500.0}}, ("Hub",)),
    ]
    for op, desc, extra, path in top_extra:
        files.add(f"paper.toml: {desc}", toml_dumps({**paper, **extra}), path, op)
    moved = copy.deepcopy(paper)
    moved["cubesat_layout"]["isp_s"] = moved["engine"].pop("isp_s")
    desc = "paper.toml: engine.isp_s moved into [cubesat_layout]"
    # [engine] is read first: its missing isp_s may be named before the stray one.
    names = ("cubesat_layout.isp_s", "engine.isp_s")
    files.add(desc, toml_dumps(moved), None, "misplaced-key", names=names)
    for desc, text, op in (
        ("empty file", "", "empty-file"),
        ("only a name", 'name = "x"\n', "only-name"),
    ):
        files.add(desc, text, None, op, names=tuple(paper))


def _cubesat_list_entries(files: _Files) -> None:
    """The paper's CubeSats as a ``[[cubesats]]`` list: the list, its first CubeSat mutated."""
    data = paper_cubesat_list()
    desc = "paper.toml with its 24 CubeSats as a [[cubesats]] list, unchanged (control)"
    files.add(desc, toml_dumps(data), None, "none", "ok")
    for op, path, desc, new, expect in mutations(data, under=("cubesats", 0)):
        if new is not DELETE and same_value(new, get_path(data, path)):
            continue
        text = toml_dumps(apply_mutation(data, path, new))
        files.add(f"paper.toml, CubeSats as a list: {desc}", text, path, op, expect)


def problem_entries() -> list[Entry]:
    """Mutated problem files: the paper flattened, the children's ``[simulation]`` on it."""
    files = _Files("P")
    _paper_node_entries(files)
    _paper_whole_file_entries(files)
    _cubesat_list_entries(files)
    return files.entries


def _child_mutation_expect(paper: dict[str, Any], path: Path_, new: Any, expect: str) -> str:
    """A deleted key of the child falls back to the paper's."""
    if new is not DELETE or path == ("simulation", "reference"):
        return expect
    try:
        get_path(paper, path)
    except (KeyError, IndexError, TypeError):
        return expect
    return "ok"


def _child_mutation_entries(files: _Files) -> None:
    paper_path = problems_dir() / "paper.toml"
    paper = load_shipped("paper")
    for base in CHILDREN:
        child = load_shipped(base)
        child["extends"] = str(paper_path)
        for op, path, desc, new, expect in mutations(child):
            if path == ("extends",):
                continue  # broken extends: extends_entries
            if new is not DELETE and same_value(new, get_path(child, path)):
                continue
            expect = _child_mutation_expect(paper, path, new, expect)
            text = toml_dumps(apply_mutation(child, path, new))
            files.add(f"{base}.toml (extends the paper): {desc}", text, path, op, expect)


def _overrides() -> list[tuple[str, dict[str, Any], str, tuple[str, ...]]]:
    """(description, the child's tables, expectation, names), in a fixed order.

    A child's ``[[arrays]]`` list replaces the paper's whole list, and its CubeSats
    (a ``[[cubesats]]`` list or a ``[cubesat_layout]``) the paper's in either form;
    a ``[cubesat_layout]`` over the paper's layout merges key by key.
    """
    paper = load_shipped("paper")
    no_hinge = {k: v for k, v in paper["arrays"][0].items() if k != "hinge_corner_m"}
    rigid = {k: v for k, v in paper["arrays"][0].items() if k != "modes"}
    two = paper_cubesat_list()["cubesats"][:2]
    old_cubesats = {"per_face": 4, "mass_kg": 3.5, "inertia_kgm2": [0.0513, 0.0513, 0.0082]}
    return [
        ("[hub] mass_kg = -1 in the child", {"hub": {"mass_kg": -1.0}}, "reject", ("hub.mass_kg",)),
        ("hub = 5 in the child", {"hub": 5}, "reject", ("hub",)),
        ("[engine] bogus = 1 in the child", {"engine": {"bogus": 1}}, "reject", ("engine.bogus",)),
        (
            '[cubesat_layout] mass_kg = "3.5"',
            {"cubesat_layout": {"mass_kg": "3.5"}},
            "reject",
            ("cubesat_layout.mass_kg",),
        ),
        (
            "[[arrays]] of one array without hinge_corner_m (the list replaces the paper's)",
            {"arrays": [no_hinge]},
            "reject",
            ("arrays[0].hinge_corner_m",),
        ),
        (
            "hub.mass_kg = 450 (valid override, control)",
            {"hub": {"mass_kg": 450.0}},
            "ok",
            (),
        ),
        (
            "the old [cubesats] table (per_face, mass_kg, inertia_kgm2)",
            {"cubesats": old_cubesats},
            "reject",
            ("cubesats",),
        ),
        (
            "[cubesat_layout] per_face = 2 (merged into the paper's face_corners layout)",
            {"cubesat_layout": {"per_face": 2}},
            "reject",
            ("cubesat_layout.per_face",),
        ),
        (
            "[[cubesats]] list and [cubesat_layout] both",
            {"cubesats": two, "cubesat_layout": {"mass_kg": 3.0}},
            "reject",
            ("cubesats", "cubesat_layout"),
        ),
        (
            "[[cubesats]] of two CubeSats (replaces the paper's layout, control)",
            {"cubesats": two},
            "ok",
            (),
        ),
        ("arrays = [] (a rigid debris, control)", {"arrays": []}, "ok", ()),
        (
            "[[arrays]] of one array without modes (a rigid appendage, control)",
            {"arrays": [rigid]},
            "ok",
            (),
        ),
    ]


def _child_override_entries(files: _Files) -> None:
    """Overrides of the paper's keys in a child, valid ones as controls."""
    paper_path = str(problems_dir() / "paper.toml")
    for desc, body, expect, names in _overrides():
        text = toml_dumps({"extends": paper_path, "name": "child", **body})
        files.add(
            f"child of the paper: {desc}",
            text,
            None,
            "override",
            expect,
            names=names,
            category="child-override",
        )


def child_entries() -> list[Entry]:
    """The children (paper_slew, paper_pointing) with their own keys mutated, extends kept."""
    files = _Files("C")
    _child_mutation_entries(files)
    _child_override_entries(files)
    return files.entries
