"""The debris as an FMU: an FMI 2.0 co-simulation unit of the nonlinear plant.

The unit is built from the model's own ``dynamics`` Function through CasADi's C
code generator (:mod:`casadi_debris.codegen._fmu_c`), wrapped in the FMI 2.0
co-simulation interface, compiled by the system's C compiler and zipped with
its sources and ``modelDescription.xml`` (:mod:`casadi_debris.codegen._fmu_variables`).

Why FMI 2.0 co-simulation and not CasADi's own ``DaeBuilder.export_fmu``: that
writes FMI 3.0 *model exchange* only (the importer brings the solver), and the
unit it wrote for a two-state oscillator fails fmpy's validation (variable
names such as ``__assign__der(x)__`` that the structured naming convention
forbids, and an incomplete ``InitialUnknowns``). FMI 2.0 co-simulation is what
Simulink's FMU block, OpenModelica and every FMI importer read, and what fmpy
validates against the standard's schema; the solver travels inside the unit,
so its answer is the same in every tool.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.dynamics import build_model
>>> from casadi_debris.codegen import write_fmu
>>> summary = write_fmu(build_model(load_problem()), "paper.fmu")  # doctest: +SKIP
>>> summary.inputs[:2]  # doctest: +SKIP
('thrust_cs01_e1_N', 'thrust_cs02_e1_N')
"""

from __future__ import annotations

import hashlib
import logging
import math
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import casadi as ca

from casadi_debris._version import __version__
from casadi_debris.codegen._fmu_c import PLANT_FILE, WRAPPER_FILE, plant_source, wrapper_source
from casadi_debris.codegen._fmu_variables import (
    Description,
    FmuLayout,
    fmu_layout,
    model_description,
)
from casadi_debris.dynamics import Model
from casadi_debris.errors import CompileError, InputShapeError, OutputError
from casadi_debris.processes import c_compiler
from casadi_debris.records import Record
from casadi_debris.store import write_atomically

LOGGER = logging.getLogger(__name__)
FMI_VERSION = "2.0"
# The fastest dynamics RK4 must resolve: the assembled array modes (up to about 40 rad/s
# on the paper's debris) and the 50 rad/s star tracker. RK4's error falls as the step to
# the fourth power; measured against CVODES on the paper's debris, a 5 ms step leaves
# 6e-4 of the peak on the second bending rate, 2 ms about 2e-5 (and 1e-9 on the attitude),
# at a cost of 50 sub-steps per 0.1 s communication step (a few microseconds each).
DEFAULT_MAX_STEP_S = 0.002
COMPILE_FLAGS = ("-std=c99", "-O2", "-fPIC", "-shared", "-fvisibility=hidden")
COMPILE_TIMEOUT_S = 900.0
# Zip entries get one fixed time stamp: the same problem gives the same bytes.
ZIP_TIME = (1980, 1, 1, 0, 0, 0)


@dataclass(frozen=True)
class FmuSettings:
    """How the FMU is built.

    Attributes
    ----------
    max_step_s : float
        Start value of the FMU's ``max_step_s`` parameter: the largest RK4
        sub-step [s] (each communication step is cut into equal sub-steps no
        longer than this). The importer may change it before initialisation.
    communication_step_s : float or None
        Step of the default experiment [s]; default the problem's control period.
    stop_time_s : float or None
        End of the default experiment [s]; default the problem's run length.
    compile : bool
        Compile the binary for this platform (``binaries/<platform>/``); False
        writes a sources-only FMU that the importer compiles.
    compiler : str or None
        The C compiler; default ``$CC``, then gcc, cc, clang on ``PATH``.
    """

    max_step_s: float = DEFAULT_MAX_STEP_S
    communication_step_s: float | None = None
    stop_time_s: float | None = None
    compile: bool = True
    compiler: str | None = None

    def __post_init__(self) -> None:
        for name in ("max_step_s", "communication_step_s", "stop_time_s"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0.0):
                raise InputShapeError(f"{name}: a positive number of seconds, got {value!r}")


