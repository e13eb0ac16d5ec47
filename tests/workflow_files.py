"""Files the tests of the jobs share: short problems, what a run folder holds, and a
manoeuvre sequence."""

from __future__ import annotations

from pathlib import Path

from casadi_debris.config import default_problem_path
from casadi_debris.store import MARKER_NAME

PROBLEMS = default_problem_path().parent

# A slew, a hold and an LVLH track with its blend: the sequence the slew command and
# cd.slew fly in their tests.
SEQUENCE = """
[simulation]
duration_s = 2000.0
reference = "sequence"

[[simulation.segments]]
kind = "slew"
axis = "z"
angle_deg = 30.0
duration_s = 600.0

[[simulation.segments]]
kind = "hold"
duration_s = 100.0

[[simulation.segments]]
kind = "track"
frame = "lvlh"
blend_s = 500.0
"""


def short_problem(folder: Path, base: str, duration_s: float) -> Path:
    """A shipped problem (``"paper_slew"``, ``"gallery/one_array"``) run for ``duration_s``
    seconds, written into ``folder``."""
    name = f"short_{Path(base).name}"
    path = folder / f"{name}.toml"
    path.write_text(
        f'extends = "{PROBLEMS / base}.toml"\nname = "{name}"\n'
        f"[simulation]\nduration_s = {duration_s}\n"
    )
    return path


def files_written(folder: Path) -> list[str]:
    """Every file below ``folder`` but the marker (which lists them), as relative paths."""
    return sorted(
        p.relative_to(folder).as_posix()
        for p in folder.rglob("*")
        if p.is_file() and p.name != MARKER_NAME
    )
