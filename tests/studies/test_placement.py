"""The placement MILP against exhaustive search, its authority against independent LPs.

Brute force: every subset of a small candidate set (and, for the failure-robust
objective, every failure set of each subset), each judged by
:func:`casadi_debris.geometry.torque_authority` with the surviving engines
available, on one geometry holding every candidate. With zero net force the
torque does not depend on the point it is taken about, so one geometry serves
all subsets.
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from casadi_debris.config import SIGNED_AXES, Problem, expand_layout, signed_axis_vector
from casadi_debris.errors import InputShapeError
from casadi_debris.geometry import build_geometry, max_thrust_N, torque_authority
from casadi_debris.studies.placement import (
    CandidateSet,
    ParetoPoint,
    PlacementSettings,
    bare_debris,
    dominates,
    face_candidates,
    mark_front,
    meets_limits,
    optimise_placement,
    pareto_front,
    parse_grid,
    placed_problem,
    placement_data,
    solve_placement,
)
from lp_reference import ZERO_FORCE, largest_alpha

TOLERANCE = 1e-7


def small_set(
    problem: Problem, size: int, seed: int, sides: tuple[int, ...] = (4,)
) -> CandidateSet:
    """``size`` mounts drawn (seeded) from the 2 x 2 grid, each with the given templates."""
    full = face_candidates(problem, (2, 2), sides)
    mounts = np.sort(np.random.default_rng(seed).choice(full.n_mounts, size, replace=False))
    kept = [c for c in full.candidates if c.mount in mounts]
    renumbered = tuple(
        dataclasses.replace(c, index=i, mount=int(np.searchsorted(mounts, c.mount)))
        for i, c in enumerate(kept)
    )
    return dataclasses.replace(full, candidates=renumbered)


class BruteForce:
    """Worst authority over disturbance of any subset, by LP on one all-candidate geometry.

    ``independent_lp``: one LP per signed axis of the tests' own (``lp_reference``: the
    largest multiple of a pure torque the engines reach at zero net force); otherwise the
    toolkit's :func:`torque_authority` (the six axes in one block LP, checked against
    the former below).
    """

    def __init__(
        self, problem: Problem, candidates: CandidateSet, independent_lp: bool = False
    ) -> None:
        self.candidates = candidates
        everyone = tuple(c.cubesat for c in candidates.candidates)
        self.geometry = build_geometry(placed_problem(problem, everyone))
        self.owner = self.geometry.engine_cubesat
        self.disturbance = np.abs(problem.disturbance.amplitude_mNm) * 1e-3
        self.independent_lp = independent_lp

    def authority(self, alive: tuple[int, ...]) -> np.ndarray:
        available = np.isin(self.owner, alive)
        if self.independent_lp:
            limits = np.where(available, max_thrust_N(self.geometry), 0.0)
            unit_Nm = 1e-3  # the LP's demand; alpha is the authority in its units
            return np.array(
                [
                    unit_Nm
                    * largest_alpha(
                        self.geometry,
                        limits,
                        unit_Nm * signed_axis_vector(n),
                        ZERO_FORCE,
                        at_most=None,
                    )
                    for n in SIGNED_AXES
                ]
            )
        authority = torque_authority(self.geometry, zero_net_force=True, available=available)
        return np.array([authority[n] for n in SIGNED_AXES])

    def ratio(self, alive: tuple[int, ...]) -> float:
        return float(np.min(self.authority(alive) / np.repeat(self.disturbance, 2)))

    def robust(self, chosen: tuple[int, ...], failures: int) -> float:
        sets = itertools.combinations(chosen, min(failures, len(chosen)))
        return min(self.ratio(tuple(c for c in chosen if c not in s)) for s in sets)

    def layouts(self, count: int):
        mounts = [c.mount for c in self.candidates.candidates]
        for subset in itertools.combinations(range(len(mounts)), count):
            if len({mounts[i] for i in subset}) == count:
                yield subset


def test_block_lp_equals_an_independent_lp_per_axis(problem):
    candidates = small_set(problem, 10, seed=10)
    reference = BruteForce(problem, candidates, independent_lp=True)
    blocks = BruteForce(problem, candidates)
    rng = np.random.default_rng(11)
    for _ in range(12):
        alive = tuple(int(i) for i in rng.choice(10, int(rng.integers(1, 10)), replace=False))
        np.testing.assert_allclose(
            blocks.authority(alive), reference.authority(alive), rtol=1e-7, atol=1e-12
        )


@pytest.mark.parametrize(
    ("size", "count", "seed", "independent_lp"),
    [(8, 4, 1, True), (10, 4, 2, False), (9, 5, 3, False)],
)
def test_milp_equals_exhaustive_search(problem, size, count, seed, independent_lp):
    candidates = small_set(problem, size, seed)
    brute = BruteForce(problem, candidates, independent_lp)
    best = max(brute.ratio(s) for s in brute.layouts(count))
    assert best > 0.1  # a search that could find nothing would prove nothing
    solution = solve_placement(
        placement_data(problem, candidates), PlacementSettings((count, count))
    )
    assert solution.optimal and solution.gap == 0.0
    assert solution.objective == pytest.approx(best, rel=TOLERANCE)
    assert brute.ratio(solution.chosen) == pytest.approx(best, rel=TOLERANCE)
    assert solution.solves[-1].objective == pytest.approx(best, rel=1e-6)


def test_templates_one_per_mount_against_exhaustive_search(problem):
    candidates = small_set(problem, 6, seed=4, sides=(0, 4))
    assert len(candidates.candidates) == 12
    brute = BruteForce(problem, candidates)
    best = max(brute.ratio(s) for s in brute.layouts(3))
    solution = solve_placement(placement_data(problem, candidates), PlacementSettings((3, 3)))
    assert solution.objective == pytest.approx(best, rel=TOLERANCE)
    mounts = [candidates.candidates[c].mount for c in solution.chosen]
    assert len(set(mounts)) == 3


@pytest.fixture(scope="module")
def robust_cases(problem):
    """The 8-candidate set, its brute force and the best robust value per failure count."""
    candidates = small_set(problem, 8, seed=5)
    brute = BruteForce(problem, candidates)
    best = {k: max(brute.robust(s, k) for s in brute.layouts(4 + k)) for k in (1, 2)}
    return candidates, brute, best


@pytest.mark.parametrize("failures", [1, 2])
@pytest.mark.parametrize("generated", [False, True])
def test_failure_robust_against_brute_force(problem, robust_cases, failures, generated):
    candidates, brute, bests = robust_cases
    count, best = 4 + failures, bests[failures]
    assert best > 0.1
    settings = PlacementSettings(
        (count, count), failures=failures, max_extensive_variables=0 if generated else 10**6
    )
    solution = solve_placement(placement_data(problem, candidates), settings)
    assert solution.method == ("generated" if generated else "extensive")
    assert solution.optimal
    assert solution.objective == pytest.approx(best, rel=TOLERANCE)
    assert brute.robust(solution.chosen, failures) == pytest.approx(best, rel=TOLERANCE)
    # The worst set it reports leaves exactly that authority.
    worst_axis = int(np.argmin(solution.worst.ratio(brute.disturbance)))
    failed = solution.worst.worst_set[worst_axis]
    alive = tuple(c for c in solution.chosen if c not in failed)
    assert brute.ratio(alive) == pytest.approx(best, rel=TOLERANCE)


def linear_added_inertia(problem: Problem, candidates: CandidateSet, chosen) -> np.ndarray:
    """Own inertia plus m (|r|^2 - r_a^2) about the bare debris' CoG, summed (diagonal)."""
    cog, _ = bare_debris(problem)
    total = np.zeros(3)
    for index in chosen:
        cubesat = candidates.candidates[index].cubesat
        r = cubesat.position_corner_m - cog
        total += np.diag(cubesat.inertia_kgm2) + cubesat.mass_kg * (r @ r - r**2)
    return total


