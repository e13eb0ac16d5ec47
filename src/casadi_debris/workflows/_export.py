"""Code that leaves the toolkit (``casadi-debris export``): the flight step as C — the
reference, attitude error, discrete reduced controller and least-fuel allocator of a
problem and a controller, written as portable C99 with its build files, README and
manifest — or, with ``fmu=``, the debris itself as an FMI 2.0 co-simulation unit.

Example
-------
>>> import casadi_debris as cd
>>> exported = cd.export("paper_slew", out="runs/export-paper_slew")  # doctest: +SKIP
>>> exported.summary.engines
24
>>> plant = cd.export("paper", fmu="paper.fmu")  # doctest: +SKIP
>>> plant.summary.fmi_version
'2.0'
"""

from __future__ import annotations

import hashlib
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any, overload

from casadi_debris.codegen import FmuSummary
from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError, ProblemFileError
from casadi_debris.records import Record
from casadi_debris.store import (
    MARKER_NAME,
    RunFolder,
    check_output_folder,
    default_run_folder,
    write_json_atomic,
)
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem


@dataclass(frozen=True)
class ExportSummary(Record):
    """What ``casadi-debris export --json`` prints (and ``summary.json`` holds).

    Attributes
    ----------
    problem, problem_sha256 : str
        The problem exported and the hash of its file.
    controller_file, controller_sha256 : str
        The controller file flown and the hash of its bytes.
    period_s : float
        Control period of the step [s].
    engines, cubesats, stages, controller_states, reference_rows : int
        Sizes of the export.
    reference_end_s : float
        Time of the reference table's last row [s] (held after it).
    toolkit_version : str
    out_dir : str
        The folder written.
    files : list of str
        The files of the export.
    """

    problem: str
    problem_sha256: str
    controller_file: str
    controller_sha256: str
    period_s: float
    engines: int
    cubesats: int
    stages: int
    controller_states: int
    reference_rows: int
    reference_end_s: float
    toolkit_version: str
    out_dir: str
    files: list[str]


@dataclass(frozen=True)
class ExportResult(JobResult):
    """A problem's flight step, written as C.

    Attributes
    ----------
    problem : Problem
    folder : Path
        The export folder (sources, Makefile, CMakeLists.txt, README.md, manifest.json).
    manifest : dict
        The content of ``manifest.json``.
    summary : ExportSummary
    """

    problem: Problem
    folder: Path
    manifest: dict[str, Any]
    summary: ExportSummary

    command = "export"

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """The export's files (already written into :attr:`folder`), copied."""
        shutil.copytree(
            self.folder, staging, dirs_exist_ok=True, ignore=shutil.ignore_patterns(MARKER_NAME)
        )


@dataclass(frozen=True)
class FmuExportResult(JobResult):
    """A problem's plant, written as an FMI 2.0 co-simulation unit.

    Attributes
    ----------
    problem : Problem
    path : Path
        The ``.fmu`` file written.
    summary : FmuSummary
    """

    problem: Problem
    path: Path
    summary: FmuSummary

    command = "export"

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """The unit (already written at :attr:`path`), copied."""
        shutil.copy2(self.path, staging / self.path.name)


@overload
def export(
    problem: ProblemLike = None,
    *,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    fmu: None = None,
    out: str | Path | None = None,
    overwrite: bool = False,
) -> ExportResult: ...


@overload
def export(
    problem: ProblemLike = None,
    *,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    fmu: str | Path,
    out: str | Path | None = None,
    overwrite: bool = False,
) -> FmuExportResult: ...


