"""The in-process corpus: every value of the shipped problems replaced by each bad value.

Generated from ``paper.toml`` and ``paper_slew.toml`` (flattened onto the paper
by the package's own merge), and from the paper with its CubeSats as a
``[[cubesats]]`` list (``paper_list``: the list and its first CubeSat only, the
other 23 are alike): every value replaced by zero, negative, NaN, inf, 1e308,
subnormal, huge integers, strings, booleans, wrong shapes and nestings; every
key deleted; unknown keys; broken ``extends``. Run by
``tests/config/test_corpus.py`` through ``model`` and ``budget`` in-process.
Case ids: ``<problem>:<dotted path>=<index of the bad value>``, ``:deleted``,
``:unknown``, ``:short``, ``:long``, and ``extends=<i>``.
"""

from __future__ import annotations

import copy
import json
import math
from collections.abc import Iterator
from typing import Any

from .shipped import flattened, paper_cubesat_list, problems_dir
from .toml_writer import is_table_array, toml_dumps

BAD_VALUES: list[Any] = [
    0,
    -1,
    1.5,
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    5e-324,
    10**400,
    2**63,
    "5",
    "",
    "x" * 2000,
    True,
    [],
    [[1.0]],
    {},
]


def _paths(data: Any, prefix: tuple = ()) -> Iterator[tuple[tuple, Any]]:
    """Every (path, value) below ``data``; tables and arrays of tables too."""
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for key, value in items:
        path = (*prefix, key)
        yield path, value
        if isinstance(value, dict) or is_table_array(value):
            yield from _paths(value, path)


def _with(data: dict[str, Any], path: tuple, value: Any = None, delete: bool = False) -> dict:
    changed = copy.deepcopy(data)
    parent = changed
    for part in path[:-1]:
        parent = parent[part]
    if delete:
        del parent[path[-1]]
    else:
        parent[path[-1]] = value
    return changed


def _node_cases(origin: str, data: dict[str, Any], under: tuple = ()) -> Iterator[tuple[str, str]]:
    """Every node of one problem: each bad value, deleted, an unknown key, lengths.

    With ``under``, only the nodes on that path and below it.
    """
    for path, original in _paths(data):
        if path[: len(under)] != under[: len(path)]:
            continue
        label = f"{origin}:{'.'.join(map(str, path))}"
        for i, bad in enumerate(BAD_VALUES):
            if bad != original or type(bad) is not type(original):
                yield f"{label}={i}", toml_dumps(_with(data, path, bad))
        if not isinstance(path[-1], int):
            yield f"{label}:deleted", toml_dumps(_with(data, path, delete=True))
        if isinstance(original, dict):
            yield f"{label}:unknown", toml_dumps(_with(data, (*path, "typo_key"), 1.0))
        if isinstance(original, list) and original and not is_table_array(original):
            yield f"{label}:short", toml_dumps(_with(data, path, original[:-1]))
            yield f"{label}:long", toml_dumps(_with(data, path, [*original, 0.5]))


def value_cases() -> list[tuple[str, str]]:
    """(case id, file text) of every mutation, in a fixed order.

    A text's ``"SELF"`` stands for the file's own path (written in when it is run).
    """
    cases: list[tuple[str, str]] = []
    for origin in ("paper", "paper_slew"):
        cases.extend(_node_cases(origin, flattened(origin)))
    cases.extend(_node_cases("paper_list", paper_cubesat_list(), under=("cubesats", 0)))
    paper = problems_dir() / "paper.toml"
    for i, target in enumerate(["absent.toml", ".", "SELF", 5, "", str(paper) + "\\u0000"]):
        value = json.dumps(target) if isinstance(target, str) else str(target)
        cases.append((f"extends={i}", f'extends = {value}\nname = "x"\n'))
    return cases
