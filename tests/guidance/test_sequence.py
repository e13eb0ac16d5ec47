"""Manoeuvre references: targets, compositions and tracks against independent computations."""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from casadi_debris.config import Problem, default_controller_path, load_problem, problem_from_dict
from casadi_debris.dynamics import attitude_error, build_model
from casadi_debris.errors import ProblemFileError
from casadi_debris.guidance import (
    body_rates,
    generate_slew,
    manoeuvre_reference,
    sample_reference,
    scenario_reference,
    segment_records,
    sequence_pieces,
)
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import simulate_closed_loop


def sequence(
    data: dict[str, Any], segments: list[dict[str, Any]], duration_s: float = 3000.0
) -> Problem:
    data["simulation"] = {
        **data["simulation"],
        "reference": "sequence",
        "duration_s": duration_s,
        "segments": segments,
    }
    return problem_from_dict(data, "<test>")


def rotation(q: np.ndarray) -> Rotation:
    return Rotation.from_quat(np.asarray(q)[..., [1, 2, 3, 0]])


def angle_between(q: np.ndarray, expected: Rotation) -> float:
    return float((rotation(q).inv() * expected).magnitude())


def test_one_slew_is_the_one_segment_case_bit_for_bit() -> None:
    """``[simulation.slew]`` flies exactly the reference it flew before segments existed."""
    problem = load_problem("paper_slew")
    reference = scenario_reference(problem)
    slew = generate_slew(problem, problem.simulation.slew, 1.0)
    before = sample_reference(reference.time_s, slew, problem.simulation.slew.start_s)
    assert np.array_equal(reference.quaternion_BN, before.quaternion_BN)
    assert reference.slew.duration_s == slew.duration_s and reference.start_s == 0.0


def test_a_hold_is_the_identity() -> None:
    reference = scenario_reference(load_problem("paper_pointing"))
    assert np.array_equal(reference.quaternion_BN, np.tile([1.0, 0, 0, 0], (59081, 1)))


def test_two_slews_compose_as_scipy(fresh_data: dict[str, Any]) -> None:
    """90 deg about x then 90 deg about y (body axes): R = Rx(90) Ry(90), hold in between."""
    segments = [
        {"kind": "slew", "axis": "x", "angle_deg": 90.0, "duration_s": 1300.0},
        {"kind": "hold", "duration_s": 100.0},
        {"kind": "slew", "axis": "y", "angle_deg": 90.0, "duration_s": 1300.0},
    ]
    problem = sequence(fresh_data, segments, duration_s=3000.0)
    reference = scenario_reference(problem)
    expected = Rotation.from_rotvec([math.pi / 2, 0, 0]) * Rotation.from_rotvec([0, math.pi / 2, 0])
    assert angle_between(reference.quaternion_BN[-1], expected) < 1e-9
    after_first = Rotation.from_rotvec([math.pi / 2, 0, 0])
    hold = (reference.time_s > 1300.0) & (reference.time_s < 1400.0)
    assert max(angle_between(q, after_first) for q in reference.quaternion_BN[hold]) < 1e-9
    kinds = [(r.segment, r.kind, r.start_s, r.end_s) for r in segment_records(reference.pieces)]
    assert kinds == [
        (1, "slew", 0.0, 1300.0),
        (2, "hold", 1300.0, 1400.0),
        (3, "slew", 1400.0, 2700.0),
        (None, "hold", 2700.0, 3000.0),
    ]


def test_a_later_start_holds_until_then(fresh_data: dict[str, Any]) -> None:
    segments = [{"kind": "slew", "axis": "z", "angle_deg": 30.0, "start_s": 200.0}]
    reference = scenario_reference(sequence(fresh_data, segments, duration_s=1500.0))
    before = reference.time_s <= 200.0
    assert np.array_equal(reference.quaternion_BN[before], np.tile([1.0, 0, 0, 0], (2001, 1)))
    assert reference.start_s == 200.0


def test_euler_and_quaternion_targets_reach_their_attitude(fresh_data: dict[str, Any]) -> None:
    angles = [20.0, -35.0, 50.0]
    segments = [
        {"kind": "slew", "euler_deg": angles, "euler_sequence": "XYZ"},
        {"kind": "hold", "duration_s": 10.0},
        {"kind": "slew", "quaternion": [0.5, 0.5, 0.5, 0.5]},
    ]
    pieces = sequence_pieces(sequence(fresh_data, segments, duration_s=5000.0), 1.0)
    end_of_first = pieces[0].end_attitude()
    assert angle_between(end_of_first, Rotation.from_euler("XYZ", angles, True)) < 1e-9
    assert angle_between(pieces[2].end_attitude(), rotation([0.5, 0.5, 0.5, 0.5])) < 1e-9


@pytest.fixture(scope="module")
def controller() -> Any:
    return Controller.from_dict(json.loads(default_controller_path().read_text())).reduced


