"""Where the CubeSats should dock: the placement study.

:func:`optimise_placement` chooses, among candidate mounts on the hub faces
(:func:`face_candidates`), where N CubeSats dock so as to maximise the worst signed
axis's zero-net-force torque authority over the disturbance (optionally over all single
or double CubeSat failures), exactly, as a mixed-integer programme solved by HiGHS
(:func:`solve_placement`), and judges the chosen layout beside the problem's own
(:class:`PlacementStudy`). :func:`pareto_front` sweeps the count against authority,
rigid slew time and Δv; :func:`placement_summary` turns a study into the records a user
reads (:class:`PlacementSummary`, what ``casadi-debris placement`` writes).

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.studies.placement import PlacementSettings, optimise_placement
>>> study = optimise_placement(load_problem(), PlacementSettings(count=(24, 24)))
>>> round(study.metrics.worst_ratio, 2) >= round(study.input_layout.metrics.worst_ratio, 2)
True
"""

from casadi_debris.studies.placement._authority import (
    WorstFailures,
    layout_authority_Nm,
    worst_failures,
)
from casadi_debris.studies.placement._candidates import (
    DEFAULT_GRID,
    MAX_GRID,
    Candidate,
    CandidateSet,
    CubeSatTemplate,
    cubesat_template,
    face_candidates,
    parse_grid,
)
from casadi_debris.studies.placement._data import PlacementData, bare_debris, placement_data
from casadi_debris.studies.placement._metrics import (
    LayoutMetrics,
    direction_dv_m_s,
    layout_metrics,
    placed_problem,
    rigid_slew_times_s,
)
from casadi_debris.studies.placement._milp import (
    OBJECTIVES,
    MilpSolve,
    PlacementSettings,
    PlacementSolution,
    meets_limits,
    slew_rows,
    solve_placement,
)
from casadi_debris.studies.placement._pareto import (
    ParetoPoint,
    dominates,
    mark_front,
    pareto_front,
)
from casadi_debris.studies.placement._records import (
    CandidateSummary,
    ChosenCubeSat,
    InputLayoutSummary,
    LayoutSummary,
    MilpSolveSummary,
    ParetoPointSummary,
    PlacementLimits,
    PlacementSummary,
    SolverSummary,
    WorstFailureSummary,
    placement_summary,
)
from casadi_debris.studies.placement._study import (
    InputLayout,
    PlacementStudy,
    judge_input_layout,
    optimise_placement,
    own_candidates,
)

__all__ = [
    "DEFAULT_GRID",
    "MAX_GRID",
    "OBJECTIVES",
    "Candidate",
    "CandidateSet",
    "CandidateSummary",
    "ChosenCubeSat",
    "CubeSatTemplate",
    "InputLayout",
    "InputLayoutSummary",
    "LayoutMetrics",
    "LayoutSummary",
    "MilpSolve",
    "MilpSolveSummary",
    "ParetoPoint",
    "ParetoPointSummary",
    "PlacementData",
    "PlacementLimits",
    "PlacementSettings",
    "PlacementSolution",
    "PlacementStudy",
    "PlacementSummary",
    "SolverSummary",
    "WorstFailureSummary",
    "WorstFailures",
    "bare_debris",
    "cubesat_template",
    "direction_dv_m_s",
    "dominates",
    "face_candidates",
    "judge_input_layout",
    "layout_authority_Nm",
    "layout_metrics",
    "mark_front",
    "meets_limits",
    "optimise_placement",
    "own_candidates",
    "pareto_front",
    "parse_grid",
    "placed_problem",
    "placement_data",
    "placement_summary",
    "rigid_slew_times_s",
    "slew_rows",
    "solve_placement",
    "worst_failures",
]
