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

from typing import TYPE_CHECKING

from casadi_debris._lazy import lazy_exports
from casadi_debris._version import __version__
from casadi_debris.config import Problem, load_problem
from casadi_debris.errors import CasadiDebrisError, ProblemFileError

if TYPE_CHECKING:
    from casadi_debris.workflows import (
        AllocationResult,
        AlternativesResult,
        BudgetResult,
        BurnResult,
        CompareResult,
        DeorbitResult,
        DesignResult,
        DetumbleResult,
        FailuresResult,
        MarginsResult,
        MissionResult,
        ModelResult,
        MonteCarloResult,
        PlacementResult,
        ReproductionResult,
        SimulationResult,
        SlewResult,
        SlewSummary,
        SynthesisResult,
        TransferResult,
        WorstCaseResult,
        allocate,
        alternatives,
        budget,
        burn,
        compare,
        deorbit,
        design,
        detumble,
        failures,
        margins,
        mission,
        model,
        montecarlo,
        placement,
        reproduce,
        simulate,
        slew,
        synthesize,
        transfer,
        worstcase,
    )

# Name -> the module that defines it, imported on first use.
_LAZY = {
    "AllocationResult": "casadi_debris.workflows._allocate",
    "allocate": "casadi_debris.workflows._allocate",
    "AlternativesResult": "casadi_debris.workflows._alternatives",
    "alternatives": "casadi_debris.workflows._alternatives",
    "BudgetResult": "casadi_debris.workflows._budget",
    "budget": "casadi_debris.workflows._budget",
    "BurnResult": "casadi_debris.workflows._burn",
    "burn": "casadi_debris.workflows._burn",
    "CompareResult": "casadi_debris.workflows._compare",
    "compare": "casadi_debris.workflows._compare",
    "DeorbitResult": "casadi_debris.workflows._deorbit",
    "deorbit": "casadi_debris.workflows._deorbit",
    "DesignResult": "casadi_debris.workflows._design",
    "design": "casadi_debris.workflows._design",
    "DetumbleResult": "casadi_debris.workflows._detumble",
    "detumble": "casadi_debris.workflows._detumble",
    "FailuresResult": "casadi_debris.workflows._failures",
    "failures": "casadi_debris.workflows._failures",
    "MarginsResult": "casadi_debris.workflows._margins",
    "margins": "casadi_debris.workflows._margins",
    "MissionResult": "casadi_debris.workflows._mission",
    "mission": "casadi_debris.workflows._mission",
    "ModelResult": "casadi_debris.workflows._model",
    "model": "casadi_debris.workflows._model",
    "MonteCarloResult": "casadi_debris.workflows._montecarlo",
    "montecarlo": "casadi_debris.workflows._montecarlo",
    "PlacementResult": "casadi_debris.workflows._placement",
    "placement": "casadi_debris.workflows._placement",
    "ReproductionResult": "casadi_debris.workflows._reproduce",
    "reproduce": "casadi_debris.workflows._reproduce",
    "SimulationResult": "casadi_debris.workflows._simulate",
    "simulate": "casadi_debris.workflows._simulate",
    "SlewResult": "casadi_debris.workflows._slew",
    "SlewSummary": "casadi_debris.workflows._slew",
    "slew": "casadi_debris.workflows._slew",
    "SynthesisResult": "casadi_debris.workflows._synthesize",
    "synthesize": "casadi_debris.workflows._synthesize",
    "TransferResult": "casadi_debris.workflows._transfer",
    "transfer": "casadi_debris.workflows._transfer",
    "WorstCaseResult": "casadi_debris.workflows._worstcase",
    "worstcase": "casadi_debris.workflows._worstcase",
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


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)
