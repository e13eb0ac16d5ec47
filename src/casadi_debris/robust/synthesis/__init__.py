"""Controller synthesis: H-infinity, μ-synthesis (D-K iteration) on any generalised plant,
order reduction, the paper's design end to end, and classical controllers beside it.

- :func:`hinf_synthesis`: H-infinity synthesis by γ bisection, verified on the plant as
  given (:class:`HinfResult`).
- :func:`musyn`: D-K iteration on any generalised plant and block structure
  (:class:`MusynResult`, its :class:`Iteration` history); :func:`closed_loop_mu`.
- :func:`reduce_controller`: balanced truncation with a stable/unstable split.
- :func:`design_controller`: the problem's robust design, from sampled plants through
  the uncertainty weight and the D-K iteration to the reduced controller
  (:class:`SynthesisSettings`, :class:`ControllerDesign`); :func:`search_design`
  searches the best performance level a design can guarantee (:class:`DesignSearch`).
- :func:`parametric_musyn`: μ-synthesis against the real-parametric model, scored by
  the mixed (D-G) bound.
- :func:`pid_controller`, :func:`lqg_controller`, :func:`classical_record`: per-axis
  PD and LQG controllers to fly beside the μ design.
"""

from casadi_debris.robust.synthesis._classical import (
    CLASSICAL_METHODS,
    ClassicalMethod,
    classical_record,
    lqg_controller,
    pid_controller,
    rigid_axis,
)
from casadi_debris.robust.synthesis._design import (
    ControllerDesign,
    SynthesisSettings,
    SynthesisSummary,
    UncertaintyFit,
    design_controller,
    fit_uncertainty,
    weight_fit_grid,
)
from casadi_debris.robust.synthesis._hinf import HinfResult, hinf_synthesis, well_conditioned
from casadi_debris.robust.synthesis._musyn import (
    Iteration,
    MusynResult,
    closed_loop_mu,
    default_frequency_grid,
    dk_iteration,
    musyn,
)
from casadi_debris.robust.synthesis._parametric import (
    ParametricSynthesis,
    mixed_bound,
    parametric_musyn,
)
from casadi_debris.robust.synthesis._reduce import reduce_controller
from casadi_debris.robust.synthesis._search import (
    REFINEMENTS,
    DesignAttempt,
    DesignSearch,
    search_design,
)

__all__ = [
    "CLASSICAL_METHODS",
    "REFINEMENTS",
    "ClassicalMethod",
    "ControllerDesign",
    "DesignAttempt",
    "DesignSearch",
    "HinfResult",
    "Iteration",
    "MusynResult",
    "ParametricSynthesis",
    "SynthesisSettings",
    "SynthesisSummary",
    "UncertaintyFit",
    "classical_record",
    "closed_loop_mu",
    "default_frequency_grid",
    "design_controller",
    "dk_iteration",
    "fit_uncertainty",
    "hinf_synthesis",
    "lqg_controller",
    "mixed_bound",
    "musyn",
    "parametric_musyn",
    "pid_controller",
    "reduce_controller",
    "rigid_axis",
    "search_design",
    "weight_fit_grid",
    "well_conditioned",
]
