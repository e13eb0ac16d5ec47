"""``[[simulation.segments]]``: targets as written, checked against scipy; bad segments named."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from casadi_debris.config import EULER_SEQUENCES, Problem, problem_from_dict
from casadi_debris.errors import ProblemFileError


def sequence(data: dict[str, Any], segments: list[dict[str, Any]], **simulation: Any) -> Problem:
    data["simulation"] = {
        **data["simulation"],
        "reference": "sequence",
        "duration_s": 3000.0,
        **simulation,
        "segments": segments,
    }
    return problem_from_dict(data, "<test>")


def scalar_last(q: np.ndarray) -> np.ndarray:
    return np.asarray(q)[[1, 2, 3, 0]]


def same_rotation(q_scalar_first: np.ndarray, rotation: Rotation) -> bool:
    other = rotation.as_quat()
    mine = scalar_last(q_scalar_first)
    return bool(min(np.abs(mine - other).max(), np.abs(mine + other).max()) < 1e-12)


def test_the_shipped_sequence_reads_as_written() -> None:
    from casadi_debris.config import load_problem

    problem = load_problem("paper_sequence")
    kinds = [segment.kind for segment in problem.simulation.segments]
    assert problem.simulation.reference == "sequence"
    assert kinds == ["slew", "hold", "slew", "track"]
    first = problem.simulation.segments[0].target
    assert first.kind == "rotation" and first.axis == (1.0, 1.0, 1.0) and first.angle_deg == 90.0


@pytest.mark.parametrize("sequence_name", ["ZYX", "xyz", "XZX", "zyz"])
def test_euler_targets_are_scipys(fresh_data: dict[str, Any], sequence_name: str) -> None:
    angles = [30.0, -20.0, 75.0]
    problem = sequence(
        fresh_data,
        [{"kind": "slew", "euler_deg": angles, "euler_sequence": sequence_name}],
    )
    target = problem.simulation.segments[0].target
    assert target.kind == "attitude"
    assert same_rotation(target.quaternion, Rotation.from_euler(sequence_name, angles, True))


def test_euler_sequence_defaults_to_intrinsic_zyx(fresh_data: dict[str, Any]) -> None:
    yaw, pitch, roll = 40.0, 10.0, -5.0
    problem = sequence(fresh_data, [{"kind": "slew", "euler_deg": [yaw, pitch, roll]}])
    # 3-2-1 by hand: C_NB = Rz(yaw) Ry(pitch) Rx(roll), turns about the body's own axes.
    c, s = np.cos, np.sin
    y, p, r = np.radians([yaw, pitch, roll])
    rz = np.array([[c(y), -s(y), 0], [s(y), c(y), 0], [0, 0, 1]])
    ry = np.array([[c(p), 0, s(p)], [0, 1, 0], [-s(p), 0, c(p)]])
    rx = np.array([[1, 0, 0], [0, c(r), -s(r)], [0, s(r), c(r)]])
    expected = Rotation.from_matrix(rz @ ry @ rx)
    assert same_rotation(problem.simulation.segments[0].target.quaternion, expected)
    assert len(EULER_SEQUENCES) == 24


def test_a_quaternion_is_normalised_within_its_tolerance(fresh_data: dict[str, Any]) -> None:
    half = math.sqrt(0.5)
    written = [round(half, 4), round(half, 4), 0.0, 0.0]  # norm 0.99999
    problem = sequence(fresh_data, [{"kind": "slew", "quaternion": written}])
    q = problem.simulation.segments[0].target.quaternion
    assert abs(np.linalg.norm(q) - 1.0) < 1e-15
    assert np.allclose(q, [half, half, 0.0, 0.0], atol=1e-4)


def test_nadir_axes_give_the_frame_offset(fresh_data: dict[str, Any]) -> None:
    """nadir_axis -> o3 and along_axis -> o1: C_OB maps them onto the frame's axes."""
    problem = sequence(
        fresh_data,
        [{"kind": "track", "frame": "nadir", "nadir_axis": "-x", "along_axis": [0.0, 1.0, 1.0]}],
    )
    target = problem.simulation.segments[0].target
    c_ob = Rotation.from_quat(scalar_last(target.quaternion)).as_matrix()
    assert np.allclose(c_ob @ [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], atol=1e-12)
    along = np.array([0.0, 1.0, 1.0]) / math.sqrt(2.0)  # already perpendicular to -x
    assert np.allclose(c_ob @ along, [1.0, 0.0, 0.0], atol=1e-12)