@dataclass(frozen=True)
class FmuSummary(Record):
    """What was written.

    Attributes
    ----------
    path : str
    fmi_version : str
        ``"2.0"``.
    fmi_type : str
        ``"co-simulation"``.
    model_identifier, guid : str
    problem : str
        The problem's name.
    platform : str or None
        The binary's FMI platform folder (``linux64``); None for sources only.
    compiler : str or None
        The compiler's first ``--version`` line.
    states, engines, modes : int
    max_step_s : float
        Default largest RK4 sub-step [s].
    inputs, outputs : list of str
    parameters : dict of str to float
        Every parameter and its start value (the problem's nominal values).
    size_bytes : int
    sha256 : str
        Of the whole ``.fmu``.
    export_time_s : float
        Wall time of the export (code generation, compile, zip).
    """

    path: str
    fmi_version: str
    fmi_type: str
    model_identifier: str
    guid: str
    problem: str
    platform: str | None
    compiler: str | None
    states: int
    engines: int
    modes: int
    max_step_s: float
    inputs: list[str] = field(default_factory=list)
    outputs: list[str] = field(default_factory=list)
    parameters: dict[str, float] = field(default_factory=dict)
    size_bytes: int = 0
    sha256: str = ""
    export_time_s: float = 0.0


def write_fmu(
    model: Model,
    path: str | Path,
    settings: FmuSettings | None = None,
    *,
    overwrite: bool = False,
) -> FmuSummary:
    """Write the FMI 2.0 co-simulation unit of ``model``'s nonlinear plant.

    Inputs: each engine's thrust [N] (``thrust_cs01_e1_N``: CubeSat 1, its
    engine 1), held over a communication step and limited to [0, one stage's
    thrust]; the disturbance torque in B [N m]. Outputs: the model's state
    (attitude ``q_BN`` scalar first, body rate [rad/s], velocity [m/s], modal
    coordinates and rates, star-tracker quaternion) and the engines' torque
    [N m] and force [N] in B. Parameters: the model's (nominal values as start),
    the initial attitude and rate, and the largest RK4 sub-step.

    Parameters
    ----------
    model : Model
        The model whose ``dynamics`` Function the FMU integrates (its modes).
    path : str or Path
        The ``.fmu`` file to write (written whole or not at all).
    settings : FmuSettings, optional
    overwrite : bool
        Replace an existing file.

    Returns
    -------
    FmuSummary

    Raises
    ------
    InputShapeError
        ``path`` does not end in ``.fmu``.
    OutputError
        ``path`` exists and ``overwrite`` is False.
    CompileError
        No C compiler, or it fails (with ``settings.compile``).
    """
    started = time.perf_counter()
    settings = settings or FmuSettings()
    target = Path(path)
    if target.suffix != ".fmu":
        raise InputShapeError(f"path: an FMU file ends in .fmu, got {str(path)!r}")
    if target.exists() and not overwrite:
        raise OutputError(f"fmu: {target} exists; pass --overwrite (overwrite=True) to replace it")
    identifier = model_identifier(model.problem.name)
    layout = fmu_layout(model, settings.max_step_s)
    plant, sizes = plant_source(model)
    xml, guid = model_description(layout, _about(model, settings, identifier))
    sources = {
        PLANT_FILE: plant,
        WRAPPER_FILE: wrapper_source(model, layout, sizes, identifier, guid),
    }
    compiler = _compiler(settings.compiler) if settings.compile else None
    binary = _compile(compiler, sources, identifier) if compiler is not None else None
    target.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(target.resolve(), lambda temporary: _zip(temporary, xml, sources, binary))
    data = target.read_bytes()
    elapsed = time.perf_counter() - started
    LOGGER.info("FMU of %s written to %s in %.1f s", model.problem.name, target, elapsed)
    built = _Built(identifier, guid, binary, compiler, data)
    return _summary(model, layout, settings, target, built, elapsed)


def model_identifier(problem_name: str) -> str:
    """The FMU's model identifier (its library's name): a C identifier from the problem's name."""
    cleaned = re.sub(r"[^A-Za-z0-9_]+", "_", problem_name).strip("_")
    return f"casadi_debris_{cleaned}" if cleaned else "casadi_debris_debris"


def fmi_platform() -> tuple[str, str]:
    """This machine's FMI 2.0 binary folder and library suffix (``linux64``, ``.so``)."""
    bits = "64" if struct.calcsize("P") == 8 else "32"
    if sys.platform.startswith("linux"):
        return f"linux{bits}", ".so"
    if sys.platform == "darwin":
        return f"darwin{bits}", ".dylib"
    if sys.platform in ("win32", "cygwin"):
        return f"win{bits}", ".dll"
    raise CompileError(f"no FMI 2.0 platform folder for {sys.platform}; use compile=False")


