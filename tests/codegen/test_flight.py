"""The flight step as C (``casadi-debris export``): it compiles clean under the flight-code
gates, allocates nothing, and gives the numbers of the Python controller, allocator and
closed loop, saturating demands and failed CubeSats included."""

from __future__ import annotations

import csv
import json
import shutil
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.cli import main
from casadi_debris.codegen import FlightLibrary, compile_library
from casadi_debris.workflows import controller_for

GCC = shutil.which("gcc")
CLANG = shutil.which("clang")
CPPCHECK = shutil.which("cppcheck")
NM = shutil.which("nm")
STRICT = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Werror")
# The hand-written sources also pass these (CasADi's generated C does not promise them).
HAND_WRITTEN_EXTRA = ("-Wconversion", "-Wshadow")
HAND_WRITTEN = ("cdb_alloc.c", "cdb_step.c", "main.c")
GENERATED = ("cdb_law.c", "cdb_data.c")
LIBRARY_SOURCES = ("cdb_step.c", "cdb_alloc.c", "cdb_law.c", "cdb_data.c")
THRUST_RTOL = 1e-9  # of the largest thrust of the step
SATURATION_BACKOFF = 1e-10  # the loop's pull-in of a saturated torque
FLAG_SATURATED, FLAG_INFEASIBLE, FLAG_BAD_INPUT = 1, 2, 16

needs_gcc = pytest.mark.skipif(GCC is None, reason="no gcc on PATH: the C export is not compiled")


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> cd.ExportResult:
    """The paper's slew exported once for the module."""
    return cd.export("paper_slew", out=tmp_path_factory.mktemp("export") / "paper_slew")


@pytest.fixture(scope="module")
def library(exported: cd.ExportResult) -> FlightLibrary:
    if GCC is None:
        pytest.skip("no gcc on PATH: the C export is not compiled")
    path = compile_library(exported.folder, compiler=GCC)
    return FlightLibrary(path, exported.folder / "manifest.json")


@pytest.fixture(scope="module")
def problem_and_allocator() -> tuple[Any, Allocator]:
    problem = cd.load_problem("paper_slew")
    return problem, Allocator.from_problem(problem)


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    scale = max(float(np.abs(b).max()), float(np.abs(a).max()))
    return 0.0 if scale == 0.0 else float(np.abs(a - b).max()) / scale


# ---------------------------------------------------------------------------- what is written


def test_export_writes_sources_build_files_and_manifest(exported: cd.ExportResult) -> None:
    folder = exported.folder
    for name in (
        "cdb_flight.h",
        "cdb_config.h",
        "cdb_law.c",
        "cdb_law.h",
        "cdb_data.c",
        "cdb_alloc.c",
        "cdb_step.c",
        "main.c",
        "Makefile",
        "CMakeLists.txt",
        "README.md",
        "manifest.json",
        "summary.json",
    ):
        assert (folder / name).is_file(), name
    manifest = json.loads((folder / "manifest.json").read_text())
    problem = cd.load_problem("paper_slew")
    record, path = controller_for(problem)
    state = PropulsionState.from_problem(problem)
    assert manifest["problem"]["sha256"] == problem.sha256
    assert manifest["controller"]["file"] == str(path)
    assert manifest["toolkit_version"] == cd.__version__
    assert manifest["period_s"] == pytest.approx(1.0 / problem.simulation.control_rate_hz)
    assert manifest["sizes"]["engines"] == state.n_engines
    assert manifest["sizes"]["cubesats"] == state.n_cubesats
    assert manifest["sizes"]["stages"] == state.n_stages
    assert manifest["sizes"]["controller_states"] == record.reduced.nstates
    # The reference table runs to the end of the slew and is held after it.
    slew = problem.simulation.slew
    assert slew is not None
    assert manifest["reference_end_s"] == pytest.approx(slew.duration_s, abs=0.1)
    summary = json.loads((folder / "summary.json").read_text())
    assert summary == exported.summary.to_json()
    readme = (folder / "README.md").read_text()
    assert "stage_1" in readme and f"thrust_{state.n_engines}_N" in readme


def test_export_refuses_what_it_does_not_carry(tmp_path: Path) -> None:
    with pytest.raises(cd.ProblemFileError, match="sensors"):
        cd.export("paper_realistic", out=tmp_path / "x")
    assert not (tmp_path / "x").exists()


