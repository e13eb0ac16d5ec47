"""Cases of a Monte Carlo campaign: the nominal plant, the corners, seeded samples.

Every case carries what is needed to re-run it alone: its id, its kind and
index, and for random samples the seed (sample ``i`` of seed ``s`` is drawn
from its own generator ``default_rng([s, i])``, so it does not depend on
how many samples the campaign had).

Corners: the two extremes of every relative uncertainty of the problem
(inertia per axis, mass, first bending frequency: 2^5 = 32) times
``montecarlo.corner_array_angles`` array angles spread evenly over the angle
range (a debris without arrays has no angle and no bending frequency:
2^4). With the paper's +-180 deg the two extremes are one attitude of the
arrays, so the angles are spaced by 360 deg / count: 8 angles (every 45 deg)
give the paper's 256 runs. For a smaller range the angles run from one
extreme to the other, both included.
"""

from __future__ import annotations

import itertools
import zlib
from dataclasses import dataclass, field

import numpy as np

from casadi_debris.config import FailureEvent, Problem
from casadi_debris.dynamics import Model
from casadi_debris.errors import SimulationError
from casadi_debris.records import Record
from casadi_debris.robust.plant import corner_angles, parameters_from_normalized

__all__ = [
    "Case",
    "corner_angles",
    "corner_case",
    "corner_cases",
    "nominal_case",
    "sample_case",
    "sample_cases",
]


@dataclass(frozen=True, eq=False)
class Case:
    """One plant of a campaign.

    Attributes
    ----------
    case_id : str
        ``"nominal"``, ``"corner-0017"`` or ``"sample-0042"``.
    kind : str
        ``"nominal"``, ``"corner"`` or ``"sample"``.
    index : int
    seed : int or None
        Seed of a random sample.
    normalized : ndarray, shape (n_parameters,)
        Position in the uncertainty box, -1 .. 1 per parameter (ordered as
        ``model.parameter_names``).
    parameters : ndarray, shape (n_parameters,)
        Model parameter vector.
    failures : tuple of FailureEvent or None
        CubeSats, stages or engines lost during the run (a failure campaign's
        case); None flies the problem's own ``[[simulation.failures]]``.
    varied : tuple of (str, float)
        The quantities of ``[[montecarlo.vary]]`` and their values in this case
        (a ``"varied"`` case; empty otherwise), in the order of the file.
    """

    case_id: str
    kind: str
    index: int
    seed: int | None
    normalized: np.ndarray
    parameters: np.ndarray
    failures: tuple[FailureEvent, ...] | None = None
    varied: tuple[tuple[str, float], ...] = ()

    @property
    def file_values(self) -> tuple[tuple[str, float], ...]:
        """The varied keys of the problem file (not model parameters): the case's problem
        is the campaign's read again with them (see
        :func:`~casadi_debris.config.problem_with_values`)."""
        return tuple((name, value) for name, value in self.varied if "." in name or "[" in name)

    def noise_seed(self, problem: Problem) -> int | None:
        """The seed of the case's sensor and engine noise (realistic sensors only).

        The nominal case keeps the problem's ``[sensors] seed`` (None); every other case
        draws its own from that seed, its kind and its index, so that the cases of a
        campaign see different noise and each one re-runs alone with the same noise.
        """
        if self.kind == "nominal":
            return None
        entropy = [problem.sensors.seed, zlib.crc32(self.kind.encode()), self.index]
        return int(np.random.SeedSequence(entropy).generate_state(1)[0])

    def identity(self) -> CaseIdentity:
        """What names the case in its results and re-runs it alone."""
        return CaseIdentity(
            self.case_id,
            self.kind,
            self.index,
            self.seed,
            tuple(self.normalized.tolist()),
            dict(self.varied),
        )


@dataclass(frozen=True)
class CaseIdentity(Record):
    """A case as its results name it (see :class:`Case`); ``varied`` by quantity name."""

    case_id: str
    kind: str
    index: int
    seed: int | None
    normalized: tuple[float, ...]
    varied: dict[str, float] = field(default_factory=dict)


def corner_cases(model: Model) -> list[Case]:
    """Every combination of the uncertainty extremes (the paper's 256)."""
    problem = model.problem
    layout = model.parameter_layout
    first = layout.index(layout.angle_names[0]) if layout.has_array_angle else layout.size
    n_angles = layout.array_angles
    others = list(itertools.product((-1.0, 1.0), repeat=layout.size - n_angles))
    angles = list(itertools.product(corner_angles(problem), repeat=n_angles))
    # Angles outermost, so that the paper's corner numbering stays what it was.
    z_all = np.array(
        [
            np.concatenate([combo[:first], angle, combo[first:]])
            for angle in angles
            for combo in others
        ]
    )
    p_all = parameters_from_normalized(model, z_all)
    return [
        Case(f"corner-{i:04d}", "corner", i, None, z_all[i], p_all[i]) for i in range(len(z_all))
    ]


def corner_case(model: Model, index: int) -> Case:
    """Corner ``index`` (0-based) of :func:`corner_cases`."""
    cases = corner_cases(model)
    if not 0 <= index < len(cases):
        raise SimulationError(f"corner index runs from 0 to {len(cases) - 1}; got {index}")
    return cases[index]


def sample_case(model: Model, index: int, seed: int) -> Case:
    """Random sample ``index`` of seed ``seed``, uniform in the uncertainty box."""
    if index < 0 or seed < 0:
        raise SimulationError(f"sample index and seed must not be negative; got {index}, {seed}")
    z = np.random.default_rng([seed, index]).uniform(-1.0, 1.0, model.parameter_layout.size)
    p = parameters_from_normalized(model, z)
    return Case(f"sample-{index:04d}", "sample", index, seed, z, p)


def sample_cases(model: Model, count: int, seed: int) -> list[Case]:
    """The first ``count`` random samples of ``seed``."""
    return [sample_case(model, i, seed) for i in range(count)]


def nominal_case(model: Model) -> Case:
    """The nominal plant."""
    zero = np.zeros(model.parameter_layout.size)
    return Case("nominal", "nominal", 0, None, zero, model.nominal_parameters)


@dataclass(frozen=True, eq=False)
class CaseBatch:
    """Cases a worker runs together, in a compiled function of ``slots`` cases."""

    cases: tuple[Case, ...]
    slots: int


def batches(cases: list[Case], size: int, workers: int) -> list[CaseBatch]:
    """``cases`` in batches of at most ``size``, at least one per worker where there are enough.

    The slots (the compiled function's cases) are a power of two, so that few
    libraries serve every campaign; the last batch leaves some unused.
    """
    per_worker = -(-len(cases) // max(1, workers))
    slots = 1
    while slots < min(size, per_worker):
        slots *= 2
    slots = min(slots, max(1, size))
    return [CaseBatch(tuple(cases[i : i + slots]), slots) for i in range(0, len(cases), slots)]
