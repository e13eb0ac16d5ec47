"""The combined system and its budgets in display units (``casadi-debris model`` / ``budget``)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from casadi_debris.budgets import BudgetItem
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, assembled_modes, build_model, shape_integrals
from casadi_debris.geometry import Geometry, array_axes, torque_authority
from casadi_debris.records import FLATTENED, Record
from casadi_debris.report._common import format_cell, format_table
from casadi_debris.report._paper import paper_figures
from casadi_debris.units import MN_PER_N


def _rounded(values: np.ndarray, digits: int = 6) -> np.ndarray:
    # + 0.0 turns -0.0 into 0.0 so directions print without a stray sign.
    return np.round(np.asarray(values, dtype=float), digits) + 0.0


def _vector(values: np.ndarray) -> tuple[float, ...]:
    return tuple(_rounded(values).tolist())


def _matrix(values: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(row) for row in _rounded(values).tolist())


@dataclass(frozen=True)
class FlexibleMode(Record):
    """An assembled free-free mode with its cantilever origin.

    ``array`` names the arrays that carry it (``"1+2"``, from 1); ``name`` and
    ``kind`` its cantilever mode; ``symmetry`` ``"in-phase"``, ``"anti-phase"``
    or ``"-"``; ``omega_rad_s``/``zeta`` the cantilever's, ``omega_free_rad_s``/
    ``zeta_free`` the assembled free-floating body's; ``mass_fraction`` and
    ``root_inertia_fraction`` the cantilever's effective shares.
    """

    array: str
    name: str
    kind: str
    symmetry: str
    omega_rad_s: float
    omega_free_rad_s: float
    zeta: float
    zeta_free: float
    mass_fraction: float
    root_inertia_fraction: float


@dataclass(frozen=True)
class ArrayOrientation(Record):
    """Which way one array lies and faces, in the body frame B (unit vectors rounded to 1e-6).

    ``array`` is its number (from 1); ``hinge_m`` its root point from the CoG and
    ``hinge_corner_m`` the same point in the hub-corner frame; ``hinge_axis`` the
    axis ``angle_deg`` (theta_SA) turns it about (``extent`` or its opposite,
    whichever points along a positive body axis); ``extent`` the direction it
    extends in from the hinge, ``width`` its in-plane width direction and ``normal``
    the normal of its face at ``angle_deg``. At angle 0 the normal is the hub axis
    after the extent's main axis in cyclic order (x, y, z, x): an array along ±y
    faces +z, one along ±z faces +x, one along ±x faces +y.
    """

    array: int
    hinge_m: tuple[float, ...]
    hinge_corner_m: tuple[float, ...]
    hinge_axis: tuple[float, ...]
    extent: tuple[float, ...]
    width: tuple[float, ...]
    normal: tuple[float, ...]
    angle_deg: float


@dataclass(frozen=True)
class Thruster(Record):
    """One engine as a user numbers it (all from 1).

    ``cubesat_engine`` is its number among its CubeSat's engines (what a failure's
    ``engine`` names); ``face`` its CubeSat's docking face (None off the faces);
    ``position_m`` from the CoG and ``direction`` (unit force on the body) in the
    body frame, rounded to 1e-6.
    """

    engine: int
    cubesat: int
    cubesat_engine: int
    isp_s: float
    face: str | None
    position_m: tuple[float, ...]
    direction: tuple[float, ...]
    max_thrust_mN: float


@dataclass(frozen=True)
class ModelSummary(Record):
    """The combined system in display units (``casadi-debris model``).

    ``cog_m`` is in the hub-corner frame; ``inertia_hub_cubesats_kgm2`` and
    ``inertia_total_kgm2`` (arrays included) are 3x3 about the CoG;
    ``torque_max_mNm`` and ``torque_max_zero_force_mNm`` the torque authority by
    signed axis (``"+x"`` ... ``"-z"``: JSON keys, not names, hence a mapping);
    ``arrays`` each array's hinge, extent, width and normal in B;
    ``notes`` what the problem file gives that this debris does not use.
    """

    problem: str
    problem_path: str
    problem_sha256: str
    mass_kg: float
    cog_m: tuple[float, ...]
    inertia_hub_cubesats_kgm2: tuple[tuple[float, ...], ...]
    inertia_total_kgm2: tuple[tuple[float, ...], ...]
    array_angle_deg: tuple[float, ...]
    arrays: tuple[ArrayOrientation, ...]
    torque_max_mNm: dict[str, float]
    torque_max_zero_force_mNm: dict[str, float]
    modes: tuple[FlexibleMode, ...]
    thrusters: tuple[Thruster, ...]
    notes: tuple[str, ...]


def describe_model(model: Problem | Model) -> ModelSummary:
    """The combined system in display units (the ``casadi-debris model`` output), of a
    problem or of its model already built."""
    model = model if isinstance(model, Model) else build_model(model)
    problem, geometry = model.problem, model.geometry
    zero_force_mNm = torque_authority(geometry, zero_net_force=True).to_mNm()
    return ModelSummary(
        problem=problem.name,
        problem_path=problem.source,
        problem_sha256=problem.sha256,
        mass_kg=geometry.mass_kg,
        cog_m=_vector(geometry.cog_corner_m),
        inertia_hub_cubesats_kgm2=_matrix(geometry.inertia_hub_cubesats_kgm2),
        inertia_total_kgm2=_matrix(geometry.inertia_total_kgm2),
        array_angle_deg=tuple(array.angle_deg for array in problem.arrays),
        arrays=_array_orientations(problem, geometry),
        torque_max_mNm=torque_authority(geometry).to_mNm(),
        torque_max_zero_force_mNm=zero_force_mNm,
        modes=_modes(model),
        thrusters=_thrusters(problem, geometry),
        notes=tuple(
            _notes(problem, model.parameter_names) + _authority_notes(problem, zero_force_mNm)
        ),
    )


def _authority_notes(problem: Problem, zero_force_mNm: dict[str, float]) -> list[str]:
    """Body axes the engines cannot hold against the disturbance at zero net force
    (``zero_force_mNm``: the authority by signed axis [mN m])."""
    notes = []
    for index, axis in enumerate("xyz"):
        disturbance_mNm = float(problem.disturbance.amplitude_mNm[index])
        short = {s: zero_force_mNm[s] for s in (f"+{axis}", f"-{axis}")}
        short = {s: v for s, v in short.items() if v < disturbance_mNm}
        if short:
            # Round-off of an LP with no authority gives 1e-20, not 0.
            given = ", ".join(f"{s} {v if v > 1e-12 else 0.0:.3g}" for s, v in short.items())
            notes.append(
                f"the engines give {given} mNm at zero net force, below the disturbance's "
                f"{disturbance_mNm:g} mNm: this swarm cannot hold the debris about {axis}"
            )
    return notes


def _modes(model: Model) -> tuple[FlexibleMode, ...]:
    problem = model.problem
    modes = []
    with_modes = sorted({a for a, _ in model.layout.mode_labels})  # array numbers, from 1
    for assembled in assembled_modes(model):
        share = assembled["array_share"]
        array = problem.arrays[with_modes[int(np.argmax(share))] - 1]
        cantilever = next(m for m in array.modes if m.name == assembled["dominant_mode"])
        integrals = shape_integrals(cantilever.kind, cantilever.order)
        carrying = [str(i + 1) for i, s in enumerate(share) if s > 0.1]
        phase = assembled["in_phase"]
        bending = cantilever.kind == "bending"
        modes.append(
            FlexibleMode(
                array="+".join(carrying),
                name=cantilever.name,
                kind=cantilever.kind,
                symmetry="-" if phase is None else ("in-phase" if phase else "anti-phase"),
                omega_rad_s=cantilever.omega_rad_s,
                omega_free_rad_s=assembled["omega_rad_s"],
                zeta=array.damping_ratio,
                zeta_free=assembled["zeta"],
                mass_fraction=integrals.mass_fraction if bending else 0.0,
                root_inertia_fraction=(
                    integrals.root_inertia_fraction if bending else integrals.mass_fraction
                ),
            )
        )
    return tuple(modes)


def _array_orientations(problem: Problem, geometry: Geometry) -> tuple[ArrayOrientation, ...]:
    """Each array's hinge and axes in B, from the same :func:`array_axes` the model uses."""
    orientations = []
    for index, (array, hinge_m) in enumerate(zip(problem.arrays, geometry.hinges_m, strict=True)):
        extent, width, normal = (
            np.array(v, dtype=float).ravel()
            for v in array_axes(array.direction, math.radians(array.angle_deg))
        )
        main = int(np.argmax(np.abs(extent)))
        orientations.append(
            ArrayOrientation(
                array=index + 1,
                hinge_m=_vector(hinge_m),
                hinge_corner_m=_vector(array.hinge_corner_m),
                hinge_axis=_vector(extent if extent[main] > 0 else -extent),
                extent=_vector(extent),
                width=_vector(width),
                normal=_vector(normal),
                angle_deg=array.angle_deg,
            )
        )
    return tuple(orientations)


