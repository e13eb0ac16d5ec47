"""Figures. The only package that imports matplotlib (headless Agg backend).

One private module per subject (slews, the closed loop, robustness, the mission, ...),
each figure function exported here, and what they share (``_style``): the paper's axis
colours, :func:`save_figure` (PNG and PDF) and :func:`limit_line`.
"""

from casadi_debris.plots._allocation import allocation_figure
from casadi_debris.plots._alternatives import alternatives_figure
from casadi_debris.plots._burn import burn_figure
from casadi_debris.plots._deorbit import decay_figure, lifetime_curve_figure
from casadi_debris.plots._detumble import detumble_figure
from casadi_debris.plots._failures import authority_loss_figure
from casadi_debris.plots._mission import altitude_figure, mission_figure
from casadi_debris.plots._placement import (
    VIEWS,
    array_outlines_corner_m,
    layout_figure,
    pareto_figure,
)
from casadi_debris.plots._robust import (
    loop_shapes_figure,
    margins_figure,
    mu_figure,
    uncertainty_weight_figure,
)
from casadi_debris.plots._simulation import closed_loop_figure, comparison_figure, thrust_figure
from casadi_debris.plots._slew import (
    manoeuvre_figure,
    plot_segment_series,
    plot_slew,
    plot_slew_comparison,
    slew_figure,
)
from casadi_debris.plots._statistics import plot_statistics, statistics_figure
from casadi_debris.plots._style import (
    AXIS_COLOURS,
    FIGURE_DPI,
    OFF_SCALE,
    STYLE,
    limit_line,
    save_figure,
)
from casadi_debris.plots._transfer import altitude_inclination, transfer_figure

__all__ = [
    "AXIS_COLOURS",
    "FIGURE_DPI",
    "OFF_SCALE",
    "STYLE",
    "VIEWS",
    "allocation_figure",
    "alternatives_figure",
    "altitude_figure",
    "altitude_inclination",
    "array_outlines_corner_m",
    "authority_loss_figure",
    "burn_figure",
    "closed_loop_figure",
    "comparison_figure",
    "decay_figure",
    "detumble_figure",
    "layout_figure",
    "lifetime_curve_figure",
    "limit_line",
    "loop_shapes_figure",
    "manoeuvre_figure",
    "margins_figure",
    "mission_figure",
    "mu_figure",
    "pareto_figure",
    "plot_segment_series",
    "plot_slew",
    "plot_slew_comparison",
    "plot_statistics",
    "save_figure",
    "slew_figure",
    "statistics_figure",
    "thrust_figure",
    "transfer_figure",
    "uncertainty_weight_figure",
]
