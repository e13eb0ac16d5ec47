"""``casadi-debris mission``'s plain text: sentences that read well and say what the run did."""

from __future__ import annotations

import dataclasses
import re

import pytest

from casadi_debris import load_problem
from casadi_debris.orbit import DV_SEARCH_MAX_M_S, DeorbitSettings
from casadi_debris.report import mission_text
from casadi_debris.studies.mission import MAX_EXTRA_STAGES, MissionSummary, plan_mission

HORIZON_YEARS = DeorbitSettings().horizon_years


@pytest.fixture(scope="module")
def paper() -> MissionSummary:
    return plan_mission(load_problem(), DeorbitSettings(minimum_swarm=False, samples=0)).summary


def _sentences(text: str) -> list[str]:
    """The lines after the timeline table."""
    return [line for line in text.splitlines() if line.endswith(".")]


def _read_well(text: str) -> None:
    assert "in beyond" not in text and "(s)" not in text and "  " not in text.split("\n")[-1]
    for sentence in _sentences(text):
        assert sentence[0].isupper(), sentence


def test_each_solar_case_says_what_it_needs_what_it_burns_and_when_it_reenters(paper) -> None:
    text = mission_text(paper, HORIZON_YEARS)
    _read_well(text)
    left = paper.deorbit_dv_available_m_s
    for case, years in paper.reentry_years.items():
        [line] = [s for s in _sentences(text) if s.startswith(f"{case.capitalize()} solar")]
        need = paper.deorbit_dv_needed_m_s[case]
        assert need is not None and years is not None  # the paper's swarm can re-enter
        assert f"needs {need:.1f} m/s" in line and f"re-enters {years:.2f} years after" in line
        if need > left:
            # It burns all it has, which is not enough: later than the limit.
            assert f"more than the {left:.1f} m/s left; burning it all" in line
            assert years > paper.limit_years
        else:
            # It burns what it needs, so it re-enters at the limit.
            assert f"of the {left:.1f} m/s left; burning that" in line
            assert years == pytest.approx(paper.limit_years, abs=0.01)
    verdict = "Meets" if paper.meets_five_year_rule else "Does NOT meet"
    assert f"{verdict} the 5-year rule" in text
    assert f"leave {left:.1f} m/s of the {paper.deorbit_dv_capacity_m_s:.1f} m/s" in text
    assert (
        paper.extra_stages_needed == 1
        and "With one more stage on every engine it would meet the rule." in text
    )
    used = re.search(r"Propellant: ([\d.]+) of ([\d.]+) kg used; ([\d.]+) kg stranded", text)
    assert used is not None
    assert float(used.group(1)) == pytest.approx(paper.propellant_used_kg, abs=5e-4)
    assert float(used.group(3)) == pytest.approx(paper.propellant_stranded_kg, abs=5e-4)


def test_a_debris_no_burn_can_bring_down_in_time_is_said_so(paper) -> None:
    """As the Zenit-2 stage of the gallery: no Δv within the search meets the rule, and
    under low activity the debris outlives the horizon."""
    stuck = dataclasses.replace(
        paper,
        reentry_years={"low": None, "high": 57.22},
        deorbit_dv_needed_m_s={"low": None, "high": None},
        meets_five_year_rule=False,
        extra_stages_needed=None,
    )
    text = mission_text(stuck, HORIZON_YEARS)
    _read_well(text)
    left = f"{paper.deorbit_dv_available_m_s:.1f}"
    assert (
        f"Low solar activity: no Δv up to {DV_SEARCH_MAX_M_S:g} m/s brings re-entry within 5 "
        f"years; burning all {left} m/s left, the debris stays up beyond the "
        f"{HORIZON_YEARS:g}-year horizon."
    ) in text
    assert "High solar activity" in text and "re-enters 57.22 years after the burn starts" in text
    assert f"Even {MAX_EXTRA_STAGES} more stages on every engine would not meet it" in text


@pytest.mark.parametrize(
    ("extra", "words"),
    [(0, None), (3, "With 3 more stages on every engine it would meet the rule.")],
)
def test_the_remedy_is_said_only_when_there_is_a_gap(paper, extra, words) -> None:
    meets = extra == 0
    summary = dataclasses.replace(paper, extra_stages_needed=extra, meets_five_year_rule=meets)
    text = mission_text(summary, HORIZON_YEARS)
    _read_well(text)
    assert ("more stage" in text) == (words is not None)
    assert text.count("Meets the 5-year rule under every solar case") == int(meets)
    if words:
        assert words in text


def _timeline_boxes(summary: MissionSummary, monkeypatch, tmp_path) -> tuple:
    """The timeline's label boxes, bar boxes and axes box in display units, as written."""
    import matplotlib.pyplot as plt

    from casadi_debris.plots import mission_figure

    figure = mission_figure(summary)
    figure.tight_layout()  # as save_figure lays it out
    figure.canvas.draw()
    timeline = figure.axes[0]
    renderer = figure.canvas.get_renderer()
    labels = [t.get_window_extent(renderer) for t in timeline.texts]
    bars = [p.get_window_extent(renderer) for p in timeline.patches]
    plt.close(figure)
    return labels, bars, timeline.get_window_extent(renderer)


def _beyond_horizon(paper: MissionSummary) -> MissionSummary:
    """The paper's mission as if the debris never came down: the decay has no end."""
    phases = list(paper.phases)
    phases[-1] = dataclasses.replace(phases[-1], duration_days=None)
    return dataclasses.replace(paper, phases=phases)


@pytest.mark.parametrize("beyond", [False, True])
def test_the_timeline_labels_overlap_neither_each_other_nor_the_bars(
    paper, monkeypatch, tmp_path, beyond
) -> None:
    summary = _beyond_horizon(paper) if beyond else paper
    labels, bars, frame = _timeline_boxes(summary, monkeypatch, tmp_path)
    assert len(labels) == len(summary.phases) and len(bars) == len(summary.phases)
    for i, label in enumerate(labels):
        assert frame.x0 - 1 <= label.x0 and label.x1 <= frame.x1 + 1, i  # inside the axes
        assert frame.y0 - 1 <= label.y0 and label.y1 <= frame.y1 + 1, i
        assert not any(label.overlaps(bar) for bar in bars), i
        assert not any(label.overlaps(other) for other in labels[i + 1 :]), i