def test_a_quaternion_target_flies_as_the_same_axis_angle(
    paper_data: dict[str, Any], controller: Any
) -> None:
    """20 deg about [1, 1, 1] written both ways: the same reference and the same run."""
    half = math.radians(20.0) / 2
    q = [math.cos(half), *(math.sin(half) / math.sqrt(3.0) * np.ones(3))]
    # 600 s: the bang-bang about [1, 1, 1] needs at least 520.2 s within the authority
    # (its gyroscopic torque included).
    timing = {"method": "bang-bang", "duration_s": 600.0}
    runs = []
    for target in ({"axis": [1, 1, 1], "angle_deg": 20.0}, {"quaternion": q}):
        data = json.loads(json.dumps(paper_data))
        problem = sequence(data, [{"kind": "slew", **target, **timing}], duration_s=620.0)
        reference = scenario_reference(problem)
        model = build_model(problem)
        runs.append((reference, simulate_closed_loop(model, controller, reference)))
    (ref_a, run_a), (ref_b, run_b) = runs
    assert np.abs(ref_a.quaternion_BN - ref_b.quaternion_BN).max() < 1e-12
    assert np.abs(run_a.error_rad - run_b.error_rad).max() < 1e-10
    assert np.abs(run_a.torque_Nm - run_b.torque_Nm).max() < 1e-10
    assert np.abs(run_a.error_rad).max() > 1e-6  # a real slew was flown


