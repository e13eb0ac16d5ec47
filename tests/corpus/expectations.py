"""What a mutated problem file should give: which keys take a zero, a negative, no value ...

and which names an error about a key may give (the key, its table, the keys it is
checked against).
"""

from __future__ import annotations

# Keys (indices dropped) where a zero is a legitimate value.
ZERO_OK = {
    "arrays.angle_deg",
    "arrays.damping_ratio",
    "cubesats.edge_margin_fraction",
    "cubesats.standoff_m",
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
# Zero on the hub's boundary (centre of gravity, hinge at a hub edge): either way.
ZERO_EITHER = {"hub.cog_corner_m", "arrays.hinges_corner_m"}
# Signed quantities.
NEGATIVE_OK = {"arrays.angle_deg", "disturbance.phase_deg", "detumble.initial_rate_rad_s"}
# Seeds: any non-negative integer numpy takes.
HUGE_INT_EITHER = {"uncertainty.seed", "montecarlo.seed"}
# 1e-300 is "positive" but absurd here.
TINY_REJECT = {
    "hub.mass_kg",
    "arrays.mass_kg",
    "cubesats.mass_kg",
    "simulation.control_rate_hz",
    "constants.earth_mu_km3_s2",
    "constants.earth_radius_km",
    "constants.standard_gravity_m_s2",
}
# Keys and tables with defaults.
DELETE_OK = {
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
# Keys checked against each other: a message naming the partner is fine.
PARTNERS = {
    "hub.size_m": ("hub.cog_corner_m", "arrays.hinges_corner_m"),
    "arrays.hinges_corner_m": ("arrays.directions",),
    "arrays.directions": ("arrays.hinges_corner_m",),
    "cubesats.mass_kg": ("engine.",),
    "engine.thrust_per_stage_mN": ("cubesats.mass_kg",),
    "engine.isp_s": ("cubesats.mass_kg",),
    "engine.stage_life_h": ("cubesats.mass_kg",),
    "engine.stages": ("cubesats.mass_kg", "simulation."),
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


def key_names(path: Path_) -> tuple[str, ...]:
    """Names an error about ``path`` may give: the key, its list, its table, partners."""
    names: list[str] = []
    strings = [p for p in path if isinstance(p, str)]
    # The key up to its last name (indices of a number list dropped).
    last_str = max(i for i, p in enumerate(path) if isinstance(p, str)) if strings else -1
    names.append(dotted(path[: last_str + 1]))
    if "modes" in strings and strings[0] == "arrays":
        names.append("arrays.modes")
    if len(strings) > 1:
        names.append(strings[0] + ".")  # another key of the same table
    names.extend(PARTNERS.get(plain_key(path), ()))
    return tuple(dict.fromkeys(n for n in names if n))