def _about(model: Model, settings: FmuSettings, identifier: str) -> Description:
    problem = model.problem
    step = settings.communication_step_s or 1.0 / problem.simulation.control_rate_hz
    return Description(
        model_name=identifier,
        model_identifier=identifier,
        description=(
            f"Nonlinear plant of the debris of problem {problem.name!r} (hub, "
            f"{len(problem.arrays)} arrays with {model.layout.n_eta} modal coordinates, "
            f"{len(model.geometry.engines)} engines); RK4 in sub-steps of at most max_step_s."
        ),
        generation_tool=f"casadi_debris {__version__} (CasADi {ca.CasadiMeta.version()})",
        source_files=(WRAPPER_FILE,),
        stop_time_s=float(settings.stop_time_s or problem.simulation.duration_s),
        step_size_s=float(step),
    )


def _compiler(given: str | None) -> str:
    found = shutil.which(given) if given else c_compiler()
    if found:
        return found
    wanted = given or "$CC, gcc, cc or clang"
    raise CompileError(
        f"no C compiler ({wanted}) to build the FMU's binary; install one, or export "
        "with compile=False for a sources-only FMU"
    )


def _compile(compiler: str, sources: dict[str, str], identifier: str) -> tuple[str, bytes]:
    """The shared library built from ``sources``: (its path in the FMU, its bytes)."""
    platform, suffix = fmi_platform()
    library = f"{identifier}{suffix}"
    with tempfile.TemporaryDirectory(prefix="casadi_debris-fmu-") as folder:
        for name, text in sources.items():
            (Path(folder) / name).write_text(text)
        # Relative names, run in the folder: no temporary path ends up in the binary.
        command = [compiler, *COMPILE_FLAGS, "-o", library, WRAPPER_FILE, "-lm"]
        try:
            finished = subprocess.run(
                command,
                cwd=folder,
                capture_output=True,
                text=True,
                timeout=COMPILE_TIMEOUT_S,
                check=False,
            )
        except (OSError, subprocess.SubprocessError) as exc:
            raise CompileError(f"{compiler} cannot be run: {exc}") from exc
        if finished.returncode != 0:
            message = (finished.stderr or finished.stdout).strip().splitlines()[:5]
            raise CompileError(f"{compiler} failed on the FMU's C: {' / '.join(message)}")
        return f"binaries/{platform}/{library}", (Path(folder) / library).read_bytes()


def _zip(path: Path, xml: str, sources: dict[str, str], binary: tuple[str, bytes] | None) -> None:
    entries: list[tuple[str, bytes, int]] = [("modelDescription.xml", xml.encode(), 0o644)]
    if binary is not None:
        entries.append((binary[0], binary[1], 0o755))
    entries += [(f"sources/{name}", text.encode(), 0o644) for name, text in sorted(sources.items())]
    with zipfile.ZipFile(path, "x", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, data, mode in entries:
            info = zipfile.ZipInfo(name, date_time=ZIP_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = (0o100000 | mode) << 16
            info.create_system = 3  # Unix: the mode above is read
            archive.writestr(info, data)


@dataclass(frozen=True)
class _Built:
    """What the export made: names, the binary (path in the FMU, bytes), the file's bytes."""

    identifier: str
    guid: str
    binary: tuple[str, bytes] | None
    compiler: str | None
    data: bytes


def _summary(
    model: Model,
    layout: FmuLayout,
    settings: FmuSettings,
    target: Path,
    built: _Built,
    elapsed: float,
) -> FmuSummary:
    binary, compiler, data = built.binary, built.compiler, built.data
    return FmuSummary(
        path=str(target),
        fmi_version=FMI_VERSION,
        fmi_type="co-simulation",
        model_identifier=built.identifier,
        guid=built.guid,
        problem=model.problem.name,
        platform=None if binary is None else binary[0].split("/")[1],
        compiler=None if compiler is None else _version_line(compiler),
        states=layout.n_states,
        engines=layout.n_engines,
        modes=model.layout.n_eta,
        max_step_s=settings.max_step_s,
        inputs=list(layout.names("input")),
        outputs=list(layout.names("output")),
        parameters={v.name: float(v.start or 0.0) for v in layout.variables
                    if v.causality == "parameter"},
        size_bytes=len(data),
        sha256=hashlib.sha256(data).hexdigest(),
        export_time_s=elapsed,
    )  # fmt: skip


def _version_line(compiler: str) -> str:
    try:
        answer = subprocess.run(
            [compiler, "--version"], capture_output=True, text=True, timeout=60, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return Path(compiler).name
    lines = answer.stdout.strip().splitlines()
    return lines[0] if lines else Path(compiler).name
