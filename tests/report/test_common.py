"""Report helpers: the paper's reference file and its tolerances, tables."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from casadi_debris.errors import InputShapeError, PaperReferenceError
from casadi_debris.report import (
    format_table,
    load_paper_reference,
    paper_figure,
    paper_figures,
    table_figures,
)

# The paper's table of results that must reproduce, as the report prints it:
# key, title start, the paper's numbers. Written out here, not read from the
# data file, so that a row lost or a number changed there is caught.
PAPER_ROWS = [
    ("mass_kg", "total mass", [668.0]),
    ("inertia_hub_cubesats_diag_kgm2", "hub + CubeSats inertia", [246.0, 66.0, 242.0]),
    ("torque_max_mNm", "max torque per axis", [4.61, 1.96, 4.26]),
    ("dv_one_stage_one_face_m_s", "Δv one stage, one face", [6.8]),
    ("dv_three_stages_one_face_m_s", "Δv three stages, one face", [20.0]),
    ("dv_one_stage_all_faces_m_s", "Δv one stage, all faces", [41.0]),
    ("dv_all_stages_all_faces_m_s", "Δv all stages, all faces", [125.0]),
    ("dv_cubesat_one_stage_m_s", "Δv one CubeSat, one stage", [300.0]),
    ("dv_transfer_m_s", "transfer 550 km 97.5° → 685 km 98.1°", [150.0]),
    ("detumble_time_h", "detumble from 1 rad/s", [15.9]),
    ("mu_peak", "μ-synthesis peak μ", [1.0, 1.0]),
    ("controller_order", "controller order", [52.0, 25.0]),
    ("margins_nominal", "loop-at-a-time margins, nominal", [15.22, 54.8]),
    ("margins_sampled", "margins over {samples} sampled plants", [13.0, 45.0, 9.0]),
    ("slew_max_error_deg", "180° slew about z: max error", [0.6]),
    ("slew_fuel_kg", "180° slew about z: fuel", [2.8e-4]),
    ("slew_duration_s", "180° slew about z: reference duration", [1228.0]),
    ("slew_envelope_cases", "slew envelope", [256.0]),
    ("pointing", "one-orbit pointing", [60.0, 60.0, 256.0, 1.0]),
]

# (key, component, kind, bound) of every tolerance, as the paper's table states it.
TOLERANCES = [
    ("mass_kg", 0, "abs", 0.5),
    ("inertia_hub_cubesats_diag_kgm2", 2, "rel", 0.06),
    ("torque_max_mNm", 0, "rel", 0.04),
    ("dv_one_stage_one_face_m_s", 0, "rel", 0.05),
    ("dv_cubesat_one_stage_m_s", 0, "range", (290.0, 340.0)),
    ("dv_transfer_m_s", 0, "range", (135.0, 160.0)),
    ("detumble_time_h", 0, "rel", 0.06),
    ("mu_peak", 1, "at_most", 1.0),
    ("controller_order", 1, "at_most", 25.0),
    ("margins_nominal", 0, "at_least", 13.0),
    ("margins_nominal", 1, "at_least", 45.0),
    ("margins_sampled", 2, "at_least", 5.0),
    ("slew_max_error_deg", 0, "at_most", 0.6),
    ("slew_fuel_kg", 0, "rel", 0.25),
    ("slew_envelope_cases", 0, "at_least", 256.0),
    ("pointing", 0, "below", 60.0),
    ("pointing", 1, "below", 60.0),
]


def test_every_row_of_the_paper_is_in_the_file_in_order():
    rows = table_figures()
    assert [f.key for f in rows] == [key for key, _, _ in PAPER_ROWS]
    for figure, (_, title, values) in zip(rows, PAPER_ROWS, strict=True):
        assert figure.title.startswith(title)
        assert list(figure.values) == pytest.approx(values, rel=1e-12)
        assert figure.judged and figure.paper and figure.accepted


def test_figures_beside_the_table_are_not_judged():
    assert paper_figure("detumble_dv_m_s").value == 0.22
    assert paper_figure("stage_life_h").value == 500.0
    assert paper_figure("stage_life_h").accepts(10.0) is None
    assert len(paper_figures()) == len(PAPER_ROWS) + 2


@pytest.mark.parametrize(("key", "index", "kind", "bound"), TOLERANCES)
def test_tolerances_are_the_papers(key, index, kind, bound):
    tolerance = paper_figure(key).components[index].tolerance
    assert tolerance is not None and tolerance.kind == kind
    assert tolerance.bound == pytest.approx(bound, rel=1e-15)


def _just(value: float, direction: float) -> float:
    """``value`` moved by a relative 1e-9 up (+1) or down (-1): beyond any rounding."""
    return value + direction * 1e-9 * max(abs(value), 1.0)


def test_abs_accepts_at_the_bound_and_refuses_beyond():
    mass = paper_figure("mass_kg")
    assert mass.accepts(668.0 + 0.5) and mass.accepts(668.0 - 0.5)
    assert not mass.accepts(_just(668.5, +1)) and not mass.accepts(_just(667.5, -1))


def test_rel_accepts_at_the_bound_and_refuses_beyond_per_component():
    torque = paper_figure("torque_max_mNm")
    paper = [4.61, 1.96, 4.26]
    for axis in range(3):
        for sign in (+1, -1):
            # 3.5 % and 4.5 % off: clear of rounding, either side of 4 %.
            inside = [p * (1 + sign * 0.035) if i == axis else p for i, p in enumerate(paper)]
            outside = [p * (1 + sign * 0.045) if i == axis else p for i, p in enumerate(paper)]
            assert torque.accepts(inside) is True
            assert torque.accepts(outside) is False
    # 5 % of 125 m/s is 6.25 m/s, exact in binary, so the bound itself is testable.
    dv = paper_figure("dv_all_stages_all_faces_m_s")
    assert dv.accepts(131.25) and dv.accepts(118.75)
    assert not dv.accepts(_just(131.25, +1)) and not dv.accepts(_just(118.75, -1))


def test_range_includes_both_ends():
    transfer = paper_figure("dv_transfer_m_s")
    assert transfer.accepts(135.0) and transfer.accepts(160.0)
    assert not transfer.accepts(_just(135.0, -1)) and not transfer.accepts(_just(160.0, +1))


def test_at_most_and_at_least_include_the_bound():
    error = paper_figure("slew_max_error_deg")
    assert error.accepts(0.6) and not error.accepts(_just(0.6, +1))
    margins = paper_figure("margins_sampled")
    assert margins.accepts([13.0, 45.0, 5.0])
    assert margins.accepts([math.inf, math.inf, math.inf])  # no crossover: no limit
    assert not margins.accepts([_just(13.0, -1), 45.0, 5.0])
    assert not margins.accepts([13.0, _just(45.0, -1), 5.0])
    assert not margins.accepts([13.0, 45.0, _just(5.0, -1)])


def test_below_excludes_the_bound():
    pointing = paper_figure("pointing")
    assert pointing.accepts([_just(60.0, -1), _just(60.0, -1), 256, 1.0])
    assert not pointing.accepts([60.0, 10.0, 256, 1.0])
    assert not pointing.accepts([10.0, 60.0, 256, 1.0])
    assert not pointing.accepts([10.0, 10.0, 255, 1.0])
    assert not pointing.accepts([10.0, 10.0, 256, 1.001])


def test_unjudged_components_and_missing_numbers():
    order = paper_figure("controller_order")
    assert order.accepts([None, 25]) is True  # the full order is not a requirement
    assert order.accepts([52, 26]) is False
    assert paper_figure("mu_peak").accepts([None, 0.9]) is False
    assert paper_figure("mass_kg").accepts(math.nan) is False


def test_wrong_count_of_numbers_is_refused():
    with pytest.raises(InputShapeError, match="torque_max_mNm: 3 number"):
        paper_figure("torque_max_mNm").accepts([4.61, 1.96])


GOOD = """
[mass_kg]
title = "total mass [kg]"
paper = "668"
accepted = "±0.5"
value = 668.0
tolerance = { abs = 0.5 }
"""


# A valid entry's fields as TOML text; each case below changes (None: drops) some.
ENTRY = {
    "title": '"t"',
    "paper": '"1"',
    "accepted": '"a"',
    "value": "1.0",
    "tolerance": "{ abs = 1.0 }",
}
MALFORMED = [
    ({"value": '"668"'}, "value"),
    ({"value": "[]"}, "value"),
    ({"tolerance": "{ near = 1.0 }"}, "tolerance"),
    ({"tolerance": "{ abs = 1.0, rel = 0.1 }"}, "tolerance"),
    ({"tolerance": "{ abs = -1.0 }"}, "tolerance"),
    ({"tolerance": "{ at_most = nan }"}, "tolerance"),
    ({"tolerance": "{ range = [5.0, 1.0] }"}, "tolerance"),
    ({"tolerance": "{ range = [1.0] }"}, "tolerance"),
    ({"value": "[1.0, 2.0]"}, "components"),
    ({"value": "[1.0, 2.0]", "components": '["a", "a"]'}, "components"),
    (
        {"value": "[1.0, 2.0]", "components": '["a", "b"]', "tolerance": "[{ rel = 0.1 }]"},
        "tolerance",
    ),
    ({"title": None}, "title"),
    ({"paper": '""'}, "paper"),
    ({"accepted": None}, "accepted"),
    ({"tolerance": None}, "tolerance"),
    ({"table": '"no"'}, "table"),
    ({"tolerence": "{ abs = 1.0 }"}, "tolerence"),
]


@pytest.mark.parametrize(("change", "named"), MALFORMED)
def test_a_malformed_entry_is_refused_by_its_key(tmp_path: Path, change: dict, named: str):
    fields = {**ENTRY, **change}
    entry = "\n".join(f"{k} = {v}" for k, v in fields.items() if v is not None)
    path = tmp_path / "paper_reference.toml"
    path.write_text(GOOD + "\n[broken_figure]\n" + entry + "\n", encoding="utf-8")
    with pytest.raises(PaperReferenceError, match=rf"\[broken_figure\.{named}\]") as caught:
        load_paper_reference(path)
    assert caught.value.key == f"broken_figure.{named}"
    assert str(path) in str(caught.value)


def test_a_file_that_is_not_toml_is_refused(tmp_path: Path):
    path = tmp_path / "paper_reference.toml"
    path.write_text("[mass_kg\n", encoding="utf-8")
    with pytest.raises(PaperReferenceError, match="cannot read"):
        load_paper_reference(path)
    assert load_paper_reference(_write(tmp_path, GOOD))["mass_kg"].accepts(668.2)


def _write(folder: Path, text: str) -> Path:
    path = folder / "good.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_file_ships_with_the_package():
    with (Path(__file__).parents[2] / "pyproject.toml").open("rb") as handle:
        package_data = tomllib.load(handle)["tool"]["setuptools"]["package-data"]
    assert "data/*.toml" in package_data["casadi_debris"]


def test_format_table_aligns_columns():
    text = format_table(["a", "value"], [["x", 1.23456], ["longer", [1.0, 2.0]]])
    lines = text.splitlines()
    assert lines[0].startswith("a       value")
    assert set(lines[1]) <= {"-", " "}
    assert "1.235" in lines[2] and "[1, 2]" in lines[3]


@pytest.mark.parametrize(
    ("outcome", "word", "text"),
    [(True, "met", "✅ met"), (False, "met", "❌ not met"), (None, "reproduced", "—")],
)
def test_a_verdict_reads_as_printed(outcome: bool | None, word: str, text: str) -> None:
    from casadi_debris.report import verdict_text

    assert verdict_text(outcome, word) == text
