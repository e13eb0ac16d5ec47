"""The engines the NMPC decides: their torque and force maps, limits and exhaust velocities."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from casadi_debris.allocation import PropulsionState
from casadi_debris.dynamics import Model
from casadi_debris.errors import InputShapeError, NoEngineError


@dataclass(frozen=True, eq=False)
class NmpcEngines:
    """Engines as the NMPC's decision variables, one column each.

    Parameters
    ----------
    torque_map : array_like, shape (3, n)
        Torque about the CoG per newton of each engine [N m / N], body frame.
    force_map : array_like, shape (3, n)
        Force on the body per newton [N / N].
    max_thrust_N : array_like, shape (n,)
        Upper limit of each engine [N] (its active stage's; 0 for a failed or spent one).
    min_thrust_N : array_like, shape (n,), optional
        Lower limit [N]; default 0 (an engine pushes one way). A negative one makes a
        two-way actuator, such as the torque box of a verification body.
    exhaust_velocity_m_s : float or array_like, shape (n,)
        Isp g0 of each engine [m/s]: the propellant term weights engine i by c_max / c_i.

    Raises
    ------
    InputShapeError
        A field of the wrong shape, not finite, or min > max, naming it.
    NoEngineError
        Every engine's limits are zero.
    """

    torque_map: np.ndarray
    force_map: np.ndarray
    max_thrust_N: np.ndarray
    min_thrust_N: np.ndarray | None = None
    exhaust_velocity_m_s: float | np.ndarray = 1.0

    def __post_init__(self) -> None:
        torque = _array("torque_map", self.torque_map)
        if torque.ndim != 2 or torque.shape[0] != 3 or torque.shape[1] == 0:
            raise InputShapeError(f"torque_map: expected shape (3, n), got {torque.shape}")
        n = torque.shape[1]
        force = _array("force_map", self.force_map)
        if force.shape != (3, n):
            raise InputShapeError(f"force_map: expected shape (3, {n}), got {force.shape}")
        upper = _array("max_thrust_N", self.max_thrust_N)
        if upper.shape != (n,):
            raise InputShapeError(f"max_thrust_N: expected shape ({n},), got {upper.shape}")
        lower = (
            np.zeros(n) if self.min_thrust_N is None else _array("min_thrust_N", self.min_thrust_N)
        )
        if lower.shape != (n,):
            raise InputShapeError(f"min_thrust_N: expected shape ({n},), got {lower.shape}")
        if np.any(lower > upper):
            raise InputShapeError("min_thrust_N: must not exceed max_thrust_N")
        if not np.any((upper > 0) | (lower < 0)):
            raise NoEngineError("every engine has failed or is spent: no engine can fire")
        exhaust = np.broadcast_to(_array("exhaust_velocity_m_s", self.exhaust_velocity_m_s), (n,))
        if np.any(exhaust <= 0):
            raise InputShapeError("exhaust_velocity_m_s: must be > 0")
        object.__setattr__(self, "torque_map", torque)
        object.__setattr__(self, "force_map", force)
        object.__setattr__(self, "max_thrust_N", upper)
        object.__setattr__(self, "min_thrust_N", lower)
        object.__setattr__(self, "exhaust_velocity_m_s", exhaust.copy())

    @classmethod
    def from_model(cls, model: Model, state: PropulsionState | None = None) -> NmpcEngines:
        """The engines of a model's problem at their active stage.

        Parameters
        ----------
        model : Model
        state : PropulsionState, optional
            Active stages and failures; default every CubeSat on its first stage.
        """
        problem, geometry = model.problem, model.geometry
        if state is None:
            state = PropulsionState.from_problem(problem)
        g0 = problem.constants.standard_gravity_m_s2
        return cls(
            torque_map=geometry.torque_map,
            force_map=geometry.force_map,
            max_thrust_N=state.max_thrust_N(),
            exhaust_velocity_m_s=np.array([engine.isp_s * g0 for engine in problem.engines]),
        )

    @property
    def n_engines(self) -> int:
        """Number of engines (columns)."""
        return int(self.torque_map.shape[1])

    @property
    def lower_N(self) -> np.ndarray:
        """Lower limit per engine [N], shape (n,)."""
        assert self.min_thrust_N is not None  # set in __post_init__
        return self.min_thrust_N

    @property
    def fuel_weights(self) -> np.ndarray:
        """c_max / c_i per engine (1 for the best Isp), 0 for a two-way actuator, shape (n,)."""
        exhaust = np.asarray(self.exhaust_velocity_m_s)
        weights = float(exhaust.max()) / exhaust
        return np.where(self.lower_N < 0, 0.0, weights)

    def with_limits(
        self, max_thrust_N: npt.ArrayLike, min_thrust_N: npt.ArrayLike | None = None
    ) -> NmpcEngines:
        """The same engines with new limits (a stage change, a failure)."""
        return NmpcEngines(
            self.torque_map,
            self.force_map,
            np.asarray(max_thrust_N, dtype=float),
            self.lower_N if min_thrust_N is None else np.asarray(min_thrust_N, dtype=float),
            self.exhaust_velocity_m_s,
        )


def _array(name: str, value: object) -> np.ndarray:
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputShapeError(f"{name}: expected numbers, got {value!r}") from None
    if not np.all(np.isfinite(array)):
        raise InputShapeError(f"{name}: must be finite")
    return array
