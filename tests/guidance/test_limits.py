"""LVLH tracks and burns checked against the engines as slews are: the torque their attitude
needs, found here by our own differences of the attitude and the allocator's facets (at zero
net force, or the slice at a burn's force), against the figures the commands report."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator, authority_polytope
from casadi_debris.cli import main
from casadi_debris.config import Problem, default_problem_path
from casadi_debris.dynamics import build_model
from casadi_debris.geometry import build_geometry, max_thrust_N
from casadi_debris.guidance import (
    BurnPlan,
    burn_limits,
    burn_thrust_N,
    segment_records,
    sequence_pieces,
)
from slew_reference import torque_set_gauge


def _track_file(folder: Path, blend_s: float, kind: str = "track") -> Path:
    """The paper's debris tracking nadir (or burning retrograde) for 6000 s from rest."""
    target = (
        'frame = "nadir"\nnadir_axis = "+z"\nalong_axis = "+x"'
        if kind == "track"
        else 'direction = "retrograde"\nbody_axis = "-y"\nthrust_fraction = 1.0'
    )
    path = folder / f"{kind}_{blend_s:g}.toml"
    path.write_text(
        f'extends = "{default_problem_path()}"\nname = "{kind}_{blend_s:g}"\n\n'
        '[simulation]\nduration_s = 6000.0\nreference = "sequence"\n\n'
        f'[[simulation.segments]]\nkind = "{kind}"\n{target}\nblend_s = {blend_s}\n'
    )
    return path


def _torque(problem: Problem, times: np.ndarray, attitude: Any) -> np.ndarray:
    """J alpha + w x J w at ``times`` (uniform), w = 2 vec(q* q') by central differences of
    the quaternions ``attitude`` gives, taken two steps past either end so that every
    difference is central."""
    step = float(times[1] - times[0])
    times = np.concatenate(
        [times[0] - step * np.arange(2, 0, -1), times, times[-1] + step * np.arange(1, 3)]
    )
    quaternion = attitude(times)
    model = build_model(problem, [])
    inertia = np.array(model.rigid_inertia(model.nominal_parameters))
    flips = np.cumsum(np.r_[0, np.einsum("ij,ij->i", quaternion[1:], quaternion[:-1]) < 0]) % 2
    q = quaternion * np.where(flips == 1, -1.0, 1.0)[:, None]  # one continuous sign
    dq = np.gradient(q, times, axis=0, edge_order=2)
    w0, v = q[:, :1], q[:, 1:]
    dw0, dv = dq[:, :1], dq[:, 1:]
    rate = 2.0 * (w0 * dv - dw0 * v - np.cross(v, dv))
    alpha = np.gradient(rate, times, axis=0, edge_order=2)
    return (alpha @ inertia.T + np.cross(rate, rate @ inertia.T))[2:-2]


def _gauge(problem: Problem, torque: np.ndarray, force_N: np.ndarray | None = None) -> float:
    geometry = build_geometry(problem)
    polytope = authority_polytope(
        geometry.torque_map, geometry.force_map, max_thrust_N(geometry), force_N=force_N
    )
    return float(np.max(torque_set_gauge(polytope, torque)))


@pytest.mark.parametrize("blend_s", [3000.0, 60.0])
def test_a_track_reports_the_share_its_torque_needs(blend_s: float, tmp_path: Path) -> None:
    problem = load_problem(_track_file(tmp_path, blend_s))
    (piece,) = [p for p in sequence_pieces(problem, 1.0) if p.kind == "track"]
    times = np.linspace(piece.start_s, piece.end_s, 30001)
    ours = _gauge(problem, _torque(problem, times, piece.attitude))
    (record,) = [
        r for r in segment_records(sequence_pieces(problem, 1.0), problem) if r.kind == "track"
    ]
    assert record.worst_authority_share == pytest.approx(ours, rel=2e-3)
    assert record.limits_ok == (ours <= 1.0)
    assert (record.limits_note == "") == record.limits_ok
    # The long blend is within the engines, the one-minute one far beyond them.
    assert record.limits_ok is (blend_s == 3000.0)


