"""What every example shares: where it writes, and whether it runs quick.

``CASADI_DEBRIS_EXAMPLES_QUICK=1`` runs each example with its quickest settings (the
tests and CI do); ``CASADI_DEBRIS_EXAMPLES_OUT`` is the folder the examples write into
(default ``runs/examples``). Nothing else is read from the environment.
"""

from __future__ import annotations

import os
from pathlib import Path

QUICK = os.environ.get("CASADI_DEBRIS_EXAMPLES_QUICK", "") not in ("", "0")
OUT = Path(os.environ.get("CASADI_DEBRIS_EXAMPLES_OUT", "runs/examples"))


def folder(name: str) -> Path:
    """The example's own output folder (created)."""
    path = OUT / name
    path.mkdir(parents=True, exist_ok=True)
    return path
