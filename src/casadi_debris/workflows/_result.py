"""What every job returns: a summary, its figures, and a ``save`` that writes what the
command writes, with the command's safety rules.

A job's result subclasses :class:`JobResult`, names its command, and says how its
folder is written (``_write``) and which figures it draws (``plot``). ``save`` does the
steps every job shares: check the folder, stage it, write into the staging folder, move
it into place whole.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from casadi_debris.config import Problem, load_problem
from casadi_debris.report.folders import RunFolder, check_output_folder

if TYPE_CHECKING:
    from matplotlib.figure import Figure

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
