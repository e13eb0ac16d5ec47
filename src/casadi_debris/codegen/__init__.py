"""Code that leaves the toolkit: the flight step as portable C99, the debris as an FMU.

- :func:`write_flight_code`: write the closed loop's step (reference, attitude error,
  discrete controller, least-fuel allocator) as C99 with its build files and manifest;
  :class:`FlightCode` says what was written. :class:`FlightLibrary` and
  :func:`compile_library` step a compiled export from Python through ctypes.
- :func:`write_fmu`: an FMI 2.0 co-simulation unit of the nonlinear plant (hub,
  arrays, engines), built from the model's CasADi code; :class:`FmuSettings` says how,
  :class:`FmuSummary` what was written.
"""

from casadi_debris.codegen._ctypes import FlightLibrary, StepOutputs, compile_library
from casadi_debris.codegen._flight import (
    FlightCode,
    control_law,
    reference_table,
    write_flight_code,
)
from casadi_debris.codegen._fmu import (
    FmuSettings,
    FmuSummary,
    fmi_platform,
    model_identifier,
    write_fmu,
)
from casadi_debris.codegen._fmu_c import plant_functions
from casadi_debris.codegen._fmu_variables import FmuLayout, FmuVariable, engine_names, fmu_layout

__all__ = [
    "FlightCode",
    "FlightLibrary",
    "FmuLayout",
    "FmuSettings",
    "FmuSummary",
    "FmuVariable",
    "StepOutputs",
    "compile_library",
    "control_law",
    "engine_names",
    "fmi_platform",
    "fmu_layout",
    "model_identifier",
    "plant_functions",
    "reference_table",
    "write_flight_code",
    "write_fmu",
]