def test_a_track_the_engines_cannot_fly_is_reported_with_a_warning(tmp_path: Path) -> None:
    path = _track_file(tmp_path, 60.0)
    result = CliRunner().invoke(main, ["slew", str(path), "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["tracks_within_limits"] is False and summary["slews_within_limits"] is True
    (track,) = summary["segments"]
    assert track["limits_ok"] is False and "torque set" in track["limits_note"]
    warnings = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and "segment 1 (track)" in warnings[0]


def test_a_burn_segment_is_checked_at_its_force_while_it_fires(tmp_path: Path) -> None:
    problem = load_problem(_track_file(tmp_path, 600.0, kind="burn"))
    (piece,) = [p for p in sequence_pieces(problem, 1.0) if p.kind == "burn"]
    assert piece.burn is not None and piece.firing_s is not None
    thrust = burn_thrust_N(Allocator.from_problem(problem), piece.burn)
    force = thrust * piece.burn.body_axis
    times = np.linspace(piece.start_s, piece.end_s, 30001)
    torque = _torque(problem, times, piece.attitude)
    firing = (times >= piece.firing_s[0]) & (times <= piece.firing_s[1])
    ours = max(_gauge(problem, torque[~firing]), _gauge(problem, torque[firing], force))
    (record,) = [r for r in segment_records([piece], problem)]
    assert record.kind == "burn"
    assert record.worst_authority_share == pytest.approx(ours, rel=2e-3)
    assert record.limits_ok == (ours <= 1.0)


@pytest.mark.parametrize("fraction", [1.0, 0.25])
def test_a_burns_attitude_is_checked_within_what_the_engines_add_to_its_thrust(
    fraction: float,
) -> None:
    """The paper's retrograde burn of the -y face turning with the LVLH frame (steady): the
    gyroscopic torque of the orbit rate within the slice of the wrench polytope at the
    burn's force."""
    problem = load_problem("paper_burn")
    plan = BurnPlan("retrograde", np.array([0.0, -1.0, 0.0]), 2000.0, fraction)
    thrust = burn_thrust_N(Allocator.from_problem(problem), plan)
    check = burn_limits(problem, plan, thrust, 10.0)
    from casadi_debris.environment import CircularOrbit
    from casadi_debris.guidance import burn_offset, frame_attitude

    times = np.linspace(0.0, 2000.0, 2001)
    orbit = CircularOrbit.from_problem(problem)
    offset = burn_offset(plan.body_axis, plan.direction_lvlh)
    torque = _torque(problem, times, lambda t: frame_attitude(orbit, offset, t))
    ours = _gauge(problem, torque, thrust * plan.body_axis)
    assert check.limits_ok and ours < 1.0
    assert check.worst_torque_set_ratio == pytest.approx(ours, rel=1e-3)


# ------------------------------------------------------------------ what the engines have left


def _one_stage(folder: Path) -> Problem:
    """The paper's burn problem with one stage per engine: a stage running dry leaves that
    engine spent (with three equal stages the next takes over at the same thrust)."""
    base = default_problem_path().parent / "paper_burn.toml"
    path = folder / "one_stage.toml"
    path.write_text(f'extends = "{base}"\nname = "one_stage"\n\n[engine]\nstages = 1\n')
    return load_problem(path)


def test_engine_limits_along_a_run_drop_where_each_stage_runs_dry(tmp_path: Path) -> None:
    """Three engines with 3 s of full thrust left, fired at 1, 1/2 and 1/4 of it: each is
    spent at 3 f_max / f (3, 6 and 12 s), by our own sum of its impulse."""
    from casadi_debris.allocation import PropulsionState
    from casadi_debris.guidance import engine_limits_along
    from casadi_debris.simulation.burn import first_stage_left

    problem = _one_stage(tmp_path)
    start = first_stage_left(PropulsionState.from_problem(problem), 3.0)
    full = start.max_thrust_N()
    period = 0.25
    thrust = np.zeros((80, full.size))
    fired = {0: 1.0, 5: 0.5, 9: 0.25}
    for engine, share in fired.items():
        thrust[:, engine] = share * full[engine]
    times, limits = engine_limits_along(start, thrust, period)
    dry = sorted(3.0 / share for share in fired.values())
    assert times[0] == 0.0 and len(times) == 1 + len(dry)
    np.testing.assert_allclose(times[1:], dry, atol=period)
    np.testing.assert_array_equal(limits[0], full)
    for row, (engine, _) in enumerate(sorted(fired.items(), key=lambda item: -item[1]), start=1):
        assert limits[row][engine] == 0.0
        assert np.count_nonzero(limits[row] == 0.0) == row  # spent engines stay spent
    assert np.all(limits[-1][[i for i in range(full.size) if i not in fired]] == full[0])
    # Not fired, nothing changes; the state given is not touched.
    quiet, unchanged = engine_limits_along(start, np.zeros_like(thrust), period)
    assert quiet.tolist() == [0.0] and np.array_equal(unchanged[0], full)
    assert np.array_equal(start.max_thrust_N(), full)


def test_a_burn_is_checked_against_the_engines_left_from_each_time_on() -> None:
    """From 1000 s the engines give half their thrust: the gauge there is our own facets'
    of the halved set; from 1000 s the engines that push along -y spent: cannot thrust."""
    from casadi_debris.environment import CircularOrbit
    from casadi_debris.guidance import burn_offset, frame_attitude

    problem = load_problem("paper_burn")
    plan = BurnPlan("retrograde", np.array([0.0, -1.0, 0.0]), 2000.0, 0.25)
    thrust = burn_thrust_N(Allocator.from_problem(problem), plan)
    geometry = build_geometry(problem)
    full = max_thrust_N(geometry)
    halved = burn_limits(
        problem,
        plan,
        thrust,
        10.0,
        engine_limits=(np.array([0.0, 1000.0]), np.vstack([full, full / 2])),
    )
    times = np.linspace(0.0, 2000.0, 2001)
    orbit = CircularOrbit.from_problem(problem)
    offset = burn_offset(plan.body_axis, plan.direction_lvlh)
    torque = _torque(problem, times, lambda t: frame_attitude(orbit, offset, t))
    force = thrust * plan.body_axis
    late = times >= 1000.0
    half = authority_polytope(geometry.torque_map, geometry.force_map, full / 2, force_N=force)
    ours = max(
        _gauge(problem, torque[~late], force), float(np.max(torque_set_gauge(half, torque[late])))
    )
    assert halved.limits_ok and ours < 1.0
    assert halved.worst_torque_set_ratio == pytest.approx(ours, rel=1e-3)
    # Full limits throughout: the check without engine limits, figure for figure.
    same = burn_limits(problem, plan, thrust, 10.0, engine_limits=(np.array([0.0]), full[None, :]))
    assert same == burn_limits(problem, plan, thrust, 10.0)
    # The engines pushing along -y spent from 1000 s: nothing else can give the thrust.
    pushing = geometry.force_map[1] < -1e-9
    spent = np.where(pushing, 0.0, full)
    check = burn_limits(
        problem,
        plan,
        thrust,
        10.0,
        engine_limits=(np.array([0.0, 1000.0]), np.vstack([full, spent])),
    )
    assert not check.limits_ok
    assert check.worst_torque_set_ratio == np.inf and check.worst_ratio_time_s == 1000.0
    assert "from t = 1000 s the engines left cannot give" in check.limits_note
