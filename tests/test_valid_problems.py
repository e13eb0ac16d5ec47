"""A campaign of unusual but valid problems (hypothesis), each checked against references
computed here (``tests/valid_problems.py``).

Problems: random hubs (size, mass, rotated inertia, CoG), zero to two arrays leaving
random faces at random hinge points and angles, five to twelve explicit CubeSats on
random faces with one to three engines in random directions and random limits, and a
disturbance a random fraction (5-80 %) of the zero-net-force authority about each axis.
Problems without zero-net-force authority about some signed axis are not valid
attitude-control problems (no disturbance is below nothing) and are skipped.

Per problem:

- mass, CoG and inertia equal a parallel-axis sum written here, and the torque
  authority (with and without net force) ``model`` reports equals linear programmes
  written here, over the engines ``model`` lists and over our own engine columns;
- the allocator meets a reachable demand (a random direction at 10-95 % of the reach an
  LP finds along it) exactly, every thrust within its limits, no net force;
- every slew method's profile satisfies the body's equation J alpha + w x J w = tau at
  every sample with the J computed here, its rate is the integral of its acceleration
  and its attitude the integral of its rate (finite differences with error bounds), it
  starts and ends at rest on target, and stays within the actuators' limits: the
  engines' torque set at zero net force (the closed loop's allocator; the gauge of
  every torque by an LP here) at torque level, every thrust within [0, f_max] and the
  torque equal to B f at thruster level; the profile's own ``limits_ok`` agrees;
- the time-optimal slew is no longer than the bang-bang at the same authority;
- no command exits 3 on the problem written as a TOML file.

Hypothesis runs derandomised (``derandomize=True``: the examples are a fixed function
of the test, the same on every machine and run), without an example database; a
failure prints the drawn problem. A few problems run by default; ``-m slow`` runs 200
per property.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, Phase, assume, given, settings
from hypothesis import strategies as st
from hypothesis.errors import HypothesisException

from casadi_debris.allocation import Allocator
from casadi_debris.cli import main
from casadi_debris.config import Problem, problem_from_dict
from casadi_debris.report import describe_model
from casadi_debris.slews import (
    OptimalSlewSettings,
    SlewProfile,
    bang_bang_slew,
    fuel_optimal_slew,
    time_optimal_slew,
)
from valid_problems import (
    SIGNED_AXES,
    Reference,
    lp_authority_Nm,
    lp_gauge,
    lp_reach,
    problems,
    reference,
    with_disturbance,
    write_toml,
)

RTOL = 1e-9
# Box and thrust limits: solvers stop within their own tolerances (IPOPT's constraint
# violation 1e-8 relative to the scaled problem), not exactly on the bound.
LIMIT_RTOL = 1e-6
# VALID_PROBLEMS_EXAMPLES shortens a slow campaign (a trial of the harness); 200 by default.
SLOW_EXAMPLES = int(os.environ.get("VALID_PROBLEMS_EXAMPLES", "200"))


def _campaign(examples: int) -> Any:
    return settings(
        max_examples=examples,
        derandomize=True,
        database=None,
        deadline=None,
        # Shrinking re-solves OCPs for minutes; the drawn problem is printed as it is.
        phases=(Phase.explicit, Phase.generate),
        suppress_health_check=list(HealthCheck),
    )


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    return value


def _many(name: str, check: Callable[..., None], *strategies: Any) -> None:
    """A slow campaign: ``check`` on SLOW_EXAMPLES drawn problems, every one checked even
    after a violation (a campaign counts them all); fails at the end with each violation.

    With ``VALID_PROBLEMS_LOG`` set, one JSON line per problem checked is appended to
    that file as it finishes (name, count, wall and CPU seconds, the outcome) and every
    violation's drawn arguments are written beside it (``<log>.<name>.<count>.json``):
    the reproducer is ``check_<name>(*arguments)``.
    """
    log = os.environ.get("VALID_PROBLEMS_LOG")
    violations: list[str] = []
    checked = 0

    @given(st.tuples(*strategies))
    @_campaign(SLOW_EXAMPLES)
    def run(drawn: tuple[Any, ...]) -> None:
        nonlocal checked
        wall, cpu = time.perf_counter(), time.process_time()
        try:
            check(*drawn)
            outcome = "ok"
        except HypothesisException:
            raise  # assume(): not a valid problem, not counted
        except Exception as error:  # every violation is counted, then reported
            outcome = f"VIOLATION {type(error).__name__}: {str(error)[:400]}"
        checked += 1
        if outcome != "ok":
            violations.append(f"problem {checked}: {outcome}")
        if log:
            record = {
                "campaign": name,
                "problem": checked,
                "wall_s": round(time.perf_counter() - wall, 2),
                "cpu_s": round(time.process_time() - cpu, 2),
                "outcome": outcome,
            }
            with open(log, "a") as handle:
                handle.write(json.dumps(record) + "\n")
            if outcome != "ok":
                arguments = [_jsonable(a) for a in drawn]
                Path(f"{log}.{name}.{checked}.json").write_text(json.dumps(arguments))

    run()
    assert not violations, f"{len(violations)} of {checked} problems:\n" + "\n".join(violations)


def _valid(data: dict[str, Any]) -> tuple[Problem, Reference, dict[str, Any]]:
    """The problem (disturbance scaled to its authority) and our reference for it."""
    ref = reference(data)
    assume(min(ref.authority_Nm(zero_net_force=True).values()) > 1e-9)
    scaled = with_disturbance(data, ref)
    return problem_from_dict(scaled, "valid"), ref, scaled


def _axes() -> st.SearchStrategy[np.ndarray]:
    def unit(v: list[float]) -> np.ndarray:
        a = np.asarray(v)
        return a / np.linalg.norm(a)

    vector = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3)
    return vector.filter(lambda v: float(np.linalg.norm(v)) > 0.2).map(unit)


# ------------------------------------------------------------------ model and authority


def check_model(data: dict[str, Any]) -> None:
    problem, ref, _ = _valid(data)
    described = describe_model(problem)
    assert described.mass_kg == pytest.approx(ref.mass_kg, rel=RTOL)
    np.testing.assert_allclose(described.cog_m, ref.cog_corner_m, rtol=0, atol=1e-6)
    scale = np.abs(ref.inertia_kgm2).max()
    # describe_model rounds its figures; 1e-8 relative covers that and nothing more.
    np.testing.assert_allclose(described.inertia_total_kgm2, ref.inertia_kgm2, atol=1e-8 * scale)
    thrusters = described.thrusters
    assert len(thrusters) == ref.max_thrust_N.size
    listed_r = np.array([t.position_m for t in thrusters])
    listed_d = np.array([t.direction for t in thrusters])
    listed_f = np.array([t.max_thrust_mN for t in thrusters]) * 1e-3
    np.testing.assert_allclose(listed_f, ref.max_thrust_N, rtol=1e-12)
    listed_torque = np.cross(listed_r, listed_d).T
    for zero_net_force, reported in (
        (False, described.torque_max_mNm),
        (True, described.torque_max_zero_force_mNm),
    ):
        ours = ref.authority_Nm(zero_net_force)
        # Over the engines `model` lists (positions and directions rounded to 1e-6 m).
        from_list = lp_authority_Nm(listed_torque, listed_d.T, listed_f, zero_net_force)
        rounding = 2e-6 * float(np.sum(ref.max_thrust_N))
        for name in SIGNED_AXES:
            assert reported[name] * 1e-3 == pytest.approx(ours[name], rel=RTOL, abs=1e-12), name
            assert from_list[name] == pytest.approx(ours[name], abs=rounding), name


@given(problems())
@_campaign(6)
def test_model_and_authority_equal_hand_sums_and_lps(data: dict[str, Any]) -> None:
    check_model(data)


@pytest.mark.slow
def test_model_and_authority_many() -> None:
    _many("model", check_model, problems())


# ------------------------------------------------------------------ allocation


def check_allocation(data: dict[str, Any], unit: np.ndarray, fraction: float) -> None:
    problem, ref, _ = _valid(data)
    allocator = Allocator.from_problem(problem)
    np.testing.assert_allclose(allocator.max_thrust_N, ref.max_thrust_N, rtol=1e-12)
    for free_force in (False, True):
        reach = lp_reach(ref, unit, zero_net_force=not free_force)
        assume(reach > 1e-9)
        demand = fraction * reach * unit
        result = allocator.allocate(demand, free_force=free_force)
        assert result.feasible and result.mode == "exact", (free_force, result.mode)
        f = result.thrust_N
        assert np.all(f >= -LIMIT_RTOL * ref.max_thrust_N)
        assert np.all(f <= ref.max_thrust_N * (1 + LIMIT_RTOL))
        # Our own columns: torque and force of the thrusts it returned.
        np.testing.assert_allclose(ref.torque_per_N @ f, demand, rtol=0, atol=1e-7 * reach)
        np.testing.assert_allclose(result.torque_Nm, demand, rtol=0, atol=1e-7 * reach)
        if not free_force:
            assert np.abs(ref.direction @ f).max() <= 1e-7 * max(float(f.sum()), 1e-12)


@given(problems(), _axes(), st.floats(0.1, 0.95))
@_campaign(6)
def test_allocation_meets_a_reachable_demand_exactly(data, unit, fraction) -> None:
    check_allocation(data, unit, fraction)


@pytest.mark.slow
def test_allocation_many() -> None:
    _many("allocation", check_allocation, problems(), _axes(), st.floats(0.1, 0.95))


# ------------------------------------------------------------------ slew profiles


def _quaternion_product(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rows of scalar-first quaternions multiplied, p (x) q."""
    w1, v1 = p[:, :1], p[:, 1:]
    w2, v2 = q[:, :1], q[:, 1:]
    return np.hstack(
        [w1 * w2 - np.sum(v1 * v2, axis=1, keepdims=True), w1 * v2 + w2 * v1 + np.cross(v1, v2)]
    )


