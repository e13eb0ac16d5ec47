"""The transfer ends on the debris' orbit; the shipped problems all say so."""

from __future__ import annotations

import dataclasses

import pytest

from casadi_debris.config import check_transfer_end, load_problem, shipped_problems
from casadi_debris.errors import ProblemFileError


@pytest.mark.parametrize("name", sorted(shipped_problems()))
def test_every_shipped_transfer_ends_on_its_debris_orbit(name: str) -> None:
    check_transfer_end(load_problem(shipped_problems()[name]))


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"to_altitude_km": 685.001}, "transfer.to_altitude_km"),
        ({"to_inclination_deg": 98.2}, "transfer.to_inclination_deg"),
    ],
)
def test_a_transfer_ending_elsewhere_is_refused_by_name(change: dict, key: str) -> None:
    problem = load_problem("paper")
    moved = dataclasses.replace(problem, transfer=dataclasses.replace(problem.transfer, **change))
    with pytest.raises(ProblemFileError, match=key):
        check_transfer_end(moved)
