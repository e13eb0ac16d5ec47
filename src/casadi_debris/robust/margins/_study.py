"""Margins of a controller on the nominal plant and over sampled uncertain plants.

The plants are linearised from the full model (all array modes, star tracker)
in design units, so the check covers what the truncated design plant left out.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from dataclasses import dataclass

import control
import numpy as np

from casadi_debris.config import Problem, limits
from casadi_debris.dynamics import build_model, linearization_function, linearize
from casadi_debris.errors import SynthesisError
from casadi_debris.parallel import ItemFailure, parallel_map
from casadi_debris.robust.margins._loop import (
    CHANNELS,
    LoopAtATime,
    LoopMargins,
    UnstableLoopError,
    disk_margins,
    loop_at_a_time,
)
from casadi_debris.robust.plant import (
    UncertaintySamples,
    frequency_response,
    sample_uncertainty,
)

DISK_GRID = np.logspace(-4, 2, 600)


@dataclass(frozen=True, eq=False)
class MarginStudy:
    """Nominal and sampled margins.

    Attributes
    ----------
    nominal : list of LoopMargins
        One per channel (x, y, z).
    nominal_disk : tuple of float
        (alpha, gain margin dB, phase margin deg) of the MIMO input loop.
    samples : UncertaintySamples
    sampled : ndarray, shape (n, 3, 3)
        Per sample and channel: gain margin dB, phase margin deg, delay margin s
        (NaN for samples whose closed loop is unstable).
    unstable : ndarray of bool, shape (n,)
    modes : str
    time_s : float
    """

    nominal: list[LoopMargins]
    nominal_disk: tuple[float, float, float]
    samples: UncertaintySamples
    sampled: np.ndarray
    unstable: np.ndarray
    modes: str
    time_s: float

    def sampled_min(self) -> dict[str, float]:
        """Worst gain, phase and delay margins over stable samples and channels."""
        stable = self.sampled[~self.unstable]
        if stable.size == 0:
            return {
                "gain_margin_db": float("nan"),
                "phase_margin_deg": float("nan"),
                "delay_margin_s": float("nan"),
            }
        return {
            "gain_margin_db": float(np.min(stable[:, :, 0])),
            "phase_margin_deg": float(np.min(stable[:, :, 1])),
            "delay_margin_s": float(np.min(stable[:, :, 2])),
        }


def margins_table(margins: list[LoopMargins]) -> dict[str, dict[str, float]]:
    """Per-channel margins keyed by axis."""
    return {
        axis: {
            "gain_margin_db": m.gain_margin_db,
            "upper_gain_margin_db": m.upper_gain_margin_db,
            "lower_gain_margin_db": m.lower_gain_margin_db,
            "phase_margin_deg": m.phase_margin_deg,
            "delay_margin_s": m.delay_margin_s,
            "crossover_rad_s": m.crossover_rad_s,
        }
        for axis, m in zip(CHANNELS, margins, strict=True)
    }


class _SampledMargins:
    """Margins of sampled plants around one controller, set up once per process.

    The model, its linearisation function and the controller's frequency
    response are built here, not per batch. Takes the controller as its
    (A, B, C, D) so that it crosses process boundaries.
    """

    def __init__(self, problem: Problem, matrices: tuple[np.ndarray, ...], modes: str):
        self.model = build_model(problem, modes=modes)
        self.function = linearization_function(self.model, sensor=True)
        self.loops = LoopAtATime(control.ss(*matrices))

    def __call__(self, parameters: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(n, 3, 3) margins (gain dB, phase deg, delay s per channel) and (n,) unstable flags."""
        sampled = np.full((len(parameters), 3, 3), np.nan)
        unstable = np.zeros(len(parameters), dtype=bool)
        for k, p in enumerate(parameters):
            plant = linearize(self.model, p, sensor=True, units="deg_mNm", function=self.function)
            try:  # LoopAtATime checks the closed-loop poles itself
                margins = self.loops(plant)
            except UnstableLoopError:
                unstable[k] = True
                continue
            for i, m in enumerate(margins):
                sampled[k, i] = (m.gain_margin_db, m.phase_margin_deg, m.delay_margin_s)
        return sampled, unstable