def check_dynamics(profile: SlewProfile, ref: Reference) -> None:
    """Rest to rest on target; J alpha + w x J w = tau at every sample; rate and attitude
    the integrals of acceleration and rate, by finite differences with their error bound."""
    t = profile.time_s
    w, a, tau, q = (
        profile.rate_rad_s,
        profile.acceleration_rad_s2,
        profile.torque_Nm,
        profile.quaternion_BN,
    )
    assert t.size >= 10 and np.all(np.diff(t) > 0)
    assert t[-1] == pytest.approx(profile.duration_s, rel=1e-6, abs=1e-6)
    J = ref.inertia_kgm2
    w_scale = max(float(np.abs(w).max()), 1e-12)
    tau_scale = max(float(np.abs(tau).max()), 1e-15)
    integration = _integration_error(profile)
    # Rest to rest, on target: the rate left at the end drifts over one slew's duration
    # (peak rate x duration ~ 2 x angle) by under 1e-5 of the angle; the attitude error
    # at the end is under 1e-5 of the angle too (solvers stop at 1e-8 on scaled states).
    # The samples of an OCP's profile are an integration of its held torque: the end rate
    # carries that integration's error too (1e-10 rad/s, which a slow 9 deg slew's 1e-5 of
    # its peak rate does not always cover).
    angle = profile.target.angle_rad
    assert np.abs(w[0]).max() <= 1e-5 * w_scale
    assert np.abs(w[-1]).max() <= 1e-5 * w_scale + integration, (w[-1], w_scale, integration)
    np.testing.assert_allclose(q[0], profile.target.q_initial_BN, atol=1e-8)
    q_f = profile.target.q_final_BN
    conjugate = np.r_[q_f[0], -q_f[1:]][None, :]
    end_error = 2.0 * np.linalg.norm(_quaternion_product(conjugate, q[-1:])[0, 1:])
    assert end_error <= 1e-5 * angle + 1e-9, (end_error, angle)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-8)
    # The body's equation at every sample (the last is the rest after the end).
    residual = a @ J.T + np.cross(w, w @ J.T) - tau
    assert np.abs(residual[:-1]).max() <= 1e-6 * tau_scale, np.abs(residual).max() / tau_scale
    check_integrals(profile, J)


