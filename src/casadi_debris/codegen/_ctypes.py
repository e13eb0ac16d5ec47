"""A compiled flight step loaded through ctypes: the bridge the tests and a
software-in-the-loop run use to call the C from Python."""

from __future__ import annotations

import ctypes
import json
import shutil
import subprocess
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.errors import CompileError
from casadi_debris.processes import c_compiler

LIBRARY_FLAGS = ("-std=c99", "-O2", "-fPIC", "-shared")
SOURCES = ("cdb_step.c", "cdb_alloc.c", "cdb_law.c", "cdb_data.c")


def compile_library(
    folder: Path,
    *,
    compiler: str | None = None,
    flags: Sequence[str] = (),
    name: str = "libcdb_flight.so",
) -> Path:
    """Compile an export's sources into a shared library in ``folder``.

    Parameters
    ----------
    folder : Path
        An export written by :func:`~casadi_debris.codegen.write_flight_code`.
    compiler : str, optional
        C compiler (default :func:`~casadi_debris.processes.c_compiler`: ``$CC``, gcc, cc, clang).
    flags : sequence of str
        Extra flags (warnings, sanitizers).
    name : str
        File name of the library.

    Raises
    ------
    CompileError
        No compiler, or it failed (its message is kept).
    """
    chosen = compiler or c_compiler()
    if chosen is None or shutil.which(chosen) is None:
        raise CompileError("no C compiler found ($CC, gcc, cc or clang)")
    command = [chosen, *LIBRARY_FLAGS, *flags, "-o", name, *SOURCES, "-lm"]
    done = subprocess.run(command, cwd=folder, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise CompileError(f"{' '.join(command)} failed: {done.stderr.strip()[:2000]}")
    return folder / name


def _structures(sizes: dict[str, int]) -> tuple[type[ctypes.Structure], type[ctypes.Structure]]:
    real = ctypes.c_double
    n_e, n_c = sizes["engines"], sizes["cubesats"]

    class Inputs(ctypes.Structure):
        _fields_ = [
            ("time_s", real),
            ("q_BN", real * 4),
            ("cubesat_failed", ctypes.c_ubyte * n_c),
            ("engine_stage", ctypes.c_int * n_e),
        ]

    class Outputs(ctypes.Structure):
        _fields_ = [
            ("thrust_N", real * n_e),
            ("engine_stage", ctypes.c_int * n_e),
            ("demand_Nm", real * 3),
            ("torque_Nm", real * 3),
            ("error_rad", real * 3),
            ("reference_BN", real * 4),
            ("scale", real),
            ("qp_iterations", ctypes.c_int),
            ("flags", ctypes.c_uint),
        ]

    return Inputs, Outputs


@dataclass
class StepOutputs:
    """One period's outputs of the C step (SI; stages 1-based, 0 when the engine is off)."""

    thrust_N: np.ndarray
    engine_stage: np.ndarray
    demand_Nm: np.ndarray
    torque_Nm: np.ndarray
    error_rad: np.ndarray
    reference_BN: np.ndarray
    scale: float
    flags: int
    qp_iterations: int
    status: int


class FlightLibrary:
    """A compiled export, stepped from Python (double-precision build).

    Parameters
    ----------
    library : Path
        The shared library (:func:`compile_library`).
    manifest : dict or Path
        The export's ``manifest.json`` (its sizes), or its path.
    """

    def __init__(self, library: Path, manifest: dict[str, Any] | Path) -> None:
        content: dict[str, Any] = (
            json.loads(manifest.read_text()) if isinstance(manifest, Path) else manifest
        )
        self.sizes: dict[str, int] = dict(content["sizes"])
        self.period_s = float(content["period_s"])
        self._lib = ctypes.CDLL(str(library))
        self._inputs_type, self._outputs_type = _structures(self.sizes)
        self._lib.cdb_state_bytes.restype = ctypes.c_ulong
        self._state = ctypes.create_string_buffer(int(self._lib.cdb_state_bytes()))
        self._lib.cdb_step.restype = ctypes.c_int
        self._lib.cdb_allocate.restype = ctypes.c_uint
        self.reset()

    def reset(self) -> None:
        """The state of ``cdb_init``: controller at rest, no warm start."""
        self._lib.cdb_init(self._state)

    def step(
        self,
        time_s: float,
        q_BN: Sequence[float],
        failed: Sequence[int] | None = None,
        stage: Sequence[int] | None = None,
    ) -> StepOutputs:
        """One ``cdb_step``.

        Parameters
        ----------
        time_s : float
        q_BN : sequence of 4 floats
            Measured attitude, scalar first.
        failed : sequence of int, optional
            Per CubeSat, 1 when failed (default none).
        stage : sequence of int, optional
            Active stage of each engine, 1-based, 0 for none (default 1 each).
        """
        n_e, n_c = self.sizes["engines"], self.sizes["cubesats"]
        inputs = self._inputs_type()
        inputs.time_s = float(time_s)
        for i, v in enumerate(q_BN):
            inputs.q_BN[i] = float(v)
        for i in range(n_c):
            inputs.cubesat_failed[i] = 0 if failed is None else int(failed[i])
        for i in range(n_e):
            inputs.engine_stage[i] = 1 if stage is None else int(stage[i])
        out = self._outputs_type()
        status = self._lib.cdb_step(ctypes.byref(inputs), ctypes.byref(out), self._state)
        return StepOutputs(
            thrust_N=np.ctypeslib.as_array(out.thrust_N).copy(),
            engine_stage=np.ctypeslib.as_array(out.engine_stage).copy(),
            demand_Nm=np.ctypeslib.as_array(out.demand_Nm).copy(),
            torque_Nm=np.ctypeslib.as_array(out.torque_Nm).copy(),
            error_rad=np.ctypeslib.as_array(out.error_rad).copy(),
            reference_BN=np.ctypeslib.as_array(out.reference_BN).copy(),
            scale=float(out.scale),
            flags=int(out.flags),
            qp_iterations=int(out.qp_iterations),
            status=int(status),
        )

    def allocate(
        self, demand_Nm: Sequence[float], limit_N: Sequence[float]
    ) -> tuple[np.ndarray, float, int, int]:
        """``cdb_allocate``: thrust [N], scale, flags and QP iterations for one demand."""
        n_e = self.sizes["engines"]
        demand = (ctypes.c_double * 3)(*[float(v) for v in demand_Nm])
        limits = (ctypes.c_double * n_e)(*[float(v) for v in limit_N])
        thrust = (ctypes.c_double * n_e)()
        scale = ctypes.c_double()
        iterations = ctypes.c_int(0)
        flags = self._lib.cdb_allocate(
            demand, limits, thrust, ctypes.byref(scale), ctypes.byref(iterations), self._state
        )
        return (
            np.ctypeslib.as_array(thrust).copy(),
            float(scale.value),
            int(flags),
            iterations.value,
        )
