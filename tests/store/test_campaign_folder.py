"""A campaign's folder: its record, its lock, bit-exact cases, and what a kill leaves."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from casadi_debris.campaigns import Bands, Case, CaseResult, CaseSummary, Extremes
from casadi_debris.errors import OutputError
from casadi_debris.store import (
    LOCK_NAME,
    MARKER_NAME,
    RECORD_NAME,
    CampaignFolder,
    CampaignIdentity,
    partial_folder,
    write_atomically,
)
from run_summaries import zero_run_summary


def _record(**changes) -> CampaignIdentity:
    fields = {
        "problem_name": "p",
        "problem_sha256": "a" * 64,
        "controller_sha256": "b" * 64,
        "case_kind": "sample",
        "seed": 1,
        "case_ids": ("sample-0000", "sample-0001"),
        "envelope_bin_s": 1.0,
    }
    return CampaignIdentity(**{**fields, **changes})


def _dead_pid() -> int:
    done = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    )
    return int(done.stdout)


def _outcome(index: int, rng: np.random.Generator) -> CaseResult:
    case = Case(f"sample-{index:04d}", "sample", index, 1, np.zeros(6), np.ones(6))
    values = rng.standard_normal((4, 5, 3)) * 1e-7  # not representable in float32
    bands = Bands(Extremes(values[0], values[1]), Extremes(values[2], values[3]))
    run = zero_run_summary(max_error_deg=float(values.max()), settle_time_s=None)
    return CaseResult(case, CaseSummary(case.identity(), run), bands)


def _write(folder: CampaignFolder, outcome: CaseResult) -> None:
    folder.write_case(outcome.case.case_id, outcome.bands.to_arrays(), outcome.summary)


def _finished(folder: CampaignFolder, cases: list[Case]) -> dict[str, CaseResult]:
    by_id = {case.case_id: case for case in cases}
    return folder.finished_cases(
        by_id,
        lambda case_id, summary, arrays: CaseResult.from_saved(by_id[case_id], summary, arrays),
    )


def _same_bands(first: Bands, second: Bands) -> bool:
    one, two = first.to_arrays(), second.to_arrays()
    return one.keys() == two.keys() and all(np.array_equal(one[k], two[k]) for k in one)


def test_record_differences_name_each_field() -> None:
    mine = _record()
    assert mine.differences(_record()) == []
    assert CampaignIdentity.from_dict(mine.to_dict()) == mine
    found = mine.differences(_record(seed=2, problem_sha256="c" * 64, case_ids=("x",)))
    assert any("seed (2 there, 1 here)" in f for f in found)
    assert any(f.startswith("problem file (sha256 cccccccccccc") for f in found)
    assert any("case list (1 cases there, 2 here)" in f for f in found)


def test_cases_come_back_bit_exact_and_temporaries_of_the_dead_are_cleaned(
    tmp_path: Path,
) -> None:
    out = tmp_path / "campaign"
    rng = np.random.default_rng(5)
    written = [_outcome(i, rng) for i in range(2)]
    with CampaignFolder.open(out, _record()) as folder:
        for outcome in written:
            _write(folder, outcome)
    dead = _dead_pid()
    stale = partial_folder(out) / "cases" / f".sample-0001.npz.casadi-debris-{dead}-0a.tmp"
    stale.write_bytes(b"half")
    stale_table = partial_folder(out) / f".campaign.nc.casadi-debris-{dead}-0b.tmp"
    stale_table.write_bytes(b"half")
    with CampaignFolder.open(out, _record()) as folder:
        assert not stale.exists() and not stale_table.exists()
        found = _finished(folder, [o.case for o in written])
        for outcome in written:
            again = found[outcome.case.case_id]
            assert _same_bands(again.bands, outcome.bands)
            assert again.summary == outcome.summary
        folder.finish()
    assert not partial_folder(out).exists()
    assert (out / MARKER_NAME).is_file() and (out / RECORD_NAME).is_file()
    assert not (out / LOCK_NAME).exists()


def test_another_campaign_is_refused_and_left_untouched(tmp_path: Path) -> None:
    out = tmp_path / "campaign"
    with CampaignFolder.open(out, _record()) as folder:
        _write(folder, _outcome(0, np.random.default_rng(1)))
    before = sorted(p.name for p in partial_folder(out).rglob("*"))
    with pytest.raises(OutputError, match=r"holds another campaign .*seed \(1 there, 7 here\)"):
        CampaignFolder.open(out, _record(seed=7))
    assert sorted(p.name for p in partial_folder(out).rglob("*")) == before


def test_cases_without_a_record_are_refused(tmp_path: Path) -> None:
    out = tmp_path / "campaign"
    (partial_folder(out) / "cases").mkdir(parents=True)
    with pytest.raises(OutputError, match=f"no {RECORD_NAME}"):
        CampaignFolder.open(out, _record())


def test_a_live_lock_is_refused_and_a_dead_one_taken_over(tmp_path: Path) -> None:
    out = tmp_path / "campaign"
    holder = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        partial_folder(out).mkdir(parents=True)
        (partial_folder(out) / LOCK_NAME).write_text(f"{holder.pid}\n")
        with pytest.raises(OutputError, match=f"in use by process {holder.pid}"):
            CampaignFolder.open(out, _record())
    finally:
        holder.kill()
        holder.wait()
    with CampaignFolder.open(out, _record()):
        assert (partial_folder(out) / LOCK_NAME).read_text().strip() == str(os.getpid())
    assert not (partial_folder(out) / LOCK_NAME).exists()


def test_a_case_of_an_older_layout_is_run_again(tmp_path: Path) -> None:
    out = tmp_path / "campaign"
    outcome = _outcome(0, np.random.default_rng(2))
    with CampaignFolder.open(out, _record()) as folder:
        _write(folder, outcome)
        cases = partial_folder(out) / "cases"
        assert _finished(folder, [outcome.case]).keys() == {"sample-0000"}
        np.savez_compressed(cases / "sample-0000.npz", bands=np.zeros((5, 12)))  # one array
        assert _finished(folder, [outcome.case]) == {}


def test_write_atomically_leaves_the_old_file_or_the_new_one(tmp_path: Path) -> None:
    target = tmp_path / "table.bin"
    target.write_bytes(b"old")

    def fail(path: Path) -> None:
        path.write_bytes(b"half")
        raise RuntimeError("killed")

    with pytest.raises(RuntimeError):
        write_atomically(target, fail)
    assert [p.name for p in tmp_path.iterdir()] == ["table.bin"] and target.read_bytes() == b"old"
    write_atomically(target, lambda path: path.write_bytes(b"new"))
    assert [p.name for p in tmp_path.iterdir()] == ["table.bin"] and target.read_bytes() == b"new"