def test_lvlh_offsets_are_attitudes_in_the_frame(fresh_data: dict[str, Any]) -> None:
    problem = sequence(
        fresh_data, [{"kind": "track", "frame": "lvlh", "axis": "z", "angle_deg": 30.0}]
    )
    target = problem.simulation.segments[0].target
    expected = Rotation.from_rotvec([0.0, 0.0, math.radians(30.0)])
    assert target.frame == "lvlh" and same_rotation(target.quaternion, expected)


def test_a_vector_axis_is_read_in_the_one_slew_table(fresh_data: dict[str, Any]) -> None:
    fresh_data["simulation"] |= {"reference": "slew", "duration_s": 1500.0}
    fresh_data["simulation"]["slew"] = {"axis": [1, 1, 1], "angle_deg": 90.0}
    problem = problem_from_dict(fresh_data, "<test>")
    assert problem.simulation.slew.axis == (1.0, 1.0, 1.0)


BAD = [
    ({"kind": "spin", "duration_s": 10.0}, "simulation.segments[0].kind", "must be one of"),
    (
        {"kind": "slew", "quaternion": [1.0, 1.0, 0.0, 0.0]},
        "simulation.segments[0].quaternion",
        "unit norm",
    ),
    ({"kind": "hold", "duration_s": -5.0}, "simulation.segments[0].duration_s", "positive"),
    ({"kind": "hold", "duration_s": 0.0}, "simulation.segments[0].duration_s", "positive"),
    ({"kind": "slew", "axis": [0, 0, 0], "angle_deg": 9.0}, "simulation.segments[0].axis", "zero"),
    ({"kind": "slew", "method": "bang-bang"}, "simulation.segments[0].axis", "needs a target"),
    (
        {"kind": "slew", "axis": "x", "angle_deg": 9.0, "quaternion": [1.0, 0, 0, 0]},
        "simulation.segments[0].quaternion",
        "one target",
    ),
    ({"kind": "hold", "axis": "x", "duration_s": 9.0}, "simulation.segments[0].axis", "no target"),
    (
        {"kind": "track", "frame": "nadir", "euler_deg": [1.0, 2.0, 3.0]},
        "simulation.segments[0].euler_deg",
        "lvlh",
    ),
    (
        {"kind": "track", "frame": "nadir", "nadir_axis": "x", "along_axis": "-x"},
        "simulation.segments[0].along_axis",
        "parallel",
    ),
    (
        {"kind": "slew", "axis": "x", "angle_deg": 9.0, "euler_sequence": "XXY"},
        "simulation.segments[0].euler_deg",
        "one target",
    ),
    (
        {"kind": "slew", "euler_deg": [1.0, 2.0, 3.0], "euler_sequence": "XXY"},
        "simulation.segments[0].euler_sequence",
        "must be one of",
    ),
    (
        {"kind": "slew", "axis": "x", "angle_deg": 9.0, "thrusters": True},
        "simulation.segments[0].thrusters",
        "not bang-bang",
    ),
    (
        {"kind": "slew", "axis": "x", "angle_deg": 9.0, "method": "fuel-optimal"},
        "simulation.segments[0].duration_s",
        "needs its duration",
    ),
    ({"kind": "hold", "duration_s": 9.0, "method": "bang-bang"}, "[0].method", "only for a slew"),
    ({"kind": "track", "frame": "lvlh", "blend_s": 0.1}, "simulation.segments[0].blend_s", "least"),
    ({"kind": "burn", "duration_s": 9.0}, "simulation.segments[0].direction", "missing"),
    ({"kind": "burn", "direction": "up"}, "simulation.segments[0].direction", "must be one of"),
    (
        {"kind": "burn", "direction": "normal", "frame": "lvlh"},
        "simulation.segments[0].frame",
        "no other target",
    ),
    (
        {"kind": "burn", "direction": "normal", "body_axis": [0, 0, 0]},
        "simulation.segments[0].body_axis",
        "zero",
    ),
    (
        {"kind": "burn", "direction": "normal", "thrust_fraction": 1.5},
        "simulation.segments[0].thrust_fraction",
        "at most",
    ),
    (
        {"kind": "burn", "direction": "normal", "thrust_fraction": 0.5, "thrust_mN": 1.0},
        "simulation.segments[0].thrust_mN",
        "not both",
    ),
    (
        {"kind": "track", "frame": "lvlh", "direction": "normal"},
        "simulation.segments[0].direction",
        "only for a burn",
    ),
    ({"kind": "burn", "direction": "normal", "method": "bang-bang"}, "[0].method", "only for a"),
]


