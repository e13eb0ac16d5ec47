"""simulate, montecarlo and reproduce from the command line: keys, folders, resume,
Dask, reproducibility, and bad input without tracebacks."""

from __future__ import annotations

import csv
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from scipy.integrate import solve_ivp

from casadi_debris.cli import main
from casadi_debris.config import default_controller_path, default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.report import normalized_column
from casadi_debris.store import MARKER_NAME

PROBLEMS = default_problem_path().parent
SIMULATE_KEYS = {
    "max_error_deg",
    "max_error_arcsec",
    "settle_time_s",
    "fuel_kg",
    "fuel_per_cubesat_kg",
    "torque_saturated_s",
    "max_torque_mNm",
    "dv_used_m_s",
    "seed",
    "parameters",
}


def invoke(*args: str) -> tuple[int, str, str]:
    runner = CliRunner()
    result = runner.invoke(main, list(args), catch_exceptions=False)
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture(scope="module")
def short_slew(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The paper's slew problem cut to its first 40 s (into the first torque transient)."""
    folder = tmp_path_factory.mktemp("problems")
    path = folder / "short_slew.toml"
    path.write_text(
        f'extends = "{PROBLEMS / "paper_slew.toml"}"\nname = "short_slew"\n'
        "[simulation]\nduration_s = 40.0\n"
    )
    return path


def test_simulate_json_has_the_issue_keys_and_writes_the_folder(
    short_slew: Path, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    code, stdout, _ = invoke("simulate", str(short_slew), "--out", str(out), "--json")
    assert code == 0
    summary = json.loads(stdout)
    assert set(summary) >= SIMULATE_KEYS
    assert len(summary["fuel_per_cubesat_kg"]) == 24
    assert summary["fuel_kg"] == pytest.approx(sum(summary["fuel_per_cubesat_kg"]))
    assert {p.name for p in out.iterdir()} == {
        MARKER_NAME,
        "summary.json",
        "series.csv",
        "closed_loop.png",
        "closed_loop.pdf",
        "thrust.png",
        "thrust.pdf",
    }
    with (out / "series.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 401  # 40 s at the 0.1 s control period, both ends
    # The written error is the summary's maximum, in degrees.
    errors = [abs(float(r[f"error_{a}_deg"])) for r in rows for a in "xyz"]
    assert max(errors) == pytest.approx(summary["max_error_deg"], rel=1e-9)


def test_simulate_corner_and_sample_rerun_the_same_case(short_slew: Path) -> None:
    code, stdout, _ = invoke("simulate", str(short_slew), "--sample", "3", "--seed", "7", "--json")
    assert code == 0
    first = json.loads(stdout)
    code, stdout, _ = invoke("simulate", str(short_slew), "--sample", "3", "--seed", "7", "--json")
    again = json.loads(stdout)
    assert first["case_id"] == "sample-0003" and first["seed"] == 7
    assert first["parameters"] == again["parameters"]
    assert first["max_error_deg"] == again["max_error_deg"]
    assert first["fuel_per_cubesat_kg"] == again["fuel_per_cubesat_kg"]
    code, stdout, _ = invoke("simulate", str(short_slew), "--corner", "255", "--json")
    corner = json.loads(stdout)
    problem = load_problem(short_slew)
    model = build_model(problem)
    # The last corner: every relative uncertainty at its upper extreme.
    assert corner["parameters"]["inertia_scale_x"] == pytest.approx(
        1 + problem.uncertainty.inertia_fraction
    )
    assert corner["parameters"]["mass_kg"] == pytest.approx(
        model.nominal.mass_kg * (1 + problem.uncertainty.mass_fraction)
    )


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--corner", "256"], "corner index runs from 0 to 255"),
        (["--corner", "1", "--sample", "2"], "either --corner or --sample"),
        (["--duration-s", "-5"], "'--duration-s': must lie in (0, 1e+07], got '-5'"),
        (["--rigid"], "--open-loop TORQUE.csv and --rigid go together"),
    ],
)
def test_simulate_bad_input_is_one_line(short_slew: Path, args: list[str], needle: str) -> None:
    code, stdout, stderr = invoke("simulate", str(short_slew), *args)
    assert code == 2
    assert needle in stderr
    assert "Traceback" not in stderr + stdout
    assert len(stderr.strip().splitlines()) == 1


def test_a_thruster_level_time_optimal_reference_is_flown(tmp_path: Path) -> None:
    """Zero net force and half the thrust: the profile's torque plus the controller's stays
    inside the allocator's set, so the loop tracks it without saturating."""
    path = tmp_path / "fast.toml"
    path.write_text(
        f'extends = "{PROBLEMS / "paper_slew.toml"}"\nname = "fast"\n'
        "[simulation]\nduration_s = 1320.0\n"
        '[simulation.slew]\naxis = "z"\nangle_deg = 180.0\nmethod = "time-optimal"\n'
        "thrusters = true\ntorque_fraction = 0.5\nfeedforward = true\n"
        # the inherited 1228 s of the bang-bang would be this slew's deadline: too short
        "duration_s = 1310.0\n"
    )
    code, out, _ = invoke("simulate", str(path), "--json")
    assert code == 0
    summary = json.loads(out)
    assert summary["torque_saturated_s"] == 0.0
    assert summary["max_error_deg"] < 0.05
    # a rest-to-rest slew at half the thrust is slower than the rigid limit at full
    assert 1200.0 < summary["slew_end_s"] < 1320.0


def test_open_loop_rigid_from_csv_matches_solve_ivp(tmp_path: Path) -> None:
    table = tmp_path / "torque.csv"
    table.write_text("t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n0,2,-1,3\n40,-1,2,0\n90,0,0,-4\n")
    code, stdout, _ = invoke(
        "simulate", "--open-loop", str(table), "--rigid", "--duration-s", "150", "--json"
    )
    assert code == 0
    summary = json.loads(stdout)
    inertia = np.array(summary["inertia_kgm2"])
    knots = np.array([0.0, 40.0, 90.0])
    torque = np.array([[2, -1, 3], [-1, 2, 0], [0, 0, -4]]) * 1e-3

    def rates(t: float, y: np.ndarray, tau: np.ndarray) -> np.ndarray:
        q, w = y[:4], y[4:]
        q_dot = 0.5 * np.concatenate([[-q[1:] @ w], q[0] * w + np.cross(q[1:], w)])
        w_dot = np.linalg.solve(inertia, tau - np.cross(w, inertia @ w))
        return np.concatenate([q_dot, w_dot])

    y = np.array([1.0, 0, 0, 0, 0, 0, 0])
    for start, end, tau in zip(knots, [40.0, 90.0, 150.0], torque, strict=True):
        y = solve_ivp(rates, (start, end), y, args=(tau,), rtol=1e-12, atol=1e-14).y[:, -1]
    assert np.abs(np.array(summary["final_quaternion"]) - y[:4]).max() < 1e-8
    assert np.abs(np.array(summary["final_rate_rad_s"]) - y[4:]).max() < 1e-10
    assert summary["series"]["time_s"][-1] == 150.0


def test_open_loop_bad_table_is_named(tmp_path: Path) -> None:
    table = tmp_path / "torque.csv"
    table.write_text("time,tx,ty,tz\n0,1,2,3\n")
    code, _, stderr = invoke("simulate", "--open-loop", str(table), "--rigid")
    assert code == 2 and "header must be t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm" in stderr
    table.write_text("t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n0,1,2,3\n0,1,2,3\n")
    code, _, stderr = invoke("simulate", "--open-loop", str(table), "--rigid")
    assert code == 2 and "increase strictly" in stderr


def _cases_table(folder: Path) -> list[dict[str, str]]:
    with (folder / "cases.csv").open() as handle:
        return list(csv.DictReader(handle))


@pytest.fixture(scope="module")
def campaign(short_slew: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("mc") / "corners"
    code, _, _ = invoke(
        "montecarlo", str(short_slew), "--max-cases", "3", "--workers", "2", "--out", str(out)
    )
    assert code == 0
    return out


def test_montecarlo_writes_cases_envelope_and_nominal(campaign: Path) -> None:
    summary = json.loads((campaign / "summary.json").read_text())
    rows = _cases_table(campaign)
    assert [r["case_id"] for r in rows] == ["corner-0000", "corner-0128", "corner-0255"]
    assert summary["cases"] == 3
    worst = max(float(r["max_error_deg"]) for r in rows)
    assert summary["worst"]["max_error_deg"]["value"] == pytest.approx(worst)
    # The envelope holds every case's error: its widest band is the worst case's maximum.
    with (campaign / "envelope.csv").open() as handle:
        envelope = list(csv.DictReader(handle))
    widest = max(
        max(abs(float(r[f"error_min_deg_{a}"])), abs(float(r[f"error_max_deg_{a}"])))
        for r in envelope
        for a in "xyz"
    )
    assert widest == pytest.approx(worst, rel=1e-12)
    assert (campaign / "nominal" / "summary.json").exists()
    assert (campaign / "envelope.png").exists()
    assert not campaign.with_name(campaign.name + ".partial").exists()


def _stored_value(ds: xr.Dataset, case_id: str, column: str) -> object:
    one = ds.sel(case=case_id)
    if column.startswith("normalized_"):
        [parameter] = [p for p in ds.parameter.values if normalized_column(p) == column]
        return one.normalized.sel(parameter=parameter).item()
    return one[column].item()


def test_campaign_nc_holds_what_the_case_files_hold(campaign: Path) -> None:
    """Rebuilt apart: numpy and json on cases/<id>.npz and .json, csv on the tables."""
    rows = _cases_table(campaign)
    record = json.loads((campaign / "campaign.json").read_text())
    envelope = np.loadtxt(campaign / "envelope.csv", delimiter=",", skiprows=1)
    with xr.open_dataset(campaign / "campaign.nc") as ds:
        assert list(ds.case.values) == [r["case_id"] for r in rows]
        assert ds.attrs["problem"] == "short_slew" and ds.attrs["case_kind"] == "corner"
        assert ds.attrs["controller_sha256"] == record["controller_sha256"]
        assert ds.attrs["problem_sha256"] == record["problem_sha256"]
        assert np.array_equal(ds.time.values, envelope[:, 0])
        for row in rows:
            case_id = row.pop("case_id")
            summary = json.loads((campaign / "cases" / f"{case_id}.json").read_text())
            with np.load(campaign / "cases" / f"{case_id}.npz") as stored:
                for name in ("error_rad", "torque_Nm"):
                    for bound in ("min", "max"):
                        written = ds[name].sel(case=case_id, bound=bound).values
                        assert np.array_equal(written, stored[f"{name}_{bound}"]), name
            for column, text in row.items():
                value = _stored_value(ds, case_id, column)
                if text == "":
                    assert value == -1 if column == "seed" else np.isnan(value), column
                else:
                    assert str(value) == text, column
            stored_fuel = ds.fuel_per_cubesat_kg.sel(case=case_id).values.tolist()
            assert stored_fuel == summary["fuel_per_cubesat_kg"]
            assert ds.max_torque_mNm.sel(case=case_id).values.tolist() == summary["max_torque_mNm"]
        # envelope.csv is the dataset's extremes over the cases, in degrees.
        lowest = ds.error_rad.sel(bound="min", axis="x").min("case").values * (180.0 / np.pi)
        assert np.array_equal(lowest, envelope[:, 1])


# What the user guide shows for a campaign in a notebook (see docs/guide/results.md).
DOCS_SNIPPET = """
from casadi_debris.store import open_campaign
ds = open_campaign("runs/slew-mc")
worst = ds.max_error_deg.idxmax().item()
ds.error_rad.sel(case=worst, bound="max").plot.line(x="time")
"""


def _snippets_opening_a_campaign() -> list[str]:
    """The snippet above, the package's Examples, and any python block of the docs that
    opens a campaign (all run in a folder where ``runs/slew-mc`` is a campaign)."""
    import doctest

    from casadi_debris import store

    found = [DOCS_SNIPPET]
    parser = doctest.DocTestParser()
    for text in (store.__doc__, store.open_campaign.__doc__):
        found.append("".join(example.source for example in parser.get_examples(text or "")))
    root = Path(__file__).parents[2]
    for page in [root / "README.md", *sorted((root / "docs").rglob("*.md"))]:
        if page.is_file():
            blocks = re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)
            found += [block for block in blocks if "open_campaign(" in block]
    return found


def test_the_documented_snippets_open_a_campaign(
    campaign: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import casadi_debris.plots  # noqa: F401  (the headless backend)

    (tmp_path / "runs").mkdir()
    (tmp_path / "runs" / "slew-mc").symlink_to(campaign)
    monkeypatch.chdir(tmp_path)
    for snippet in _snippets_opening_a_campaign():
        namespace: dict[str, object] = {}
        exec(compile(snippet, "snippet", "exec"), namespace)
        dataset = namespace["ds"]
        assert isinstance(dataset, xr.Dataset) and dataset.sizes["case"] == 3
        dataset.close()


def test_montecarlo_resumes_from_the_cases_on_disk_bit_exact(
    short_slew: Path, campaign: Path, tmp_path: Path
) -> None:
    out = tmp_path / "resumed"
    partial = tmp_path / "resumed.partial"
    (partial / "cases").mkdir(parents=True)
    shutil.copy(campaign / "campaign.json", partial)
    for case_id in ("corner-0000", "corner-0255"):  # as if interrupted after two cases
        for suffix in (".json", ".npz"):
            shutil.copy(campaign / "cases" / f"{case_id}{suffix}", partial / "cases")
    code, stdout, _ = invoke(
        "montecarlo",
        str(short_slew),
        "--max-cases",
        "3",
        "--workers",
        "1",
        "--out",
        str(out),
        "--json",
    )
    assert code == 0
    printed = json.loads(stdout)
    assert printed["resumed_cases"] == 2
    # The keys the command matrix asks of a campaign's --json (its cell runs under -m slow).
    assert {"cases", "nominal", "controller_path"} <= set(printed)
    assert json.loads((out / "summary.json").read_text())["cases"] == printed["cases"] == 3
    for table in ("cases.csv", "envelope.csv"):
        assert (out / table).read_bytes() == (campaign / table).read_bytes(), table
    with (
        xr.open_dataset(out / "campaign.nc") as resumed,
        xr.open_dataset(campaign / "campaign.nc") as whole,
    ):
        xr.testing.assert_identical(resumed, whole)
    assert sorted(p.name for p in (out / "cases").iterdir()) == sorted(
        p.name for p in (campaign / "cases").iterdir()
    )
    assert not partial.exists()


@pytest.mark.parametrize(
    ("change", "differs"),
    [
        (["--max-cases", "2"], "case list"),
        (["--samples", "3", "--seed", "5"], "case_kind"),
        (["--controller", "OTHER"], "controller file"),
        (["PROBLEM"], "problem file"),
    ],
)
def test_montecarlo_refuses_to_resume_another_campaign(
    short_slew: Path, campaign: Path, tmp_path: Path, change: list[str], differs: str
) -> None:
    partial = tmp_path / "resumed.partial"
    (partial / "cases").mkdir(parents=True)
    shutil.copy(campaign / "campaign.json", partial)
    shutil.copy(campaign / "cases" / "corner-0000.json", partial / "cases")
    problem = short_slew
    if "PROBLEM" in change:
        problem = tmp_path / "other.toml"
        problem.write_text(short_slew.read_text().replace("40.0", "41.0"))
        change = ["--max-cases", "3"]
    if "OTHER" in change:
        other = tmp_path / "controller.json"
        shipped = json.loads(default_controller_path().read_text())
        other.write_text(json.dumps(shipped, indent=2))
        change = ["--max-cases", "3", "--controller", str(other)]
    before = sorted(p.name for p in partial.rglob("*"))
    code, _, stderr = invoke(
        "montecarlo", str(problem), *change, "--workers", "1", "--out", str(tmp_path / "resumed")
    )
    assert code == 2, stderr
    assert "holds another campaign" in stderr and differs in stderr
    assert sorted(p.name for p in partial.rglob("*")) == before


def test_montecarlo_samples_are_reproducible(short_slew: Path, tmp_path: Path) -> None:
    tables = []
    for name in ("a", "b"):
        out = tmp_path / name
        code, _, _ = invoke(
            "montecarlo",
            str(short_slew),
            "--samples",
            "1",
            "--seed",
            "11",
            "--workers",
            "1",
            "--out",
            str(out),
        )
        assert code == 0
        tables.append(_cases_table(out))
    assert tables[0] == tables[1]
    assert [r["seed"] for r in tables[0]] == ["11"]


@pytest.mark.slow
def test_montecarlo_on_dask_gives_the_same_numbers(short_slew: Path, tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True) as cluster:
        out = tmp_path / "dask"
        code, _, _ = invoke(
            "montecarlo",
            str(short_slew),
            "--samples",
            "2",
            "--seed",
            "11",
            "--scheduler",
            cluster.scheduler_address,
            "--out",
            str(out),
        )
    assert code == 0
    local = tmp_path / "local"
    code, _, _ = invoke(
        "montecarlo",
        str(short_slew),
        "--samples",
        "2",
        "--seed",
        "11",
        "--workers",
        "1",
        "--out",
        str(local),
    )
    assert _cases_table(out) == _cases_table(local)
    with (
        xr.open_dataset(out / "campaign.nc") as on_dask,
        xr.open_dataset(local / "campaign.nc") as here,
    ):
        xr.testing.assert_identical(on_dask, here)


def test_montecarlo_bad_input(short_slew: Path, tmp_path: Path) -> None:
    code, _, stderr = invoke(
        "montecarlo", str(short_slew), "--corners", "--samples", "3", "--out", str(tmp_path / "x")
    )
    assert code == 2 and "either --corners or --samples" in stderr
    code, _, stderr = invoke("montecarlo", str(short_slew), "--workers", "0")
    assert code == 2 and "'--workers': 0 is not in the range 1<=x<=256" in stderr
    code, _, stderr = invoke(
        "montecarlo",
        str(short_slew),
        "--samples",
        "1",
        "--scheduler",
        "tcp://127.0.0.1:1",
        "--out",
        str(tmp_path / "y"),
    )
    assert code == 2
    assert not (tmp_path / "y").exists()


UNIT_SUFFIXES = ("_deg", "_arcsec", "_kg", "_s", "_m_s", "_mNm", "_Nm", "_N", "_mN", "_rad",
                 "_deg_s", "_rad_s")  # fmt: skip
PURE_NUMBERS = ("scale", "switches", "solves", "steps", "events")
"""Figures without a unit: their names say they count or scale."""


def _numeric_keys(value: object, prefix: str = "") -> list[str]:
    if isinstance(value, dict):
        found = []
        for key, item in value.items():
            if isinstance(item, dict):
                found += _numeric_keys(item, f"{prefix}{key}.")
            elif isinstance(item, int | float | list) and not isinstance(item, bool):
                found.append(f"{prefix}{key}")
        return found
    return []


def test_every_figure_and_column_names_its_unit(short_slew: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    code, stdout, _ = invoke("simulate", str(short_slew), "--out", str(out), "--json")
    assert code == 0
    names = _numeric_keys(json.loads(stdout))
    with (out / "series.csv").open() as handle:
        names += next(csv.reader(handle))
    unnamed = [
        n for n in names if not n.endswith(UNIT_SUFFIXES) and not any(w in n for w in PURE_NUMBERS)
    ]
    assert not unnamed, unnamed
    # engines and CubeSats counted from 1 in the columns, as everywhere a user reads
    assert "thrust_01_mN" in names and "thrust_00_mN" not in names
