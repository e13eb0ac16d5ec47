"""The figures of one closed-loop run, as a typed record (:class:`RunSummary`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.records import Record
from casadi_debris.units import ARCSEC_PER_RAD, MNM_PER_NM

if TYPE_CHECKING:
    from casadi_debris.simulation._run import ClosedLoopResult

# Settling: the error's largest component stays below this from then on.
SETTLE_BAND_ARCSEC = 60.0


@dataclass(frozen=True)
class EventSummary(Record):
    """A change of the engines during a run, as a user reads it (ids from 1).

    Attributes
    ----------
    time_s : float
    kind : {"stage_depleted", "stage_failed", "cubesat_failed", "engine_failed"}
    cubesat : int
        1-based.
    engine : int or None
        1-based among its CubeSat's engines, for a CubeSat with several.
    stage, next_stage : int or None
        1-based; ``next_stage`` None when the CubeSat has none left.
    stage_switch : bool
        Whether the stage that fires changed.
    event : str
        The event in words.
    """

    time_s: float
    kind: str
    cubesat: int
    engine: int | None
    stage: int | None
    next_stage: int | None
    stage_switch: bool
    event: str


@dataclass(frozen=True, kw_only=True)
class RunSummary(Record):
    """Figures of one closed-loop run, units in the names.

    Attributes
    ----------
    max_error_deg, max_error_arcsec : float
        Largest attitude error component over the run.
    max_error_per_axis_deg : tuple of 3 float
    final_error_arcsec : float
    settle_time_s : float or None
        From then on every error component stays inside ``settle_band_arcsec``;
        None when the run ends outside it.
    settle_band_arcsec : float
    fuel_kg, fuel_worst_cubesat_kg : float
    fuel_per_cubesat_kg : tuple of float, one per CubeSat (CubeSat 1 first)
    slew_start_s, slew_end_s, fuel_slew_kg : float or None
        The reference slew's window and the propellant burnt inside it; None
        without a slew.
    dv_used_m_s : float
        Rocket equation over the propellant burnt.
    torque_saturated_s : float
        Time the demand was scaled down.
    min_scale : float
        Smallest saturation factor (1: every demand met).
    max_torque_mNm, max_demand_mNm : tuple of 3 float
        Largest |component| of the applied torque and of the demand.
    stage_switches : int
    events : tuple of EventSummary
    allocation_residual_Nm, max_net_force_N : float
    allocation_point_solves : int
    duration_s, control_period_s : float
    steps : int
    parameters : dict of str to float
        Model parameters by name.
    wall_time_s : float
    compiled_step : bool or None
        Whether the control period ran as compiled C code (None: not recorded).
    noise_seed : int or None
        Seed of the sensors' and engines' noise (None: the ideal loop).
    max_estimation_error_arcsec : float or None
        Largest component of the attitude the controller was told minus the
        true one (None: the ideal loop, where it is the star tracker's lag).
    """

    max_error_deg: float
    max_error_arcsec: float
    max_error_per_axis_deg: tuple[float, ...]
    final_error_arcsec: float
    settle_time_s: float | None
    settle_band_arcsec: float
    fuel_kg: float
    fuel_per_cubesat_kg: tuple[float, ...]
    fuel_worst_cubesat_kg: float
    slew_start_s: float | None = None
    slew_end_s: float | None = None
    fuel_slew_kg: float | None = None
    dv_used_m_s: float
    torque_saturated_s: float
    min_scale: float
    max_torque_mNm: tuple[float, ...]
    max_demand_mNm: tuple[float, ...]
    stage_switches: int
    events: tuple[EventSummary, ...]
    allocation_residual_Nm: float
    max_net_force_N: float
    allocation_point_solves: int
    duration_s: float
    control_period_s: float
    steps: int
    parameters: dict[str, float]
    wall_time_s: float
    compiled_step: bool | None = None
    noise_seed: int | None = None
    max_estimation_error_arcsec: float | None = None


def settle_time_s(
    time_s: np.ndarray, error_rad: np.ndarray, band_rad: float = SETTLE_BAND_ARCSEC / ARCSEC_PER_RAD
) -> float | None:
    """First instant after which every error component stays inside ``band_rad``.

    None when the run ends outside the band.
    """
    outside = np.abs(error_rad).max(axis=1) > band_rad
    if outside[-1]:
        return None
    if not outside.any():
        return 0.0
    return float(time_s[np.flatnonzero(outside)[-1] + 1])


def fuel_between_kg(result: ClosedLoopResult, start_s: float, end_s: float) -> float:
    """Propellant burnt in the steps starting in [``start_s``, ``end_s``) [kg], each
    engine at its own Isp."""
    inside = (result.time_s[:-1] >= start_s) & (result.time_s[:-1] < end_s)
    impulse_Ns = result.thrust_N[inside].sum(axis=0) * result.control_period_s
    return float(np.sum(impulse_Ns / result.propulsion.exhaust_velocity_m_s))


def summarize(result: ClosedLoopResult) -> RunSummary:
    """The figures of ``result``."""
    fuel = result.fuel_per_cubesat_kg
    fuel_kg = float(fuel.sum())
    max_error = float(np.abs(result.error_rad).max())
    start, end = result.slew_window_s if result.slew_window_s is not None else (None, None)
    mass_kg = result.total_mass_kg
    return RunSummary(
        max_error_deg=math.degrees(max_error),
        max_error_arcsec=max_error * ARCSEC_PER_RAD,
        max_error_per_axis_deg=tuple(np.degrees(np.abs(result.error_rad).max(axis=0))),
        final_error_arcsec=float(np.abs(result.error_rad[-1]).max() * ARCSEC_PER_RAD),
        settle_time_s=settle_time_s(result.time_s, result.error_rad),
        settle_band_arcsec=SETTLE_BAND_ARCSEC,
        fuel_kg=fuel_kg,
        fuel_per_cubesat_kg=tuple(fuel),
        fuel_worst_cubesat_kg=float(fuel.max()),
        slew_start_s=start,
        slew_end_s=end,
        fuel_slew_kg=None if start is None or end is None else fuel_between_kg(result, start, end),
        dv_used_m_s=result.exhaust_velocity_m_s * math.log(mass_kg / (mass_kg - fuel_kg)),
        torque_saturated_s=float(np.sum(result.scale < 1.0) * result.control_period_s),
        min_scale=float(result.scale.min()) if len(result.scale) else 1.0,
        max_torque_mNm=tuple(np.abs(result.torque_Nm).max(axis=0) * MNM_PER_NM),
        max_demand_mNm=tuple(np.abs(result.demand_Nm).max(axis=0) * MNM_PER_NM),
        stage_switches=sum(event.switched for event in result.events),
        events=tuple(event.record() for event in result.events),
        allocation_residual_Nm=result.allocation_residual_Nm,
        max_net_force_N=float(np.abs(result.force_N).max()) if len(result.force_N) else 0.0,
        allocation_point_solves=result.point_solves,
        duration_s=float(result.time_s[-1]),
        control_period_s=result.control_period_s,
        steps=len(result.scale),
        parameters=dict(result.parameters),
        wall_time_s=result.wall_time_s,
        compiled_step=result.compiled_step,
        noise_seed=result.noise_seed,
        max_estimation_error_arcsec=None
        if result.noise_seed is None or not len(result.scale)
        else float(np.abs(result.estimation_error_rad).max() * ARCSEC_PER_RAD),
    )