def test_cli_export_json_and_bad_input(tmp_path: Path) -> None:
    runner = CliRunner()
    done = runner.invoke(main, ["export", "paper_slew", "--out", str(tmp_path / "e"), "--json"])
    assert done.exit_code == 0, done.output
    printed = json.loads(done.output)
    assert printed["engines"] == 24 and Path(printed["out_dir"]) == tmp_path / "e"
    again = runner.invoke(main, ["export", "paper_slew", "--out", str(tmp_path / "e")])
    assert again.exit_code == 2 and "--out" in again.output
    missing = runner.invoke(
        main, ["export", "paper_slew", "--controller", str(tmp_path / "none.json")]
    )
    assert missing.exit_code == 2 and "controller file" in missing.output
    assert "Traceback" not in missing.output


# ---------------------------------------------------------------------------- quality gates


@pytest.mark.parametrize("compiler", ["gcc", "clang"])
def test_export_compiles_clean_under_the_flight_code_flags(
    exported: cd.ExportResult, compiler: str, tmp_path: Path
) -> None:
    path = shutil.which(compiler)
    if path is None:
        pytest.skip(f"no {compiler} on PATH")
    for name in HAND_WRITTEN + GENERATED:
        flags = STRICT + (HAND_WRITTEN_EXTRA if name in HAND_WRITTEN else ())
        command = [path, *flags, "-c", str(exported.folder / name), "-o", str(tmp_path / "x.o")]
        done = subprocess.run(command, capture_output=True, text=True, check=False)
        assert done.returncode == 0, f"{compiler} {name}: {done.stderr}"


@needs_gcc
@pytest.mark.skipif(NM is None, reason="no nm on PATH")
def test_no_allocation_and_no_mutable_globals(exported: cd.ExportResult, tmp_path: Path) -> None:
    assert GCC is not None and NM is not None
    for name in LIBRARY_SOURCES:
        obj = tmp_path / f"{name}.o"
        subprocess.run(
            [GCC, *STRICT, "-c", str(exported.folder / name), "-o", str(obj)], check=True
        )
        symbols = subprocess.run([NM, str(obj)], capture_output=True, text=True, check=True).stdout
        rows = [line.split() for line in symbols.splitlines()]
        names = {row[-1] for row in rows}
        assert not names & {"malloc", "calloc", "realloc", "free", "alloca"}, name
        # Writable data (D, d, B, b, C): none; the tables are read-only (R, r).
        kinds = {row[-2] for row in rows if len(row) >= 2}
        assert not kinds & set("DdBbC"), f"{name} holds writable globals: {symbols}"


@pytest.mark.skipif(CPPCHECK is None, reason="no cppcheck on PATH")
def test_cppcheck_reports_nothing(exported: cd.ExportResult) -> None:
    assert CPPCHECK is not None
    # The constant tables are left out: 1 MB of numbers, nothing to check, minutes to parse.
    files = [str(exported.folder / name) for name in (*HAND_WRITTEN, "cdb_law.c")]
    command = [
        CPPCHECK,
        "--error-exitcode=1",
        "--std=c99",
        "--quiet",
        "--enable=warning,portability",
        "--max-configs=1",
        *files,
    ]
    done = subprocess.run(command, capture_output=True, text=True, check=False, timeout=300)
    assert done.returncode == 0, done.stderr


# ---------------------------------------------------------------------------- same numbers