def _integration_error(profile: SlewProfile) -> float:
    """The largest error of the profile's rates as its integration measured it (rad/s): an
    OCP's profile integrates its held torque with CVODES, which bounds each step's local
    error only; the profile records its difference from an integration a hundred times
    tighter. 0 for a profile evaluated in closed form (the bang-bang)."""
    return float(profile.settings.get("integration_rate_error_rad_s", 0.0))


def check_integrals(profile: SlewProfile, J: np.ndarray) -> None:
    """Rate the integral of acceleration, attitude the integral of rate (trapezoids with
    their error bounds, plus the integration's own error)."""
    t = profile.time_s
    w, a, q = profile.rate_rad_s, profile.acceleration_rad_s2, profile.quaternion_BN
    w_scale = max(float(np.abs(w).max()), 1e-12)
    a_scale = max(float(np.abs(a).max()), 1e-12)
    # w(t_k+1) - w(t_k) = integral of alpha, by the trapezoid. With the torque piecewise
    # constant or smooth (one jump at most per step), alpha = J^-1 (tau - w x J w) is a
    # jump plus a drift whose rate is at most |J^-1| |d(w x J w)/dt| <= 2 cond(J) |w| |alpha|,
    # so the trapezoid's error is at most dt |alpha_k+1 - alpha_k| / 2 + 3/2 dt^2 drift.
    dt = np.diff(t)[:, None]
    jump = np.abs(np.diff(a, axis=0))
    drift = 2.0 * np.linalg.cond(J) * w_scale * a_scale
    error = np.abs(np.diff(w, axis=0) - dt * (a[1:] + a[:-1]) / 2)
    # Plus arithmetic: the rates come out of the solver's sums at about 1e-15 of their
    # peak, so differences under 1e-12 of it are rounding (a step of a few ns at a switch
    # leaves nothing else); a body equation broken shows at 1e-6 and above.
    rounding = 1e-12 * (w_scale + float(np.max(dt)) * a_scale)
    # And the integration's error: each of the step's two rates is off by at most the
    # error the profile measured, plus the tighter integration's own (its tolerances a
    # hundred times smaller: 1 % of it). A step of 1e-7 s at a switch shows nothing else.
    integration = 2.02 * _integration_error(profile)
    bound = dt * jump / 2 + 1.5 * dt**2 * drift + 1e-9 * dt * a_scale + rounding + integration
    # The last step ends at rest: alpha's sample there is after the end, not before it.
    assert np.all(error[:-1] <= bound[:-1]), float(np.max(error[:-1] - bound[:-1]))
    # q' = q (x) (0, w) / 2: trapezoid again; with w continuous its error is O(dt^2 jump(alpha)).
    half = lambda k: 0.5 * _quaternion_product(q[k], np.hstack([np.zeros((len(k), 1)), w[k]]))  # noqa: E731
    k = np.arange(t.size - 1)
    q_error = np.abs(q[1:] - q[:-1] - dt * (half(k) + half(k + 1)) / 2).max(axis=1)
    q_bound = (
        dt[:, 0] ** 2 * jump.max(axis=1)
        + dt[:, 0] ** 3 * (w_scale**3 + 3 * w_scale * a_scale)
        + 1e-9
    )
    assert np.all(q_error <= q_bound), float(np.max(q_error / q_bound))


