"""``casadi_debris.allocate`` is the ``allocate`` command: the same allocation from Python
as ``casadi-debris allocate ... --json`` prints, checked against an independent LP."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.allocation import PropulsionState
from casadi_debris.cli import main
from casadi_debris.errors import AllocationError, InputShapeError, OutputError
from lp_reference import least_mass_flow_kg_s

# Figures that time the solver, not what it solved.
VOLATILE = ("solve_time_us",)


def _cli_json(*arguments: str) -> dict:
    result = CliRunner().invoke(main, ["allocate", *arguments, "--json"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    payload = json.loads(result.stdout)
    for key in VOLATILE:
        payload.pop(key)
    return payload


def _python_json(result: cd.AllocationResult) -> dict:
    payload = result.summary.to_json()
    for key in VOLATILE:
        payload.pop(key)
    return payload


@pytest.mark.parametrize(
    ("problem", "arguments", "keywords"),
    [
        (None, ["--torque-mNm", "1", "0.5", "-0.8"], {"torque_mNm": (1.0, 0.5, -0.8)}),
        (
            None,
            ["--torque-mNm", "20", "0", "0", "--failed", "3,17", "--free-force"],
            {"torque_mNm": (20.0, 0.0, 0.0), "failed": [3, 17], "free_force": True},
        ),
        (
            "side_engines_12",
            ["--torque-mNm", "2", "0", "0", "--failed-engines", "1:1,5:2"],
            {"torque_mNm": (2.0, 0.0, 0.0), "failed_engines": [(1, 1), (5, 2)]},
        ),
    ],
)
def test_python_and_command_line_give_the_same_allocation(
    problem: str | None, arguments: list[str], keywords: dict
) -> None:
    from_cli = _cli_json(*([problem] if problem else []), *arguments)
    result = cd.allocate(problem, **keywords)
    assert _python_json(result) == from_cli


def test_a_reachable_demand_is_met_exactly_at_the_least_mass_flow() -> None:
    result = cd.allocate("side_engines_12", torque_mNm=(2.0, -0.5, 0.3), force_mN=(0.1, 0, 0))
    allocation, geometry = result.allocation, result.geometry
    assert result.summary.feasible and result.summary.mode == "exact"
    # The thrusts make the torque and force asked for, through the geometry's own maps.
    np.testing.assert_allclose(geometry.torque_map @ allocation.thrust_N, [2e-3, -5e-4, 3e-4])
    np.testing.assert_allclose(geometry.force_map @ allocation.thrust_N, [1e-4, 0, 0], atol=1e-15)
    # ... at the least mass flow an LP (HiGHS, not the QP) finds.
    exhaust = result.state.exhaust_velocity_m_s
    limits = np.array([engine.max_thrust_N for engine in geometry.engines])
    least = least_mass_flow_kg_s(
        geometry, limits, exhaust, np.array([2e-3, -5e-4, 3e-4]), np.array([1e-4, 0, 0])
    )
    assert least is not None
    assert result.summary.fuel_rate_kg_s == pytest.approx(least, rel=1e-6)


def test_failed_cubesats_and_engines_are_one_based_and_checked() -> None:
    result = cd.allocate(torque_mNm=(1.0, 0.0, 0.0), failed=[1, 24])
    assert result.summary.failed_cubesats == (1, 24)
    assert result.allocation.thrust_N[0] == result.allocation.thrust_N[23] == 0.0
    with pytest.raises(InputShapeError, match="from 1 to 24"):
        cd.allocate(torque_mNm=(1.0, 0.0, 0.0), failed=[0])
    with pytest.raises(AllocationError, match=r"CubeSat 3 has engines 1\.\.1"):
        cd.allocate(torque_mNm=(1.0, 0.0, 0.0), failed_engines=[(3, 2)])
    with pytest.raises(AllocationError, match="--force-mN or --free-force"):
        cd.allocate(torque_mNm=(1.0, 0.0, 0.0), force_mN=(0, 0, 0), free_force=True)


def test_a_stage_state_is_taken_as_given_and_left_unchanged(tmp_path: Path) -> None:
    state = PropulsionState.from_problem(cd.load_problem())
    state.fail_stage(4, 0)
    before = state.to_dict()
    result = cd.allocate(torque_mNm=(0.0, 0.0, 1.0), stage_state=state)
    assert state.to_dict() == before
    assert result.summary.active_stage[4] == 2
    path = tmp_path / "state.json"
    path.write_text(json.dumps(before))
    from_file = cd.allocate(torque_mNm=(0.0, 0.0, 1.0), stage_state=path)
    assert _python_json(from_file) == _python_json(result)
    assert _cli_json("--torque-mNm", "0", "0", "1", "--stage-state", str(path)) == _python_json(
        result
    )


def test_save_writes_the_summary_and_never_overwrites(tmp_path: Path) -> None:
    result = cd.allocate(torque_mNm=(1.0, 0.5, -0.8))
    out = result.save(tmp_path / "allocation", plots=False)
    assert json.loads((out / "summary.json").read_text()) == result.summary.to_json()
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == ["summary.json"]
    with pytest.raises(OutputError):
        result.save(out)
    result.save(out, overwrite=True)
    assert (out / "thrust.png").is_file() and (out / "thrust.pdf").is_file()


def test_plot_draws_every_engine_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    result = cd.allocate(torque_mNm=(20.0, 0.0, 0.0), failed=[3])
    figures = result.plot()
    assert set(figures) == {"thrust"} and list(tmp_path.iterdir()) == []
    bars, torque = figures["thrust"].axes
    # Limits first (outlines), then the thrusts, one bar per engine.
    heights = [patch.get_height() for patch in bars.patches]
    engines = len(result.summary.thrust_mN)
    np.testing.assert_array_equal(heights[:engines], result.summary.thrust_limit_mN)
    np.testing.assert_array_equal(heights[engines:], result.summary.thrust_mN)
    assert heights[2] == 0.0  # CubeSat 3 is out
    achieved = [patch.get_height() for patch in torque.patches][3:]
    np.testing.assert_allclose(achieved, result.summary.torque_achieved_mNm)
    plt.close(figures["thrust"])
