"""The controller record round-trips through plain data and rejects bad files."""

from __future__ import annotations

import json

import control
import numpy as np
import pytest

from casadi_debris.errors import ProblemFileError
from casadi_debris.robust.plant import Controller


def _record():
    reduced = control.ss(np.diag([-1.0, -2.0]), np.ones((2, 3)), np.ones((3, 2)), np.eye(3))
    full = control.ss(np.diag([-1.0, -2.0, -3.0]), np.ones((3, 3)), np.ones((3, 3)), np.eye(3))
    return Controller(reduced, full, 0.98, 0.99, "abc", 7, {"mu_per_iteration": [1.2, 0.98]})


def test_round_trip_through_json():
    record = _record()
    data = json.loads(json.dumps(record.to_dict()))
    assert data["order_full"] == 3 and data["order_reduced"] == 2
    assert len(data["A"]) == 2 and len(data["B"][0]) == 3
    back = Controller.from_dict(data)
    omega = np.logspace(-2, 2, 7)
    np.testing.assert_allclose(
        back.reduced.frequency_response(omega).frdata,
        record.reduced.frequency_response(omega).frdata,
    )
    assert back.full.nstates == 3
    assert back.details["mu_per_iteration"] == [1.2, 0.98]
    assert back.seed == 7 and back.problem_sha256 == "abc"


def test_missing_and_bad_keys_named():
    data = _record().to_dict()
    del data["A"]
    with pytest.raises(ProblemFileError, match="A: missing"):
        Controller.from_dict(data, "k.json")
    data = _record().to_dict()
    del data["mu_peak"]  # the μ bookkeeping is a design's, a plain controller has none
    assert Controller.from_dict(data).mu_peak is None
    data["mu_peak_reduced"] = -1.0
    with pytest.raises(ProblemFileError, match="mu_peak_reduced: must be a non-negative"):
        Controller.from_dict(data)
    data = _record().to_dict()
    data["B"] = [[1.0, 2.0]]
    with pytest.raises(ProblemFileError, match="3-input, 3-output"):
        Controller.from_dict(data)
    data = _record().to_dict()
    data["D"][0][0] = float("nan")
    with pytest.raises(ProblemFileError, match="finite"):
        Controller.from_dict(data)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        (lambda d: d.__setitem__("B", d["B"][:-1]), "B"),
        (lambda d: d.__setitem__("A", [1.0, 2.0, 3.0]), "A"),
        (lambda d: d["C"][0].__setitem__(0, 1e308), "C"),
        (lambda d: d.__setitem__("format_version", 99), "format_version"),
        (lambda d: d.__setitem__("mu_peak", "high"), "mu_peak"),
    ],
)
def test_a_damaged_controller_file_is_refused_naming_the_key(change, key) -> None:
    import copy

    from casadi_debris.config import default_controller_path

    data = copy.deepcopy(json.loads(default_controller_path().read_text()))
    change(data)
    with pytest.raises(ProblemFileError, match=f"^ctl.json: {key}: "):
        Controller.from_dict(data, "ctl.json")