def check_torque_set(
    profile: SlewProfile, ref: Reference, torque_fraction: float = 1.0, zero_net_force: bool = True
) -> None:
    """Every sample's torque within the engines' torque set (zero net force, the closed
    loop's allocator: its gauge by an LP here per distinct torque), times the torque
    fraction; the profile's own check agrees (``limits_ok`` honest, the same worst gauge)."""
    gauge = lp_gauge(ref, profile.torque_Nm, zero_net_force)
    worst = int(np.argmax(gauge))
    assert gauge[worst] <= torque_fraction * (1 + LIMIT_RTOL), (
        f"torque {profile.torque_Nm[worst] * 1e3} mNm at t = {profile.time_s[worst]:.1f} s "
        f"needs {gauge[worst]:.6g} x the engines' torque set"
    )
    assert profile.limits.limits_ok, profile.limits.limits_note
    assert profile.limits.limits_zero_net_force == zero_net_force
    assert profile.limits.worst_torque_set_ratio == pytest.approx(gauge[worst], rel=1e-6, abs=1e-9)


def check_thrusts(profile: SlewProfile, ref: Reference, zero_net_force: bool) -> None:
    """Every thrust within [0, f_max]; the torque B f; (no net force)."""
    f = profile.thrust_N
    assert f.shape == (profile.time_s.size, ref.max_thrust_N.size)
    assert np.all(f >= -LIMIT_RTOL * ref.max_thrust_N), float(f.min())
    assert np.all(f <= ref.max_thrust_N * (1 + LIMIT_RTOL)), float(np.max(f / ref.max_thrust_N))
    scale = float(ref.max_thrust_N.sum() * np.abs(ref.torque_per_N).max())
    np.testing.assert_allclose(f @ ref.torque_per_N.T, profile.torque_Nm, rtol=0, atol=1e-6 * scale)
    if zero_net_force:
        assert np.abs(f @ ref.direction.T).max() <= 1e-6 * float(ref.max_thrust_N.sum())


