"""Readers of the debris and its swarm: ``[hub]``, ``[arrays]``, ``[cubesats]``, ``[engine]``.

Each reader takes one :class:`~casadi_debris.config.table.Table`, bounds every
number by :mod:`~casadi_debris.config.limits` and returns a frozen dataclass of
:mod:`~casadi_debris.config.schema`.
"""

from __future__ import annotations

import numpy as np

from casadi_debris.config import limits
from casadi_debris.config.checks import check_inertia, check_on_face
from casadi_debris.config.schema import (
    MODE_KINDS,
    SIGNED_AXES,
    Arrays,
    Constants,
    CubeSats,
    Engine,
    Hub,
    Mode,
)
from casadi_debris.config.table import Table
from casadi_debris.units import N_PER_MN, SECONDS_PER_HOUR


def read_hub(t: Table) -> Hub:
    """``[hub]``: mass, size, centre of gravity inside it, inertia."""
    size = t.array("size_m", (3,), limits.HUB_SIZE_M)
    cog = t.array("cog_corner_m", (3,), limits.POSITION_M)
    if np.any(cog > size):
        raise t.error(t.key("cog_corner_m"), f"must lie inside the hub (0 .. {list(size)} m)")
    inertia = t.array("inertia_kgm2", (3, 3), limits.INERTIA_KGM2)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    hub = Hub(t.number("mass_kg", limits.MASS_KG), size, cog, inertia)
    t.done()
    return hub


def read_mode(t: Table) -> Mode:
    """One ``[[arrays.modes]]`` entry."""
    mode = Mode(
        name=t.label("name"),
        kind=t.text("kind", MODE_KINDS),
        order=t.integer("order", limits.MODE_ORDER),
        omega_rad_s=t.number("omega_rad_s", limits.MODE_OMEGA_RAD_S),
    )
    t.done()
    return mode


def read_arrays(t: Table, hub_size: np.ndarray) -> Arrays:
    """``[arrays]``: the identical arrays, their hinges on the hub's faces, their modes."""
    inertia = t.array("inertia_kgm2", (3,), limits.PRINCIPAL_INERTIA_KGM2)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    hinges = t.array("hinges_corner_m", (None, 3), limits.POSITION_M, max_rows=limits.MAX_ARRAYS)
    directions = t.texts("directions", SIGNED_AXES, limits.MAX_ARRAYS)
    if len(directions) != len(hinges):
        raise t.error(
            t.key("directions"), f"needs one entry per hinge ({len(hinges)}), got {len(directions)}"
        )
    for i, (hinge, direction) in enumerate(zip(hinges, directions, strict=True)):
        check_on_face(t, f"hinges_corner_m[{i}]", hinge, direction, hub_size)
    modes = tuple(read_mode(m) for m in t.tables("modes", limits.MAX_MODES))
    names = [m.name for m in modes]
    if len(set(names)) != len(names):
        raise t.error(t.key("modes"), f"mode names must be unique, got {names}")
    kinds_orders = [(m.kind, m.order) for m in modes]
    if len(set(kinds_orders)) != len(kinds_orders):
        raise t.error(t.key("modes"), "two modes have the same kind and order")
    if ("bending", 1) not in kinds_orders:
        raise t.error(t.key("modes"), "needs the first bending mode (kind bending, order 1)")
    arrays = Arrays(
        mass_kg=t.number("mass_kg", limits.MASS_KG),
        length_m=t.number("length_m", limits.LENGTH_M),
        width_m=t.number("width_m", limits.LENGTH_M),
        inertia_kgm2=inertia,
        hinges_corner_m=hinges,
        directions=directions,
        angle_deg=t.number("angle_deg", limits.ANGLE_DEG),
        damping_ratio=t.number("damping_ratio", limits.FRACTION_BELOW_ONE),
        modes=modes,
    )
    t.done()
    return arrays


def read_cubesats(t: Table) -> CubeSats:
    """``[cubesats]``: the corner layout, four per face."""
    inertia = t.array("inertia_kgm2", (3,), limits.PRINCIPAL_INERTIA_KGM2)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    per_face = t.integer("per_face", limits.Range(1, 4))
    if per_face != 4:
        raise t.error(t.key("per_face"), f"only the corner layout (4) is supported, got {per_face}")
    cubesats = CubeSats(
        per_face=per_face,
        mass_kg=t.number("mass_kg", limits.CUBESAT_MASS_KG),
        inertia_kgm2=inertia,
        edge_margin_fraction=t.number("edge_margin_fraction", limits.FRACTION_BELOW_ONE),
        standoff_m=t.number("standoff_m", limits.STANDOFF_M),
    )
    t.done()
    return cubesats


def read_engine(t: Table) -> Engine:
    """``[engine]``: one staged iESE per CubeSat."""
    engine = Engine(
        stages=t.integer("stages", limits.STAGES),
        emitters_per_stage=t.integer("emitters_per_stage", limits.EMITTERS_PER_STAGE),
        thrust_per_stage_mN=t.number("thrust_per_stage_mN", limits.THRUST_MN),
        isp_s=t.number("isp_s", limits.ISP_S),
        stage_life_h=t.number("stage_life_h", limits.STAGE_LIFE_H),
    )
    t.done()
    return engine


def check_propellant(t: Table, engine: Engine, cubesats: CubeSats, constants: Constants) -> None:
    """Refuse engines whose propellant (all stages) is not below the CubeSat's mass.

    A stage burns ``thrust x life / (Isp g0)`` [kg] (as
    :func:`casadi_debris.allocation.stage_propellant_kg` computes it), so a
    CubeSat carries ``stages`` times that; it cannot weigh more than the
    CubeSat itself, and the rocket equation's logarithm would fail if it did.

    Parameters
    ----------
    t : Table
        The top-level table (the error names ``engine.stage_life_h``).
    engine, cubesats, constants
        Already read.

    Raises
    ------
    ProblemFileError
        Naming ``engine.stage_life_h``, the usual culprit of the product.
    """
    stage_kg = (
        engine.thrust_per_stage_mN
        * N_PER_MN
        * engine.stage_life_h
        * SECONDS_PER_HOUR
        / (engine.isp_s * constants.standard_gravity_m_s2)
    )
    total_kg = engine.stages * stage_kg
    if total_kg >= cubesats.mass_kg:
        raise t.error(
            "engine.stage_life_h",
            f"the propellant of {engine.stages} stage(s), {engine.stages} x thrust x life / "
            f"(Isp g0) = {total_kg:.4g} kg, must be below the CubeSat's mass "
            f"({cubesats.mass_kg:g} kg, cubesats.mass_kg); shorten the stage life "
            "or lower the thrust",
        )
