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
        ExportResult,
        FailuresResult,
        FmuExportResult,
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
        export,
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
    "ExportResult",
    "FailuresResult",
    "FmuExportResult",
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
    "export",
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


# The jobs and their results: every exported name not imported above, found in
# casadi_debris.workflows (which itself imports each job's module on first use).
_LAZY = {name: "casadi_debris.workflows" for name in __all__ if name not in globals()}
__getattr__, __dir__ = lazy_exports(__name__, _LAZY)