def _bang_bang(problem: Problem, axis: np.ndarray, angle_rad: float, **extra: Any) -> SlewProfile:
    probe = bang_bang_slew(problem, axis, angle_rad, check_vibration=False)
    # About 300 samples whatever the body's size.
    sample = max(1e-3, probe.duration_s / 300)
    return bang_bang_slew(problem, axis, angle_rad, check_vibration=False, sample_s=sample, **extra)


def check_bang_bang(data: dict[str, Any], axis: np.ndarray, angle_deg: float) -> None:
    problem, ref, _ = _valid(data)
    profile = _bang_bang(problem, axis, math.radians(angle_deg))
    check_dynamics(profile, ref)
    check_torque_set(profile, ref)


slew_axes = _axes()
slew_angles = st.floats(5.0, 180.0)


@given(problems(), slew_axes, slew_angles)
@_campaign(2)
def test_bang_bang_profile_obeys_the_body_and_the_box(data, axis, angle_deg) -> None:
    check_bang_bang(data, axis, angle_deg)


@pytest.mark.slow
def test_bang_bang_many() -> None:
    _many("bang_bang", check_bang_bang, problems(), slew_axes, slew_angles)


def _options(reference_s: float, **extra: Any) -> OptimalSlewSettings:
    return OptimalSlewSettings(
        sample_s=max(1e-3, reference_s / 300),
        check_vibration=False,
        starts=2,
        seed=0,
        workers=1,
        **extra,
    )


def check_time_optimal(
    data: dict[str, Any], axis: np.ndarray, angle_deg: float
) -> tuple[SlewProfile, Reference]:
    problem, ref, _ = _valid(data)
    angle = math.radians(angle_deg)
    bang_bang = _bang_bang(problem, axis, angle)
    profile = time_optimal_slew(problem, axis, angle, options=_options(bang_bang.duration_s))
    check_dynamics(profile, ref)
    check_torque_set(profile, ref)
    # Same torque set, and the eigenaxis bang-bang is one of its feasible profiles.
    assert profile.duration_s <= bang_bang.duration_s * (1 + 1e-6), (
        profile.duration_s,
        bang_bang.duration_s,
    )
    return profile, ref


@given(problems(), slew_axes, slew_angles)
@_campaign(1)
def test_time_optimal_profile_obeys_the_body_and_beats_the_bang_bang(data, axis, angle_deg) -> None:
    profile, ref = check_time_optimal(data, axis, angle_deg)
    # The bound counts the integration's error, and no more: dynamics wrong by 1 % fail.
    assert 0.0 < _integration_error(profile) < 1e-6 * float(np.abs(profile.rate_rad_s).max())
    wrong_torque = dataclasses.replace(profile, torque_Nm=1.01 * profile.torque_Nm)
    with pytest.raises(AssertionError):
        check_dynamics(wrong_torque, ref)
    # Rates the integral of a 1 % larger acceleration: the trapezoid check alone sees it.
    wrong_rate = dataclasses.replace(profile, rate_rad_s=1.01 * profile.rate_rad_s)
    with pytest.raises(AssertionError):
        check_integrals(wrong_rate, ref.inertia_kgm2)


@pytest.mark.slow
def test_time_optimal_many() -> None:
    _many("time_optimal", check_time_optimal, problems(), slew_axes, slew_angles)


def check_fuel_optimal(
    data: dict[str, Any], axis: np.ndarray, angle_deg: float, stretch: float
) -> None:
    problem, ref, _ = _valid(data)
    angle = math.radians(angle_deg)
    duration = stretch * _bang_bang(problem, axis, angle).duration_s
    profile = fuel_optimal_slew(
        problem, axis, angle, duration_s=duration, options=_options(duration)
    )
    check_dynamics(profile, ref)
    check_torque_set(profile, ref)
    assert profile.duration_s == pytest.approx(duration, rel=1e-6)


# A fuel-optimal OCP on a random swarm takes about half a minute: under -m slow only (the
# paper's fuel-optimal slews run by default in tests/slews/test_profiles.py).
@pytest.mark.slow
@given(problems(), slew_axes, slew_angles, st.floats(1.2, 3.0))
@_campaign(1)
def test_fuel_optimal_profile_obeys_the_body_and_the_box(data, axis, angle_deg, stretch) -> None:
    check_fuel_optimal(data, axis, angle_deg, stretch)


