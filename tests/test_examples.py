"""The scripts of ``examples/`` run from a fresh install with their quick settings, and
use only the front door (names exported by ``casadi_debris``)."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

import casadi_debris

EXAMPLES = Path(__file__).parents[1] / "examples"
SCRIPTS = sorted(p for p in EXAMPLES.glob("*.py") if not p.name.startswith("_"))
# Examples that take tens of seconds even when quick run under -m slow; `.ci/run` runs
# them in a step of their own.
SLOW = {"design_and_fly", "mission_to_reentry", "montecarlo_in_xarray", "optimal_slew"}


def _casadi_debris_uses(path: Path) -> list[str]:
    """What a script takes from casadi_debris: imported names and ``cd.<name>`` uses."""
    tree = ast.parse(path.read_text())
    used = []
    aliases = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "casadi_debris":
                    aliases.add(alias.asname or alias.name)
                elif alias.name.startswith("casadi_debris."):
                    used.append(alias.name)
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("casadi_debris"):
            if node.module != "casadi_debris":
                used.append(node.module or "")
            used.extend(f"casadi_debris.{a.name}" for a in node.names)
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in aliases
        ):
            used.append(f"casadi_debris.{node.attr}")
    return used


def test_there_are_examples() -> None:
    assert len(SCRIPTS) >= 1


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_an_example_uses_only_the_front_door(script: Path) -> None:
    exported = {f"casadi_debris.{name}" for name in casadi_debris.__all__}
    outside = sorted(set(_casadi_debris_uses(script)) - exported)
    assert not outside, f"{script.name} reaches past the front door: {outside}"


@pytest.mark.parametrize(
    "script",
    [
        pytest.param(s, marks=[pytest.mark.slow] if s.stem in SLOW else [], id=s.stem)
        for s in SCRIPTS
    ],
)
def test_an_example_runs(script: Path, tmp_path: Path) -> None:
    environment = {
        **os.environ,
        "CASADI_DEBRIS_EXAMPLES_QUICK": "1",
        "CASADI_DEBRIS_EXAMPLES_OUT": str(tmp_path),
        "MPLBACKEND": "Agg",
    }
    finished = subprocess.run(
        [sys.executable, script.name],
        cwd=EXAMPLES,
        env=environment,
        capture_output=True,
        text=True,
        check=False,
    )
    assert finished.returncode == 0, finished.stdout + finished.stderr
    assert finished.stdout.strip(), "an example says what it found"
    assert any((tmp_path / script.stem).iterdir()), "an example writes its figures"
