"""Readers of the orbit and of the environment torques (``[orbit]``, ``[environment]``).

Both tables' optional keys take the defaults of their dataclasses
(:class:`~casadi_debris.config._schema.Orbit`,
:class:`~casadi_debris.config._schema.Environment`); an absent ``[environment]``
switches every environment torque off, as in the paper.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

from casadi_debris.config import limits
from casadi_debris.config._schema import ENVIRONMENT_TORQUES, Environment, Orbit
from casadi_debris.config._table import Table, frozen_array, show

_DEFAULT_ENVIRONMENT = Environment()


def read_orbit(t: Table) -> Orbit:
    """``[orbit]``: altitude and inclination, the node and the phase at t = 0 optional."""
    orbit = Orbit(
        altitude_km=t.number("altitude_km", limits.ALTITUDE_KM),
        inclination_deg=t.number("inclination_deg", limits.INCLINATION_DEG),
        raan_deg=_optional(t, "raan_deg", Orbit.raan_deg, t.number, limits.ANGLE_DEG),
        argument_of_latitude_deg=_optional(
            t,
            "argument_of_latitude_deg",
            Orbit.argument_of_latitude_deg,
            t.number,
            limits.ANGLE_DEG,
        ),
    )
    t.done()
    return orbit


def _optional(t: Table, name: str, default: Any, read: Callable[..., Any], *args: Any) -> Any:
    """``read(name, *args)`` when the key is given, else ``default`` (noted for the schema)."""
    if t.has(name):
        return read(name, *args)
    return default


def read_environment(top: Table) -> Environment:
    """``[environment]`` (absent: no environment torque)."""
    if not top.has("environment"):
        top.taken.add("environment")
        return _DEFAULT_ENVIRONMENT
    t = top.table("environment")
    d = _DEFAULT_ENVIRONMENT
    torques: tuple[Any, ...] = ()
    if t.has("torques"):
        value = t.data["torques"]
        if value == []:  # an empty list: none, as when the key is left out
            t.record("torques", kind="texts", choices=ENVIRONMENT_TORQUES, max_count=4)
            t.taken.add("torques")
        else:
            torques = t.texts("torques", ENVIRONMENT_TORQUES, len(ENVIRONMENT_TORQUES))
            if len(set(torques)) != len(torques):
                raise t.error(t.key("torques"), f"lists a torque twice: {show(list(torques))}")
    numbers = {
        "density_kg_m3": limits.DENSITY_KG_M3,
        "drag_coefficient": limits.DRAG_COEFFICIENT,
        "solar_pressure_N_m2": limits.SOLAR_PRESSURE_N_M2,
        "specular_reflectivity": limits.REFLECTIVITY,
        "diffuse_reflectivity": limits.REFLECTIVITY,
        "sun_longitude_deg": limits.ANGLE_DEG,
        "field_equator_T": limits.FIELD_T,
        "dipole_tilt_deg": limits.DIPOLE_TILT_DEG,
        "dipole_longitude_deg": limits.ANGLE_DEG,
        "greenwich_angle_deg": limits.ANGLE_DEG,
    }
    values: dict[str, Any] = {
        name: _optional(t, name, getattr(d, name), t.number, bounds)
        for name, bounds in numbers.items()
    }
    values["eclipse"] = _optional(t, "eclipse", d.eclipse, t.boolean)
    dipole = _optional(t, "residual_dipole_Am2", None, t.array, (3,), limits.RESIDUAL_DIPOLE_AM2)
    values["residual_dipole_Am2"] = frozen_array(
        d.residual_dipole_Am2 if dipole is None else dipole
    )
    if values["specular_reflectivity"] + values["diffuse_reflectivity"] > 1.0:
        raise t.error(
            t.key("diffuse_reflectivity"),
            "specular_reflectivity + diffuse_reflectivity must be at most 1 (the rest is "
            f"absorbed), got {values['specular_reflectivity']:g} + "
            f"{values['diffuse_reflectivity']:g}",
        )
    t.done()
    return dataclasses.replace(d, torques=torques, **values)
