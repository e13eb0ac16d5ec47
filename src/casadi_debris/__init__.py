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
    from casadi_debris.workflows.budget import BudgetResult, budget
    from casadi_debris.workflows.compare import CompareResult, compare
    from casadi_debris.workflows.design import DesignResult, design
    from casadi_debris.workflows.failures import FailuresResult, failures
    from casadi_debris.workflows.margins import MarginsResult, margins
    from casadi_debris.workflows.model import ModelResult, model
    from casadi_debris.workflows.montecarlo import MonteCarloResult, montecarlo
    from casadi_debris.workflows.reproduce import ReproductionResult, reproduce
    from casadi_debris.workflows.simulate import SimulationResult, simulate
    from casadi_debris.workflows.slew import SlewResult, SlewSummary, slew
    from casadi_debris.workflows.synthesize import SynthesisResult, synthesize
    from casadi_debris.workflows.worstcase import WorstCaseResult, worstcase

# Name -> the module that defines it, imported on first use.
_LAZY = {
    "allocate": "casadi_debris.workflows.allocate",
    "AllocationResult": "casadi_debris.workflows.allocate",
    "budget": "casadi_debris.workflows.budget",
    "BudgetResult": "casadi_debris.workflows.budget",
    "design": "casadi_debris.workflows.design",
    "DesignResult": "casadi_debris.workflows.design",
    "margins": "casadi_debris.workflows.margins",
    "MarginsResult": "casadi_debris.workflows.margins",
    "model": "casadi_debris.workflows.model",
    "ModelResult": "casadi_debris.workflows.model",
    "reproduce": "casadi_debris.workflows.reproduce",
    "ReproductionResult": "casadi_debris.workflows.reproduce",
    "simulate": "casadi_debris.workflows.simulate",
    "SimulationResult": "casadi_debris.workflows.simulate",
    "slew": "casadi_debris.workflows.slew",
    "SlewResult": "casadi_debris.workflows.slew",
    "SlewSummary": "casadi_debris.workflows.slew",
    "montecarlo": "casadi_debris.workflows.montecarlo",
    "MonteCarloResult": "casadi_debris.workflows.montecarlo",
    "worstcase": "casadi_debris.workflows.worstcase",
    "WorstCaseResult": "casadi_debris.workflows.worstcase",
    "failures": "casadi_debris.workflows.failures",
    "FailuresResult": "casadi_debris.workflows.failures",
    "compare": "casadi_debris.workflows.compare",
    "CompareResult": "casadi_debris.workflows.compare",
    "synthesize": "casadi_debris.workflows.synthesize",
    "SynthesisResult": "casadi_debris.workflows.synthesize",
}

__all__ = [
    "AllocationResult",
    "BudgetResult",
    "CasadiDebrisError",
    "CompareResult",
    "DesignResult",
    "FailuresResult",
    "MarginsResult",
    "ModelResult",
    "MonteCarloResult",
    "Problem",
    "ProblemFileError",
    "ReproductionResult",
    "SimulationResult",
    "SlewResult",
    "SlewSummary",
    "SynthesisResult",
    "WorstCaseResult",
    "__version__",
    "allocate",
    "budget",
    "compare",
    "design",
    "failures",
    "load_problem",
    "margins",
    "model",
    "montecarlo",
    "reproduce",
    "simulate",
    "slew",
    "synthesize",
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
