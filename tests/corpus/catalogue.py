"""The whole corpus, in a fixed order, with its fast subset (seeded, reproducible)."""

from __future__ import annotations

import random
from collections import defaultdict
from dataclasses import replace

from .entry import Entry
from .extends import extends_entries
from .invocations import Invocations
from .options import (
    allocate_entries,
    common_entries,
    compare_entries,
    margins_entries,
    montecarlo_entries,
    reproduce_entries,
    simulate_entries,
    slew_entries,
    synthesize_entries,
)
from .output_folders import out_checked_first_entries, overwrite_entries
from .problem_files import child_entries, problem_entries
from .semantic import semantic_entries
from .syntax import syntax_entries

SEED = 20250111
FAST_FILES = 150
# Picked but left to the whole corpus: a valid name runs simulate and margins to the end
# (half a minute of the fast subset's CPU); the invalid names check the rule, and a valid
# name on an extended problem runs by default in tests/cli/test_simulation.py.
SLOW_PICKS = frozenset({"name-valid"})


def cli_entries() -> list[Entry]:
    """Bad invocations of every command (``K…``, numbered in this order)."""
    inv = Invocations()
    for family in (
        common_entries,
        synthesize_entries,
        margins_entries,
        allocate_entries,
        slew_entries,
        simulate_entries,
        montecarlo_entries,
        reproduce_entries,
        compare_entries,
        overwrite_entries,
        out_checked_first_entries,
    ):
        family(inv)
    return inv.entries


def _fast_pick(files: list[Entry], rng: random.Random) -> set[int]:
    """Indices of :data:`FAST_FILES` entries, picked in turn from each kind of mutation."""
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
    return chosen


def corpus(seed: int = SEED) -> list[Entry]:
    """The whole corpus, with the fast subset marked (seeded, reproducible)."""
    rng = random.Random(seed)
    files = problem_entries() + child_entries()
    chosen = _fast_pick(files, rng)
    files = [
        replace(e, fast=(i in chosen and e.category not in SLOW_PICKS) or e.category == "none")
        for i, e in enumerate(files)
    ]
    extra = extends_entries() + semantic_entries() + syntax_entries(rng)
    return files + extra + cli_entries()