@needs_gcc
def test_allocation_is_the_python_allocators(
    library: FlightLibrary, problem_and_allocator: tuple[Any, Allocator]
) -> None:
    """Random demands from far below an engine's torque to far beyond reach, with none,
    one and three CubeSats failed: the same thrust as the Python allocator (and, when
    saturated, its scale and the thrust the loop allocates after its 1e-10 pull-in)."""
    problem, _ = problem_and_allocator
    rng = np.random.default_rng(20261128)
    saturated = 0
    for failed in ((), (3,), (0, 5, 17)):
        state = PropulsionState.from_problem(problem)
        for cubesat in failed:
            state.fail_cubesat(cubesat)
        allocator = Allocator.from_problem(problem, state=state)
        limits = state.max_thrust_N()
        for _ in range(80):
            demand = rng.normal(size=3) * 10 ** rng.uniform(-7, -1.5)
            thrust, scale, flags, _ = library.allocate(demand, limits)
            expected = allocator.allocate(demand)
            assert not flags & FLAG_INFEASIBLE, (failed, demand)
            assert scale == pytest.approx(expected.scale, rel=1e-12, abs=1e-15)
            assert np.all(thrust[limits == 0] == 0.0)
            assert np.all(thrust <= limits)
            if expected.feasible:
                assert not flags & FLAG_SATURATED
            else:
                saturated += 1
                assert flags & FLAG_SATURATED
                expected = allocator.allocate(scale * (1 - SATURATION_BACKOFF) * demand)
                assert expected.feasible
            assert _relative(thrust, expected.thrust_N) <= THRUST_RTOL, (failed, demand)
            torque = allocator.torque_map @ thrust
            target = scale * demand
            assert np.abs(torque - target).max() <= 1e-9 * np.abs(target).max()
    assert saturated > 20  # the saturation path was exercised


def _loop_record(duration_s: float) -> dict[str, np.ndarray]:
    """The Python closed loop of the paper's slew: what its star tracker measured, and
    what its controller and allocator answered."""
    from casadi_debris.dynamics import build_model

    run = cd.simulate("paper_slew", duration_s=duration_s)
    result = run.result
    layout = build_model(run.problem).layout
    return {
        "time_s": result.time_s[:-1],
        "measured": result.state[:-1, layout.q_st],
        "reference": result.reference_BN[:-1],
        "demand": result.demand_Nm,
        "scale": result.scale,
        "thrust": result.thrust_N,
        "error": result.measured_error_rad,
    }


def _replay(library: FlightLibrary, record: dict[str, np.ndarray]) -> list[Any]:
    library.reset()
    return [
        library.step(record["time_s"][k], record["measured"][k])
        for k in range(len(record["demand"]))
    ]


def _assert_same_as_loop(outputs: list[Any], record: dict[str, np.ndarray]) -> None:
    for k, out in enumerate(outputs):
        assert out.status == 0 and not out.flags & FLAG_INFEASIBLE, k
        np.testing.assert_array_equal(out.reference_BN, record["reference"][k])
        np.testing.assert_allclose(out.error_rad, record["error"][k], rtol=1e-12, atol=1e-18)
        np.testing.assert_allclose(out.demand_Nm, record["demand"][k], rtol=1e-12, atol=1e-18)
        assert out.scale == pytest.approx(record["scale"][k], rel=1e-12)
        assert bool(out.flags & FLAG_SATURATED) == bool(record["scale"][k] < 1.0), k
        assert _relative(out.thrust_N, record["thrust"][k]) <= THRUST_RTOL, k
        np.testing.assert_array_equal(out.engine_stage, np.ones(len(out.thrust_N)))


@needs_gcc
def test_step_is_the_loops_first_periods(library: FlightLibrary) -> None:
    """The first 30 s of the paper's slew, step by step: the reference, the attitude
    error, the controller's demand (state carried by the C) and the thrusts of the loop."""
    record = _loop_record(30.0)
    outputs = _replay(library, record)
    _assert_same_as_loop(outputs, record)


@needs_gcc
def test_step_with_a_failed_cubesat_and_other_stages(
    library: FlightLibrary, problem_and_allocator: tuple[Any, Allocator]
) -> None:
    problem, _ = problem_and_allocator
    state = PropulsionState.from_problem(problem)
    state.fail_cubesat(4)
    allocator = Allocator.from_problem(problem, state=state)
    failed = np.zeros(state.n_cubesats, dtype=int)
    failed[4] = 1
    stages = np.ones(state.n_engines, dtype=int)
    stages[7], stages[9] = 2, 0  # engine 8 on its second stage, engine 10 spent
    limits = state.max_thrust_N()
    limits[7] = state.stage_thrust_N[7, 1]
    limits[9] = 0.0
    allocator.set_max_thrust(limits)
    library.reset()
    angle = np.deg2rad(2.0)  # a 2 deg error about x: a demand the engines meet
    q = np.array([np.cos(angle / 2), np.sin(angle / 2), 0.0, 0.0])
    for k in range(5):
        out = library.step(0.1 * k, q, failed=failed, stage=stages)
        assert out.thrust_N[4] == 0.0 and out.engine_stage[4] == 0
        assert out.thrust_N[9] == 0.0 and out.engine_stage[9] == 0
        assert out.engine_stage[7] == 2
        expected = allocator.allocate(out.demand_Nm)
        if out.scale < 1.0:
            expected = allocator.allocate(out.scale * (1 - SATURATION_BACKOFF) * out.demand_Nm)
        assert _relative(out.thrust_N, expected.thrust_N) <= THRUST_RTOL
        np.testing.assert_allclose(
            out.torque_Nm, allocator.torque_map @ out.thrust_N, rtol=1e-12, atol=1e-18
        )


