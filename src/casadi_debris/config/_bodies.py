"""Readers of the debris and its swarm: ``[hub]``, ``[[arrays]]``, the CubeSats, ``[engine]``.

Each reader takes one :class:`~casadi_debris.config._table.Table`, bounds every
number by :mod:`~casadi_debris.config.limits` and returns a frozen dataclass of
:mod:`~casadi_debris.config._schema`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from casadi_debris.config import limits
from casadi_debris.config._checks import check_inertia, check_on_surface, check_outside_hub
from casadi_debris.config._layouts import expand_layout, signed_axis_vector
from casadi_debris.config._schema import (
    LAYOUT_KINDS,
    MODE_KINDS,
    SIGNED_AXES,
    Array,
    CubeSat,
    CubeSatLayout,
    Engine,
    EngineDefaults,
    Hub,
    Mode,
)
from casadi_debris.config._table import Table, frozen_array, show


def read_hub(t: Table) -> Hub:
    """``[hub]``: mass, size, centre of gravity inside it, inertia."""
    size = t.array("size_m", (3,), limits.HUB_SIZE_M)
    cog = t.array("cog_corner_m", (3,), limits.POSITION_M)
    if np.any(cog > size):
        raise t.error(t.key("cog_corner_m"), f"must lie inside the hub (0 .. {size.tolist()} m)")
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


def read_direction(t: Table, name: str) -> np.ndarray:
    """A signed axis (``"+x"`` ... ``"-z"``) or a 3-vector, returned as a unit vector."""
    value = t.raw(name)
    if isinstance(value, str):
        t.record(name, kind="text", choices=SIGNED_AXES)
        if value not in SIGNED_AXES:
            raise t.error(
                t.key(name),
                f"must be a signed axis ({', '.join(SIGNED_AXES)}) or 3 numbers; got {show(value)}",
            )
        return frozen_array(signed_axis_vector(value))
    vector = t.array(name, (3,), limits.DIRECTION)
    norm = float(np.linalg.norm(vector))
    if norm < 1e-9:
        raise t.error(t.key(name), "must not be zero (it is a direction)")
    return frozen_array(vector / norm)


def read_array(t: Table, hub_size: np.ndarray) -> Array:
    """One ``[[arrays]]`` entry: its hinge on the hub's surface, its size, its modes."""
    inertia = t.array("inertia_kgm2", (3,), limits.PRINCIPAL_INERTIA_KGM2)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    hinge = t.array("hinge_corner_m", (3,), limits.POSITION_M)
    direction = read_direction(t, "direction")
    check_on_surface(t, "hinge_corner_m", hinge, direction, hub_size)
    modes = _read_modes(t) if t.has("modes") else ()
    array = Array(
        hinge_corner_m=hinge,
        direction=direction,
        mass_kg=t.number("mass_kg", limits.MASS_KG),
        length_m=t.number("length_m", limits.LENGTH_M),
        width_m=t.number("width_m", limits.LENGTH_M),
        inertia_kgm2=inertia,
        angle_deg=t.number("angle_deg", limits.ANGLE_DEG),
        damping_ratio=t.number("damping_ratio", limits.FRACTION_BELOW_ONE),
        modes=modes,
    )
    t.done()
    return array


def _read_modes(t: Table) -> tuple[Mode, ...]:
    if t.data["modes"] == []:  # a rigid appendage
        t.raw("modes")
        return ()
    modes = tuple(read_mode(m) for m in t.tables("modes", limits.MAX_MODES))
    names = [m.name for m in modes]
    if len(set(names)) != len(names):
        raise t.error(t.key("modes"), f"mode names must be unique, got {names}")
    kinds_orders = [(m.kind, m.order) for m in modes]
    if len(set(kinds_orders)) != len(kinds_orders):
        raise t.error(t.key("modes"), "two modes have the same kind and order")
    return modes