def test_added_inertia_limit_against_exhaustive_search(problem):
    candidates = small_set(problem, 10, seed=6)
    brute = BruteForce(problem, candidates)
    added = {s: linear_added_inertia(problem, candidates, s) for s in brute.layouts(4)}
    limit = np.median(np.array(list(added.values())), axis=0)
    feasible = [s for s, a in added.items() if np.all(a <= limit)]
    best = max(brute.ratio(s) for s in feasible)
    settings = PlacementSettings((4, 4), max_added_inertia_kgm2=tuple(limit))
    solution = solve_placement(placement_data(problem, candidates), settings)
    assert solution.objective == pytest.approx(best, rel=TOLERANCE)
    # Conservative: the inertia about the combined CoG is never above the linear sum.
    placed = build_geometry(placed_problem(problem, candidates.cubesats(solution.chosen)))
    _, bare = bare_debris(problem)
    assert np.all(np.diag(placed.inertia_total_kgm2 - bare) <= limit + 1e-9)


def test_slew_limit_against_exhaustive_search(problem):
    candidates = small_set(problem, 10, seed=7)
    brute = BruteForce(problem, candidates)
    _, bare = bare_debris(problem)
    angle = math.pi

    def slew_bound_s(subset) -> float:
        inertia = np.diag(bare) + linear_added_inertia(problem, candidates, subset)
        authority = brute.authority(subset).reshape(3, 2).min(axis=1)
        times = [
            2 * math.sqrt(angle * inertia[a] / authority[a]) if authority[a] > 0 else math.inf
            for a in range(3)
        ]
        return max(times)

    layouts = list(brute.layouts(4))
    times = {s: slew_bound_s(s) for s in layouts}
    limit = float(np.median([t for t in times.values() if math.isfinite(t)]))
    best = max(brute.ratio(s) for s in layouts if times[s] <= limit)
    settings = PlacementSettings((4, 4), max_slew_s=limit)
    solution = solve_placement(placement_data(problem, candidates), settings)
    assert solution.objective == pytest.approx(best, rel=TOLERANCE)
    assert times[solution.chosen] <= limit * (1 + 1e-9)


