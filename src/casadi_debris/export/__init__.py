"""Leaving the toolkit: the debris as an FMU for other simulators.

- :func:`write_fmu`: an FMI 2.0 co-simulation unit of the nonlinear plant (hub,
  arrays, engines), built from the model's CasADi code; :class:`FmuSettings`
  says how, :class:`FmuSummary` what was written.
"""

from casadi_debris.export._fmu import (
    FmuSettings,
    FmuSummary,
    fmi_platform,
    model_identifier,
    write_fmu,
)
from casadi_debris.export._fmu_c import plant_functions
from casadi_debris.export._fmu_variables import FmuLayout, FmuVariable, engine_names, fmu_layout

__all__ = [
    "FmuLayout",
    "FmuSettings",
    "FmuSummary",
    "FmuVariable",
    "engine_names",
    "fmi_platform",
    "fmu_layout",
    "model_identifier",
    "plant_functions",
    "write_fmu",
]
