"""Margins of the attitude loop: loop-at-a-time and disk margins, nominal and over
sampled uncertain plants.

- :func:`loop_at_a_time` / :class:`LoopAtATime`: the gain, phase and delay margins of
  each loop broken at one plant input, the others closed (:class:`LoopMargins`);
  :func:`sampled_loop_at_a_time` over thousands of sampled plants, the controller's
  response computed once.
- :func:`disk_margins`: balanced disk margins of the full MIMO loop.
- :func:`margin_study`: the controller's margins on the nominal plant and over the
  problem's sampled plants (:class:`MarginStudy`), with :func:`margins_table` and the
  loop shapes (:func:`loop_shapes`) the report draws.
"""

from casadi_debris.robust.margins._loop import (
    CHANNELS,
    MARGIN_GRID,
    LoopAtATime,
    LoopMargins,
    closed_loop_matrix,
    closed_loop_poles,
    disk_margins,
    loop_at_a_time,
    loop_margins,
    return_ratio,
    return_ratios,
    sampled_loop_at_a_time,
)
from casadi_debris.robust.margins._study import (
    MarginStudy,
    loop_shapes,
    margin_study,
    margins_table,
)

__all__ = [
    "CHANNELS",
    "MARGIN_GRID",
    "LoopAtATime",
    "LoopMargins",
    "MarginStudy",
    "closed_loop_matrix",
    "closed_loop_poles",
    "disk_margins",
    "loop_at_a_time",
    "loop_margins",
    "loop_shapes",
    "margin_study",
    "margins_table",
    "return_ratio",
    "return_ratios",
    "sampled_loop_at_a_time",
]