def test_count_range_takes_the_best_count(problem):
    candidates = small_set(problem, 8, seed=8)
    brute = BruteForce(problem, candidates)
    best = max(brute.ratio(s) for n in (3, 4) for s in brute.layouts(n))
    solution = solve_placement(placement_data(problem, candidates), PlacementSettings((3, 4)))
    assert solution.objective == pytest.approx(best, rel=TOLERANCE)


def test_paper_mounts_are_the_two_by_two_grid_and_among_the_default(problem):
    paper = expand_layout(problem.cubesat_layout, problem.hub.size_m, problem.engine)
    assert face_candidates(problem, (2, 2)).match(paper) == tuple(range(24))
    default = face_candidates(problem)
    assert len(default.candidates) == 96
    assert default.match(problem.cubesats) is not None


def test_paper_grid_at_24_is_the_paper_layout_and_its_authority(problem):
    study = optimise_placement(problem, PlacementSettings((24, 24)), grid=(2, 2))
    independent = torque_authority(build_geometry(problem), zero_net_force=True)
    for name in SIGNED_AXES:
        assert study.metrics.authority_Nm[name] == pytest.approx(independent[name], rel=1e-9)
    assert study.input_layout.among_candidates == tuple(range(24))
    assert study.solution.chosen == tuple(range(24))


def test_default_grid_beats_the_paper_at_24(problem):
    study = optimise_placement(problem, PlacementSettings((24, 24)))
    assert study.solution.optimal
    # The paper's layout is a candidate, so the optimum is at least as good.
    assert study.metrics.worst_ratio >= study.input_layout.metrics.worst_ratio - 1e-9
    chosen = study.candidates.cubesats(study.solution.chosen)
    independent = torque_authority(
        build_geometry(placed_problem(problem, chosen)), zero_net_force=True
    )
    disturbance = np.abs(problem.disturbance.amplitude_mNm) * 1e-3
    worst = min(independent[n] / disturbance["xyz".index(n[1])] for n in SIGNED_AXES)
    assert study.solution.objective == pytest.approx(worst, rel=1e-9)