def _thrusters(problem: Problem, geometry: Geometry) -> tuple[Thruster, ...]:
    return tuple(
        Thruster(
            engine=engine.index + 1,
            cubesat=engine.cubesat + 1,
            # Its number among its CubeSat's own engines: what a failure's `engine` names.
            cubesat_engine=sum(
                e.cubesat == engine.cubesat for e in geometry.engines[: engine.index]
            )
            + 1,
            isp_s=problem.engines[engine.index].isp_s,
            face=geometry.cubesats[engine.cubesat].face,
            position_m=_vector(engine.position_m),
            direction=_vector(engine.direction),
            max_thrust_mN=engine.max_thrust_N * MN_PER_N,
        )
        for engine in geometry.engines
    )


def _paper_cells(key: str, ours: Any, show_paper: bool) -> list[str]:
    figure = paper_figures().get(key) if show_paper else None
    if figure is None:
        return ["", ""]
    mark = {True: "ok", False: "OUTSIDE", None: ""}[figure.accepts(ours)]
    paper = figure.value if len(figure.values) == 1 else list(figure.values)
    return [format_cell(paper), mark]


def model_text(summary: ModelSummary, show_paper: bool) -> str:
    """Readable tables of :func:`describe_model`'s output."""
    headers = (
        ["quantity", "toolkit", "paper", "check"] if show_paper else ["quantity", "value", "", ""]
    )
    parts = [
        f"Problem {summary.problem} ({summary.problem_path})",
        "",
        format_table(headers, _quantity_rows(summary, show_paper)),
        "",
        *_arrays_section(summary.arrays),
        _modes_heading(summary.array_angle_deg),
        _modes_table(summary.modes),
        "",
        "Engines (body frame B, origin at the CoG; direction = unit force on the body)",
        _thrusters_table(summary.thrusters),
        *(f"note: {note}" for note in summary.notes),
    ]
    return "\n".join(parts)


