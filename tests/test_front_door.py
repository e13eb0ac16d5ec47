"""``casadi-debris X ARGS`` and ``casadi_debris.X(...)`` are the same job.

Every command's options are keywords of the function of the command's name, so that a
flag and a keyword never disagree: same name, and the same default where both are plain
values. Options that only steer the command line (where to write, JSON or text) are
left out.
"""

from __future__ import annotations

import inspect

import click
import pytest

import casadi_debris as cd
from casadi_debris.cli import main

# Options of the command line only: the problem argument (the function's first
# parameter), the run folder and how the result is shown.
COMMAND_LINE_ONLY = {"problem_file", "out", "overwrite", "as_json", "no_plots"}

# Options that start another job from the same command: ``simulate --open-loop TABLE
# --rigid`` integrates a torque table on the rigid body (a check of the integrator), which
# Python calls as ``casadi_debris.simulation.open_loop_rigid``.
OTHER_JOB = {("simulate", "open_loop"), ("simulate", "rigid")}

# Commands that are not jobs: they print what the toolkit knows.
NOT_JOBS = {"problems", "schema"}

# Commands whose function has not landed yet, one per line.
NOT_YET: set[str] = set()

JOBS = sorted(set(main.commands) - NOT_JOBS)


def _options(command: click.Command) -> dict[str, click.Parameter]:
    return {
        p.name: p
        for p in command.params
        if p.name and p.name not in COMMAND_LINE_ONLY and (command.name, p.name) not in OTHER_JOB
    }


@pytest.mark.parametrize("name", JOBS)
def test_every_option_is_a_keyword_of_the_job(name: str) -> None:
    if name in NOT_YET:
        pytest.xfail(f"cd.{name} has not landed")
    function = getattr(cd, name)
    parameters = inspect.signature(function).parameters
    first = next(iter(parameters.values()))
    command = main.commands[name]
    if any(p.name == "problem_file" for p in command.params):
        assert first.name == "problem", f"cd.{name} takes the problem first"
    missing = sorted(set(_options(command)) - set(parameters))
    assert not missing, f"options of `casadi-debris {name}` that cd.{name} lacks: {missing}"


@pytest.mark.parametrize("name", JOBS)
def test_a_flag_and_its_keyword_default_alike(name: str) -> None:
    if name in NOT_YET:
        pytest.xfail(f"cd.{name} has not landed")
    parameters = inspect.signature(getattr(cd, name)).parameters
    for option_name, option in _options(main.commands[name]).items():
        keyword = parameters.get(option_name)
        if keyword is None or keyword.default is None or option.default is None:
            continue  # None: "the problem's own value", resolved the same way by both
        plain = (bool, int, float, str)
        if isinstance(option.default, plain) and isinstance(keyword.default, plain):
            assert option.default == keyword.default, (
                f"--{option_name.replace('_', '-')} defaults to {option.default!r}, "
                f"cd.{name}({option_name}=...) to {keyword.default!r}"
            )


def test_not_yet_lists_only_commands() -> None:
    assert set(main.commands) >= NOT_YET


@pytest.mark.parametrize("name", sorted(cd.__all__))
def test_every_exported_name_resolves(name: str) -> None:
    assert getattr(cd, name) is not None
    assert name in dir(cd)