@pytest.mark.parametrize(("segment", "key", "words"), BAD)
def test_bad_segments_are_named(
    fresh_data: dict[str, Any], segment: dict[str, Any], key: str, words: str
) -> None:
    with pytest.raises(ProblemFileError, match=words) as caught:
        sequence(fresh_data, [segment])
    assert caught.value.field.endswith(key)


def test_overlapping_segments_are_refused(fresh_data: dict[str, Any]) -> None:
    segments = [
        {"kind": "hold", "duration_s": 100.0, "start_s": 50.0},
        {"kind": "hold", "duration_s": 100.0, "start_s": 120.0},
    ]
    with pytest.raises(ProblemFileError, match="overlaps") as caught:
        sequence(fresh_data, segments)
    assert caught.value.field == "simulation.segments[1].start_s"


def test_only_the_last_segment_may_run_to_the_end(fresh_data: dict[str, Any]) -> None:
    segments = [{"kind": "hold"}, {"kind": "slew", "axis": "x", "angle_deg": 9.0}]
    with pytest.raises(ProblemFileError, match="only the last") as caught:
        sequence(fresh_data, segments)
    assert caught.value.field == "simulation.segments[0].duration_s"


def test_segments_past_the_run_are_refused(fresh_data: dict[str, Any]) -> None:
    segments = [{"kind": "hold", "duration_s": 2000.0}, {"kind": "hold", "duration_s": 2000.0}]
    with pytest.raises(ProblemFileError, match="past the run") as caught:
        sequence(fresh_data, segments)
    assert caught.value.field == "simulation.segments[1].duration_s"


@pytest.mark.parametrize(
    ("reference", "table", "key"),
    [
        ("sequence", None, "simulation.segments"),
        ("hold", "segments", "simulation.segments"),
        ("sequence", "slew", "simulation.slew"),
    ],
)
def test_reference_and_tables_agree(
    fresh_data: dict[str, Any], reference: str, table: str | None, key: str
) -> None:
    fresh_data["simulation"]["reference"] = reference
    if table == "segments":
        fresh_data["simulation"]["segments"] = [{"kind": "hold"}]
    elif table == "slew":
        fresh_data["simulation"]["slew"] = {"axis": "x", "angle_deg": 9.0}
    with pytest.raises(ProblemFileError) as caught:
        problem_from_dict(fresh_data, "<test>")
    assert caught.value.field == key


def test_a_burn_reads_its_axis_and_thrust(fresh_data: dict[str, Any]) -> None:
    segment = {"kind": "burn", "direction": "antinormal", "body_axis": "-z", "thrust_mN": 1.5}
    burn = sequence(fresh_data, [segment]).simulation.segments[0].burn
    assert burn is not None
    # SI inside: the file's mN become N in the request.
    assert (burn.direction, burn.body_axis, burn.thrust_N) == ("antinormal", "-z", 1.5e-3)
    assert burn.thrust_fraction == 1.0 and burn.duration_s is None


