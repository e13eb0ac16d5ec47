"""What a mutated problem file should give: which keys take a zero, a negative, no value ...

and which names an error about a key may give (the key, its table, the keys it is
checked against).

Keys are written without list indices (``arrays.modes.omega_rad_s`` for
``arrays[1].modes[2].omega_rad_s``, ``cubesats.engines.isp_s``).
"""

from __future__ import annotations

# Keys where a zero is a legitimate value.
ZERO_OK = {
    "arrays.angle_deg",
    "arrays.damping_ratio",
    "cubesat_layout.edge_margin_fraction",
    "cubesat_layout.standoff_m",
    "cubesats.engines.offset_m",
    "disturbance.amplitude_mNm",
    "disturbance.phase_deg",
    "detumble.initial_rate_rad_s",
    "uncertainty.inertia_fraction",
    "uncertainty.mass_fraction",
    "uncertainty.array_angle_deg",
    "uncertainty.bending_frequency_fraction",
    "uncertainty.seed",
    "montecarlo.seed",
    "orbit.inclination_deg",
    "transfer.from_inclination_deg",
    "transfer.to_inclination_deg",
    "simulation.slew.start_s",
}
# Either way, depending on the component: a zero on the hub's boundary (centre of
# gravity, hinge at a hub edge, a CubeSat moved onto an edge of its face or off it),
# a component of a direction vector (the vector may be left zero).
ZERO_EITHER = {
    "hub.cog_corner_m",
    "arrays.hinge_corner_m",
    "cubesats.position_corner_m",
    "cubesats.engines.direction",
}
# Signed quantities (a direction's components, an engine's offset from its CubeSat).
NEGATIVE_OK = {
    "arrays.angle_deg",
    "cubesats.engines.direction",
    "cubesats.engines.offset_m",
    "disturbance.phase_deg",
    "detumble.initial_rate_rad_s",
}
# Seeds: any non-negative integer numpy takes.
HUGE_INT_EITHER = {"uncertainty.seed", "montecarlo.seed"}
# 1e-300 is "positive" but absurd here.
TINY_REJECT = {
    "hub.mass_kg",
    "arrays.mass_kg",
    "cubesat_layout.mass_kg",
    "cubesats.mass_kg",
    "requirements.pointing_arcsec",
    "requirements.slew_error_deg",
    "simulation.control_rate_hz",
    "constants.earth_mu_km3_s2",
    "constants.earth_radius_km",
    "constants.standard_gravity_m_s2",
}
# Keys and tables with defaults, or whose absence is a valid problem: no [[arrays]]
# (a rigid debris), an array without modes (a rigid appendage), one array or one
# CubeSat fewer, an engine key taken from [engine].
DELETE_OK = {
    "arrays",
    "arrays.modes",
    "arrays[]",
    "arrays.modes[]",
    "cubesats[]",
    "cubesats.face",
    "cubesats.engines.offset_m",
    "cubesats.engines.stages",
    "cubesats.engines.emitters_per_stage",
    "cubesats.engines.thrust_per_stage_mN",
    "cubesats.engines.isp_s",
    "cubesats.engines.stage_life_h",
    "cubesat_layout.faces",
    "cubesat_layout.main_engine",
    "cubesat_layout.side_engines",
    "requirements",
    "requirements.pointing_arcsec",
    "requirements.slew_error_deg",
    "simulation",
    "simulation.duration_s",
    "simulation.control_rate_hz",
    "simulation.integrator_steps",
    "simulation.slew.method",
    "simulation.slew.start_s",
    "simulation.slew.duration_s",
    "simulation.slew.torque_fraction",
    "simulation.slew.feedforward",
    "simulation.slew.thrusters",
    "montecarlo",
    "montecarlo.corner_array_angles",
    "montecarlo.samples",
    "montecarlo.seed",
}
DELETE_EITHER = {"description"}
# Tables that may be empty (every key has a default).
EMPTY_TABLE_OK = {"simulation", "montecarlo", "requirements"}
# Arrays of tables: what ``= []`` and the first entry twice give (default: reject).
EMPTY_ARRAY_OK = {"arrays", "arrays.modes"}  # a rigid debris, a rigid appendage
DUPLICATE_ITEM = {
    "arrays": "either",  # a third array where the first is: nothing checks overlaps
    "cubesats": "either",  # a 25th CubeSat where the first is: nothing checks overlaps
    "cubesats.engines": "ok",  # the same engine twice on one CubeSat: twice the thrust
}
# Lists whose last entry dropped is still valid (a layout on five faces).
DROP_LAST_OK = {"cubesat_layout.faces"}
# Switches whose other value is still valid (cubesat_layout.main_engine = false leaves
# the paper's layout, without side engines, with no engine at all: refused).
FLIP_OK = {"simulation.slew.feedforward"}
# Keys checked against each other: a message naming the partner is fine. A partner
# starting with "." is a key of the same table (``.direction`` of ``arrays[1]``).
PARTNERS = {
    "hub.size_m": (
        "hub.cog_corner_m",
        "arrays[0].hinge_corner_m",
        "arrays[0].direction",
        "arrays[1].hinge_corner_m",
        "arrays[1].direction",
        "cubesat_layout.",
    ),
    "arrays.hinge_corner_m": (".direction",),
    "arrays.direction": (".hinge_corner_m",),
    "cubesats.position_corner_m": (".face",),
    "cubesats.face": (".position_corner_m",),
    "cubesats.mass_kg": (".engines[0].stage_life_h",),
    "cubesat_layout.mass_kg": ("engine.",),
    "engine.thrust_per_stage_mN": ("cubesat_layout.mass_kg",),
    "engine.isp_s": ("cubesat_layout.mass_kg",),
    "engine.stage_life_h": ("cubesat_layout.mass_kg",),
    "engine.stages": ("cubesat_layout.mass_kg", "simulation."),
    "sensor.star_tracker_bandwidth_rad_s": ("simulation.",),
    "simulation.control_rate_hz": ("sensor.star_tracker_bandwidth_rad_s",),
    "simulation.integrator_steps": ("sensor.star_tracker_bandwidth_rad_s",),
    "constants.earth_radius_km": ("orbit.", "transfer."),
    "constants.earth_mu_km3_s2": ("orbit.", "transfer."),
    "orbit.altitude_km": ("constants.", "transfer."),
}