def kepler_frame(problem: Problem, time_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """r and v by hand from the circular orbit's elements (not environment/orbit.py)."""
    orbit, constants = problem.orbit, problem.constants
    a = (constants.earth_radius_km + orbit.altitude_km) * 1e3
    mu = constants.earth_mu_km3_s2 * 1e9
    n = math.sqrt(mu / a**3)
    i, raan = math.radians(orbit.inclination_deg), math.radians(orbit.raan_deg)
    u = math.radians(orbit.argument_of_latitude_deg) + n * time_s
    node = np.array([math.cos(raan), math.sin(raan), 0.0])
    up = np.array([-math.cos(i) * math.sin(raan), math.cos(i) * math.cos(raan), math.sin(i)])
    r = a * (np.cos(u)[:, None] * node + np.sin(u)[:, None] * up)
    v = a * n * (-np.sin(u)[:, None] * node + np.cos(u)[:, None] * up)
    return r, v


def test_nadir_track_points_its_axes_from_r_and_v(fresh_data: dict[str, Any]) -> None:
    """After its start-up the body's nadir axis points at -r and its along axis along v."""
    fresh_data["orbit"] |= {"raan_deg": 30.0, "argument_of_latitude_deg": 40.0}
    segment = {"kind": "track", "frame": "nadir", "nadir_axis": "-y", "along_axis": "+z"}
    problem = sequence(fresh_data, [{**segment, "blend_s": 600.0}], duration_s=3000.0)
    reference = scenario_reference(problem)
    on_track = reference.time_s >= 600.0
    times = reference.time_s[on_track]
    c_nb = rotation(reference.quaternion_BN[on_track]).as_matrix()
    r, v = kepler_frame(problem, times)
    nadir = c_nb @ np.array([0.0, -1.0, 0.0])
    along = c_nb @ np.array([0.0, 0.0, 1.0])
    assert np.abs(nadir + r / np.linalg.norm(r, axis=1, keepdims=True)).max() < 1e-9
    assert np.abs(along - v / np.linalg.norm(v, axis=1, keepdims=True)).max() < 1e-9


def test_lvlh_track_aligns_the_body_with_the_frame(fresh_data: dict[str, Any]) -> None:
    problem = sequence(fresh_data, [{"kind": "track", "frame": "lvlh", "blend_s": 300.0}])
    reference = scenario_reference(problem)
    late = reference.time_s >= 300.0
    c_nb = rotation(reference.quaternion_BN[late]).as_matrix()
    r, v = kepler_frame(problem, reference.time_s[late])
    h = np.cross(r, v)
    o2 = -h / np.linalg.norm(h, axis=1, keepdims=True)
    o3 = -r / np.linalg.norm(r, axis=1, keepdims=True)
    o1 = np.cross(o2, o3)
    for column, axis in enumerate((o1, o2, o3)):
        assert np.abs(c_nb[:, :, column] - axis).max() < 1e-9


@pytest.mark.slow  # six bang-bang solves (with their least-fuel thrust) onto the moving frame
def test_a_track_starts_and_stops_at_rest(fresh_data: dict[str, Any]) -> None:
    """Slew onto nadir, track, hold: attitude and rate continuous, the rate rising to the
    orbit rate n at the peak acceleration 1.875 n / T of the smoothstep, then back to 0."""
    blend_s = 400.0
    segments = [
        {"kind": "slew", "frame": "nadir", "torque_fraction": 0.5},
        {"kind": "track", "frame": "nadir", "duration_s": 1500.0, "blend_s": blend_s},
        {"kind": "hold", "duration_s": 300.0},
    ]
    problem = sequence(fresh_data, segments, duration_s=5000.0)
    reference = manoeuvre_reference(problem, 0.5)
    t, q, rate = reference.time_s, reference.quaternion_BN, reference.rate_rad_s
    slew, track, hold = reference.summary.segments[:3]
    n = math.sqrt(problem.constants.earth_mu_km3_s2 * 1e9 / (
        (problem.constants.earth_radius_km + problem.orbit.altitude_km) * 1e3) ** 3)  # fmt: skip
    speed = np.linalg.norm(rate, axis=1)
    # At the joins only what the slew's own last half second leaves (its deceleration).
    assert speed[np.abs(t - track.start_s) < 1.0].max() < 0.01 * n
    middle = (t > track.start_s + blend_s + 1) & (t < track.end_s - blend_s - 1)
    assert np.abs(speed[middle] - n).max() < 1e-9
    assert speed[t > track.end_s + 1.0].max() < 1e-9
    step = np.linalg.norm(attitude_error(q[:-1], q[1:]), axis=1)
    assert step.max() < 0.5 * 1.01 * speed.max()  # no jump: each step within the rate
    spin_up = (t > track.start_s) & (t < track.start_s + blend_s)
    acceleration = np.linalg.norm(np.diff(rate, axis=0), axis=1) / 0.5
    peak = acceleration[spin_up[:-1]].max()
    assert peak == pytest.approx(1.875 * n / blend_s, rel=0.01)
    assert hold.kind == "hold" and slew.kind == "slew"


def test_a_slew_onto_a_frame_lands_where_the_track_starts(fresh_data: dict[str, Any]) -> None:
    """Its end is the frame's attitude half a start-up later, so the start-up is a pure turn
    about the orbit normal (no correction): q(t0 + T) = frame(t0 + T)."""
    blend_s = 600.0
    segments = [
        {"kind": "slew", "frame": "lvlh", "euler_deg": [0.0, 10.0, 0.0], "method": "bang-bang"},
        {"kind": "track", "frame": "lvlh", "euler_deg": [0.0, 10.0, 0.0], "blend_s": blend_s},
    ]
    problem = sequence(fresh_data, segments, duration_s=5000.0)
    pieces = sequence_pieces(problem, 1.0)
    slew, track = pieces[0], pieces[1]
    frame_end = track.attitude(np.array([track.start_s + blend_s, 4000.0]))
    n = 2 * math.pi / (98.5 * 60)  # about the orbit rate: the check needs only its scale
    # Past the start-up the track is on the frame: compare with the frame itself.
    from casadi_debris.environment import CircularOrbit
    from casadi_debris.guidance import frame_attitude

    offset = problem.simulation.segments[1].target.quaternion
    frame = frame_attitude(
        CircularOrbit.from_problem(problem), offset, np.array([track.start_s + blend_s, 4000.0])
    )
    for mine, theirs in zip(frame_end, frame, strict=True):
        assert angle_between(mine, rotation(theirs)) < 1e-9
    lead = frame_attitude(
        CircularOrbit.from_problem(problem), offset, np.array([slew.end_s + blend_s / 2])
    )[0]
    assert angle_between(slew.end_attitude(), rotation(lead)) < 2e-3 * n


def test_body_rates_of_a_steady_spin() -> None:
    times = np.linspace(0.0, 10.0, 101)
    omega = np.array([0.01, -0.02, 0.03])
    turned = Rotation.from_rotvec(times[:, None] * omega)
    q = turned.as_quat()[:, [3, 0, 1, 2]]
    assert np.abs(body_rates(times, q) - omega).max() < 1e-12


def test_a_slew_onto_its_start_is_named(fresh_data: dict[str, Any]) -> None:
    problem = sequence(fresh_data, [{"kind": "slew", "quaternion": [1.0, 0.0, 0.0, 0.0]}])
    with pytest.raises(ProblemFileError, match="nothing to slew") as caught:
        scenario_reference(problem)
    assert caught.value.field == "simulation.segments[0]"


def test_a_track_too_short_for_its_start_up_is_named(fresh_data: dict[str, Any]) -> None:
    segments = [
        {"kind": "track", "frame": "lvlh", "duration_s": 500.0, "blend_s": 300.0},
        {"kind": "hold"},
    ]
    with pytest.raises(ProblemFileError, match="does not fit") as caught:
        scenario_reference(sequence(fresh_data, segments))
    assert caught.value.field == "simulation.segments[0].blend_s"


def test_an_infeasible_slew_names_its_duration(fresh_data: dict[str, Any]) -> None:
    segments = [{"kind": "slew", "axis": "z", "angle_deg": 180.0, "duration_s": 10.0}]
    with pytest.raises(ProblemFileError) as caught:
        scenario_reference(sequence(fresh_data, segments))
    assert caught.value.field == "simulation.segments[0].duration_s"
