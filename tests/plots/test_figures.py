"""What every figure shares: the style sheet, and PNG with a PDF beside it."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt

from casadi_debris.plots import STYLE, save_figure


def test_a_figure_is_written_as_png_and_vector_pdf(tmp_path: Path) -> None:
    figure, axes = plt.subplots()
    axes.plot([0, 1], [0, 1])
    written = save_figure(figure, tmp_path / "line.png")
    assert written == tmp_path / "line.png"
    assert written.read_bytes().startswith(b"\x89PNG")
    assert (tmp_path / "line.pdf").read_bytes().startswith(b"%PDF")
    assert not plt.fignum_exists(figure.number)  # closed


def test_the_style_sheet_is_shipped_and_in_force() -> None:
    assert STYLE.is_file()
    sheet = matplotlib.rc_params_from_file(str(STYLE), use_default_template=False)
    assert matplotlib.rcParams["font.size"] == sheet["font.size"] == 9
    assert matplotlib.rcParams["pdf.fonttype"] == 42  # fonts embedded as TrueType, editable
