"""casadi_debris: attitude control of space debris with docked iESE CubeSats.

Every job of the command line is a function here, named like the command, taking a
problem (a :class:`Problem`, a problem file or a shipped name) and keyword settings:

>>> import casadi_debris as cd
>>> problem = cd.load_problem("paper_slew")
>>> run = cd.simulate(problem, duration_s=300.0)  # doctest: +SKIP
>>> run.summary.requirements_met  # doctest: +SKIP
True

The jobs are imported when first used, so that ``import casadi_debris`` stays quick.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from casadi_debris._version import __version__
from casadi_debris.config import Problem, load_problem
from casadi_debris.errors import CasadiDebrisError, ProblemFileError

if TYPE_CHECKING:
    from casadi_debris.workflows.alternatives import AlternativesResult, alternatives
    from casadi_debris.workflows.burn import BurnResult, burn
    from casadi_debris.workflows.deorbit import DeorbitResult, deorbit
    from casadi_debris.workflows.detumble import DetumbleResult, detumble
    from casadi_debris.workflows.mission import MissionResult, mission
    from casadi_debris.workflows.placement import PlacementResult, placement
    from casadi_debris.workflows.simulate import SimulationResult, simulate
    from casadi_debris.workflows.transfer import TransferResult, transfer

# Name -> the module that defines it, imported on first use.
_LAZY = {
    "alternatives": "casadi_debris.workflows.alternatives",
    "AlternativesResult": "casadi_debris.workflows.alternatives",
    "placement": "casadi_debris.workflows.placement",
    "PlacementResult": "casadi_debris.workflows.placement",
    "transfer": "casadi_debris.workflows.transfer",
    "TransferResult": "casadi_debris.workflows.transfer",
    "burn": "casadi_debris.workflows.burn",
    "BurnResult": "casadi_debris.workflows.burn",
    "detumble": "casadi_debris.workflows.detumble",
    "DetumbleResult": "casadi_debris.workflows.detumble",
    "mission": "casadi_debris.workflows.mission",
    "MissionResult": "casadi_debris.workflows.mission",
    "deorbit": "casadi_debris.workflows.deorbit",
    "DeorbitResult": "casadi_debris.workflows.deorbit",
    "simulate": "casadi_debris.workflows.simulate",
    "SimulationResult": "casadi_debris.workflows.simulate",
}

__all__ = [
    "AlternativesResult",
    "BurnResult",
    "CasadiDebrisError",
    "DeorbitResult",
    "DetumbleResult",
    "MissionResult",
    "PlacementResult",
    "Problem",
    "ProblemFileError",
    "SimulationResult",
    "TransferResult",
    "__version__",
    "alternatives",
    "burn",
    "deorbit",
    "detumble",
    "load_problem",
    "mission",
    "placement",
    "simulate",
    "transfer",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'casadi_debris' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
