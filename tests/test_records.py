"""One JSON form for every result: records round-trip, flatten, and refuse what they lack."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np
import pytest

from casadi_debris.campaigns import CaseIdentity, CaseSummary
from casadi_debris.records import FLATTENED, OPTIONAL, Record, to_jsonable
from casadi_debris.simulation import EventSummary
from run_summaries import zero_run_summary


@dataclass(frozen=True)
class Inner(Record):
    name: str
    values: tuple[float, ...]


@dataclass(frozen=True)
class Outer(Record):
    inner: Inner = field(metadata=FLATTENED)
    children: tuple[Inner, ...]
    by_axis: dict[str, float]
    maybe: float | None


def test_a_record_comes_back_from_its_json_text() -> None:
    record = Outer(Inner("a", (1.0, 2.5)), (Inner("b", ()),), {"+x": 3.0}, None)
    text = json.dumps(record.to_json())
    assert json.loads(text) == {
        "name": "a",
        "values": [1.0, 2.5],
        "children": [{"name": "b", "values": []}],
        "by_axis": {"+x": 3.0},
        "maybe": None,
    }
    assert Outer.from_json(json.loads(text)) == record


def test_numpy_becomes_plain_and_non_finite_becomes_null() -> None:
    value = to_jsonable({"a": np.arange(3), "b": np.float32(0.5), "c": np.inf, "d": np.bool_(1)})
    assert value == {"a": [0, 1, 2], "b": 0.5, "c": None, "d": True}
    assert type(value["a"][0]) is int and type(value["d"]) is bool


def test_unknown_keys_and_missing_fields_are_refused() -> None:
    data = Outer(Inner("a", ()), (), {}, 1.0).to_json()
    with pytest.raises(ValueError, match=r"unknown field.*extra"):
        Outer.from_json({**data, "extra": 1})
    del data["name"]
    with pytest.raises(TypeError):
        Outer.from_json(data)


def test_a_campaign_case_is_one_flat_row_that_reads_back() -> None:
    event = EventSummary(5.0, "stage_depleted", 3, None, 1, 2, True, "CubeSat 3: stage 1 empty")
    run = zero_run_summary(max_error_deg=0.45, events=(event,), settle_time_s=None)
    case = CaseSummary(CaseIdentity("corner-0142", "corner", 142, None, (1.0, -1.0)), run)
    row = json.loads(json.dumps(case.to_json()))
    assert row["case_id"] == "corner-0142" and row["max_error_deg"] == 0.45
    assert row["events"][0]["cubesat"] == 3 and "run" not in row and "identity" not in row
    assert CaseSummary.from_json(row) == case
    assert math.isnan(CaseSummary.from_json({**row, "fuel_kg": None}).run.fuel_kg)


@dataclass(frozen=True)
class Stages(Record):
    name: str
    skipped: Inner | None = field(default=None, metadata=OPTIONAL)
    ran: Inner | None = field(default=None, metadata=OPTIONAL)


def test_an_optional_field_is_absent_when_none_and_none_when_absent() -> None:
    record = Stages("run", ran=Inner("b", (1.0,)))
    data = record.to_json()
    assert data == {"name": "run", "ran": {"name": "b", "values": [1.0]}}
    assert Stages.from_json(json.loads(json.dumps(data))) == record
    assert Stages.from_json({"name": "x"}) == Stages("x")
