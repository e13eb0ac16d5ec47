"""Cases of a campaign that varies the quantities of ``[[montecarlo.vary]]``.

The campaign is every combination of the ``corners`` quantities (``2^k``
cases; one when there are none) times ``samples`` draws of the ``uniform`` and
``normal`` quantities (one draw when there are none). Case ``i`` takes corner
combination ``i mod 2^k`` and draw ``j = i div 2^k``; draw ``j`` of seed ``s``
comes from its own generator ``default_rng([s, j])``, one number per random
quantity in the order of the file, so that it depends neither on the count of
cases nor on the corners (every corner combination meets the same draws:
common random numbers, which keep a corner's effect apart from the draws').

A normal is truncated to ``[low, high]`` (by default the key's allowed range)
and drawn by inverting its distribution function, so one uniform number
makes one value whatever the truncation.

Model parameters (``mass_kg``, ...) go into the case's parameter vector and
cost nothing; file keys are kept in :attr:`Case.varied`, and the case's
problem and model are rebuilt from them when it runs (see
:func:`~casadi_debris.campaigns.run_case`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
from scipy import special

from casadi_debris.campaigns._cases import Case
from casadi_debris.config import Problem, VariedQuantity
from casadi_debris.dynamics import Model
from casadi_debris.errors import ModelError, ProblemFileError, SimulationError
from casadi_debris.robust.plant import normalized_from_parameters

CASE_KIND = "varied"


def corner_values(quantities: Sequence[VariedQuantity]) -> np.ndarray:
    """Every combination of the corner quantities' ``low`` and ``high``, shape (2^k, k).

    The first quantity changes slowest (``itertools.product`` order).
    """
    corners = [(q.low, q.high) for q in quantities if q.distribution == "corners"]
    rows = list(itertools.product(*corners))
    return np.array(rows, dtype=float).reshape(len(rows), len(corners))


def corner_row(quantities: Sequence[VariedQuantity], corner: int) -> list[float]:
    """Row ``corner`` of :func:`corner_values` without building the others: bit ``k - 1 - j``
    of ``corner`` picks ``high`` for the ``j``-th corner quantity."""
    corners = [q for q in quantities if q.distribution == "corners"]
    k = len(corners)
    return [
        float(q.high if (corner >> (k - 1 - j)) & 1 else q.low)  # type: ignore[arg-type]
        for j, q in enumerate(corners)
    ]


def draw(quantity: VariedQuantity, u: float) -> float:
    """The value of a ``uniform`` or ``normal`` quantity at the uniform number ``u`` in [0, 1).

    Parameters
    ----------
    quantity : VariedQuantity
    u : float
        One draw of a uniform distribution on [0, 1).

    Returns
    -------
    float
        ``low + u (high - low)``, or the truncated normal's quantile at ``u``.
    """
    low, high = quantity.low, quantity.high
    if quantity.distribution == "uniform":
        assert low is not None and high is not None
        return float(low + u * (high - low))
    if quantity.distribution != "normal":
        raise SimulationError(f"{quantity.path}: {quantity.distribution} values are not drawn")
    mean, sigma = float(quantity.mean or 0.0), float(quantity.sigma or 0.0)
    a = -math.inf if low is None else (low - mean) / sigma
    b = math.inf if high is None else (high - mean) / sigma
    cdf_a, cdf_b = special.ndtr(a), special.ndtr(b)
    value = mean + sigma * float(special.ndtri(cdf_a + u * (cdf_b - cdf_a)))
    # Rounding at the far tails may step a hair outside the truncation.
    return float(
        np.clip(value, -math.inf if low is None else low, math.inf if high is None else high)
    )


def draws(quantities: Sequence[VariedQuantity], seed: int, draw_index: int) -> list[float]:
    """The random quantities' values of draw ``draw_index`` of ``seed``, in the file's order."""
    random = [q for q in quantities if q.distribution != "corners"]
    u = np.random.default_rng([seed, draw_index]).uniform(0.0, 1.0, len(random))
    return [draw(q, float(x)) for q, x in zip(random, u, strict=True)]


def varied_count(problem: Problem, samples: int) -> int:
    """Cases of the campaign: ``2^k`` corner combinations times the draws."""
    quantities = problem.montecarlo.vary
    n_corners = 2 ** sum(q.distribution == "corners" for q in quantities)
    random = any(q.distribution != "corners" for q in quantities)
    return n_corners * (samples if random else 1)


def varied_case(model: Model, index: int, seed: int) -> Case:
    """Case ``index`` (0-based) of the campaign ``[[montecarlo.vary]]`` describes.

    Raises
    ------
    ProblemFileError
        A model parameter the model does not have, or a value it refuses
        (naming ``montecarlo.vary[i]``).
    SimulationError
        A negative index or seed.
    """
    problem = model.problem
    quantities = problem.montecarlo.vary
    if not quantities:
        raise SimulationError("the problem varies nothing ([[montecarlo.vary]] is empty)")
    if index < 0 or seed < 0:
        raise SimulationError(f"case index and seed must not be negative; got {index}, {seed}")
    check_parameter_quantities(model)
    n_corners = 2 ** sum(q.distribution == "corners" for q in quantities)
    corner, draw_index = index % n_corners, index // n_corners
    drawn = iter(draws(quantities, seed, draw_index))
    picked = iter(corner_row(quantities, corner))
    values = [
        float(next(picked) if q.distribution == "corners" else next(drawn)) for q in quantities
    ]
    parameters = _parameters(model, quantities, values)
    return Case(
        f"varied-{index:04d}",
        CASE_KIND,
        index,
        seed,
        normalized_from_parameters(model, parameters),
        parameters,
        varied=tuple((q.path, v) for q, v in zip(quantities, values, strict=True)),
    )


def varied_cases(model: Model, samples: int, seed: int) -> list[Case]:
    """Every case of the campaign (see the module's description), in index order."""
    problem = model.problem
    return [varied_case(model, i, seed) for i in range(varied_count(problem, samples))]


def check_parameter_quantities(model: Model) -> None:
    """Refuse model parameters the model lacks and bounds it cannot take, naming the entry.

    Raises
    ------
    ProblemFileError
        ``montecarlo.vary[i].path`` (unknown parameter) or ``.low`` / ``.high``.
    """
    problem = model.problem
    for i, quantity in enumerate(problem.montecarlo.vary):
        if not quantity.is_parameter:
            continue
        where = f"montecarlo.vary[{i}]"
        if quantity.path not in model.parameter_layout.names:
            names = ", ".join(dict.fromkeys(model.parameter_layout.names))
            raise ProblemFileError(
                f"{where}.path",
                f"{quantity.path} is not a parameter of this model ({names})",
                problem.source,
            )
        for bound in ("low", "high"):
            value = getattr(quantity, bound)
            if value is None or not math.isfinite(value):
                continue
            try:
                model.nominal.replace(**{quantity.path: value})
            except ModelError as exc:
                raise ProblemFileError(f"{where}.{bound}", str(exc), problem.source) from None


def _parameters(
    model: Model, quantities: Sequence[VariedQuantity], values: list[float]
) -> np.ndarray:
    """The model's nominal parameter vector with the varied model parameters set."""
    problem = model.problem
    named = {q.path: v for q, v in zip(quantities, values, strict=True) if q.is_parameter}
    if not named:
        return model.nominal_parameters.copy()
    try:
        return model.nominal.replace(**named).to_vector()
    except ModelError as exc:
        raise ProblemFileError("montecarlo.vary", str(exc), problem.source) from None
