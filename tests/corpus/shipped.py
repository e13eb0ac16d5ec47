"""The shipped problems the corpus mutates, parsed, and the children flattened onto the paper.

The flattening is the package's own ``extends`` merge
(:func:`casadi_debris.config.loader._merge`), not a copy of it.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from casadi_debris.config.loader import _merge as merge_tables

CHILDREN = ("paper_slew", "paper_pointing")


def problems_dir() -> Path:
    """The folder of the shipped problem files (``paper.toml`` and its children)."""
    from casadi_debris.config import default_problem_path

    return default_problem_path().parent


def load_toml(path: Path) -> dict[str, Any]:
    with path.open("rb") as handle:
        return tomllib.load(handle)


def load_shipped(base: str) -> dict[str, Any]:
    """``problems/<base>.toml`` as parsed, ``extends`` kept."""
    return load_toml(problems_dir() / f"{base}.toml")


def flattened(base: str) -> dict[str, Any]:
    """``problems/<base>.toml`` as one problem: a child merged onto the paper, ``extends`` gone.

    The result shares unchanged values with the paper's data: copy before changing it.
    """
    data = load_shipped(base)
    if "extends" not in data:
        return data
    paper = load_shipped("paper")
    return merge_tables(paper, {k: v for k, v in data.items() if k != "extends"})