def test_mark_front_keeps_exactly_the_undominated(problem):
    rng = np.random.default_rng(9)
    metrics = optimise_placement(problem, PlacementSettings((24, 24)), grid=(2, 2)).metrics
    points = []
    for i in range(30):
        ratio = {n: float(rng.uniform(1, 3)) for n in SIGNED_AXES}
        dv = {n: float(rng.choice([0.0, 3.0, 6.0])) for n in SIGNED_AXES}
        fake = dataclasses.replace(
            metrics,
            count=int(rng.integers(8, 12)),
            ratio=ratio,
            dv_one_stage_m_s=dv,
            worst_axis=min(ratio, key=ratio.__getitem__),
            slew_s=rng.uniform(900, 1800, 3),
        )
        points.append(ParetoPoint(str(i), None, fake, None, True))
    marked = mark_front(points)
    for p in marked:
        beaten = any(
            q is not p
            and q.metrics.count <= p.metrics.count
            and q.metrics.worst_ratio >= p.metrics.worst_ratio
            and q.metrics.slowest_slew_s <= p.metrics.slowest_slew_s
            and q.metrics.weakest_dv_m_s >= p.metrics.weakest_dv_m_s
            and q.figures().tolist() != p.figures().tolist()
            for q in marked
        )
        assert p.on_front == (not beaten)
    assert dominates(np.array([1.0, 1.0]), np.array([1.0, 2.0]))
    assert not dominates(np.array([1.0, 1.0]), np.array([1.0, 1.0]))


@pytest.mark.parametrize(
    ("text", "words"),
    [("4x", "--candidates"), ("0x3", "--candidates"), ("13", "1 to 12"), ("a", "4x4")],
)
def test_bad_grid_names_the_option(text, words):
    with pytest.raises(InputShapeError, match=words):
        parse_grid(text)


def test_bad_count_and_impossible_limit(problem):
    data = placement_data(problem, face_candidates(problem, (2, 2)))
    with pytest.raises(InputShapeError, match="--count"):
        solve_placement(data, PlacementSettings((25, 25)))
    with pytest.raises(InputShapeError, match="--max-added-inertia"):
        solve_placement(data, PlacementSettings((12, 12), max_added_inertia_kgm2=(1.0, 1.0, 1.0)))


def test_zero_disturbance_is_refused(problem):
    quiet = dataclasses.replace(
        problem,
        disturbance=dataclasses.replace(
            problem.disturbance, amplitude_mNm=np.array([0.7, 0.0, 0.7])
        ),
    )
    with pytest.raises(InputShapeError, match=r"disturbance\.amplitude_mNm"):
        placement_data(quiet, face_candidates(quiet, (2, 2)))


def test_incumbent_is_kept_and_checked_against_the_limits(problem, robust_cases):
    candidates, brute, bests = robust_cases
    layouts = list(brute.layouts(5))
    best = max(layouts, key=lambda s: brute.robust(s, 1))
    data = placement_data(problem, candidates)
    settings = PlacementSettings((5, 5), failures=1, max_extensive_variables=0)
    solution = solve_placement(data, settings, incumbents=[best, (0, 1)])  # (0, 1): wrong count
    assert solution.objective == pytest.approx(bests[1], rel=TOLERANCE)
    assert solution.optimal
    assert not meets_limits(data, settings, (0, 1))
    assert meets_limits(data, settings, best)


def test_pareto_sweep_points_are_the_layouts_they_name(problem):
    data = placement_data(problem, face_candidates(problem, (2, 2)))
    points = pareto_front(problem, data, [12, 24], PlacementSettings((1, 1)), fractions=(0.98,))
    assert points[-1].label == "input" and points[-1].chosen == tuple(range(24))
    disturbance = np.abs(problem.disturbance.amplitude_mNm) * 1e-3
    for point in points[:-1]:
        chosen = data.candidates.cubesats(point.chosen)
        authority = torque_authority(
            build_geometry(placed_problem(problem, chosen)), zero_net_force=True
        )
        worst = min(authority[n] / disturbance["xyz".index(n[1])] for n in SIGNED_AXES)
        assert point.metrics.worst_ratio == pytest.approx(worst, rel=1e-12)
        assert point.metrics.count == len(point.chosen)
        if point.max_slew_s is not None:
            assert point.metrics.slowest_slew_s <= point.max_slew_s * (1 + 1e-6)
    # With all 24 mounts taken there is one layout: the paper's, on the front.
    at_24 = [p for p in points if p.metrics.count == 24]
    paper = points[-1].metrics.worst_ratio
    assert all(p.metrics.worst_ratio == pytest.approx(paper, rel=1e-9) for p in at_24)
    assert points[-1].on_front