def _notes(problem: Problem, parameter_names: tuple[str, ...]) -> list[str]:
    """What the problem file gives that this debris does not use."""
    unused = []
    if "array_angle_offset_rad" not in parameter_names:
        unused.append(f"uncertainty.array_angle_deg ({problem.uncertainty.array_angle_deg:g})")
    if "bending_frequency_scale" not in parameter_names:
        fraction = problem.uncertainty.bending_frequency_fraction
        unused.append(f"uncertainty.bending_frequency_fraction ({fraction:g})")
    if not unused:
        return []
    why = "has no arrays" if not problem.arrays else "has no first bending mode"
    return [
        f"{' and '.join(unused)} dropped: this debris {why}, so the model has no such parameter"
    ]


def _quantity_rows(summary: ModelSummary, show_paper: bool) -> list[list[Any]]:
    """Mass, CoG, inertia and torque authority, each with the paper's figure when shown."""
    torque = summary.torque_max_mNm
    torque_pos = [torque["+x"], torque["+y"], torque["+z"]]
    torque_neg = [torque["-x"], torque["-y"], torque["-z"]]
    zero_force = summary.torque_max_zero_force_mNm
    inertia_hc = np.array(summary.inertia_hub_cubesats_kgm2)
    return [
        [
            "total mass [kg]",
            summary.mass_kg,
            *_paper_cells("mass_kg", summary.mass_kg, show_paper),
        ],
        ["CoG, hub-corner frame [m]", list(summary.cog_m), "", ""],
        [
            "hub + CubeSats inertia diag [kg m^2]",
            np.diag(inertia_hc).tolist(),
            *_paper_cells("inertia_hub_cubesats_diag_kgm2", np.diag(inertia_hc), show_paper),
        ],
        ["hub + CubeSats inertia off-diag xy,xz,yz", _offdiag(inertia_hc), "", ""],
        [
            "full rigid inertia diag (arrays incl.)",
            np.diag(summary.inertia_total_kgm2).tolist(),
            "",
            "",
        ],
        [
            "max torque +x,+y,+z [mNm]",
            torque_pos,
            *_paper_cells("torque_max_mNm", torque_pos, show_paper),
        ],
        [
            "max torque -x,-y,-z [mNm]",
            torque_neg,
            *_paper_cells("torque_max_mNm", torque_neg, show_paper),
        ],
        [
            "  zero net force, +x,+y,+z",
            [zero_force[k] for k in ("+x", "+y", "+z")],
            "",
            "",
        ],
        [
            "  zero net force, -x,-y,-z",
            [zero_force[k] for k in ("-x", "-y", "-z")],
            "",
            "",
        ],
    ]


