"""What every command shares: one-line usage errors and bounded numbers."""

from __future__ import annotations

import click
import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.cli.common import BoundedFloat


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["nosuch"], "No such command 'nosuch'"),
        (["simulate", "--duration-s", "abc"], "'--duration-s': 'abc' is not a valid float"),
        (["allocate"], "Missing option '--torque-mNm'"),
        (["model", "--bogus"], "No such option '--bogus'"),
        (["allocate", "--torque-mNm", "1", "2"], "'--torque-mNm' requires 3 arguments"),
    ],
)
def test_a_usage_error_is_one_line_naming_the_option(args: list[str], needle: str) -> None:
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0], lines


def test_help_and_version_still_exit_0() -> None:
    assert CliRunner().invoke(main, ["--help"]).exit_code == 0
    assert CliRunner().invoke(main, ["simulate", "-h"]).exit_code == 0
    assert "version" in CliRunner().invoke(main, ["--version"]).output


@pytest.mark.parametrize(
    ("text", "ok"),
    [
        ("1", True),
        ("0", False),
        ("10", True),
        ("10.000001", False),
        ("nan", False),
        ("inf", False),
        ("-inf", False),
        ("1e308", False),
    ],
)
def test_bounded_float_takes_finite_numbers_inside_its_range(text: str, ok: bool) -> None:
    kind = BoundedFloat(0.0, 10.0, low_open=True)
    if ok:
        assert kind.convert(text, None, None) == float(text)
    else:
        with pytest.raises(click.BadParameter, match=r"finite|\(0, 10\]"):
            kind.convert(text, None, None)


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["synthesize", "--d-orders", "1000"], "--d-orders"),
        (["synthesize", "--d-orders", "1,2,3,4,5,6,7"], "--d-orders"),
        (["synthesize", "--mu-points", "100000"], "--mu-points"),
        (["synthesize", "--max-iterations", "1000"], "--max-iterations"),
        (["synthesize", "--seed", "-1"], "--seed"),
        (["margins", "--samples", "1000000000"], "--samples"),
        (["margins", "--seed", str(2**32)], "--seed"),
        (["simulate", "--duration-s", "1e12"], "--duration-s"),
        (["simulate", "--duration-s", "nan"], "--duration-s"),
        (["simulate", "--duration-s", "0.01"], "--duration-s"),
        (["simulate", "--corner", "256", "--duration-s", "1"], "--corner"),
        (["simulate", "--sample", "-3"], "--sample"),
        (["montecarlo", "--samples", "1000000000"], "--samples"),
        (["montecarlo", "--max-cases", "0"], "--max-cases"),
        (["montecarlo", "--workers", "0"], "--workers"),
        (["reproduce", "--workers", "100000"], "--workers"),
    ],
)
def test_out_of_range_options_are_refused_before_work(args: list[str], needle: str) -> None:
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], lines


def test_the_command_line_loads_no_heavy_library_before_a_command_runs() -> None:
    import subprocess
    import sys

    code = (
        "import sys, casadi_debris.cli; "
        "print(sorted(m for m in ('casadi', 'control', 'matplotlib', 'scipy', 'osqp', 'daqp')"
        " if m in sys.modules))"
    )
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert loaded.stdout.strip() == "[]", loaded.stdout + loaded.stderr


def test_allocate_options_are_the_allocators_own() -> None:
    from casadi_debris import allocation
    from casadi_debris.cli import allocate

    assert allocate.SATURATION_MODES == allocation.SATURATION_MODES
    assert allocate.DEFAULT_SOLVER == allocation.DEFAULT_SOLVER


@pytest.mark.slow
def test_quiet_prints_no_progress_and_verbose_logs_the_stages(tmp_path) -> None:
    from casadi_debris.config import default_problem_path

    problem = tmp_path / "short.toml"
    problem.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        'name = "short"\n[simulation]\nduration_s = 30.0\n'
    )
    args = ["montecarlo", str(problem), "--samples", "2", "--workers", "1"]
    runner = CliRunner()
    plain = runner.invoke(main, [*args, "--out", str(tmp_path / "a")])
    assert plain.exit_code == 0, plain.output
    assert "short: 2/2 cases" in plain.stderr
    quiet = runner.invoke(main, ["-q", *args, "--out", str(tmp_path / "b")])
    assert quiet.exit_code == 0, quiet.output
    assert quiet.stderr == ""
    verbose = runner.invoke(main, ["-v", *args, "--out", str(tmp_path / "c")])
    assert verbose.exit_code == 0, verbose.output
    assert "short: 2 cases (0 on disk, 2 to run)" in verbose.stderr


def test_progress_off_a_terminal_is_a_line_per_tenth_and_the_last(capsys, monkeypatch):
    from casadi_debris.cli import common

    monkeypatch.setattr(common.sys.stderr, "isatty", lambda: False)
    show = common.counter_progress("slew Monte Carlo")
    for done in range(0, 257):
        show(done, 256)
    lines = capsys.readouterr().err.splitlines()
    assert "\r" not in "".join(lines)
    assert 10 <= len(lines) <= 12  # 0, each tenth, the end (no time gap this short)
    assert lines[-1].startswith("slew Monte Carlo: 256/256 cases, ")
    assert "left" in lines[-1]


def test_progress_on_a_terminal_is_one_bar_redrawn(capsys, monkeypatch):
    from casadi_debris.cli import common

    monkeypatch.setattr(common.sys.stderr, "isatty", lambda: True)
    show = common.counter_progress("runs", "runs")
    for done in range(0, 5):
        show(done, 4)
    err = capsys.readouterr().err
    assert err.count("\r") == 5 and err.endswith("\n") and err.count("\n") == 1
    assert "[" + "#" * common.BAR_WIDTH + "] 4/4 runs" in err
