"""The shared option decorators give every command the options it had when each wrote its own.

Other tools read these commands' options by name, so the names, their order (the
order ``--help`` lists them in), the defaults and the help texts are checked here
through click's introspection, against the texts written out literally.
"""

from __future__ import annotations

from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from casadi_debris.cli import main

OVERWRITE_HELP = (
    "Replace an existing result written by casadi-debris (atomically); "
    "without it an existing non-empty output is refused."
)
CONTROLLER_HELP = (
    "Controller file written by synthesize [the shipped paper controller, for the paper's "
    "plant only]."
)
MISMATCH_HELP = (
    "Fly a controller designed for another plant (a robustness study); the summary "
    "records both plants' hashes."
)

# The commands whose decorators the shared ones replaced: every parameter in --help order.
PARAMETERS = {
    "transfer": ["problem_file", "objective", "out", "overwrite", "as_json"],
    "deorbit": [
        "problem_file",
        "solar",
        "limit_years",
        "drag_coefficient",
        "held",
        "minimum_swarm",
        "samples",
        "seed",
        "workers",
        "out",
        "overwrite",
        "as_json",
    ],
    "design": [
        "problem_file",
        "out",
        "quick",
        "method",
        "weights",
        "samples",
        "seed",
        "workers",
        "overwrite",
        "as_json",
    ],
    "compare": [
        "problem_files",
        "methods",
        "controller",
        "allow_mismatch",
        "out",
        "overwrite",
        "as_json",
    ],
    "alternatives": ["problem_files", "max_failed", "out", "overwrite", "as_json"],
    "reproduce": ["out", "quick", "resynthesize", "workers", "overwrite", "as_json"],
    "synthesize": [
        "problem_file",
        "out",
        "mu_points",
        "max_iterations",
        "d_orders",
        "samples",
        "seed",
        "overwrite",
        "as_json",
    ],
    "margins": [
        "problem_file",
        "controller",
        "allow_mismatch",
        "samples",
        "seed",
        "out",
        "no_plots",
        "overwrite",
        "as_json",
    ],
    "simulate": [
        "problem_file",
        "corner",
        "sample",
        "seed",
        "parameters",
        "open_loop",
        "rigid",
        "duration_s",
        "axis",
        "angle_deg",
        "failed",
        "controller",
        "allow_mismatch",
        "out",
        "no_plots",
        "overwrite",
        "as_json",
    ],
    "montecarlo": [
        "problem_file",
        "corners",
        "samples",
        "seed",
        "max_cases",
        "workers",
        "scheduler",
        "controller",
        "allow_mismatch",
        "no_jit",
        "batch_cases",
        "out",
        "overwrite",
        "as_json",
    ],
    "slew": [
        "problem_file",
        "axis",
        "angle_deg",
        "method",
        "duration_s",
        "torque_fraction",
        "rate_limit_deg_s",
        "smoothing_s",
        "flexible",
        "flexible_method",
        "thrusters",
        "zero_net_force",
        "sample_s",
        "starts",
        "seed",
        "workers",
        "out",
        "overwrite",
        "as_json",
    ],
}

# --out of each: (help, default).
OUT = {
    "transfer": ("Run folder [runs/transfer-<problem>].", None),
    "deorbit": ("Run folder [runs/deorbit-<problem>].", None),
    "design": ("Run folder [runs/design-<problem>].", None),
    "montecarlo": ("Run folder [runs/montecarlo-<problem>].", None),
    "compare": (None, Path("runs") / "compare"),
    "alternatives": ("Run folder.", Path("runs") / "alternatives"),
    "reproduce": ("Report folder.", Path("runs") / "reproduce"),
    "synthesize": (
        "Run folder for controller.json and summary.json [runs/synthesize-<problem>].",
        None,
    ),
    "margins": ("Folder for summary.json and the plots [runs/margins-<problem>].", None),
    "simulate": ("Run folder.", None),
    "slew": ("Run folder.", None),
}