@pytest.mark.slow
def test_fuel_optimal_many() -> None:
    _many(
        "fuel_optimal", check_fuel_optimal, problems(), slew_axes, slew_angles, st.floats(1.2, 3.0)
    )


def check_thruster_level(data: dict[str, Any], axis: np.ndarray, angle_deg: float) -> None:
    problem, ref, _ = _valid(data)
    angle = math.radians(angle_deg)
    bang_bang = _bang_bang(problem, axis, angle)
    profile = time_optimal_slew(
        problem, axis, angle, options=_options(bang_bang.duration_s, thrusters=True)
    )
    assert profile.thrusters
    check_dynamics(profile, ref)
    check_thrusts(profile, ref, zero_net_force=False)
    # Its own rule: the net force free, a larger set than the torque level's at zero net
    # force, so a thruster-level slew may be faster than a torque-level one.
    check_torque_set(profile, ref, zero_net_force=False)


@given(problems(), slew_axes, slew_angles)
@_campaign(1)
def test_thruster_level_profile_obeys_the_body_and_the_engines(data, axis, angle_deg) -> None:
    check_thruster_level(data, axis, angle_deg)


@pytest.mark.slow
def test_thruster_level_many() -> None:
    _many("thruster_level", check_thruster_level, problems(), slew_axes, slew_angles)


# ------------------------------------------------------------------ the command line


# (command, output modes by default): the optimal slews (a minute each on a loaded
# machine; their profiles are checked above, and the command matrix runs them on three
# problems) only in the slow run, which takes every command in every mode.
CLI_COMMANDS = (
    (("model",), ("text", "json")),
    (("budget",), ("text", "json")),
    (("allocate", "--torque-mNm", "DEMAND"), ("text", "json")),
    (("slew", "--method", "bang-bang", "--axis", "AXIS"), ("text", "json")),
    (("slew", "--method", "time-optimal", "--starts", "2", "--axis", "AXIS"), ()),
    (("slew", "--method", "time-optimal", "--thrusters", "--axis", "AXIS"), ()),
)


def check_commands(
    data: dict[str, Any], axis: np.ndarray, folder: Path, every_mode: bool = False
) -> None:
    """Every command on the problem as a user writes it: never exit 3 (a bug), exit 0 (or,
    for an optimal slew, 2 with one line saying why), JSON that parses, and a slew's
    ``limits_ok`` honest: its torque in ``profile.csv`` gauged in the engines' torque set
    by LPs here agrees with the worst gauge the summary gives, and ``limits_ok`` is that
    gauge at most 1."""
    _, ref, scaled = _valid(data)
    path = write_toml(scaled, folder / "valid.toml")
    # Half the reach along the slew axis with zero net force: a demand met exactly.
    demand = [f"{c:.9g}" for c in 0.5e3 * lp_reach(ref, axis, zero_net_force=True) * axis]
    axis_text = ",".join(f"{c:.6f}" for c in axis)
    runner = CliRunner()
    for number, (command, modes) in enumerate(CLI_COMMANDS):
        args: list[str] = []
        for word in command:
            if word == "DEMAND":
                args += demand
            else:
                args.append(axis_text if word == "AXIS" else word)
        writes = command[0] == "slew"
        run = folder / f"run{number}"
        out = ["--out", str(run)] if writes else []
        for mode in [
            ["--json"] if m == "json" else [] for m in (("text", "json") if every_mode else modes)
        ]:
            result = runner.invoke(main, ["-q", command[0], str(path), *args[1:], *out, *mode])
            assert result.exit_code != 3, (command, mode, result.output)
            assert result.output.strip() and "Traceback" not in result.output
            if result.exit_code == 2 and "time-optimal" in command:
                # An optimal slew IPOPT did not solve: said in one line, nothing written.
                assert len(result.output.strip().splitlines()) == 1, result.output
                continue
            assert result.exit_code == 0, (command, mode, result.output)
            if mode:
                summary = json.loads(result.stdout)
                if writes:
                    check_honest_limits(summary, run / "profile.csv", ref)
            if writes:
                out = ["--out", str(run), "--overwrite"]


