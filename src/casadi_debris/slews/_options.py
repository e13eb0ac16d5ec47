"""Settings of the optimal slews: one frozen, validated :class:`OptimalSlewSettings`.

What a slew is asked to do (the target, the objective, the duration, the
authority) is a :class:`~casadi_debris.config.SlewRequest`; how it is modelled and
solved (rigid or flexible, torque or thruster level, how fine, how checked) is a
:class:`OptimalSlewSettings`, derived from the request
(:meth:`OptimalSlewSettings.for_request`) and shared by
:func:`~casadi_debris.slews._optimal.time_optimal_slew`,
:func:`~casadi_debris.slews._optimal.fuel_optimal_slew` and the pieces of the OCP.
"""

from __future__ import annotations

import dataclasses
import numbers
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from casadi_debris.errors import InputShapeError
from casadi_debris.slews._maneuver import check_positive, check_torque_fraction

if TYPE_CHECKING:
    from casadi_debris.config import SlewRequest

DEFAULT_RESIDUAL_ENERGY_FRACTION = 0.01
DEFAULT_SAMPLE_S = 1.0
FLEXIBLE_METHODS = ("ocp", "shaper")
DEFAULT_STARTS = 16


@dataclass(frozen=True)
class OptimalSlewSettings:
    """How an optimal slew is modelled, transcribed and checked.

    Every field is checked on construction; a bad one raises
    :class:`~casadi_debris.errors.InputShapeError` naming it.

    Attributes
    ----------
    flexible : bool
        Keep the array modes: the vibration energy left at the end is constrained to
        0.8 x max(``residual_energy_fraction`` x the rigid-limit bang-bang's, 1e-12 x
        the slew's peak kinetic energy) (:mod:`casadi_debris.slews._modal_window`).
    thrusters : bool
        Thrust per engine as the decision variable (0 <= f <= torque_fraction f_max).
    zero_net_force : bool
        Thruster level: the engines' net force is zero at every instant, as the
        closed loop's allocator keeps it, so the closed loop can fly the profile.
    torque_fraction : float
        Share of the torque authority usable in (0, 1]: of each per-axis limit at
        torque level, of each engine's thrust at thruster level.
    single_axis : bool
        Restrict the torque to the eigenaxis (the single-degree-of-freedom slew);
        torque level and time-optimal only.
    intervals : int, optional
        Collocation intervals (even, >= 2; default 40); a flexible slew adds its 32
        window intervals.
    residual_energy_fraction : float
        Flexible only: the reported limit on the vibration energy left, as a fraction
        of what the bang-bang at the rigid limit leaves (> 0).
    sample_s : float
        Output sample spacing, s (> 0; the control knots are added).
    check_vibration : bool
        Integrate the result on the full flexible model for the residual vibration.
    flexible_method : {"ocp", "shaper"}
        Flexible only: ``"ocp"`` solves with the modal states (falling back to the
        shaper, and saying so in ``settings["flexible_method"]``, if IPOPT fails);
        ``"shaper"`` passes the rigid optimum through a zero-vibration shaper.
    starts : int
        Time-optimal slews: how many initial guesses (>= 1; the first is the eigenaxis
        bang-bang, the others symmetry-breaking ones, :mod:`casadi_debris.slews._global_slew`).
        At thruster level the torque box is searched with as many, and the thruster
        NLP started from at most four (:mod:`casadi_debris.slews._thruster_search`).
    seed : int
        Seed of the random starts (>= 0), recorded in the settings.
    workers : int, optional
        Processes for the starts (>= 1); default two when there are at least four
        starts and two cores, in the main process only.
    refine : bool
        Refine the best start's switch times and verify them by integration.

    Examples
    --------
    >>> options = OptimalSlewSettings(thrusters=True, zero_net_force=True)
    >>> dataclasses.replace(options, torque_fraction=0.5).torque_fraction
    0.5
    """

    flexible: bool = False
    thrusters: bool = False
    zero_net_force: bool = False
    torque_fraction: float = 1.0
    single_axis: bool = False
    intervals: int | None = None
    residual_energy_fraction: float = DEFAULT_RESIDUAL_ENERGY_FRACTION
    sample_s: float = DEFAULT_SAMPLE_S
    check_vibration: bool = True
    flexible_method: str = "ocp"
    starts: int = DEFAULT_STARTS
    seed: int = 0
    workers: int | None = None
    refine: bool = True

    def __post_init__(self) -> None:
        check_torque_fraction(self.torque_fraction)
        check_positive("residual_energy_fraction", self.residual_energy_fraction)
        check_positive("sample_s", self.sample_s)
        intervals = self.intervals
        if intervals is not None and (intervals < 2 or intervals % 2):
            raise InputShapeError(f"intervals: must be an even number >= 2, got {intervals}")
        _check_count("starts", self.starts, 1)
        _check_count("seed", self.seed, 0)
        if self.workers is not None:
            _check_count("workers", self.workers, 1)
        if self.single_axis and self.thrusters:
            raise InputShapeError("single_axis applies to torque-level slews only")
        if self.zero_net_force and not self.thrusters:
            raise InputShapeError(
                "zero_net_force applies to thruster-level slews (a torque-level one has no force)"
            )
        if self.flexible_method not in FLEXIBLE_METHODS:
            raise InputShapeError(
                f"flexible_method: one of {', '.join(FLEXIBLE_METHODS)}, "
                f"got {self.flexible_method!r}"
            )

    @classmethod
    def for_request(
        cls,
        request: SlewRequest,
        *,
        sample_s: float = DEFAULT_SAMPLE_S,
        check_vibration: bool = True,
        starts: int | None = None,
        seed: int = 0,
        workers: int | None = None,
    ) -> OptimalSlewSettings:
        """How to solve ``request``: its model (rigid or flexible, torque or thruster level,
        zero net force, torque fraction) and the solver's choices given here.

        Parameters
        ----------
        request : SlewRequest
            What the slew does; its ``torque_fraction`` None is the whole authority.
        sample_s : float
            Output sample spacing [s].
        check_vibration : bool
            Integrate the result on the full flexible model for the residual vibration.
        starts : int, optional
            Initial guesses of a time-optimal slew (default ``DEFAULT_STARTS``).
        seed, workers : int
            See the attributes.
        """
        return cls(
            flexible=request.flexible,
            thrusters=request.thrusters,
            zero_net_force=request.zero_net_force,
            torque_fraction=1.0 if request.torque_fraction is None else request.torque_fraction,
            sample_s=sample_s,
            check_vibration=check_vibration,
            flexible_method=request.flexible_method,
            starts=DEFAULT_STARTS if starts is None else starts,
            seed=seed,
            workers=workers,
        )

    @classmethod
    def merged(
        cls, caller: str, options: OptimalSlewSettings | None, keywords: dict[str, Any]
    ) -> OptimalSlewSettings:
        """``options`` (or the defaults) with the fields given as keywords replaced.

        Parameters
        ----------
        caller : str
            The public function's name, for the message about an unknown keyword.
        options : OptimalSlewSettings, optional
        keywords : dict
            Field names of :class:`OptimalSlewSettings` and their values.

        Raises
        ------
        TypeError
            A keyword that is no field, worded as Python words it for a function.
        """
        known = {field.name for field in dataclasses.fields(cls)}
        for name in keywords:
            if name not in known:
                raise TypeError(f"{caller}() got an unexpected keyword argument {name!r}")
        return dataclasses.replace(cls() if options is None else options, **keywords)


def _check_count(name: str, value: int, least: int) -> None:
    """Raise unless ``value`` is an integer (not a bool) of at least ``least``, naming it."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < least:
        raise InputShapeError(f"{name}: must be an integer >= {least}, got {value!r}")
