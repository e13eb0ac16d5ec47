"""Static types: mypy over the packages that are clean, with the settings of pyproject.toml.

``CLEAN`` grows as the rest of ``src/`` becomes clean; when it covers everything,
``mypy`` alone (its ``files`` setting is all of ``src/casadi_debris``) is the check.
"""

from __future__ import annotations

import hashlib
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
PACKAGE = ROOT / "src" / "casadi_debris"
# mypy's cache: outside the repository, one per checkout, kept between runs (a cold
# run takes about 20 s of CPU, a warm one a few).
CACHE = Path(tempfile.gettempdir()) / (
    "casadi_debris-mypy-" + hashlib.sha256(str(ROOT.resolve()).encode()).hexdigest()[:12]
)

# Packages and modules checked with zero errors allowed.
CLEAN = [
    "config",
    "geometry.py",
    "model",
    "allocation",
    "robust",
    "budgets.py",
    "errors.py",
    "processes.py",
    "plots",
    "cli",
    "workflows",
]


def test_clean_packages_exist():
    missing = [name for name in CLEAN if not (PACKAGE / name).exists()]
    assert not missing, f"listed in CLEAN but not in src/casadi_debris: {missing}"


def test_package_is_marked_typed():
    # PEP 561: without py.typed, users' type checkers ignore the package's annotations.
    assert (PACKAGE / "py.typed").is_file()
    with open(ROOT / "pyproject.toml", "rb") as file:
        package_data = tomllib.load(file)["tool"]["setuptools"]["package-data"]
    assert "py.typed" in package_data["casadi_debris"]


def test_mypy_clean():
    pytest.importorskip("mypy", reason="mypy is in the test extra: pip install -e '.[test]'")
    targets = [str(PACKAGE / name) for name in CLEAN]
    command = [
        sys.executable,
        "-m",
        "mypy",
        "--config-file",
        str(ROOT / "pyproject.toml"),
        # Modules outside CLEAN are read for their types, their own errors not reported.
        "--follow-imports=silent",
        f"--cache-dir={CACHE}",
        *targets,
    ]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, check=False)
    elapsed_s = time.perf_counter() - start
    errors = [line for line in result.stdout.splitlines() if ": error:" in line]
    assert result.returncode == 0 and not errors, (
        f"mypy found {len(errors)} errors in {elapsed_s:.0f} s:\n" + result.stdout + result.stderr
    )
