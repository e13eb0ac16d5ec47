"""What a closed-loop run gives: :class:`ClosedLoopResult` (time series and figures, SI)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from casadi_debris.allocation import PropulsionState
from casadi_debris.simulation._events import RunEvent
from casadi_debris.simulation._summary import (
    SETTLE_BAND_ARCSEC,
    RunSummary,
    settle_time_s,
    summarize,
)
from casadi_debris.units import ARCSEC_PER_RAD


@dataclass(eq=False)
class ClosedLoopResult:
    """Time series and figures of one closed-loop run (SI units).

    Attributes
    ----------
    time_s : ndarray, shape (n + 1,)
        Control instants, 0 .. duration.
    state : ndarray, shape (n + 1, n_x)
        Plant state (model layout) at each instant.
    rate_rad_s : ndarray, shape (n + 1, 3)
        Body rate omega_BN in B.
    reference_BN : ndarray, shape (n + 1, 4)
    error_rad : ndarray, shape (n + 1, 3)
        True attitude minus reference (doubled error-quaternion vector).
    measured_error_rad : ndarray, shape (n, 3)
        What the star tracker told the controller at each step.
    demand_Nm, torque_Nm : ndarray, shape (n, 3)
        Controller demand, and the allocator's torque ``B f`` held over each step.
    force_N : ndarray, shape (n, 3)
        Net force of the thrust (zero to round-off).
    scale : ndarray, shape (n,)
        Saturation factor alpha (1: demand met).
    thrust_N : ndarray, shape (n, n_engines)
    disturbance_Nm : ndarray, shape (n, 3)
        At the start of each step.
    propulsion : PropulsionState
        At the end.
    events : list of RunEvent
        Failures and depleted stages, in time order.
    parameters : dict
        Model parameters by name.
    control_period_s : float
    allocation_residual_Nm : float
        Largest |B f - applied torque| over the run.
    point_solves : int
        QP solves the allocator needed (the rest reused active sets).
    wall_time_s : float
    slew_window_s : (float, float) or None
        Start and end of the reference slew [s].
    compiled_step : bool or None
        Whether the control period ran as compiled C code.
    authority_time_s : ndarray, shape (m,)
        When the torque authority took each of its values: the start, and each
        failure or depleted stage after which the loop was rebuilt [s].
    authority_Nm : ndarray, shape (m, 6)
        Largest pure torque at zero net force about +x, -x, +y, -y, +z, -z
        (magnitudes) from each of those instants on [N m].
    noise_seed : int or None
        Seed of the sensors' and engines' noise (None: the ideal loop, no noise).
    """

    time_s: np.ndarray
    state: np.ndarray
    rate_rad_s: np.ndarray
    reference_BN: np.ndarray
    error_rad: np.ndarray
    measured_error_rad: np.ndarray
    demand_Nm: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    scale: np.ndarray
    thrust_N: np.ndarray
    disturbance_Nm: np.ndarray
    propulsion: PropulsionState
    fuel_start_kg: np.ndarray
    events: list[RunEvent]
    parameters: dict[str, float]
    control_period_s: float
    total_mass_kg: float
    allocation_residual_Nm: float
    point_solves: int
    wall_time_s: float
    slew_window_s: tuple[float, float] | None = None
    compiled_step: bool | None = None
    authority_time_s: np.ndarray = field(default_factory=lambda: np.zeros(0))
    authority_Nm: np.ndarray = field(default_factory=lambda: np.zeros((0, 6)))
    noise_seed: int | None = None

    @property
    def fuel_per_cubesat_kg(self) -> np.ndarray:
        """Propellant burnt by each CubeSat during the run, shape (n_cubesats,) [kg]."""
        return self.propulsion.per_cubesat(self.fuel_per_engine_kg)

    @property
    def fuel_per_engine_kg(self) -> np.ndarray:
        """Propellant burnt by each engine during the run, shape (n_engines,) [kg]."""
        return (self.fuel_start_kg - self.propulsion.propellant_kg).sum(axis=1)

    @property
    def exhaust_velocity_m_s(self) -> float:
        """Effective exhaust velocity of the propellant burnt [m/s].

        The engines' one exhaust velocity when they share an Isp; otherwise the
        mean over the engines weighted by the propellant each burnt (total
        impulse over total propellant, the velocity the rocket equation takes
        for the run's Delta v), or their plain mean if nothing was burnt.
        """
        exhaust = self.propulsion.exhaust_velocity_m_s
        if np.all(exhaust == exhaust[0]):
            return float(exhaust[0])
        fuel = self.fuel_per_engine_kg
        if fuel.sum() <= 0.0:
            return float(np.mean(exhaust))
        return float(np.sum(fuel * exhaust) / fuel.sum())

    @property
    def estimation_error_rad(self) -> np.ndarray:
        """What the controller was told minus the truth, shape (n, 3) [rad]:
        ``measured_error_rad - error_rad`` at the start of each step."""
        return self.measured_error_rad - self.error_rad[:-1]

    def settle_time_s(self, band_rad: float = SETTLE_BAND_ARCSEC / ARCSEC_PER_RAD) -> float | None:
        """First instant after which every error component stays inside ``band_rad``.

        None when the run ends outside the band.
        """
        return settle_time_s(self.time_s, self.error_rad, band_rad)

    def summary(self) -> RunSummary:
        """Figures of the run, units in the names."""
        return summarize(self)
