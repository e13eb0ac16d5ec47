"""Static types: mypy over all of ``src/casadi_debris``, with the settings of pyproject.toml.

The whole package is checked, zero errors allowed; pyproject's ``[tool.mypy] files``
names the package, so ``mypy`` run alone at the repository's root is the same check.
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


def test_mypy_settings_cover_the_package():
    # `mypy` alone checks what pyproject names: all of the package, nothing left out.
    with open(ROOT / "pyproject.toml", "rb") as file:
        settings = tomllib.load(file)["tool"]["mypy"]
    assert settings["files"] == ["src/casadi_debris"]
    assert "exclude" not in settings


def test_package_is_marked_typed():
    # PEP 561: without py.typed, users' type checkers ignore the package's annotations.
    assert (PACKAGE / "py.typed").is_file()
    with open(ROOT / "pyproject.toml", "rb") as file:
        package_data = tomllib.load(file)["tool"]["setuptools"]["package-data"]
    assert "py.typed" in package_data["casadi_debris"]


def test_mypy_clean():
    pytest.importorskip("mypy", reason="mypy is in the test extra: pip install -e '.[test]'")
    command = [
        sys.executable,
        "-m",
        "mypy",
        "--config-file",
        str(ROOT / "pyproject.toml"),
        f"--cache-dir={CACHE}",
        str(PACKAGE),
    ]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, check=False)
    elapsed_s = time.perf_counter() - start
    errors = [line for line in result.stdout.splitlines() if ": error:" in line]
    assert result.returncode == 0 and not errors, (
        f"mypy found {len(errors)} errors in {elapsed_s:.0f} s:\n" + result.stdout + result.stderr
    )
