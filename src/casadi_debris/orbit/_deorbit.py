"""The least Δv that brings the debris down within five years, and what it takes of the swarm.

For each solar-activity case (constant indices, :mod:`~casadi_debris.orbit._atmosphere`)
and each way of lowering the orbit,

- ``spiral``: retrograde thrust all the orbit round (the orbit stays circular
  and shrinks), or
- ``perigee``: retrograde thrust on arcs centred on apogee (burns near apogee
  lower the perigee; the arc is a trade between Δv, which favours short arcs,
  and burn duration, which counts against the five years),

the burn is flown with the swarm's torque-free thrust
(:mod:`~casadi_debris.orbit._propulsion`) and drag acting together, then the
debris decays. The time counted against the rule runs from the start of the
burn to re-entry (:mod:`~casadi_debris.orbit._lifetime`). The re-entry time
falls as the Δv grows, so the least Δv is a root (Brent) of
``reentry(dv) - limit``. A case needing more than the swarm carries is solved
as if the last thrust level went on: that Δv is what a larger swarm must give.

Drag area: while burning, the attitude is held with the firing direction
against the velocity (each direction its own area); after the burn the debris
is taken to tumble (the mean area), unless told to keep the attitude of the
strongest direction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError
from casadi_debris.geometry import build_geometry
from casadi_debris.orbit._atmosphere import (
    SolarActivity,
    density_table,
    log_interp,
    solar_case,
)
from casadi_debris.orbit._ballistic import Ballistic, ballistic
from casadi_debris.orbit._lifetime import (
    DecayHistory,
    DensityFunction,
    Earth,
    RetrogradeBurn,
    propagate_decay,
)
from casadi_debris.orbit._propulsion import SwarmThrust, swarm_thrust
from casadi_debris.records import Record
from casadi_debris.units import M_PER_KM, SECONDS_PER_DAY, SECONDS_PER_HOUR

FIVE_YEARS = 5.0
DV_TOLERANCE_M_S = 0.05
DV_SEARCH_MAX_M_S = 3000.0
STRATEGIES: dict[str, float] = {"spiral": 180.0, "perigee": 90.0, "perigee_narrow": 45.0}
"""Strategy name -> half-width of the thrust arc about apogee [deg] (180: all the orbit)."""


@dataclass(frozen=True)
class DeorbitSettings:
    """How the plan is made.

    Attributes
    ----------
    solar : tuple of str
        Solar-activity cases (``low``, ``mean``, ``high``).
    limit_years : float
        Re-entry within this long of the burn's start (the FCC's five years).
    strategies : tuple of str
        Keys of :data:`STRATEGIES` to try; the least Δv wins.
    drag_coefficient : float or None
        Default the problem's ``[environment] drag_coefficient``.
    tumbling : bool
        After the burn the debris tumbles (mean area); False: it is held with the
        strongest thrust direction against the velocity.
    horizon_years : float
        Lifetimes beyond this are reported as infinite (JSON null).
    minimum_swarm : bool
        Also search the fewest CubeSats that meet the limit (a bisection of plans).
    samples, seed : int
        Runs of the lifetime Monte Carlo of the governing plan (0: none) and its seed.
    workers : int
        Local worker processes of that Monte Carlo.
    """

    solar: tuple[str, ...] = ("low", "mean", "high")
    limit_years: float = FIVE_YEARS
    strategies: tuple[str, ...] = tuple(STRATEGIES)
    drag_coefficient: float | None = None
    tumbling: bool = True
    horizon_years: float = 200.0
    minimum_swarm: bool = True
    samples: int = 0
    seed: int = 20250103
    workers: int = 1

    def __post_init__(self) -> None:
        for name in self.solar:
            solar_case(name)
        if not self.solar:
            raise InputShapeError("solar: at least one case (low, mean, high)")
        unknown = [s for s in self.strategies if s not in STRATEGIES]
        if unknown or not self.strategies:
            raise InputShapeError(f"strategies: some of {', '.join(STRATEGIES)}, got {unknown}")
        if not (math.isfinite(self.limit_years) and self.limit_years > 0.0):
            raise InputShapeError(f"limit_years: a positive number, got {self.limit_years!r}")
        if not (math.isfinite(self.horizon_years) and self.horizon_years > self.limit_years):
            raise InputShapeError(
                f"horizon_years: a number above limit_years, got {self.horizon_years!r}"
            )
        if self.samples < 0 or self.workers < 1:
            raise InputShapeError(
                f"samples >= 0 and workers >= 1, got {self.samples} and {self.workers}"
            )


@dataclass(frozen=True)
class DeorbitCase(Record):
    """The plan under one solar-activity case.

    Attributes
    ----------
    solar : str
    f107_sfu, f107a_sfu, ap : float
        The indices NRLMSIS was given.
    natural_lifetime_years : float
        Without a burn (NaN/null beyond the horizon).
    strategy : str
        ``spiral`` or a ``perigee`` arc (see ``arc_half_width_deg``).
    arc_half_width_deg : float
    deorbit_dv_m_s : float
        Least Δv that re-enters within the limit (NaN/null if none below the search bound).
    within_capacity : bool
        The swarm carries that Δv (torque-free).
    flown_dv_m_s : float
        The Δv of the plan the swarm flies: the least one, or all it has.
    impulse_Ns, propellant_kg, firing_time_h : float
        Of the flown burn (engine-on time, directions one after another).
    burn_duration_days : float
        Calendar time of the flown burn (longer than the firing time on arcs).
    reentry_years : float
        Of the flown plan, from the burn's start.
    meets_five_year_rule : bool
        Re-entry of the flown plan within the limit.
    perigee_after_burn_km, apogee_after_burn_km : float
    stages_used : int
        Stages (over all engines) that fire at all.
    cubesats_used : int
    directions_used : int
        Body directions turned against the velocity, one after another.
    stages_per_cubesat : tuple of int
        CubeSat 1, 2, ...: stages begun (over its engines).
    """

    solar: str
    f107_sfu: float
    f107a_sfu: float
    ap: float
    natural_lifetime_years: float
    strategy: str
    arc_half_width_deg: float
    deorbit_dv_m_s: float
    within_capacity: bool
    flown_dv_m_s: float
    impulse_Ns: float
    propellant_kg: float
    firing_time_h: float
    burn_duration_days: float
    reentry_years: float
    meets_five_year_rule: bool
    perigee_after_burn_km: float
    apogee_after_burn_km: float
    stages_used: int
    cubesats_used: int
    directions_used: int
    stages_per_cubesat: tuple[int, ...]


@dataclass(frozen=True, eq=False)
class DeorbitModel:
    """Everything one re-entry time needs, built once for a problem.

    Attributes
    ----------
    problem : Problem
        The problem it was built for.
    earth : Earth
    semi_major_axis_m, inclination_rad : float
    decay : Ballistic
        Drag after the burn.
    burn_areas_m2 : tuple of float
        Drag area while each thrust segment fires.
    thrust : SwarmThrust
    """

    problem: Problem
    earth: Earth
    semi_major_axis_m: float
    inclination_rad: float
    decay: Ballistic
    burn_areas_m2: tuple[float, ...]
    thrust: SwarmThrust

    @classmethod
    def from_problem(
        cls,
        problem: Problem,
        settings: DeorbitSettings,
        *,
        thrust: SwarmThrust | None = None,
        mass_kg: float | None = None,
    ) -> DeorbitModel:
        """The model of ``problem``'s debris and swarm.

        ``thrust`` (default: the swarm with full tanks, :func:`swarm_thrust`) and
        ``mass_kg`` (default: the combined body's) describe a swarm that has already
        spent some of its propellant.
        """
        geometry = build_geometry(problem)
        thrust = thrust or swarm_thrust(problem, geometry)
        cd = settings.drag_coefficient
        # The debris flies against its push: the flow comes along -direction, body axes.
        held = [
            ballistic(
                problem,
                geometry=geometry,
                flow_body=-s.direction_body,
                drag_coefficient=cd,
                mass_kg=mass_kg,
            )
            for s in thrust.segments
        ]
        tumbling = ballistic(problem, geometry=geometry, drag_coefficient=cd, mass_kg=mass_kg)
        decay = tumbling if settings.tumbling else held[0]
        earth = Earth.from_problem(problem)
        return cls(
            problem=problem,
            earth=earth,
            semi_major_axis_m=earth.radius_m + problem.orbit.altitude_km * M_PER_KM,
            inclination_rad=math.radians(problem.orbit.inclination_deg),
            decay=decay,
            burn_areas_m2=tuple(b.area_m2 for b in held),
            thrust=thrust,
        )

    def density(self, activity: SolarActivity) -> DensityFunction:
        """The averaged NRLMSIS density at a constant activity."""
        table = density_table(
            round(math.degrees(self.inclination_rad), 3), radius_m=self.earth.radius_m
        )
        profile = table.profile(activity.f107_sfu)

        def rho(altitude_m: np.ndarray, time_s: float) -> np.ndarray:
            return np.exp(log_interp(table.altitudes_m, profile, np.maximum(altitude_m, 0.0)))

        return rho

    def impulse_for(self, dv_m_s: float) -> float:
        """Rocket equation: the impulse that gives ``dv_m_s`` to the whole body [N s]."""
        ve = self.thrust.exhaust_speed_m_s
        return self.decay.mass_kg * ve * (1.0 - math.exp(-dv_m_s / ve))

    def dv_for(self, impulse_Ns: float) -> float:
        """The inverse of :meth:`impulse_for` [m/s]."""
        ve = self.thrust.exhaust_speed_m_s
        return -ve * math.log(1.0 - impulse_Ns / (self.decay.mass_kg * ve))

    @property
    def capacity_dv_m_s(self) -> float:
        return self.dv_for(self.thrust.impulse_Ns)

    def fly(
        self,
        dv_m_s: float,
        density: DensityFunction,
        half_width_deg: float,
        horizon_years: float,
    ) -> DecayHistory:
        """Burn ``dv_m_s`` on the arc, then decay: the averaged orbit to re-entry."""
        segments = self.thrust.segments
        burn = RetrogradeBurn(
            thrust_N=tuple(s.thrust_N for s in segments),
            impulse_Ns=tuple(s.impulse_Ns for s in segments),
            target_impulse_Ns=self.impulse_for(dv_m_s),
            exhaust_speed_m_s=self.thrust.exhaust_speed_m_s,
            drag_area_m2=self.burn_areas_m2,
            half_width_rad=math.radians(half_width_deg),
        )
        return propagate_decay(
            self.semi_major_axis_m,
            0.0,
            self.decay.mass_kg,
            drag_area_m2=self.decay.area_m2,
            drag_coefficient=self.decay.drag_coefficient,
            density=density,
            earth=self.earth,
            inclination_rad=self.inclination_rad,
            burn=burn if dv_m_s > 0.0 else None,
            horizon_years=horizon_years,
        )


def least_dv_m_s(
    model: DeorbitModel,
    density: DensityFunction,
    half_width_deg: float,
    limit_years: float,
    horizon_years: float,
) -> float:
    """Least Δv re-entering within ``limit_years`` of the burn's start [m/s]; NaN if none
    up to :data:`DV_SEARCH_MAX_M_S`."""

    def late(dv: float) -> float:
        history = model.fly(dv, density, half_width_deg, horizon_years)
        years = min(history.reentry_years, horizon_years)
        return years - limit_years

    if late(0.0) <= 0.0:
        return 0.0
    low, high = 0.0, 25.0
    while late(high) > 0.0:
        low, high = high, 2.0 * high
        if high > DV_SEARCH_MAX_M_S:
            return math.nan
    dv = float(brentq(late, low, high, xtol=DV_TOLERANCE_M_S))
    # Brent's root may sit a hair on the late side: step to the side that meets the limit.
    while late(dv) > 0.0:
        dv += DV_TOLERANCE_M_S
    return dv


def best_strategy(
    model: DeorbitModel, density: DensityFunction, settings: DeorbitSettings
) -> tuple[float, str]:
    """The least Δv over the settings' strategies [m/s] and its strategy (NaN and the
    first strategy when none reaches the limit)."""
    options = {
        name: least_dv_m_s(
            model, density, STRATEGIES[name], settings.limit_years, settings.horizon_years
        )
        for name in settings.strategies
    }
    finite = {k: v for k, v in options.items() if math.isfinite(v)}
    if not finite:
        return math.nan, settings.strategies[0]
    best = min(finite, key=lambda k: finite[k])
    return finite[best], best


def plan_case(
    model: DeorbitModel, activity: SolarActivity, settings: DeorbitSettings
) -> DeorbitCase:
    """The least-Δv strategy under one solar case, and the plan the swarm can fly."""
    density = model.density(activity)
    natural = model.fly(0.0, density, 180.0, settings.horizon_years).reentry_years
    needed, strategy = best_strategy(model, density, settings)
    capacity = model.capacity_dv_m_s
    within = math.isfinite(needed) and needed <= capacity * (1.0 + 1e-9)
    flown = needed if within else capacity
    history = model.fly(flown, density, STRATEGIES[strategy], settings.horizon_years)
    return _case_record(model, activity, settings, natural, strategy, needed, flown, history)


def _case_record(
    model: DeorbitModel,
    activity: SolarActivity,
    settings: DeorbitSettings,
    natural: float,
    strategy: str,
    needed: float,
    flown: float,
    history: DecayHistory,
) -> DeorbitCase:
    impulse = model.impulse_for(flown)
    engines = model.thrust.engine_impulse(impulse)
    stages = np.ceil(engines / model.thrust.stage_impulse_Ns - 1e-9).astype(int)
    n_cubesats = int(model.thrust.engine_cubesat.max()) + 1
    per_cubesat = np.bincount(model.thrust.engine_cubesat, weights=stages, minlength=n_cubesats)
    end = int(np.searchsorted(history.time_s, history.burn_end_s))
    end = min(end, len(history.time_s) - 1)
    starts = np.cumsum([0.0, *(s.impulse_Ns for s in model.thrust.segments)])[:-1]
    used_directions = int(np.count_nonzero(starts < impulse - 1e-9))
    reentry = history.reentry_years
    return DeorbitCase(
        solar=activity.name,
        f107_sfu=activity.f107_sfu,
        f107a_sfu=activity.f107a_sfu,
        ap=activity.ap,
        natural_lifetime_years=natural,
        strategy="spiral" if STRATEGIES[strategy] >= 180.0 else "perigee",
        arc_half_width_deg=STRATEGIES[strategy],
        deorbit_dv_m_s=needed,
        within_capacity=bool(math.isfinite(needed) and flown >= needed - 1e-9),
        flown_dv_m_s=flown,
        impulse_Ns=impulse,
        propellant_kg=impulse / model.thrust.exhaust_speed_m_s,
        firing_time_h=model.thrust.firing_time_s(impulse) / SECONDS_PER_HOUR,
        burn_duration_days=history.burn_end_s / SECONDS_PER_DAY,
        reentry_years=reentry,
        meets_five_year_rule=bool(reentry <= settings.limit_years),
        perigee_after_burn_km=float(history.perigee_altitude_m[end]) / M_PER_KM,
        apogee_after_burn_km=float(history.apogee_altitude_m[end]) / M_PER_KM,
        stages_used=int(stages.sum()),
        cubesats_used=int(np.count_nonzero(per_cubesat)),
        directions_used=used_directions,
        stages_per_cubesat=tuple(int(s) for s in per_cubesat),
    )
