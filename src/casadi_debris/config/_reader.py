"""Validation of a parsed problem: :func:`problem_from_dict` and the smaller tables.

The debris and swarm tables are read in :mod:`~casadi_debris.config._bodies`,
the runs in :mod:`~casadi_debris.config._runs`; the checks across tables (the
propellant against the CubeSat's mass, the integration step against the
fastest dynamics) are made here once everything is read.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from casadi_debris.config import limits
from casadi_debris.config._bodies import (
    check_propellant,
    read_arrays,
    read_cubesats,
    read_engine_defaults,
    read_hub,
)
from casadi_debris.config._environment import read_environment, read_orbit
from casadi_debris.config._realism import read_realism
from casadi_debris.config._runs import check_integration_step, read_montecarlo, read_simulation
from casadi_debris.config._schema import (
    DEFAULT_MONTECARLO,
    DEFAULT_REQUIREMENTS,
    DEFAULT_SIMULATION,
    Constants,
    Detumble,
    Disturbance,
    Problem,
    Requirements,
    Sensor,
    Transfer,
    Uncertainty,
    Weights,
)
from casadi_debris.config._table import Table, show
from casadi_debris.config._varied import parse_path, resolve_vary, with_value, without_vary
from casadi_debris.errors import ProblemFileError


def _read_disturbance(t: Table) -> Disturbance:
    disturbance = Disturbance(
        amplitude_mNm=t.array("amplitude_mNm", (3,), limits.DISTURBANCE_MNM),
        period_min=t.number("period_min", limits.DISTURBANCE_PERIOD_MIN),
        phase_deg=t.array("phase_deg", (3,), limits.ANGLE_DEG),
    )
    t.done()
    return disturbance


def _read_uncertainty(t: Table) -> Uncertainty:
    uncertainty = Uncertainty(
        inertia_fraction=t.number("inertia_fraction", limits.FRACTION_BELOW_ONE),
        mass_fraction=t.number("mass_fraction", limits.FRACTION_BELOW_ONE),
        array_angle_deg=t.number("array_angle_deg", limits.UNCERTAINTY_ANGLE_DEG),
        bending_frequency_fraction=t.number(
            "bending_frequency_fraction", limits.FRACTION_BELOW_ONE
        ),
        samples=t.integer("samples", limits.UNCERTAINTY_SAMPLES),
        seed=t.integer("seed", limits.SEED),
        independent_array_angles=(
            t.boolean("independent_array_angles") if t.has("independent_array_angles") else False
        ),
    )
    t.done()
    return uncertainty


def _read_weights(t: Table) -> Weights:
    weights = Weights(
        closed_loop_bandwidth_rad_s=t.number("closed_loop_bandwidth_rad_s", limits.BANDWIDTH_RAD_S),
        epsilon=t.number("epsilon", limits.SMALL_GAIN),
        control_rolloff_rad_s=t.number("control_rolloff_rad_s", limits.BANDWIDTH_RAD_S),
        control_rolloff_high_frequency_gain=t.number(
            "control_rolloff_high_frequency_gain", limits.SMALL_GAIN
        ),
        error_scaling_deg=t.array("error_scaling_deg", (3,), limits.SCALING),
        control_scaling_mNm=t.array("control_scaling_mNm", (3,), limits.SCALING),
        disturbance_scaling_mNm=t.array("disturbance_scaling_mNm", (3,), limits.SCALING),
    )
    t.done()
    return weights


def _read_detumble(t: Table) -> Detumble:
    detumble = Detumble(t.array("initial_rate_rad_s", (3,), limits.RATE_RAD_S))
    t.done()
    return detumble


def _read_numbers(t: Table, cls: type, ranges: Mapping[str, limits.Range]) -> Any:
    """A dataclass of plain numbers, one range per field (in field order)."""
    value = cls(*(t.number(name, bounds) for name, bounds in ranges.items()))
    t.done()
    return value


SENSOR_RANGES = {"star_tracker_bandwidth_rad_s": limits.BANDWIDTH_RAD_S}
REQUIREMENTS_RANGES = {
    "pointing_arcsec": limits.POINTING_ARCSEC,
    "slew_error_deg": limits.SLEW_ERROR_DEG,
}
TRANSFER_RANGES = {
    "from_altitude_km": limits.ALTITUDE_KM,
    "from_inclination_deg": limits.INCLINATION_DEG,
    "to_altitude_km": limits.ALTITUDE_KM,
    "to_inclination_deg": limits.INCLINATION_DEG,
}
CONSTANTS_RANGES = {
    "earth_mu_km3_s2": limits.EARTH_MU_KM3_S2,
    "earth_radius_km": limits.EARTH_RADIUS_KM,
    "standard_gravity_m_s2": limits.STANDARD_GRAVITY_M_S2,
}


def _optional_table(top: Table, name: str, defaults: Mapping[str, Any]) -> Table:
    """The table ``name`` with missing keys taken from ``defaults`` (absent table: all)."""
    given = top.data.get(name, {})
    top.taken.add(name)
    if not isinstance(given, Mapping):
        raise top.error(top.key(name), f"must be a table, got {show(given)}")
    return Table({**defaults, **given}, top.key(name), top.source)


def _check_corner_count(top: Table, problem: Problem) -> None:
    """Independent array angles multiply the corner set: keep it a campaign one can run."""
    arrays = len(problem.arrays)
    if not (problem.uncertainty.independent_array_angles and arrays > 1):
        return
    count = problem.montecarlo.corner_array_angles**arrays * 2**5
    if count > limits.MAX_CORNER_CASES:
        raise top.error(
            "montecarlo.corner_array_angles",
            f"with independent angles for {arrays} arrays the corner set has "
            f"{problem.montecarlo.corner_array_angles}^{arrays} x 2^5 = {count} cases, at most "
            f"{limits.MAX_CORNER_CASES}; lower corner_array_angles",
        )


def _with_vary_resolved(top: Table, problem: Problem) -> Problem:
    """Check ``[[montecarlo.vary]]`` against the problem just read (see config.varied)."""
    if not problem.montecarlo.vary:
        return problem
    vary = resolve_vary(Table({}, "montecarlo", top.source), problem, problem_from_dict)
    return replace(problem, montecarlo=replace(problem.montecarlo, vary=vary))


def problem_from_dict(
    data: Mapping[str, Any], source: str | None = None, sha256: str = ""
) -> Problem:
    """Validate a parsed problem (as from TOML) and return it frozen.

    Every number must lie in its range of :mod:`~casadi_debris.config.limits`;
    the tables must also agree with each other (propellant below the
    CubeSat's mass, integration step against the fastest dynamics).

    Parameters
    ----------
    data : mapping
        The problem's tables, as :func:`tomllib.load` returns them.
    source : str, optional
        Where it came from, for messages.
    sha256 : str, optional
        Hash of the file's bytes, recorded with results.

    Raises
    ------
    ProblemFileError
        Naming the first offending key.
    """
    top = Table(data, "", source)
    name = top.label("name")
    description = top.prose("description")
    hub = read_hub(top.table("hub"))
    arrays = read_arrays(top, hub.size_m)
    engine = read_engine_defaults(top.table("engine"))
    cubesats, layout = read_cubesats(top, hub.size_m, engine)
    sensor: Sensor = _read_numbers(top.table("sensor"), Sensor, SENSOR_RANGES)
    constants = _read_numbers(top.table("constants"), Constants, CONSTANTS_RANGES)
    check_propellant(top, cubesats, layout, constants.standard_gravity_m_s2)
    simulation_table = _optional_table(top, "simulation", DEFAULT_SIMULATION)
    simulation = read_simulation(
        simulation_table,
        engines_per_cubesat=[len(c.engines) for c in cubesats],
        n_stages=max(e.stages for c in cubesats for e in c.engines),
    )
    fast_rates = {"sensor.star_tracker_bandwidth_rad_s": sensor.star_tracker_bandwidth_rad_s}
    for a, array in enumerate(arrays):
        for i, mode in enumerate(array.modes):
            fast_rates[f"arrays[{a}].modes[{i}].omega_rad_s"] = mode.omega_rad_s
    check_integration_step(simulation_table, simulation, fast_rates)
    problem = Problem(
        name=name,
        description=description,
        hub=hub,
        arrays=arrays,
        cubesats=cubesats,
        cubesat_layout=layout,
        engine=engine,
        requirements=_read_numbers(
            _optional_table(top, "requirements", DEFAULT_REQUIREMENTS),
            Requirements,
            REQUIREMENTS_RANGES,
        ),
        disturbance=_read_disturbance(top.table("disturbance")),
        sensor=sensor,
        uncertainty=_read_uncertainty(top.table("uncertainty")),
        weights=_read_weights(top.table("weights")),
        orbit=read_orbit(top.table("orbit")),
        transfer=_read_numbers(top.table("transfer"), Transfer, TRANSFER_RANGES),
        detumble=_read_detumble(top.table("detumble")),
        constants=constants,
        simulation=simulation,
        montecarlo=read_montecarlo(_optional_table(top, "montecarlo", DEFAULT_MONTECARLO)),
        environment=read_environment(top),
        **read_realism(top),
        source=source or "<dict>",
        sha256=sha256,
        data=data,
    )
    _check_corner_count(top, problem)
    problem = _with_vary_resolved(top, problem)
    if "extends" in data:  # followed by the loader, which checked it
        top.record("extends", kind="text", choices=None)
        top.taken.add("extends")
    top.done()
    return problem


def problem_with_values(problem: Problem, values: Sequence[tuple[str, float]]) -> Problem:
    """``problem`` read again with the file keys of ``values`` set (the case of a campaign).

    The name, description, run (``[simulation]``, unless a key of it varies), the
    campaign settings and the hash of the file are ``problem``'s own; every other
    part comes from the problem read again, so that what derives from a key (the
    CubeSats a layout places, the checks across tables) follows it.

    Parameters
    ----------
    problem : Problem
        Read from a file or :func:`~casadi_debris.config.problem_from_dict` (with ``data``).
    values : sequence of (str, float)
        Dotted key (see :func:`parse_path`) and value, in the key's unit.

    Raises
    ------
    ProblemFileError
        A value the readers refuse, naming the key.
    """
    if not values:
        return problem
    data = without_vary(problem.data)
    for path, value in values:
        try:
            data = with_value(data, parse_path(path), float(value))
        except ValueError as exc:
            raise ProblemFileError(path, str(exc), problem.source) from None
    rebuilt = problem_from_dict(data, problem.source, problem.sha256)
    keep_run = not any(path.startswith("simulation") for path, _ in values)
    return dataclasses.replace(
        rebuilt,
        name=problem.name,
        description=problem.description,
        simulation=problem.simulation if keep_run else rebuilt.simulation,
        montecarlo=problem.montecarlo,
        data=problem.data,
    )