def test_a_burn_plan_is_derived_from_its_request(fresh_data: dict[str, Any]) -> None:
    """The plan resolves the request's axis (a name, a vector, or the swarm's strongest
    torque-free direction) to a unit vector and takes the firing time its segment gives."""
    from casadi_debris.config import BurnRequest
    from casadi_debris.errors import SimulationError
    from casadi_debris.guidance import plan_burn, strongest_axis

    problem = problem_from_dict(fresh_data, "<test>")
    named = plan_burn(problem, BurnRequest("normal", "-z", thrust_N=2e-3, duration_s=60.0))
    assert np.array_equal(named.body_axis, [0.0, 0.0, -1.0])
    assert (named.direction, named.duration_s, named.thrust_N) == ("normal", 60.0, 2e-3)
    vector = plan_burn(problem, BurnRequest("prograde", (3.0, 0.0, 4.0)), duration_s=30.0)
    assert np.allclose(vector.body_axis, [0.6, 0.0, 0.8], rtol=0, atol=1e-15)
    assert vector.duration_s == 30.0 and vector.thrust_fraction == 1.0
    strongest = plan_burn(problem, BurnRequest("retrograde", thrust_fraction=0.5), 10.0)
    assert np.allclose(strongest.body_axis, strongest_axis(problem), rtol=0, atol=1e-15)
    with pytest.raises(SimulationError, match="duration_s: a burn needs its firing time"):
        plan_burn(problem, BurnRequest("normal"))


def test_a_slew_segment_and_the_one_slew_table_read_into_one_request(
    fresh_data: dict[str, Any],
) -> None:
    """A slew segment holds one SlewRequest whose target, start and duration are the
    segment's; ``[simulation.slew]`` reads into the same type, and flies as that segment."""
    from casadi_debris.config import Segment, SlewRequest

    written = {"method": "time-optimal", "thrusters": True, "torque_fraction": 0.5}
    segment = sequence(
        fresh_data,
        [{"kind": "slew", "axis": "y", "angle_deg": 40.0, "start_s": 10.0, **written}],
    ).simulation.segments[0]
    request = segment.slew
    assert isinstance(request, SlewRequest)
    assert request.target is segment.target and request.target.axis == "y"
    assert (request.start_s, request.duration_s) == (segment.start_s, segment.duration_s)
    assert (request.method, request.torque_fraction) == ("time-optimal", 0.5)
    # A problem file's thruster level is at zero net force, as the loop's allocator flies it.
    assert request.thrusters and request.zero_net_force

    del fresh_data["simulation"]["segments"]
    fresh_data["simulation"] |= {"reference": "slew", "duration_s": 1500.0}
    fresh_data["simulation"]["slew"] = {"axis": "y", "angle_deg": 40.0, "start_s": 10.0}
    fresh_data["simulation"]["slew"] |= written
    one = problem_from_dict(fresh_data, "<test>").simulation
    assert isinstance(one.slew, SlewRequest)
    flown = Segment.of_slew(one.slew)
    assert flown.slew is one.slew and flown.target is one.slew.target
    assert (flown.kind, flown.start_s, flown.duration_s) == ("slew", 10.0, None)
    assert (one.slew.axis, one.slew.angle_deg) == ("y", 40.0)


def test_a_turn_has_an_axis_and_an_attitude_has_none(fresh_data: dict[str, Any]) -> None:
    from casadi_debris.config import slew_about
    from casadi_debris.errors import InputShapeError

    turn = slew_about("-x", 25.0, method="fuel-optimal", duration_s=600.0)
    assert (turn.axis, turn.angle_deg, turn.method, turn.duration_s) == (
        "-x",
        25.0,
        "fuel-optimal",
        600.0,
    )
    attitude = sequence(
        fresh_data, [{"kind": "slew", "quaternion": [0.0, 1.0, 0.0, 0.0]}]
    ).simulation.segments[0]
    assert attitude.slew is not None
    with pytest.raises(InputShapeError, match="axis: the slew's target is an attitude, not a turn"):
        _ = attitude.slew.axis
