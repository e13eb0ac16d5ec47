"""What every job returns: a summary, its figures, and a ``save`` that writes what the
command writes, with the command's safety rules.

A job's result subclasses :class:`JobResult`, names its command, and says how its
folder is written (``_write``) and which figures it draws (``plot``). ``save`` does the
steps every job shares: check the folder, stage it, write into the staging folder, move
it into place whole.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from casadi_debris.config import Problem, load_problem
from casadi_debris.store import MARKER_NAME, RunFolder, check_output_folder

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from casadi_debris.workflows._margins import MarginsResult

ProblemLike = Problem | str | Path | None
"""A :class:`~casadi_debris.config.Problem`, a problem file, a shipped name
(``"paper_slew"``) or None (the paper's problem)."""


def as_problem(problem: ProblemLike) -> Problem:
    """The problem a job was given, loaded if it is a file or a shipped name."""
    return problem if isinstance(problem, Problem) else load_problem(problem)


@dataclass(frozen=True)
class JobResult:
    """Base of the jobs' results: ``summary``, ``plot()`` and ``save(folder)``.

    Subclasses are frozen dataclasses with a ``summary`` field (a record with
    ``to_json()``) and set :attr:`command`, the command whose folder ``save`` writes.
    """

    command: ClassVar[str] = ""

    def plot(self) -> dict[str, Figure]:
        """The result's figures by the file stem ``save`` writes them under; nothing is
        written (close them with ``matplotlib.pyplot.close``). None by default."""
        return {}

    def save(self, folder: str | Path, *, overwrite: bool = False, plots: bool = True) -> Path:
        """Write the result into ``folder`` as the command does.

        The folder is written whole or not at all; an existing one is replaced only with
        ``overwrite`` and only if this toolkit wrote it.

        Parameters
        ----------
        folder : str or Path
            The run folder.
        overwrite : bool
            Replace a run folder this toolkit wrote.
        plots : bool
            Write the figures too (PNG).

        Returns
        -------
        Path
            The folder written.
        """
        out = Path(folder)
        check_output_folder(out, overwrite=overwrite)
        with RunFolder.claim(out, overwrite=overwrite, command=self.command) as staging:
            self._write(staging, out, plots=plots)
        return out

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """Write the files into ``staging``; ``out`` is where they will end up (for the
        ``out_dir`` a summary records)."""
        raise NotImplementedError(f"{type(self).__name__} does not define how it is saved")


@dataclass(frozen=True)
class ReportFolderResult(JobResult):
    """A job that writes its report folder as it runs (its campaigns keep every case on
    disk for a resume), so the folder is written when the job returns: ``save`` copies
    it elsewhere and ``plot`` gives the margin study's figures.

    Attributes
    ----------
    folder : Path
        The report folder the job wrote.
    margins : MarginsResult
        The margin study of the controller over sampled plants.
    """

    folder: Path
    margins: MarginsResult

    def plot(self) -> dict[str, Figure]:
        """The margin study's figures, by the path ``save`` writes them under
        (``margins/mu``, ``margins/margins``, ...); the campaigns' envelopes are the
        ``slew/`` and ``pointing/`` folders' PNGs. Nothing is written."""
        return {f"margins/{name}": figure for name, figure in self.margins.plot().items()}

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """The report folder's files but its marker, copied (written as the job ran)."""
        shutil.copytree(
            self.folder, staging, dirs_exist_ok=True, ignore=shutil.ignore_patterns(MARKER_NAME)
        )