def read_arrays(top: Table, hub_size: np.ndarray) -> tuple[Array, ...]:
    """``[[arrays]]``: zero or more appendages (none, or ``arrays = []``: a rigid debris)."""
    if not top.has("arrays"):
        return ()
    value = top.raw("arrays")
    if isinstance(value, Mapping):
        raise top.error(
            "arrays",
            "must be an array of tables, one [[arrays]] per array (each with hinge_corner_m "
            "and direction), or arrays = [] for a rigid debris",
        )
    if value == []:
        return ()
    return tuple(read_array(a, hub_size) for a in top.tables("arrays", limits.MAX_ARRAYS))


def _stage_values(t: Table) -> dict[str, Any]:
    """The stages, emitters, thrust, Isp and life of an engine (``[engine]`` or one engine)."""
    return {
        "stages": t.integer("stages", limits.STAGES),
        "emitters_per_stage": t.integer("emitters_per_stage", limits.EMITTERS_PER_STAGE),
        "thrust_per_stage_mN": t.number("thrust_per_stage_mN", limits.THRUST_MN),
        "isp_s": t.number("isp_s", limits.ISP_S),
        "stage_life_h": t.number("stage_life_h", limits.STAGE_LIFE_H),
    }


def read_engine_defaults(t: Table) -> EngineDefaults:
    """``[engine]``: the stages, thrust, Isp and life of engines that do not say otherwise."""
    engine = EngineDefaults(**_stage_values(t))
    t.done()
    return engine


def _read_engine(t: Table) -> Engine:
    engine = Engine(
        direction=read_direction(t, "direction"),
        offset_m=t.array("offset_m", (3,), limits.OFFSET_M),
        **_stage_values(t),
    )
    t.done()
    return engine


def _read_cubesat(t: Table, hub_size: np.ndarray, defaults: EngineDefaults) -> CubeSat:
    position = t.array("position_corner_m", (3,), limits.CUBESAT_POSITION_M)
    face = t.text("face", SIGNED_AXES) if t.has("face") else None
    check_outside_hub(t, "position_corner_m", position, face, hub_size)
    value = t.data.get("inertia_kgm2")
    principal = isinstance(value, list) and not any(isinstance(v, list) for v in value)
    inertia = t.array(
        "inertia_kgm2",
        (3,) if principal else (3, 3),
        limits.PRINCIPAL_INERTIA_KGM2 if principal else limits.INERTIA_KGM2,
    )
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    engine_defaults = {"offset_m": [0.0, 0.0, 0.0], **dataclasses.asdict(defaults)}
    engines = tuple(
        _read_engine(Table({**engine_defaults, **e.data}, e.path, e.source))
        for e in t.tables("engines", limits.MAX_ENGINES_PER_CUBESAT)
    )
    cubesat = CubeSat(
        position_corner_m=position,
        mass_kg=t.number("mass_kg", limits.CUBESAT_MASS_KG),
        inertia_kgm2=frozen_array(np.diag(inertia) if inertia.ndim == 1 else inertia),
        face=face,
        engines=engines,
    )
    t.done()
    return cubesat


def read_layout(t: Table) -> CubeSatLayout:
    """``[cubesat_layout]``: a generator of the CubeSat list (see :mod:`.layouts`)."""
    inertia = t.array("inertia_kgm2", (3,), limits.PRINCIPAL_INERTIA_KGM2)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    kind = t.text("kind", LAYOUT_KINDS)
    faces = t.texts("faces", SIGNED_AXES, len(SIGNED_AXES)) if t.has("faces") else SIGNED_AXES
    if len(set(faces)) != len(faces):
        raise t.error(t.key("faces"), f"each face at most once, got {list(faces)}")
    per_face = t.integer("per_face", limits.Range(1, limits.MAX_CUBESATS))
    if kind == "face_corners" and per_face != 4:
        raise t.error(
            t.key("per_face"),
            f"face_corners places 4 per face (one near each corner), got {per_face}; "
            'kind = "face_grid" places any number',
        )
    side_engines = t.integer("side_engines", limits.Range(0, 4)) if t.has("side_engines") else 0
    if side_engines not in (0, 2, 4):
        raise t.error(t.key("side_engines"), f"must be 0, 2 or 4, got {side_engines}")
    layout = CubeSatLayout(
        kind=kind,
        faces=faces,
        per_face=per_face,
        edge_margin_fraction=t.number("edge_margin_fraction", limits.FRACTION_BELOW_ONE),
        standoff_m=t.number("standoff_m", limits.STANDOFF_M),
        mass_kg=t.number("mass_kg", limits.CUBESAT_MASS_KG),
        inertia_kgm2=inertia,
        main_engine=t.boolean("main_engine") if t.has("main_engine") else True,
        side_engines=side_engines,
    )
    if not layout.main_engine and layout.side_engines == 0:
        raise t.error(t.key("main_engine"), "a CubeSat needs an engine: a main or side engines")
    t.done()
    return layout


