"""Flight code: the closed loop's step as portable C99, proven equal to the simulation.

- :func:`write_flight_code`: write the C, its build files and manifest for a problem.
- :class:`FlightCode`: what was written.
- :class:`FlightLibrary`, :func:`compile_library`: a compiled export stepped from Python
  through ctypes.

The package also calls as the job ``casadi_debris.export(problem, ...)``
(:mod:`~casadi_debris.export._package`).
"""

from casadi_debris.export._ctypes import FlightLibrary, StepOutputs, compile_library
from casadi_debris.export._flight import FlightCode, control_law, reference_table, write_flight_code
from casadi_debris.export._package import callable_package

callable_package(__name__)

__all__ = [
    "FlightCode",
    "FlightLibrary",
    "StepOutputs",
    "compile_library",
    "control_law",
    "reference_table",
    "write_flight_code",
]