def _margins_of(margins: _SampledMargins, parameters: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return margins(parameters)


def margin_study(
    problem: Problem,
    controller: control.StateSpace,
    samples: int = 3000,
    seed: int | None = None,
    modes: str = "all",
    workers: int = 2,
    progress: Callable[[int, int], None] | None = None,
) -> MarginStudy:
    """Loop-at-a-time margins, nominal and over seeded samples of the uncertainty set.

    Parameters
    ----------
    problem : Problem
    controller : control.StateSpace
        Attitude error [deg] -> torque [mNm], u = K e.
    samples : int
        Number of sampled plants (the 64 corners first).
    seed : int, optional
        Default: the problem's uncertainty seed.
    modes : str
        Modes of the analysis plants (default all).
    workers : int
        Processes for the samples (1: in this process); see
        ``casadi_debris.parallel.parallel_map``.
    progress : callable, optional
        ``progress(done, total)`` after each batch, in completion order.

    Raises
    ------
    SynthesisError
        ``samples`` outside :data:`limits.MARGIN_SAMPLES` or ``seed`` outside 0 .. 2**32 - 1.
    Exception
        What the margins of a sampled plant raised (the other workers are
        stopped): one plant without margins makes the study unusable.
    """
    for name, value, allowed in (
        ("samples", samples, limits.MARGIN_SAMPLES),
        ("seed", seed, limits.SEED),
    ):
        problem_found = None if value is None else allowed.violation(value)
        if problem_found:
            raise SynthesisError(f"{name}: {problem_found}, got {value}")
    start = time.perf_counter()
    model = build_model(problem, modes=modes)
    nominal_plant = linearize(model, sensor=True, units="deg_mNm")
    nominal = loop_at_a_time(nominal_plant, controller)
    nominal_disk = disk_margins(nominal_plant, controller, DISK_GRID)
    drawn = sample_uncertainty(model, samples, seed)
    batches = np.array_split(drawn.parameters, max(1, min(len(drawn.parameters) // 50, 60)))
    matrices = tuple(np.asarray(m) for m in control.ssdata(controller))
    results: list[tuple[np.ndarray, np.ndarray] | None] = [None] * len(batches)
    done = 0
    with parallel_map(
        _margins_of,
        batches,
        functools.partial(_SampledMargins, problem, matrices, modes),
        workers=max(1, workers),  # 0 or less has always meant "in this process"
    ) as finished:
        for item in finished:
            if isinstance(item, ItemFailure):
                # A plant whose margins cannot be computed makes the study unusable.
                item.reraise()
            results[item.index] = item.value
            done += len(item.item)
            if progress:
                progress(done, len(drawn.parameters))
    parts = [r for r in results if r is not None]
    return MarginStudy(
        nominal=nominal,
        nominal_disk=nominal_disk,
        samples=drawn,
        sampled=np.concatenate([r[0] for r in parts]),
        unstable=np.concatenate([r[1] for r in parts]),
        modes=modes,
        time_s=time.perf_counter() - start,
    )


def loop_shapes(
    plant: control.StateSpace, controller: control.StateSpace, omega: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Singular values of S = (I + G K)^-1 and T_i = K G (I + K G)^-1, each (n_omega, 3)."""
    g = frequency_response(plant, omega)
    k = frequency_response(controller, omega)
    eye = np.eye(g.shape[1])
    sensitivity = np.linalg.inv(eye + g @ k)
    input_loop = k @ g
    complementary = input_loop @ np.linalg.inv(eye + input_loop)
    return (
        np.linalg.svd(sensitivity, compute_uv=False),
        np.linalg.svd(complementary, compute_uv=False),
    )
