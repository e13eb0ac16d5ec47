"""What the closed loop is asked to follow, derived from the problem's ``[simulation]``.

- :func:`scenario_reference`: the reference of a problem at its control instants (a
  hold, its one slew, or its sequence of segments), as a :class:`Reference`;
  :func:`sample_reference`: a slew profile sampled at given instants.
- :func:`generate_slew`, :func:`solve_slew`: the slew a ``[simulation.slew]`` asks for.
- :func:`manoeuvre_reference`, :func:`sequence_pieces`: a sequence of slews, holds,
  LVLH tracks and burns (:class:`Piece`, :class:`SegmentPlanSummary`).
- :func:`frame_attitude`, :func:`track_attitudes`, :func:`body_rates`: frame targets.
- :class:`BurnPlan` (:func:`plan_burn`, from a :class:`~casadi_debris.config.BurnRequest`),
  :func:`burn_windows`, :func:`burn_thrust_N`: orbit-raising burns.

Nothing here closes a loop or integrates the model (that is
:mod:`casadi_debris.simulation`).
"""

from casadi_debris.guidance._burn_plan import (
    BurnPlan,
    BurnWindow,
    attitude_limits,
    burn_limits,
    burn_offset,
    burn_thrust_N,
    burn_windows,
    direction_inertial,
    engine_limits_along,
    plan_burn,
    strongest_axis,
    torque_free_thrust_N,
)
from casadi_debris.guidance._reference import (
    Reference,
    control_instants,
    sample_reference,
    scenario_reference,
)
from casadi_debris.guidance._sequence import (
    ManoeuvreReference,
    ManoeuvreSummary,
    Piece,
    SegmentPlanSummary,
    manoeuvre_reference,
    sample_pieces,
    segment_records,
    sequence_pieces,
)
from casadi_debris.guidance._slew import generate_slew, slew_quaternions, solve_slew
from casadi_debris.guidance._targets import (
    blend,
    body_rates,
    continuous_sign,
    frame_attitude,
    lvlh_matrices,
    smoothstep,
    smoothstep_integral,
    track_attitudes,
)

__all__ = [
    "BurnPlan",
    "BurnWindow",
    "ManoeuvreReference",
    "ManoeuvreSummary",
    "Piece",
    "Reference",
    "SegmentPlanSummary",
    "attitude_limits",
    "blend",
    "body_rates",
    "burn_limits",
    "burn_offset",
    "burn_thrust_N",
    "burn_windows",
    "continuous_sign",
    "control_instants",
    "direction_inertial",
    "engine_limits_along",
    "frame_attitude",
    "generate_slew",
    "lvlh_matrices",
    "manoeuvre_reference",
    "plan_burn",
    "sample_pieces",
    "sample_reference",
    "scenario_reference",
    "segment_records",
    "sequence_pieces",
    "slew_quaternions",
    "smoothstep",
    "smoothstep_integral",
    "solve_slew",
    "strongest_axis",
    "torque_free_thrust_N",
    "track_attitudes",
]
