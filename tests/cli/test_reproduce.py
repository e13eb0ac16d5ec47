"""The verdict table ``reproduce`` and ``design`` print from their records."""

from __future__ import annotations

import json
import re

import pytest

from casadi_debris.cli.reproduce import TABLE_KEYS, echo_verdicts
from casadi_debris.report import ReproductionRow, ReproductionSummary


def _summary() -> tuple[ReproductionSummary, list[ReproductionRow]]:
    rows = [
        ReproductionRow("mass_kg", "total mass [kg]", "668", "±0.5", "667.1", (667.1,), False),
        ReproductionRow("x", "an unjudged row", "1", "—", "2", (2.0,), None),
    ]
    summary = ReproductionSummary(
        problem="paper", problem_sha256="0" * 64, controller_path="/c.json", quick=True,
        workers=1, time_s=1.0, reproduced=0, rows=2, table=tuple(r.entry() for r in rows),
        out_dir="/report",
    )  # fmt: skip
    return summary, rows


def test_the_table_prints_each_rows_columns_and_verdict(capsys: pytest.CaptureFixture) -> None:
    summary, rows = _summary()
    echo_verdicts(summary, summary.table, TABLE_KEYS, "0 of 2 rows reproduced", as_json=False)
    lines = capsys.readouterr().out.splitlines()
    assert lines[-1] == "0 of 2 rows reproduced"
    for row in rows:
        [line] = [line for line in lines if row.result in line]
        cells = [row.result, row.paper, row.accepted, row.ours, row.verdict]
        assert re.split(r"\s{2,}", line.strip()) == cells


def test_as_json_the_summary_is_printed_whole(capsys: pytest.CaptureFixture) -> None:
    summary, _ = _summary()
    echo_verdicts(summary, summary.table, TABLE_KEYS, "unused", as_json=True)
    assert json.loads(capsys.readouterr().out) == summary.to_json()
