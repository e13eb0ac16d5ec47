"""The cases of a failure campaign: counts, 1-based ids, the failures a run takes."""

from __future__ import annotations

import itertools
from math import comb

import numpy as np
import pytest

from casadi_debris.config import Problem
from casadi_debris.studies.failures import (
    FAILED_STAGE,
    FailureCase,
    FailureStudyError,
    case_count,
    failure_cases,
)


def test_the_paper_swarm_has_24_single_and_276_double_failures_and_24_stage_cases() -> None:
    cases = failure_cases(24, 2, stages=True)
    singles = [c for c in cases if len(c.cubesats) == 1]
    doubles = [c for c in cases if len(c.cubesats) == 2]
    stages = [c for c in cases if c.stage_of]
    assert (len(singles), len(doubles), len(stages)) == (24, 276, 24)
    assert len(cases) == case_count(24, 2, stages=True) == 324
    # Every pair once, as a brute-force double loop finds them.
    pairs = {(i, j) for i in range(24) for j in range(24) if i < j}
    assert {c.cubesats for c in doubles} == pairs
    assert len({c.case_id for c in cases}) == len(cases)


@pytest.mark.parametrize(("n", "k"), [(6, 1), (6, 3), (7, 7), (12, 4)])
def test_counts_are_sums_of_binomials(n: int, k: int) -> None:
    cases = failure_cases(n, k, stages=False)
    assert len(cases) == sum(comb(n, size) for size in range(1, k + 1))
    expected = {
        combo for size in range(1, k + 1) for combo in itertools.combinations(range(n), size)
    }
    assert {c.cubesats for c in cases} == expected


@pytest.mark.parametrize("bad", [0, -1, 25, 100])
def test_a_count_outside_the_swarm_is_refused(bad: int) -> None:
    with pytest.raises(FailureStudyError, match=r"max_failed must lie in 1\.\.24"):
        failure_cases(24, bad)


def test_ids_are_one_based_for_users() -> None:
    case = FailureCase(cubesats=(2, 16))
    assert case.case_id == "failed-3-17"
    assert case.label == "CubeSat 3, 17"
    stage = FailureCase(stage_of=(0,))
    assert stage.case_id == "stage-1"
    assert stage.label == f"stage {FAILED_STAGE + 1} of CubeSat 1" == "stage 1 of CubeSat 1"
    assert FailureCase().case_id == "none"


def test_a_failed_cubesat_takes_its_engines_out_and_a_failed_stage_hands_over(
    problem: Problem,
) -> None:
    state = FailureCase(cubesats=(2, 16)).propulsion(problem)
    assert np.flatnonzero(~state.available).tolist() == [2, 16]
    staged = FailureCase(stage_of=(4,)).propulsion(problem)
    assert staged.available.all()
    assert staged.active_stage[4] == 1 and staged.active_stage[3] == 0
    # One stage of propellant fewer at the same thrust: the firing time left drops by a third.
    life = staged.remaining_life_s()
    assert life[4] == pytest.approx(life[3] * 2 / 3, rel=1e-12)
    events = FailureCase(cubesats=(2,), stage_of=(4,)).events
    assert [(e.time_s, e.cubesat, e.stage) for e in events] == [(0.0, 2, None), (0.0, 4, 0)]
