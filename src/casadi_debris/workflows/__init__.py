"""The jobs users run, as documented Python functions; the command line only adapts them.

- :func:`~casadi_debris.workflows._controller.load_controller`: a controller file.
- :func:`~casadi_debris.workflows._montecarlo.montecarlo`: a Monte-Carlo
  campaign written (and resumed) case by case into a folder.
- :func:`~casadi_debris.workflows._reproduce.reproduce`: the paper end to end.
- :func:`~casadi_debris.workflows._compare.compare`: fuel budgets side by side.

Nothing here prints: progress goes to the callbacks a caller passes, messages
to :mod:`logging`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from casadi_debris._lazy import lazy_exports

if TYPE_CHECKING:
    from casadi_debris.workflows._allocate import (
        AllocationResult,
        allocate,
    )
    from casadi_debris.workflows._alternatives import (
        AlternativesResult,
        alternatives,
    )
    from casadi_debris.workflows._budget import (
        BudgetResult,
        budget,
    )
    from casadi_debris.workflows._burn import (
        BurnResult,
        burn,
    )
    from casadi_debris.workflows._campaign import (
        CaseSelection,
        SimulationSummary,
        check_scheduler_address,
        one_case,
    )
    from casadi_debris.workflows._compare import (
        CompareResult,
        compare,
    )
    from casadi_debris.workflows._controller import (
        controller_for,
        load_controller,
    )
    from casadi_debris.workflows._deorbit import (
        DeorbitResult,
        deorbit,
    )
    from casadi_debris.workflows._design import (
        SLEW_RUN_FACTOR,
        DesignMethod,
        DesignResult,
        binding_limits,
        design,
        verification_problems,
    )
    from casadi_debris.workflows._detumble import (
        DetumbleResult,
        detumble,
        momentum_bound_s,
    )
    from casadi_debris.workflows._export import (
        ExportResult,
        ExportSummary,
        FmuExportResult,
        export,
    )
    from casadi_debris.workflows._failures import (
        DEFAULT_CORNERS,
        FailuresResult,
        failures,
    )
    from casadi_debris.workflows._margins import (
        MarginsResult,
        margins,
    )
    from casadi_debris.workflows._mission import (
        MissionResult,
        mission,
    )
    from casadi_debris.workflows._model import (
        ModelResult,
        model,
    )
    from casadi_debris.workflows._montecarlo import (
        MonteCarloResult,
        montecarlo,
    )
    from casadi_debris.workflows._placement import (
        PlacementResult,
        placement,
    )
    from casadi_debris.workflows._reproduce import (
        QUICK,
        ReproductionResult,
        reproduce,
    )
    from casadi_debris.workflows._simulate import (
        SimulationResult,
        simulate,
    )
    from casadi_debris.workflows._slew import (
        SlewResult,
        SlewSummary,
        slew,
    )
    from casadi_debris.workflows._synthesize import (
        SynthesisResult,
        synthesize,
    )
    from casadi_debris.workflows._transfer import (
        TransferResult,
        transfer,
    )
    from casadi_debris.workflows._worstcase import (
        WorstCaseResult,
        worstcase,
    )

__all__ = [
    "DEFAULT_CORNERS",
    "QUICK",
    "SLEW_RUN_FACTOR",
    "AllocationResult",
    "AlternativesResult",
    "BudgetResult",
    "BurnResult",
    "CaseSelection",
    "CompareResult",
    "DeorbitResult",
    "DesignMethod",
    "DesignResult",
    "DetumbleResult",
    "ExportResult",
    "ExportSummary",
    "FailuresResult",
    "FmuExportResult",
    "MarginsResult",
    "MissionResult",
    "ModelResult",
    "MonteCarloResult",
    "PlacementResult",
    "ReproductionResult",
    "SimulationResult",
    "SimulationSummary",
    "SlewResult",
    "SlewSummary",
    "SynthesisResult",
    "TransferResult",
    "WorstCaseResult",
    "allocate",
    "alternatives",
    "binding_limits",
    "budget",
    "burn",
    "check_scheduler_address",
    "compare",
    "controller_for",
    "deorbit",
    "design",
    "detumble",
    "export",
    "failures",
    "load_controller",
    "margins",
    "mission",
    "model",
    "momentum_bound_s",
    "montecarlo",
    "one_case",
    "placement",
    "reproduce",
    "simulate",
    "slew",
    "synthesize",
    "transfer",
    "verification_problems",
    "worstcase",
]

# Imported on first use: the commands import this package for a few helpers, and the
# modules behind the rest bring in matplotlib, the studies and the simulation.
_LAZY = {
    "AllocationResult": "casadi_debris.workflows._allocate",
    "allocate": "casadi_debris.workflows._allocate",
    "AlternativesResult": "casadi_debris.workflows._alternatives",
    "alternatives": "casadi_debris.workflows._alternatives",
    "BudgetResult": "casadi_debris.workflows._budget",
    "budget": "casadi_debris.workflows._budget",
    "BurnResult": "casadi_debris.workflows._burn",
    "burn": "casadi_debris.workflows._burn",
    "CaseSelection": "casadi_debris.workflows._campaign",
    "one_case": "casadi_debris.workflows._campaign",
    "SimulationSummary": "casadi_debris.workflows._campaign",
    "check_scheduler_address": "casadi_debris.workflows._campaign",
    "CompareResult": "casadi_debris.workflows._compare",
    "compare": "casadi_debris.workflows._compare",
    "load_controller": "casadi_debris.workflows._controller",
    "controller_for": "casadi_debris.workflows._controller",
    "DeorbitResult": "casadi_debris.workflows._deorbit",
    "deorbit": "casadi_debris.workflows._deorbit",
    "DesignMethod": "casadi_debris.workflows._design",
    "SLEW_RUN_FACTOR": "casadi_debris.workflows._design",
    "verification_problems": "casadi_debris.workflows._design",
    "DesignResult": "casadi_debris.workflows._design",
    "design": "casadi_debris.workflows._design",
    "binding_limits": "casadi_debris.workflows._design",
    "DetumbleResult": "casadi_debris.workflows._detumble",
    "detumble": "casadi_debris.workflows._detumble",
    "momentum_bound_s": "casadi_debris.workflows._detumble",
    "ExportResult": "casadi_debris.workflows._export",
    "ExportSummary": "casadi_debris.workflows._export",
    "FmuExportResult": "casadi_debris.workflows._export",
    "export": "casadi_debris.workflows._export",
    "DEFAULT_CORNERS": "casadi_debris.workflows._failures",
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
    "QUICK": "casadi_debris.workflows._reproduce",
    "ReproductionResult": "casadi_debris.workflows._reproduce",
    "reproduce": "casadi_debris.workflows._reproduce",
    "SimulationResult": "casadi_debris.workflows._simulate",
    "simulate": "casadi_debris.workflows._simulate",
    "SlewSummary": "casadi_debris.workflows._slew",
    "SlewResult": "casadi_debris.workflows._slew",
    "slew": "casadi_debris.workflows._slew",
    "SynthesisResult": "casadi_debris.workflows._synthesize",
    "synthesize": "casadi_debris.workflows._synthesize",
    "TransferResult": "casadi_debris.workflows._transfer",
    "transfer": "casadi_debris.workflows._transfer",
    "WorstCaseResult": "casadi_debris.workflows._worstcase",
    "worstcase": "casadi_debris.workflows._worstcase",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)
