"""What a campaign and a single run share: the cases a campaign runs
(:class:`CaseSelection`), the one case a run flies (:func:`one_case`,
:func:`parameters_case`) and the record of a run (:class:`SimulationSummary`).

The campaign itself is :func:`casadi_debris.montecarlo`
(:mod:`casadi_debris.workflows._montecarlo`).
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.campaigns import (
    Case,
    corner_case,
    corner_cases,
    nominal_case,
    requirement_shortfalls,
    sample_case,
    sample_cases,
    varied_case,
    varied_cases,
)
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, Parameters
from casadi_debris.errors import InputShapeError, ModelError
from casadi_debris.records import FLATTENED, OPTIONAL, Record
from casadi_debris.robust.plant import Controller, normalized_from_parameters
from casadi_debris.simulation import ClosedLoopResult, RunSummary, SimulationError

LOGGER = logging.getLogger(__name__)

_SCHEDULER_ADDRESS = re.compile(r"(tcp|tls)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9.-]{1,253}):(\d{1,5})")

Progress = Callable[[int, int], None]
"""``progress(done, total)``: cases finished in this run, of the cases it runs."""


@dataclass(frozen=True)
class CaseSelection:
    """Which cases a campaign runs.

    Attributes
    ----------
    corners : bool
        Every corner of the uncertainty set (the default when ``samples`` is None
        and the problem has no ``[[montecarlo.vary]]``).
    samples : int, optional
        That many seeded random samples instead (of the uncertainty set, or the
        draws of ``[[montecarlo.vary]]``: see :mod:`casadi_debris.campaigns._sampling`).
    seed : int, optional
        Seed of the samples (default the problem's ``montecarlo.seed``).
    max_cases : int, optional
        Keep that many cases spread evenly over the list (a quick look).
    """

    corners: bool = False
    samples: int | None = None
    seed: int | None = None
    max_cases: int | None = None

    def cases(self, model: Model) -> list[Case]:
        """The chosen cases, in campaign order."""
        problem = model.problem
        if self.samples is not None and self.corners:
            raise InputShapeError("give either --corners or --samples, not both")
        if problem.montecarlo.vary and not self.corners:
            seed = problem.montecarlo.seed if self.seed is None else self.seed
            count = problem.montecarlo.samples if self.samples is None else self.samples
            chosen = varied_cases(model, count, seed)
        elif self.samples is not None:
            seed = problem.montecarlo.seed if self.seed is None else self.seed
            chosen = sample_cases(model, self.samples, seed)
        else:
            chosen = corner_cases(model)
        if self.max_cases is not None and self.max_cases < len(chosen):
            picks = np.unique(np.linspace(0, len(chosen) - 1, self.max_cases).round().astype(int))
            chosen = [chosen[i] for i in picks]
        return chosen


def one_case(model: Model, corner: int | None, sample: int | None, seed: int | None) -> Case:
    """Corner ``corner``, sample ``sample`` (with ``seed``), or the nominal case.

    With ``[[montecarlo.vary]]``, ``sample`` is that campaign's case of that index.
    """
    problem = model.problem
    if corner is not None and sample is not None:
        raise InputShapeError("give either --corner or --sample, not both")
    if corner is not None:
        try:
            return corner_case(model, corner)
        except SimulationError as exc:
            raise InputShapeError(f"--corner: {exc}") from None
    if sample is not None:
        seed = problem.montecarlo.seed if seed is None else seed
        if problem.montecarlo.vary:
            try:
                return varied_case(model, sample, seed)
            except SimulationError as exc:
                raise InputShapeError(f"--sample: {exc}") from None
        return sample_case(model, sample, seed)
    return nominal_case(model)


def parameters_case(model: Model, values: Any, case_id: str) -> Case:
    """A case at given parameter values: ``values`` maps every model parameter name
    (``inertia_scale_x`` ... ``bending_frequency_scale``, SI) to its value, as the
    ``parameters`` of a file that ``worstcase`` writes.

    Raises
    ------
    InputShapeError
        Not a mapping, unknown or missing names, or values that are not positive
        finite numbers where they must be.
    """
    where = "--parameters: parameters"
    if not isinstance(values, dict):
        raise InputShapeError(f"{where}: expected an object of name: value")
    if any(isinstance(v, bool) or not isinstance(v, int | float) for v in values.values()):
        raise InputShapeError(f"{where}: every value must be a number")
    try:
        named = Parameters.from_mapping(model.parameter_layout, values)
    except ModelError as exc:
        raise InputShapeError(f"{where}: {exc}") from None
    p = named.to_vector()
    z = normalized_from_parameters(model, p)
    return Case(case_id, "parameters", 0, None, z, p)


@dataclass(frozen=True, kw_only=True)
class SimulationSummary(Record):
    """A run's figures and what identifies it: the case, its seed, the files, the plants.

    Attributes
    ----------
    problem, problem_sha256, plant_sha256 : str
    controller_plant_sha256 : str or None
        The plant the controller was designed for (None: not recorded).
    case_id : str
    seed : int or None
    controller_path : str
    out_dir : str or None
        Where the run was written, if it was.
    run : RunSummary
        The figures, written into the same JSON object.
    requirements_met : bool or None
        Whether the run meets the problem's ``[requirements]`` (None: not judged).
    requirement_shortfalls : tuple of str or None
        How it misses them, one sentence each (None when met or not judged).
    """

    problem: str
    problem_sha256: str
    plant_sha256: str
    controller_plant_sha256: str | None
    case_id: str
    seed: int | None
    controller_path: str
    out_dir: str | None = None
    run: RunSummary = field(metadata=FLATTENED)
    requirements_met: bool | None = field(default=None, metadata=OPTIONAL)
    requirement_shortfalls: tuple[str, ...] | None = field(default=None, metadata=OPTIONAL)

    def __getattr__(self, name: str) -> Any:
        # The JSON form flattens ``run`` into the record, so ``summary.max_error_deg`` reads
        # in Python as it does in summary.json.
        if name.startswith("__") or name == "run":
            raise AttributeError(name)
        return getattr(self.run, name)


def run_summary(
    problem: Problem,
    case: Case,
    result: ClosedLoopResult,
    controller_path: Path,
    record: Controller | None = None,
) -> SimulationSummary:
    """A run's figures plus what identifies it (case, seed, files, the plants), judged
    against the problem's ``[requirements]``."""
    run = result.summary()
    shortfalls = requirement_shortfalls(problem, run)
    return SimulationSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        plant_sha256=problem.plant_sha256,
        controller_plant_sha256=None if record is None else record.problem_sha256,
        case_id=case.case_id,
        seed=case.seed,
        controller_path=str(controller_path),
        run=run,
        requirements_met=not shortfalls,
        requirement_shortfalls=shortfalls or None,
    )


def check_scheduler_address(address: str) -> None:
    """Refuse anything but ``tcp://host:port`` or ``tls://host:port`` (no other schemes).

    Dask unpickles what a scheduler sends: only the address the user gave is
    contacted, and only over Dask's own TCP or TLS transports.
    """
    match = _SCHEDULER_ADDRESS.fullmatch(address)
    if match is None or not 1 <= int(match[3]) <= 65535:
        raise InputShapeError(
            f"--scheduler: expected tcp://host:port or tls://host:port, got {address!r}"
        )