# Header next to the mode's field it shows, so that the two cannot drift apart.
_MODE_COLUMNS = (
    ("array", "array"),
    ("mode", "name"),
    ("symmetry", "symmetry"),
    ("omega [rad/s]", "omega_rad_s"),
    ("omega_free [rad/s]", "omega_free_rad_s"),
    ("zeta", "zeta"),
    ("mass frac", "mass_fraction"),
    ("root inertia frac", "root_inertia_fraction"),
)


def _arrays_section(arrays: Sequence[ArrayOrientation]) -> list[str]:
    """The arrays' hinges and axes, with the rule for angle 0 (nothing for a rigid debris)."""
    if not arrays:
        return []
    table = format_table(
        ["array", "hinge [m]", "hinge axis", "extent", "width", "normal", "angle [deg]"],
        [
            [
                a.array,
                list(a.hinge_m),
                list(a.hinge_axis),
                list(a.extent),
                list(a.width),
                list(a.normal),
                a.angle_deg,
            ]
            for a in arrays
        ],
    )
    return [
        "Arrays (body frame B, origin at the CoG; the angle turns an array about its hinge axis)",
        "At angle 0 an array's normal is the hub axis after its extent's in the order x, y, z, x:",
        "an array along ±y faces +z, along ±z faces +x, along ±x faces +y.",
        table,
        "",
    ]


def _modes_heading(angles_deg: Sequence[float]) -> str:
    if not angles_deg:
        return "Flexible modes: none (a rigid debris, no arrays)"
    return (
        "Flexible modes (array angles "
        + ", ".join(f"{angle:g}" for angle in angles_deg)
        + " deg; omega = cantilever, omega_free = assembled free-floating body)"
    )


def _modes_table(modes: Sequence[FlexibleMode]) -> str:
    """The assembled flexible modes with their cantilever origin."""
    return format_table(
        [header for header, _ in _MODE_COLUMNS],
        [[getattr(mode, name) for _, name in _MODE_COLUMNS] for mode in modes],
    )


def _thrusters_table(thrusters: Sequence[Thruster]) -> str:
    """Each CubeSat engine: face, position, force direction and thrust."""
    return format_table(
        ["engine", "cubesat", "face", "position [m]", "direction", "max thrust [mN]"],
        [
            [
                t.engine,
                t.cubesat,
                t.face or "-",
                list(t.position_m),
                list(t.direction),
                t.max_thrust_mN,
            ]
            for t in thrusters
        ],
    )


def _offdiag(matrix: np.ndarray) -> list[float]:
    return [float(matrix[0, 1]), float(matrix[0, 2]), float(matrix[1, 2])]


@dataclass(frozen=True)
class BudgetSummary(Record):
    """``casadi-debris budget --json``: the problem, every budget figure under its own key
    (a mapping, flattened: the keys carry the units, ``dv_transfer_m_s``, and
    :func:`~casadi_debris.budgets.compute_budgets` decides them), and ``how`` each was
    computed, by the same keys."""

    problem: str
    problem_sha256: str
    figures: dict[str, float] = field(metadata=FLATTENED)
    how: dict[str, str]


def budget_summary(problem: Problem, items: Sequence[BudgetItem]) -> BudgetSummary:
    """The budget ``items`` of ``problem`` as a record."""
    return BudgetSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        figures={item.key: item.value for item in items},
        how={item.key: item.how for item in items},
    )


def budget_text(items: Sequence[BudgetItem], problem_label: str, show_paper: bool) -> str:
    """Readable table of the budget items, with how each was computed."""
    rows = [
        [item.key, item.value, *_paper_cells(item.key, item.value, show_paper), item.how]
        for item in items
    ]
    headers = ["figure", "toolkit", "paper", "check", "how"]
    return f"Budgets for {problem_label}\n\n" + format_table(headers, rows)
