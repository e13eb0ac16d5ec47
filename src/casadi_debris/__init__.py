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
    from casadi_debris.workflows.allocate import AllocationResult, allocate
    from casadi_debris.workflows.alternatives import AlternativesResult, alternatives
    from casadi_debris.workflows.budget import BudgetResult, budget
    from casadi_debris.workflows.burn import BurnResult, burn
    from casadi_debris.workflows.compare import CompareResult, compare
    from casadi_debris.workflows.deorbit import DeorbitResult, deorbit
    from casadi_debris.workflows.design import DesignResult, design
    from casadi_debris.workflows.detumble import DetumbleResult, detumble
    from casadi_debris.workflows.failures import FailuresResult, failures
    from casadi_debris.workflows.margins import MarginsResult, margins
    from casadi_debris.workflows.mission import MissionResult, mission
    from casadi_debris.workflows.model import ModelResult, model
    from casadi_debris.workflows.montecarlo import MonteCarloResult, montecarlo
    from casadi_debris.workflows.placement import PlacementResult, placement
    from casadi_debris.workflows.reproduce import ReproductionResult, reproduce
    from casadi_debris.workflows.simulate import SimulationResult, simulate
    from casadi_debris.workflows.slew import SlewResult, SlewSummary, slew
    from casadi_debris.workflows.synthesize import SynthesisResult, synthesize
    from casadi_debris.workflows.transfer import TransferResult, transfer
    from casadi_debris.workflows.worstcase import WorstCaseResult, worstcase

# Name -> the module that defines it, imported on first use.
_LAZY = {
    "AllocationResult": "casadi_debris.workflows.allocate",
    "allocate": "casadi_debris.workflows.allocate",
    "AlternativesResult": "casadi_debris.workflows.alternatives",
    "alternatives": "casadi_debris.workflows.alternatives",
    "BudgetResult": "casadi_debris.workflows.budget",
    "budget": "casadi_debris.workflows.budget",
    "BurnResult": "casadi_debris.workflows.burn",
    "burn": "casadi_debris.workflows.burn",
    "CompareResult": "casadi_debris.workflows.compare",
    "compare": "casadi_debris.workflows.compare",
    "DeorbitResult": "casadi_debris.workflows.deorbit",
    "deorbit": "casadi_debris.workflows.deorbit",
    "DesignResult": "casadi_debris.workflows.design",
    "design": "casadi_debris.workflows.design",
    "DetumbleResult": "casadi_debris.workflows.detumble",
    "detumble": "casadi_debris.workflows.detumble",
    "FailuresResult": "casadi_debris.workflows.failures",
    "failures": "casadi_debris.workflows.failures",
    "MarginsResult": "casadi_debris.workflows.margins",
    "margins": "casadi_debris.workflows.margins",
    "MissionResult": "casadi_debris.workflows.mission",
    "mission": "casadi_debris.workflows.mission",
    "ModelResult": "casadi_debris.workflows.model",
    "model": "casadi_debris.workflows.model",
    "MonteCarloResult": "casadi_debris.workflows.montecarlo",
    "montecarlo": "casadi_debris.workflows.montecarlo",
    "PlacementResult": "casadi_debris.workflows.placement",
    "placement": "casadi_debris.workflows.placement",
    "ReproductionResult": "casadi_debris.workflows.reproduce",
    "reproduce": "casadi_debris.workflows.reproduce",
    "SimulationResult": "casadi_debris.workflows.simulate",
    "simulate": "casadi_debris.workflows.simulate",
    "SlewResult": "casadi_debris.workflows.slew",
    "SlewSummary": "casadi_debris.workflows.slew",
    "slew": "casadi_debris.workflows.slew",
    "SynthesisResult": "casadi_debris.workflows.synthesize",
    "synthesize": "casadi_debris.workflows.synthesize",
    "TransferResult": "casadi_debris.workflows.transfer",
    "transfer": "casadi_debris.workflows.transfer",
    "WorstCaseResult": "casadi_debris.workflows.worstcase",
    "worstcase": "casadi_debris.workflows.worstcase",
}

__all__ = [
    "AllocationResult",
    "AlternativesResult",
    "BudgetResult",
    "BurnResult",
    "CasadiDebrisError",
    "CompareResult",
    "DeorbitResult",
    "DesignResult",
    "DetumbleResult",
    "FailuresResult",
    "MarginsResult",
    "MissionResult",
    "ModelResult",
    "MonteCarloResult",
    "PlacementResult",
    "Problem",
    "ProblemFileError",
    "ReproductionResult",
    "SimulationResult",
    "SlewResult",
    "SlewSummary",
    "SynthesisResult",
    "TransferResult",
    "WorstCaseResult",
    "__version__",
    "allocate",
    "alternatives",
    "budget",
    "burn",
    "compare",
    "deorbit",
    "design",
    "detumble",
    "failures",
    "load_problem",
    "margins",
    "mission",
    "model",
    "montecarlo",
    "placement",
    "reproduce",
    "simulate",
    "slew",
    "synthesize",
    "transfer",
    "worstcase",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'casadi_debris' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
