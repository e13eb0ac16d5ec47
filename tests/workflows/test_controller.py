"""Which controller flies on which problem: the plant hash and the mismatch rule."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.config import default_controller_path, default_problem_path, with_duration
from casadi_debris.dynamics import build_model
from casadi_debris.errors import ControllerMismatchError, ProblemFileError
from casadi_debris.geometry import build_geometry
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import simulate_closed_loop
from casadi_debris.workflows import controller_for

PROBLEMS = default_problem_path().parent


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


@pytest.fixture
def heavy(tmp_path: Path) -> Path:
    return _write(
        tmp_path / "heavy.toml",
        f'extends = "{PROBLEMS / "paper_slew.toml"}"\nname = "heavy"\n[hub]\nmass_kg = 600.0\n',
    )


def test_runs_and_comments_do_not_change_the_plant(tmp_path: Path) -> None:
    paper = load_problem()
    # The shipped slew and pointing problems change only the runs: one plant.
    for name in ("paper_slew.toml", "paper_pointing.toml"):
        assert load_problem(PROBLEMS / name).plant_sha256 == paper.plant_sha256
    renamed = _write(
        tmp_path / "renamed.toml",
        f'# a comment\nextends = "{default_problem_path()}"\nname = "renamed"\n'
        "[simulation]\nduration_s = 100.0\n[orbit]\naltitude_km = 700.0\n",
    )
    other = load_problem(renamed)
    assert other.sha256 != paper.sha256 and other.plant_sha256 == paper.plant_sha256


def test_a_layout_and_the_list_it_expands_to_are_one_plant(tmp_path: Path) -> None:
    paper = load_problem()
    lines = [f'extends = "{default_problem_path()}"', 'name = "explicit"']
    for cubesat in paper.cubesats:
        lines += [
            "[[cubesats]]",
            f"position_corner_m = {cubesat.position_corner_m.tolist()}",
            f"mass_kg = {cubesat.mass_kg!r}",
            f"inertia_kgm2 = {cubesat.inertia_kgm2.tolist()}",
            f'face = "{cubesat.face}"',
        ]
        for engine in cubesat.engines:
            # Written as the signed axis a user would type: the layout's directions carry
            # -0.0 components, which must not make it another plant.
            axis = "xyz"[int(abs(engine.direction).argmax())]
            sign = "+" if engine.direction.sum() > 0 else "-"
            lines += ["[[cubesats.engines]]", f'direction = "{sign}{axis}"']
    explicit = load_problem(_write(tmp_path / "explicit.toml", "\n".join(lines) + "\n"))
    assert explicit.cubesat_layout is None and len(explicit.cubesats) == 24
    assert explicit.plant_sha256 == paper.plant_sha256
    ours, theirs = build_geometry(explicit), build_geometry(paper)
    assert (ours.torque_map == theirs.torque_map).all()
    assert (ours.inertia_total_kgm2 == theirs.inertia_total_kgm2).all()


def test_the_shipped_controller_flies_only_on_the_papers_plant(heavy: Path) -> None:
    record, path = controller_for(load_problem(PROBLEMS / "paper_slew.toml"))
    assert path == default_controller_path() and record.problem_sha256
    with pytest.raises(ControllerMismatchError, match="casadi-debris design"):
        controller_for(load_problem(heavy))


def test_a_controller_for_another_plant_needs_allow_mismatch(heavy: Path) -> None:
    problem = load_problem(heavy)
    with pytest.raises(ControllerMismatchError, match="--allow-mismatch"):
        controller_for(problem, default_controller_path())
    record, _ = controller_for(problem, default_controller_path(), allow_mismatch=True)
    assert record.problem_sha256 == load_problem().plant_sha256 != problem.plant_sha256


def test_a_plain_state_space_file_is_flown_as_given(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A controller of the user's own: A, B, C, D and nothing else, no plant to check."""
    shipped = json.loads(default_controller_path().read_text())
    plain = _write(tmp_path / "plain.json", json.dumps({k: shipped[k] for k in "ABCD"}))
    problem = load_problem("paper_slew")
    with caplog.at_level("WARNING"):
        record, _ = controller_for(problem, plain)
    assert "records no plant" in caplog.text
    assert record.mu_peak is None and record.full is None and record.problem_sha256 == ""
    # The same matrices as the shipped file: the same closed-loop run, to the bit.
    short = with_duration(problem, 30.0)
    runs = [
        simulate_closed_loop(build_model(short), r.reduced, scenario_reference(short))
        for r in (record, controller_for(short)[0])
    ]
    assert np.array_equal(runs[0].error_rad, runs[1].error_rad)


def test_a_plain_file_with_a_bad_matrix_names_it(tmp_path: Path) -> None:
    shipped = json.loads(default_controller_path().read_text())
    data = {k: shipped[k] for k in "ABCD"} | {"B": shipped["B"][:-1]}
    with pytest.raises(ProblemFileError, match="B: must be"):
        controller_for(load_problem(), _write(tmp_path / "bad.json", json.dumps(data)))


@pytest.mark.parametrize("command", ["simulate", "margins", "montecarlo"])
def test_commands_refuse_a_mismatch_in_one_line(heavy: Path, tmp_path: Path, command: str) -> None:
    result = CliRunner().invoke(main, [command, str(heavy), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "--controller" in lines[0] and "casadi-debris design" in lines[0]
    assert not (tmp_path / "out").exists()


def test_compare_refuses_a_variant_of_another_plant(heavy: Path, tmp_path: Path) -> None:
    args = ["compare", str(PROBLEMS / "paper_slew.toml"), str(heavy), "--out", str(tmp_path / "c")]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 2 and "heavy" in result.stderr
    assert not (tmp_path / "c").exists()


def test_an_optional_setting_at_its_default_is_the_same_plant(tmp_path: Path) -> None:
    paper = load_problem()
    body = f'extends = "{default_problem_path()}"\n[uncertainty]\nindependent_array_angles = '
    same = load_problem(_write(tmp_path / "same.toml", body + "false\n"))
    other = load_problem(_write(tmp_path / "other.toml", body + "true\n"))
    assert same.plant_sha256 == paper.plant_sha256 != other.plant_sha256