@needs_gcc
def test_bad_input_is_refused_with_zero_thrust(library: FlightLibrary) -> None:
    library.reset()
    out = library.step(0.0, [float("nan"), 0.0, 0.0, 0.0])
    assert out.status == 1 and out.flags == FLAG_BAD_INPUT
    assert not out.thrust_N.any()
    out = library.step(0.0, [0.0, 0.0, 0.0, 0.0])
    assert out.status == 1 and out.flags == FLAG_BAD_INPUT


# ---------------------------------------------------------------------------- whole slew


def _input_csv(path: Path, record: dict[str, np.ndarray], sizes: dict[str, int]) -> None:
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(
            ["time_s", "q0", "q1", "q2", "q3"]
            + [f"failed_{i + 1}" for i in range(sizes["cubesats"])]
            + [f"stage_{i + 1}" for i in range(sizes["engines"])]
        )
        for k in range(len(record["demand"])):
            writer.writerow(
                [repr(float(record["time_s"][k]))]
                + [repr(float(v)) for v in record["measured"][k]]
                + [0] * sizes["cubesats"]
                + [1] * sizes["engines"]
            )


def _read_outputs(path: Path) -> dict[str, np.ndarray]:
    with path.open() as handle:
        rows = list(csv.reader(handle))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    return {name: values[:, i] for i, name in enumerate(header)}


@needs_gcc
@pytest.mark.slow
def test_whole_slew_and_the_harness_replay_under_sanitizers(
    library: FlightLibrary, exported: cd.ExportResult, tmp_path: Path
) -> None:
    """The whole 1500 s of the paper's slew (its saturated stretch included) against the
    loop; then main.c's replay of the same inputs, built with the Makefile and again under
    AddressSanitizer and UndefinedBehaviorSanitizer, writes the same outputs."""
    assert GCC is not None
    record = _loop_record(1500.0)
    assert (record["scale"] < 1.0).sum() > 50
    outputs = _replay(library, record)
    _assert_same_as_loop(outputs, record)
    build = tmp_path / "build"
    shutil.copytree(exported.folder, build)
    subprocess.run(["make", "-C", str(build), f"CC={GCC}"], check=True, capture_output=True)
    sanitized = build / "cdb_replay_sanitized"
    subprocess.run(
        [
            GCC,
            *STRICT,
            "-g",
            "-fsanitize=address,undefined",
            "-fno-sanitize-recover=all",
            "-o",
            str(sanitized),
            *(str(build / name) for name in ("main.c", *LIBRARY_SOURCES)),
            "-lm",
        ],
        check=True,
    )
    inputs = tmp_path / "inputs.csv"
    _input_csv(inputs, record, library.sizes)
    for binary in (build / "cdb_replay", sanitized):
        written = tmp_path / f"{binary.name}.csv"
        done = subprocess.run(
            [str(binary), str(inputs), str(written)], capture_output=True, text=True, check=False
        )
        assert done.returncode == 0 and done.stderr == "", done.stderr
        table = _read_outputs(written)
        thrust = np.column_stack(
            [table[f"thrust_{i + 1}_N"] for i in range(library.sizes["engines"])]
        )
        expected = np.array([out.thrust_N for out in outputs])
        np.testing.assert_allclose(thrust, expected, rtol=1e-12, atol=1e-18)
        np.testing.assert_array_equal(table["flags"], [out.flags for out in outputs])
        demand = np.column_stack([table[f"demand_{axis}_Nm"] for axis in "xyz"])
        np.testing.assert_allclose(
            demand, [out.demand_Nm for out in outputs], rtol=1e-12, atol=1e-18
        )
