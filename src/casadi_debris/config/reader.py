"""Validation of a parsed problem: one reader per table, :func:`problem_from_dict` on top."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from casadi_debris.config.checks import check_inertia, check_on_face
from casadi_debris.config.schema import (
    AXIS_NAMES,
    DEFAULT_MONTECARLO,
    DEFAULT_SIMULATION,
    MODE_KINDS,
    REFERENCE_KINDS,
    SIGNED_AXES,
    SLEW_METHODS,
    Arrays,
    Constants,
    CubeSats,
    Detumble,
    Disturbance,
    Engine,
    FailureEvent,
    Hub,
    Mode,
    MonteCarlo,
    Orbit,
    Problem,
    Sensor,
    Simulation,
    SlewReference,
    Transfer,
    Uncertainty,
    Weights,
)
from casadi_debris.config.table import Table


def _read_hub(t: Table) -> Hub:
    size = t.array("size_m", (3,), positive=True)
    cog = t.array("cog_corner_m", (3,))
    if np.any(cog < 0) or np.any(cog > size):
        raise t.error(t.key("cog_corner_m"), f"must lie inside the hub (0 .. {list(size)} m)")
    inertia = t.array("inertia_kgm2", (3, 3))
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    hub = Hub(t.number("mass_kg", positive=True), size, cog, inertia)
    t.done()
    return hub


def _read_mode(t: Table) -> Mode:
    mode = Mode(
        name=t.text("name"),
        kind=t.text("kind", MODE_KINDS),
        order=t.integer("order", minimum=1),
        omega_rad_s=t.number("omega_rad_s", positive=True),
    )
    t.done()
    return mode


def _read_arrays(t: Table, hub_size: np.ndarray) -> Arrays:
    inertia = t.array("inertia_kgm2", (3,), positive=True)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    hinges = t.array("hinges_corner_m", (None, 3))
    directions = t.texts("directions", SIGNED_AXES)
    if len(directions) != len(hinges):
        raise t.error(
            t.key("directions"), f"needs one entry per hinge ({len(hinges)}), got {len(directions)}"
        )
    for i, (hinge, direction) in enumerate(zip(hinges, directions, strict=True)):
        check_on_face(t, f"hinges_corner_m[{i}]", hinge, direction, hub_size)
    modes = tuple(_read_mode(m) for m in t.tables("modes"))
    names = [m.name for m in modes]
    if len(set(names)) != len(names):
        raise t.error(t.key("modes"), f"mode names must be unique, got {names}")
    kinds_orders = [(m.kind, m.order) for m in modes]
    if len(set(kinds_orders)) != len(kinds_orders):
        raise t.error(t.key("modes"), "two modes have the same kind and order")
    if ("bending", 1) not in kinds_orders:
        raise t.error(t.key("modes"), "needs the first bending mode (kind bending, order 1)")
    arrays = Arrays(
        mass_kg=t.number("mass_kg", positive=True),
        length_m=t.number("length_m", positive=True),
        width_m=t.number("width_m", positive=True),
        inertia_kgm2=inertia,
        hinges_corner_m=hinges,
        directions=directions,
        angle_deg=t.number("angle_deg"),
        damping_ratio=t.number("damping_ratio", nonnegative=True, below=1.0),
        modes=modes,
    )
    t.done()
    return arrays


def _read_cubesats(t: Table) -> CubeSats:
    inertia = t.array("inertia_kgm2", (3,), positive=True)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    per_face = t.integer("per_face", minimum=1)
    if per_face != 4:
        raise t.error(t.key("per_face"), f"only the corner layout (4) is supported, got {per_face}")
    cubesats = CubeSats(
        per_face=per_face,
        mass_kg=t.number("mass_kg", positive=True),
        inertia_kgm2=inertia,
        edge_margin_fraction=t.number("edge_margin_fraction", nonnegative=True, below=1.0),
        standoff_m=t.number("standoff_m", nonnegative=True),
    )
    t.done()
    return cubesats


def _read_engine(t: Table) -> Engine:
    engine = Engine(
        stages=t.integer("stages", minimum=1),
        emitters_per_stage=t.integer("emitters_per_stage", minimum=1),
        thrust_per_stage_mN=t.number("thrust_per_stage_mN", positive=True),
        isp_s=t.number("isp_s", positive=True),
        stage_life_h=t.number("stage_life_h", positive=True),
    )
    t.done()
    return engine


def _read_disturbance(t: Table) -> Disturbance:
    disturbance = Disturbance(
        amplitude_mNm=t.array("amplitude_mNm", (3,), nonnegative=True),
        period_min=t.number("period_min", positive=True),
        phase_deg=t.array("phase_deg", (3,)),
    )
    t.done()
    return disturbance


def _read_sensor(t: Table) -> Sensor:
    sensor = Sensor(t.number("star_tracker_bandwidth_rad_s", positive=True))
    t.done()
    return sensor


def _read_uncertainty(t: Table) -> Uncertainty:
    uncertainty = Uncertainty(
        inertia_fraction=t.number("inertia_fraction", nonnegative=True, below=1.0),
        mass_fraction=t.number("mass_fraction", nonnegative=True, below=1.0),
        array_angle_deg=t.number("array_angle_deg", nonnegative=True, at_most=180.0),
        bending_frequency_fraction=t.number(
            "bending_frequency_fraction", nonnegative=True, below=1.0
        ),
        samples=t.integer("samples", minimum=1),
        seed=t.integer("seed", minimum=0),
    )
    t.done()
    return uncertainty


def _read_weights(t: Table) -> Weights:
    weights = Weights(
        closed_loop_bandwidth_rad_s=t.number("closed_loop_bandwidth_rad_s", positive=True),
        epsilon=t.number("epsilon", positive=True, below=1.0),
        control_rolloff_rad_s=t.number("control_rolloff_rad_s", positive=True),
        control_rolloff_high_frequency_gain=t.number(
            "control_rolloff_high_frequency_gain", positive=True, below=1.0
        ),
        error_scaling_deg=t.array("error_scaling_deg", (3,), positive=True),
        control_scaling_mNm=t.array("control_scaling_mNm", (3,), positive=True),
        disturbance_scaling_mNm=t.array("disturbance_scaling_mNm", (3,), positive=True),
    )
    t.done()
    return weights


def _read_slew(t: Table) -> SlewReference:
    axis = t.text("axis", AXIS_NAMES)
    slew = SlewReference(
        axis=axis,
        angle_deg=t.number("angle_deg", positive=True, at_most=180.0),
        method=t.text("method", SLEW_METHODS) if "method" in t.data else "bang-bang",
        start_s=t.number("start_s", nonnegative=True) if "start_s" in t.data else 0.0,
        duration_s=t.number("duration_s", positive=True) if "duration_s" in t.data else None,
        torque_fraction=(
            t.number("torque_fraction", positive=True, at_most=1.0)
            if "torque_fraction" in t.data
            else None
        ),
        feedforward=t.boolean("feedforward") if "feedforward" in t.data else False,
        thrusters=t.boolean("thrusters") if "thrusters" in t.data else False,
    )
    if slew.method == "fuel-optimal" and slew.duration_s is None:
        raise t.error(t.key("duration_s"), "missing: a fuel-optimal slew needs its duration")
    if slew.thrusters and slew.method == "bang-bang":
        raise t.error(
            t.key("thrusters"), "only for time-optimal and fuel-optimal slews (not bang-bang)"
        )
    t.done()
    return slew


def _read_failure(t: Table, n_cubesats: int, n_stages: int) -> FailureEvent:
    cubesat = t.integer("cubesat", minimum=1)
    if cubesat > n_cubesats:
        raise t.error(t.key("cubesat"), f"CubeSats are numbered 1 to {n_cubesats}; got {cubesat}")
    stage = t.integer("stage", minimum=1) if "stage" in t.data else None
    if stage is not None and stage > n_stages:
        raise t.error(t.key("stage"), f"stages are numbered 1 to {n_stages}; got {stage}")
    event = FailureEvent(
        time_s=t.number("time_s", nonnegative=True),
        cubesat=cubesat - 1,
        stage=None if stage is None else stage - 1,
    )
    t.done()
    return event


def _read_simulation(t: Table, n_cubesats: int, n_stages: int) -> Simulation:
    reference = t.text("reference", REFERENCE_KINDS)
    has_slew = "slew" in t.data
    if reference == "slew" and not has_slew:
        raise t.error(t.key("slew"), 'missing: reference = "slew" needs a [simulation.slew] table')
    if reference == "hold" and has_slew:
        raise t.error(t.key("slew"), 'only allowed with reference = "slew"')
    simulation = Simulation(
        duration_s=t.number("duration_s", positive=True),
        control_rate_hz=t.number("control_rate_hz", positive=True),
        integrator_steps=t.integer("integrator_steps", minimum=1),
        reference=reference,
        slew=_read_slew(t.table("slew")) if has_slew else None,
        failures=tuple(
            sorted(
                (_read_failure(f, n_cubesats, n_stages) for f in t.tables("failures")),
                key=lambda event: event.time_s,
            )
        )
        if "failures" in t.data
        else (),
    )
    t.done()
    return simulation


def _read_montecarlo(t: Table) -> MonteCarlo:
    montecarlo = MonteCarlo(
        corner_array_angles=t.integer("corner_array_angles", minimum=1),
        samples=t.integer("samples", minimum=1),
        seed=t.integer("seed", minimum=0),
    )
    t.done()
    return montecarlo


def _optional_table(top: Table, name: str, defaults: Mapping[str, Any]) -> Table:
    """The table ``name`` with missing keys taken from ``defaults`` (absent table: all)."""
    given = top.data.get(name, {})
    top.taken.add(name)
    if not isinstance(given, Mapping):
        raise top.error(top.key(name), "must be a table")
    return Table({**defaults, **given}, top.key(name), top.source)


def _read_simple(t: Table, cls: type, names: tuple[str, ...], **checks: Any) -> Any:
    value = cls(*(t.number(n, **checks) for n in names))
    t.done()
    return value


def problem_from_dict(
    data: Mapping[str, Any], source: str | None = None, sha256: str = ""
) -> Problem:
    """Validate a parsed problem (as from TOML) and return it frozen.

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
    hub = _read_hub(top.table("hub"))
    detumble_table = top.table("detumble")
    detumble = Detumble(detumble_table.array("initial_rate_rad_s", (3,)))
    detumble_table.done()
    transfer = _read_simple(
        top.table("transfer"),
        Transfer,
        ("from_altitude_km", "from_inclination_deg", "to_altitude_km", "to_inclination_deg"),
        nonnegative=True,
    )
    cubesats = _read_cubesats(top.table("cubesats"))
    engine = _read_engine(top.table("engine"))
    problem = Problem(
        name=top.text("name"),
        description=top.text("description"),
        hub=hub,
        arrays=_read_arrays(top.table("arrays"), hub.size_m),
        cubesats=cubesats,
        engine=engine,
        disturbance=_read_disturbance(top.table("disturbance")),
        sensor=_read_sensor(top.table("sensor")),
        uncertainty=_read_uncertainty(top.table("uncertainty")),
        weights=_read_weights(top.table("weights")),
        orbit=_read_simple(
            top.table("orbit"), Orbit, ("altitude_km", "inclination_deg"), nonnegative=True
        ),
        transfer=transfer,
        detumble=detumble,
        constants=_read_simple(
            top.table("constants"),
            Constants,
            ("earth_mu_km3_s2", "earth_radius_km", "standard_gravity_m_s2"),
            positive=True,
        ),
        simulation=_read_simulation(
            _optional_table(top, "simulation", DEFAULT_SIMULATION),
            n_cubesats=6 * cubesats.per_face,
            n_stages=engine.stages,
        ),
        montecarlo=_read_montecarlo(_optional_table(top, "montecarlo", DEFAULT_MONTECARLO)),
        source=source or "<dict>",
        sha256=sha256,
    )
    if "extends" in data:
        top.taken.add("extends")
    top.done()
    return problem