def export(
    problem: ProblemLike = None,
    *,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    fmu: str | Path | None = None,
    out: str | Path | None = None,
    overwrite: bool = False,
) -> ExportResult | FmuExportResult:
    """Write the C99 flight step of a problem and a controller, or the plant as an FMU.

    The step does, per control period, what the toolkit's closed loop does: the
    reference at that instant, the attitude error of the measured quaternion, the
    discrete reduced controller, the saturation scale and the least-fuel thrust of
    every engine (failed CubeSats and stages as inputs). See the folder's README.md.
    With ``fmu``, the nonlinear plant (hub, arrays, engines) is written instead, as
    one FMI 2.0 co-simulation file (:func:`casadi_debris.codegen.write_fmu`).

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    controller : str or Path, optional
        A controller file (``controller.json`` of ``design``); default the shipped paper
        controller, for the paper's plant only.
    allow_mismatch : bool
        Export a controller designed for another plant anyway.
    fmu : str or Path, optional
        Write the plant as this ``.fmu`` file instead of the flight step (no
        controller is involved: ``controller`` and ``out`` must not be given).
    out : str or Path, optional
        The folder; default ``runs/export-<problem>``.
    overwrite : bool
        Replace a folder this toolkit wrote.

    Returns
    -------
    ExportResult or FmuExportResult
        :class:`FmuExportResult` when ``fmu`` is given.

    Raises
    ------
    InputShapeError
        ``fmu`` given with ``controller`` or ``out``.
    ProblemFileError
        The problem asks for realistic sensors, an estimator, a delay, engine effects or
        a burn, which this export does not carry yet.
    ControllerMismatchError
        The controller was designed for another plant (and ``allow_mismatch`` is false).
    """
    from casadi_debris.codegen import write_flight_code
    from casadi_debris.dynamics import build_model
    from casadi_debris.guidance import burn_windows, scenario_reference
    from casadi_debris.simulation import Realism, discretize_controller

    problem = as_problem(problem)
    if fmu is not None:
        return _export_fmu(problem, Path(fmu), controller=controller, out=out, overwrite=overwrite)
    folder = Path(out) if out is not None else default_run_folder("export", problem.name)
    check_output_folder(folder, overwrite=overwrite)
    record, resolved = controller_for(problem, controller, allow_mismatch=allow_mismatch)
    reference = scenario_reference(problem)
    period = float(reference.time_s[1] - reference.time_s[0])
    if Realism.of(problem, period) is not None:
        raise ProblemFileError(
            "sensors",
            "the flight-code export carries the ideal loop only: realistic sensors, "
            "[estimation], a [controller] delay or [actuators] effects are not exported yet",
            problem.source,
        )
    if burn_windows(reference, period):
        raise ProblemFileError(
            "simulation.sequence", "a burn cannot be exported yet", problem.source
        )
    model = build_model(problem)
    discrete = discretize_controller(record.reduced, period)
    controller_sha256 = hashlib.sha256(resolved.read_bytes()).hexdigest()
    identity = {"file": str(resolved), "sha256": controller_sha256}
    with RunFolder.claim(folder, overwrite=overwrite, command="export") as staging:
        code = write_flight_code(model, discrete, reference, staging, identity=identity)
        summary = ExportSummary(
            problem=problem.name,
            problem_sha256=problem.sha256,
            controller_file=str(resolved),
            controller_sha256=controller_sha256,
            period_s=period,
            engines=code.manifest["sizes"]["engines"],
            cubesats=code.manifest["sizes"]["cubesats"],
            stages=code.manifest["sizes"]["stages"],
            controller_states=code.manifest["sizes"]["controller_states"],
            reference_rows=code.manifest["sizes"]["reference_rows"],
            reference_end_s=code.manifest["reference_end_s"],
            toolkit_version=code.manifest["toolkit_version"],
            out_dir=str(folder),
            files=sorted([*code.files, "summary.json"]),
        )
        write_json_atomic(staging / "summary.json", summary)
    return ExportResult(problem=problem, folder=folder, manifest=code.manifest, summary=summary)


def _export_fmu(
    problem: Problem,
    path: Path,
    *,
    controller: str | Path | None,
    out: str | Path | None,
    overwrite: bool,
) -> FmuExportResult:
    """The plant of ``problem`` as the FMU ``path``."""
    from casadi_debris.codegen import write_fmu
    from casadi_debris.dynamics import build_model

    for name, value in (("controller", controller), ("out", out)):
        if value is not None:
            raise InputShapeError(
                f"fmu: the FMU is the plant alone; {name} does not apply (give one of fmu "
                "or the flight step's controller and out)"
            )
    if path.suffix != ".fmu":
        raise InputShapeError(f"fmu: {path} must end in .fmu (an FMU is a zip file named so)")
    summary = write_fmu(build_model(problem), path, overwrite=overwrite)
    return FmuExportResult(problem=problem, path=path, summary=summary)
