"""Errors of casadi_debris.

Every error the toolkit raises on purpose derives from :class:`CasadiDebrisError` and
from the builtin it refines (a bad problem file is also a ``ValueError``, an unusable
output folder an ``OSError``), so that ``except ValueError`` still catches it. The
command line turns a :class:`CasadiDebrisError` into one clear line and exit status 2,
except an :class:`InternalError` (a bug, not the user's mistake): exit status 3.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any


class CasadiDebrisError(Exception):
    """Base of every error raised on purpose by casadi_debris."""


class InternalError(CasadiDebrisError, RuntimeError):
    """Something the toolkit promised did not hold: a bug to report, not bad input."""


# ------------------------------------------------------------ files and folders


class ProblemFileError(CasadiDebrisError, ValueError):
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


class ControllerMismatchError(ProblemFileError):
    """The controller was designed for another plant than the problem's."""


class UnreadableFileError(CasadiDebrisError, OSError):
    """Why a file given by the user cannot be read (the caller adds which file it was)."""


class OutputError(CasadiDebrisError, OSError):
    """An output location cannot be used as asked (exists, not writable, no room)."""


class PaperReferenceError(CasadiDebrisError, ValueError):
    """The paper's reference file is missing, not TOML, or has a malformed entry.

    Parameters
    ----------
    key : str
        The entry at fault (``"mass_kg"``), with the field where it helps
        (``"mass_kg.tolerance"``); empty when the file as a whole is at fault.
    message : str
        What is wrong with it.
    source : str
        The file read.
    """

    def __init__(self, key: str, message: str, source: str) -> None:
        self.key = key
        self.source = source
        where = f"[{key}] " if key else ""
        super().__init__(f"{source}: {where}{message}")


# ------------------------------------------------------------ inputs and models


class ModelError(CasadiDebrisError, ValueError):
    """A model cannot be built or linearised from the parameters given."""


class InputShapeError(CasadiDebrisError, ValueError):
    """An array argument has the wrong shape or non-finite entries."""


# --------------------------------------------------------------- robust control


class SynthesisError(CasadiDebrisError, RuntimeError):
    """Robust controller synthesis or analysis failed."""


class UnstableLoopError(SynthesisError):
    """The closed loop is unstable, so its margins are meaningless."""


# ------------------------------------------------------------------- allocation


class AllocationError(CasadiDebrisError):
    """A thrust allocation cannot be set up or solved (bad demand, no engines, unknown solver)."""


class DemandError(AllocationError, InputShapeError):
    """A demand the allocator refuses: wrong shape, not finite, or absurdly large.

    Both an :class:`~casadi_debris.errors.AllocationError` and an
    :class:`~casadi_debris.errors.InputShapeError` (what shape and finiteness
    errors were before).

    Parameters
    ----------
    argument : str
        Name of the argument, e.g. ``"torque_Nm"``.
    problem : str
        What is wrong, without the values.
    values : list of float, optional
        The offending demand (or row), in SI.
    unit : str
        Unit of ``values``.
    row : int, optional
        Row of a batch or series (0-based).
    bound : float, optional
        The largest component accepted [``unit``], for an absurd demand.
    """

    def __init__(
        self,
        argument: str,
        problem: str,
        *,
        values: list[float] | None = None,
        unit: str = "",
        row: int | None = None,
        bound: float | None = None,
    ) -> None:
        self.argument = argument
        self.problem = problem
        self.values = values
        self.row = row
        self.bound = bound
        where = argument if row is None else f"{argument}[{row}]"
        got = "" if values is None else f" (got {values}{' ' + unit if unit else ''})"
        super().__init__(f"{where}: {problem}{got}")


class UnknownSolverError(AllocationError, ValueError):
    """A QP back-end was asked for by a name that is not installed."""


class NoEngineError(AllocationError, RuntimeError):
    """Every CubeSat has failed or is spent: no torque can be made."""


class AllocationInternalError(InternalError):
    """Neither the back-end nor HiGHS gave a finite allocation within the promised accuracy.

    A bug, not bad input (the command line reports it as an internal error).
    """


# ------------------------------------------------------------------------ slews


class SlewInfeasibleError(CasadiDebrisError, ValueError):
    """A slew cannot be done as asked (e.g. a duration below the time-optimal minimum)."""


class SlewNotConvergedError(SlewInfeasibleError):
    """IPOPT ended in a status other than success: the slew may exist, it was not found."""


class NotBangBangError(CasadiDebrisError, ValueError):
    """The collocation solution is not bang-bang (a singular arc, or too few intervals)."""


# ----------------------------------------------------- simulation and campaigns


class SimulationError(CasadiDebrisError, ValueError):
    """A closed-loop run cannot be set up as asked."""


class CasesFailedError(SimulationError):
    """Cases raised while they ran (every other case ran to its end).

    Attributes
    ----------
    failures : list of CaseFailure
        The cases that raised, with their error type and message.
    """

    def __init__(self, failures: Sequence[Any]) -> None:
        first = failures[0]
        super().__init__(
            f"{len(failures)} case(s) failed, the first {first.case.case_id}: "
            f"{first.error_type}: {first.message}"
        )
        self.failures = list(failures)


class SchedulerError(SimulationError):
    """The Dask scheduler asked for cannot be used (not installed, not reachable)."""


class FailureStudyError(CasadiDebrisError, ValueError):
    """A failure campaign asked for something its problem cannot give."""


class CompileError(CasadiDebrisError, RuntimeError):
    """A Function cannot be compiled to C or loaded (no usable compiler or cache folder)."""


# ------------------------------------------------------------- worker processes


class WorkerStartError(InternalError):
    """A worker's ``initializer`` raised; the message holds the worker's traceback."""


class SchedulerUnavailableError(CasadiDebrisError, RuntimeError):
    """The Dask scheduler asked for cannot be used (``distributed`` missing, unreachable)."""


class RemoteError(InternalError):
    """An exception raised in another process, as its traceback text (a ``__cause__``)."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.text = text

    def __str__(self) -> str:
        return self.text


class CampaignInterrupted(KeyboardInterrupt):
    """Ctrl-C during a campaign: the finished cases are on disk for a resume.

    A ``KeyboardInterrupt``, not a :class:`CasadiDebrisError`: the user stopped the run,
    nothing went wrong, and whoever catches Ctrl-C catches this too.
    """

    def __init__(self, done: int, total: int, partial: Path) -> None:
        super().__init__(
            f"interrupted: {done} of {total} cases are kept in {partial}; "
            "run the same command again to resume"
        )
