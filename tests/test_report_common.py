"""Report helpers: tolerance checks against the paper, tables."""

from __future__ import annotations

from casadi_debris.report.common import format_table, within_tolerance


def test_within_tolerance_uses_design_table():
    assert within_tolerance("mass_kg", 668.4) is True
    assert within_tolerance("mass_kg", 668.6) is False
    assert within_tolerance("torque_max_mNm", [4.61 * 1.039, 1.96, 4.26]) is True
    assert within_tolerance("torque_max_mNm", [4.61 * 1.041, 1.96, 4.26]) is False
    assert within_tolerance("dv_transfer_m_s", 161.0) is False
    assert within_tolerance("detumble_dv_m_s", 0.3) is None


def test_format_table_aligns_columns():
    text = format_table(["a", "value"], [["x", 1.23456], ["longer", [1.0, 2.0]]])
    lines = text.splitlines()
    assert lines[0].startswith("a       value")
    assert set(lines[1]) <= {"-", " "}
    assert "1.235" in lines[2] and "[1, 2]" in lines[3]