def read_cubesats(
    top: Table, hub_size: np.ndarray, defaults: EngineDefaults
) -> tuple[tuple[CubeSat, ...], CubeSatLayout | None]:
    """The CubeSats: an explicit ``[[cubesats]]`` list or a ``[cubesat_layout]``, not both."""
    given = [name for name in ("cubesats", "cubesat_layout") if top.has(name)]
    if not given:
        raise top.error("cubesats", "missing: give a [[cubesats]] list or a [cubesat_layout]")
    if len(given) == 2:
        raise top.error(
            "cubesats", "give either a [[cubesats]] list or a [cubesat_layout], not both"
        )
    if given == ["cubesat_layout"]:
        layout = read_layout(top.table("cubesat_layout"))
        cubesats = expand_layout(layout, hub_size, defaults)
    else:
        if isinstance(top.data["cubesats"], Mapping):
            raise top.error(
                "cubesats",
                "must be an array of tables, one [[cubesats]] per CubeSat; the paper's corner "
                'layout is [cubesat_layout] with kind = "face_corners"',
            )
        tables = top.tables("cubesats", limits.MAX_CUBESATS)
        layout, cubesats = None, tuple(_read_cubesat(c, hub_size, defaults) for c in tables)
    if len(cubesats) > limits.MAX_CUBESATS:
        raise top.error(
            "cubesat_layout", f"places {len(cubesats)} CubeSats, at most {limits.MAX_CUBESATS}"
        )
    n_engines = sum(len(c.engines) for c in cubesats)
    if n_engines > limits.MAX_ENGINES:
        raise top.error(given[0], f"{n_engines} engines in all, at most {limits.MAX_ENGINES}")
    return cubesats, layout


def check_propellant(
    top: Table, cubesats: tuple[CubeSat, ...], layout: CubeSatLayout | None, g0_m_s2: float
) -> None:
    """Refuse CubeSats whose engines' propellant (all stages) is not below the CubeSat's mass.

    A stage burns ``thrust x life / (Isp g0)`` [kg]
    (:meth:`~casadi_debris.config.Engine.stage_propellant_kg`); a CubeSat
    carries that for every stage of every engine. It cannot weigh more
    than the CubeSat itself, and the rocket equation's logarithm would fail if it
    did.

    Raises
    ------
    ProblemFileError
        Naming ``engine.stage_life_h`` for generated CubeSats (their engines take
        the ``[engine]`` values) or the CubeSat's first engine's ``stage_life_h``.
    """
    for index, cubesat in enumerate(cubesats):
        total_kg = sum(e.stages * e.stage_propellant_kg(g0_m_s2) for e in cubesat.engines)
        if total_kg < cubesat.mass_kg:
            continue
        where = (
            "engine.stage_life_h"
            if layout is not None
            else f"cubesats[{index}].engines[0].stage_life_h"
        )
        mass_key = "cubesat_layout.mass_kg" if layout is not None else f"cubesats[{index}].mass_kg"
        raise top.error(
            where,
            f"the propellant of CubeSat {index + 1}'s {len(cubesat.engines)} engine(s), "
            f"stages x thrust x life / (Isp g0) summed = {total_kg:.4g} kg, must be below "
            f"the CubeSat's mass ({cubesat.mass_kg:g} kg, {mass_key}); shorten the stage life "
            "or lower the thrust",
        )
