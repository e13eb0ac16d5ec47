"""A corpus of broken problem files through ``casadi-debris model`` and ``budget``.

Generated from the shipped problems: every value replaced by zero, negative,
NaN, inf, 1e308, subnormal, huge integers, strings, booleans, wrong shapes and
nestings; every key deleted; unknown keys; broken ``extends``. Each file runs
in-process through the command line with a time limit, and must end with exit
status 0 (a mutation that is still a valid problem) or 2 with one line naming
the file and a key; never 3 (an internal error), never a hang. The default
selection runs a seeded sample; ``-m slow`` runs all of it.
"""

from __future__ import annotations

import copy
import json
import math
import random
import re
import tomllib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from test_config_files import no_hang

PROBLEMS = Path(__file__).parents[1] / "problems"
SAMPLE_SIZE = 60
SEED = 20250111

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


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {_toml_value(v)}" for k, v in value.items()) + "}"


def _is_table_array(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def to_toml(data: dict[str, Any], name: str = "") -> str:
    """A TOML document of ``data`` (scalars first, then tables and arrays of tables)."""
    lines = [f"[{name}]"] if name else []
    nested = {k: v for k, v in data.items() if isinstance(v, dict) or _is_table_array(v)}
    for key, value in data.items():
        if key not in nested:
            lines.append(f"{json.dumps(key)} = {_toml_value(value)}")
    for key, value in nested.items():
        full = f"{name}.{json.dumps(key)}" if name else json.dumps(key)
        if isinstance(value, dict):
            lines.append(to_toml(value, full))
        else:
            for item in value:
                rows = [f"{json.dumps(k)} = {_toml_value(v)}" for k, v in item.items()]
                lines.append("\n".join([f"[[{full}]]", *rows]))
    return "\n".join(lines) + "\n"


def _merge(base: dict[str, Any], override: dict[str, Any]) -> dict[str, Any]:
    merged = dict(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key] = _merge(merged[key], value)
        else:
            merged[key] = value
    return merged


def _shipped() -> dict[str, dict[str, Any]]:
    paper = tomllib.loads((PROBLEMS / "paper.toml").read_text())
    slew = tomllib.loads((PROBLEMS / "paper_slew.toml").read_text())
    slew.pop("extends")
    return {"paper": paper, "paper_slew": _merge(paper, slew)}


def _paths(data: Any, prefix: tuple = ()) -> Iterator[tuple[tuple, Any]]:
    """Every (path, value) below ``data``; tables and arrays of tables too."""
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for key, value in items:
        path = (*prefix, key)
        yield path, value
        if isinstance(value, dict) or _is_table_array(value):
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


def corpus() -> list[tuple[str, str]]:
    """(case id, file text) of every mutation, in a fixed order."""
    cases = []
    for origin, data in _shipped().items():
        for path, original in _paths(data):
            label = f"{origin}:{'.'.join(map(str, path))}"
            for i, bad in enumerate(BAD_VALUES):
                if bad != original or type(bad) is not type(original):
                    cases.append((f"{label}={i}", to_toml(_with(data, path, bad))))
            if not isinstance(path[-1], int):
                cases.append((f"{label}:deleted", to_toml(_with(data, path, delete=True))))
            if isinstance(original, dict):
                typo = _with(data, (*path, "typo_key"), 1.0)
                cases.append((f"{label}:unknown", to_toml(typo)))
            if isinstance(original, list) and original and not _is_table_array(original):
                cases.append((f"{label}:short", to_toml(_with(data, path, original[:-1]))))
                cases.append((f"{label}:long", to_toml(_with(data, path, [*original, 0.5]))))
    paper = PROBLEMS / "paper.toml"
    for i, target in enumerate(["absent.toml", ".", "SELF", 5, "", str(paper) + "\\u0000"]):
        value = json.dumps(target) if isinstance(target, str) else str(target)
        cases.append((f"extends={i}", f'extends = {value}\nname = "x"\n'))
    return cases


CORPUS = corpus()
SAMPLE = sorted(random.Random(SEED).sample(range(len(CORPUS)), SAMPLE_SIZE))
KEY = re.compile(r'[A-Za-z0-9_"\\\[\]. -]+')


def _check(tmp_path: Path, case: str, text: str) -> None:
    path = tmp_path / "case.toml"
    path.write_text(text.replace('"SELF"', json.dumps(str(path))))
    for command in ("model", "budget"):
        with no_hang(60):
            result = CliRunner().invoke(main, [command, str(path), "--json"])
        assert result.exit_code in (0, 2), f"{case} {command}: {result.output[-500:]}"
        if result.exit_code == 0:
            json.loads(result.stdout)
            continue
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1, f"{case} {command}: {result.stderr[-500:]}"
        prefix = f"error: {path}: "
        assert lines[0].startswith(prefix), f"{case} {command}: {lines[0]}"
        key, _, message = lines[0][len(prefix) :].partition(": ")
        assert message and KEY.fullmatch(key), f"{case} {command}: {lines[0]}"


def test_corpus_is_large_enough():
    assert len(CORPUS) >= 1000


@pytest.mark.parametrize("index", SAMPLE, ids=[CORPUS[i][0] for i in SAMPLE])
def test_sampled_broken_files_exit_2_naming_a_key(tmp_path, index):
    _check(tmp_path, *CORPUS[index])


@pytest.mark.slow
def test_every_broken_file_exits_0_or_2_naming_a_key(tmp_path):
    for case, text in CORPUS:
        _check(tmp_path, case, text)
