"""casadi_debris: attitude control of space debris with docked iESE CubeSats.

Start with :func:`load_problem` (the paper's setup by default), then
:func:`casadi_debris.geometry.build_geometry` and
:func:`casadi_debris.model.build_model`.
"""

from casadi_debris.config import Problem, load_problem
from casadi_debris.errors import CasadiDebrisError, ProblemFileError

__all__ = ["CasadiDebrisError", "Problem", "ProblemFileError", "load_problem"]
__version__ = "0.1.0"  # the one place the version is written (pyproject.toml reads it)