def _options(name: str) -> dict[str, click.Parameter]:
    return {param.opts[0]: param for param in main.commands[name].params}


@pytest.mark.parametrize("name", sorted(PARAMETERS))
def test_each_command_keeps_its_parameters_in_their_order(name: str) -> None:
    names = [param.name for param in main.commands[name].params]
    assert names == PARAMETERS[name]


@pytest.mark.parametrize("name", sorted(OUT))
def test_out_is_a_folder_with_the_commands_own_help_and_default(name: str) -> None:
    out = _options(name)["--out"]
    help_text, default = OUT[name]
    assert out.opts == ["--out"]
    assert out.help == help_text  # type: ignore[attr-defined]
    assert out.default == default
    # A default is shown only where there is one (``[default: runs/compare]``).
    assert bool(out.show_default) == (default is not None)  # type: ignore[attr-defined]
    assert isinstance(out.type, click.Path)
    assert out.type.file_okay is False and out.type.dir_okay is True


@pytest.mark.parametrize("name", sorted(OUT))
def test_overwrite_and_json_are_the_shared_flags(name: str) -> None:
    options = _options(name)
    assert options["--overwrite"].help == OVERWRITE_HELP  # type: ignore[attr-defined]
    assert options["--json"].help == "Print JSON for scripts."  # type: ignore[attr-defined]
    assert options["--json"].name == "as_json"
    # What a run gets when the flag is not given (click 8.5 keeps an unset sentinel in
    # .default and resolves it here).
    context = click.Context(main.commands[name])
    for flag in ("--overwrite", "--json"):
        assert options[flag].is_flag and options[flag].get_default(context) is False  # type: ignore[attr-defined]


@pytest.mark.parametrize("name", ["compare", "margins", "simulate", "montecarlo"])
def test_controller_options_are_the_file_and_the_mismatch_flag(name: str) -> None:
    options = _options(name)
    controller, mismatch = options["--controller"], options["--allow-mismatch"]
    assert controller.name == "controller" and controller.default is None
    assert controller.help == CONTROLLER_HELP  # type: ignore[attr-defined]
    assert mismatch.help == MISMATCH_HELP  # type: ignore[attr-defined]
    assert mismatch.is_flag  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    "args",
    [
        ["transfer", "no_such_problem.toml"],
        ["deorbit", "no_such_problem.toml"],
        ["design", "no_such_problem.toml"],
        ["synthesize", "no_such_problem.toml"],
        ["slew", "no_such_problem.toml"],
    ],
)
def test_a_bad_problem_file_is_still_one_line_and_exit_2(args: list[str], tmp_path) -> None:
    result = CliRunner().invoke(main, [*args, "--out", str(tmp_path / "run")])
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: ")
    assert "no_such_problem" in result.stderr
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize(
    ("name", "flag", "default", "help_text", "limit"),
    [
        ("synthesize", "--mu-points", 150, "Frequencies of the mu grid.", "MU_POINTS"),
        ("synthesize", "--max-iterations", 8, "D-K iterations at most.", "DK_ITERATIONS"),
        ("margins", "--samples", 3000, "Sampled uncertain plants.", "MARGIN_SAMPLES"),
        ("deorbit", "--seed", 20250103, "Seed of the Monte Carlo.", "SEED"),
    ],
)
def test_bounded_options_keep_their_range_default_and_help(
    name: str, flag: str, default: int, help_text: str, limit: str
) -> None:
    from casadi_debris.config import limits

    allowed = getattr(limits, limit)
    option = _options(name)[flag]
    assert option.default == default and option.show_default is True  # type: ignore[attr-defined]
    assert option.help == help_text  # type: ignore[attr-defined]
    assert isinstance(option.type, click.IntRange)
    assert (option.type.min, option.type.max) == (allowed.low, allowed.high)
    below = CliRunner().invoke(main, [name, flag, str(allowed.low - 1)])
    assert below.exit_code == 2 and flag in below.stderr