Path_ = tuple[str | int, ...]


def dotted(path: Path_) -> str:
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + part
    return out


def plain_key(path: Path_) -> str:
    """Dotted key without list indices: ``arrays.modes.omega_rad_s``."""
    return ".".join(p for p in path if isinstance(p, str))


def item_key(path: Path_) -> str:
    """``plain_key`` of an entry of an array of tables, marked: ``arrays[]``, ``arrays.modes[]``."""
    return plain_key(path) + "[]"


def key_names(path: Path_) -> tuple[str, ...]:
    """Names an error about ``path`` may give: the key, its list, its table, partners.

    Indices of arrays of tables stay in (``arrays[1].modes[2].omega_rad_s``); those
    of a list of numbers are dropped (``hub.size_m`` for ``hub.size_m[1]``).
    """
    names: list[str] = []
    strings = [i for i, p in enumerate(path) if isinstance(p, str)]
    last_str = strings[-1] if strings else -1
    names.append(dotted(path[: last_str + 1]))
    if "modes" in path[:last_str] and path[0] == "arrays":
        names.append(dotted(path[: path.index("modes") + 1]))  # arrays[0].modes
    if len(strings) > 1:  # another key of the same table (hub., simulation., arrays[0].)
        names.append(dotted(path[: strings[1]]) + ".")
    table = dotted(path[:last_str])
    for partner in PARTNERS.get(plain_key(path), ()):
        names.append(table + partner if partner.startswith(".") else partner)
    return tuple(dict.fromkeys(n for n in names if n))
