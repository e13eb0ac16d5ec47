"""Errors of casadi_debris.

Every error the toolkit raises on purpose derives from :class:`CasadiDebrisError`,
so the command line can turn it into one clear message and a non-zero exit.
"""

from __future__ import annotations


class CasadiDebrisError(Exception):
    """Base of every error raised on purpose by casadi_debris."""


class ProblemFileError(CasadiDebrisError):
    """A problem file (or a parameter set) is missing, malformed or unphysical.

    Parameters
    ----------
    field : str
        Dotted path of the offending key, e.g. ``"hub.inertia_kgm2"``; empty
        when the file as a whole is at fault.
    message : str
        What is wrong with it.
    source : str, optional
        The file the key came from.
    """

    def __init__(self, field: str, message: str, source: str | None = None) -> None:
        self.field = field
        self.source = source
        where = f"{source}: " if source else ""
        key = f"{field}: " if field else ""
        super().__init__(f"{where}{key}{message}")


class ModelError(CasadiDebrisError):
    """A model cannot be built or linearised from the parameters given."""


class InputShapeError(CasadiDebrisError):
    """An array argument has the wrong shape or non-finite entries."""


class SynthesisError(CasadiDebrisError):
    """Robust controller synthesis or analysis failed."""


class AllocationError(CasadiDebrisError):
    """A thrust allocation cannot be set up or solved (bad demand, no engines, unknown solver)."""


class SlewInfeasibleError(CasadiDebrisError):
    """A slew cannot be done as asked (e.g. a duration below the time-optimal minimum)."""