def check_honest_limits(summary: dict[str, Any], profile_csv: Path, ref: Reference) -> None:
    """A slew summary's ``limits_ok`` and worst gauge against its profile's torque."""
    with profile_csv.open() as handle:
        rows = list(csv.DictReader(handle))
    torque = np.array([[float(r[f"torque_{a}_mNm"]) for a in "xyz"] for r in rows]) * 1e-3
    zero_net_force = summary["limits_zero_net_force"]
    gauge = float(np.max(lp_gauge(ref, torque, zero_net_force)))
    assert summary["worst_torque_set_ratio"] == pytest.approx(gauge, rel=1e-6, abs=1e-9)
    assert summary["limits_ok"] == (summary["worst_torque_set_ratio"] <= 1.0 + 1e-6)


@given(data=problems(), axis=slew_axes)
@_campaign(1)
def test_commands_never_exit_3(data, axis, tmp_path_factory) -> None:
    check_commands(data, axis, tmp_path_factory.mktemp("valid"))


@pytest.mark.slow
def test_commands_many(tmp_path_factory) -> None:
    def check(data: dict[str, Any], axis: np.ndarray) -> None:
        check_commands(data, axis, tmp_path_factory.mktemp("valid"), every_mode=True)

    _many("commands", check, problems(), slew_axes)


# ------------------------------------------------------------------ two problems by hand


def _round_off_swarm(paper_data: dict[str, Any]) -> dict[str, Any]:
    """The paper's debris with eight CubeSats, each a main engine and two side engines
    whose directions carry the round-off a computed direction has (cos 90 deg = 6e-17)."""
    data = {k: v for k, v in paper_data.items() if k != "cubesat_layout"}
    data["name"] = "round-off"
    spots = [
        ("-x", [0.0, 0.3, 0.2]),
        ("+x", [0.75, 0.3, 0.2]),
        ("-x", [0.0, 2.7, 0.8]),
        ("+x", [0.75, 2.7, 0.8]),
        ("-y", [0.375, 0.0, 0.2]),
        ("+y", [0.375, 3.0, 0.8]),
        ("-z", [0.2, 1.0, 0.0]),
        ("+z", [0.5, 2.0, 1.0]),
    ]
    cubesats = []
    for face, position in spots:
        axis = "xyz".index(face[1])
        inward = [0.0, 0.0, 0.0]
        inward[axis] = -1.0 if face[0] == "+" else 1.0
        side = [0.0, 0.0, 0.0]
        side[(axis + 1) % 3] = 1.0
        side[axis] = math.cos(math.pi / 2)
        engines = [{"direction": d} for d in (inward, side, [-c for c in side])]
        cubesats.append(
            {
                "position_corner_m": position,
                "mass_kg": 3.5,
                "inertia_kgm2": [0.0513, 0.0513, 0.0082],
                "face": face,
                "engines": engines,
            }
        )
    data["cubesats"] = cubesats
    return data


def test_fuel_optimal_slew_with_round_off_in_engine_directions(paper_data) -> None:
    """A direction component of 6e-17 is a valid input; the slew must not turn it to NaN."""
    data = _round_off_swarm(paper_data)
    problem, ref = problem_from_dict(data, "round-off"), reference(data)
    angle = math.radians(30.0)
    profile = fuel_optimal_slew(problem, "z", angle, duration_s=3000.0, options=_options(3000.0))
    check_dynamics(profile, ref)
    check_torque_set(profile, ref)


def test_paper_bang_bang_about_a_non_principal_axis_keeps_the_box(paper_data) -> None:
    """The paper's debris, 180 deg about (1, 1, 1): the gyroscopic torque counts too."""
    problem = problem_from_dict(paper_data, "paper")
    profile = bang_bang_slew(problem, [1.0, 1.0, 1.0], math.pi, check_vibration=False)
    # The reference's own geometry: the paper's layout expanded, as `model` lists it.
    described = describe_model(problem)
    r = np.array([t.position_m for t in described.thrusters])
    d = np.array([t.direction for t in described.thrusters])
    f_max = np.array([t.max_thrust_mN for t in described.thrusters]) * 1e-3
    ref = Reference(
        mass_kg=described.mass_kg,
        cog_corner_m=np.asarray(described.cog_m),
        inertia_kgm2=np.asarray(described.inertia_total_kgm2),
        torque_per_N=np.cross(r, d).T,
        direction=d.T,
        max_thrust_N=f_max,
    )
    check_dynamics(profile, ref)
    check_torque_set(profile, ref)
