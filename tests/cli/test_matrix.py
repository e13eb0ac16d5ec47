"""Every command of ``casadi-debris --help``, in every output mode, on several problems.

Each command runs in-process with the quickest settings it has, on the paper's problem
and on two gallery problems of other shapes (``rigid_no_arrays``: no arrays, no modes;
``side_engines_12``: 60 engines, side-panel ones among them), twice:

- plain text, without ``--out``, from a scratch working folder: exit 0, some output,
  no traceback, and the default run folder (``runs/<command>-<problem>``) holds a
  ``summary.json`` that parses;
- ``--json --out DIR``: exit 0, stdout parses as one JSON object with the command's
  expected top-level keys, and ``DIR/summary.json`` parses.

Exit 3 (an internal error) is a failure whatever the command. Commands that fly a
controller are given the shipped paper controller with ``--allow-mismatch`` on the
gallery problems (designing one for each would take minutes; ``design`` itself is
checked on its own).

By default a quick command runs in plain text and with ``--json --out`` on all three
problems; a command that takes tens of seconds even at its quickest runs only its
``--json --out`` cell on the paper's problem. A command whose own test
(``tests/test_workflows_<command>.py``) already runs ``--json --out`` by default on the
paper's problem and on another shape, comparing it with the Python function
(``elsewhere``), leaves its ``--json --out`` cells here to ``-m slow``. The rest of the
cells, and ``reproduce --quick``, run under ``-m slow``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from casadi_debris.cli import main
from casadi_debris.config import default_problem_path

PAPER = default_problem_path()
GALLERY = PAPER.parent / "gallery"
PROBLEMS = {
    "paper": PAPER,
    "rigid_no_arrays": GALLERY / "rigid_no_arrays.toml",
    "side_engines_12": GALLERY / "side_engines_12.toml",
}
PAPER_CONTROLLER = PAPER.parent.parent / "data" / "paper_controller.json"


@dataclass(frozen=True)
class Command:
    """One command line of the matrix.

    ``args`` follow the problem file; ``keys`` must be among the top-level keys of its
    ``--json`` output; ``folder`` is the run folder it writes without ``--out`` (None:
    none); ``out``: it takes ``--out``; ``flies``: it flies a controller; ``slow``: which
    cells run only under ``-m slow``: ``""`` none, ``"long"`` all but the paper's
    ``--json`` one (tens of seconds each), ``"gallery-json"`` the gallery's ``--json``
    ones, ``"gallery"`` the gallery's (the problem's shape changes only numbers),
    ``"all"`` every one (minutes). ``elsewhere``: the test file that runs the
    command with ``--json --out`` on the paper's problem by default (its JSON cells run
    here under ``-m slow``).
    """

    name: str
    args: tuple[str, ...]
    keys: frozenset[str]
    folder: str | None = "{command}-{problem}"
    out: bool = True
    flies: bool = False
    slow: str = ""
    label: str = field(default="")
    elsewhere: str = ""

    @property
    def id(self) -> str:
        return self.label or self.name


def _command(name: str, *args: str, keys: tuple[str, ...], **kwargs: object) -> Command:
    return Command(name, args, frozenset(keys), **kwargs)  # type: ignore[arg-type]


COMMANDS = (
    _command(
        "export",
        keys=("problem", "engines", "period_s", "out_dir"),
        flies=True,
        elsewhere="tests/codegen/test_flight.py",
    ),
    _command(
        "model",
        keys=("problem", "mass_kg", "torque_max_zero_force_mNm", "thrusters"),
        folder=None,
        out=False,
    ),
    _command(
        "budget",
        keys=("problem", "dv_one_stage_one_face_m_s", "detumble_time_h"),
        folder=None,
        out=False,
    ),
    _command(
        "allocate",
        "--torque-mNm",
        "0.5",
        "-0.3",
        "0.2",
        keys=("problem", "feasible", "thrust_mN", "torque_achieved_mNm"),
        folder=None,
        out=False,
    ),
    _command(
        "alternatives",
        "--max-failed",
        "0",
        keys=("designs", "max_failed"),
        folder="alternatives",
        elsewhere="tests/workflows/test_alternatives.py",
    ),
    _command(
        "slew",
        "--method",
        "bang-bang",
        keys=("problem", "method", "duration_s", "max_torque_mNm"),
        label="slew-bang-bang",
        folder=None,
        elsewhere="tests/workflows/test_slew.py",
    ),
    _command(
        "slew",
        "--method",
        "time-optimal",
        "--angle-deg",
        "30",
        "--starts",
        "2",
        keys=("problem", "method", "duration_s", "max_torque_mNm"),
        label="slew-time-optimal",
        slow="long",
        folder=None,
    ),
    _command(
        "slew",
        "--method",
        "time-optimal",
        "--thrusters",
        "--angle-deg",
        "30",
        keys=("problem", "method", "duration_s", "max_torque_mNm"),
        label="slew-time-optimal-thrusters",
        # The same command, plain and --json --out on these three problems, is
        # tests/cli/test_slew.py::test_thruster_level_time_optimal_slew_runs_every_way.
        slow="all",
        folder=None,
    ),
    _command(
        "slew",
        "--method",
        "fuel-optimal",
        "--angle-deg",
        "30",
        "--duration-s",
        "1500",
        keys=("problem", "method", "duration_s", "fuel_kg"),
        label="slew-fuel-optimal",
        slow="long",
        folder=None,
    ),
    _command(
        "simulate",
        "--duration-s",
        "1",
        "--no-plots",
        keys=("duration_s", "max_error_deg", "fuel_kg", "controller_path"),
        folder=None,
        flies=True,
    ),
    _command(
        "margins",
        "--samples",
        "1",
        "--no-plots",
        keys=("nominal", "controller_path", "controller_order"),
        flies=True,
        elsewhere="tests/workflows/test_margins.py",
    ),
    _command(
        "burn",
        "--hours",
        "0.01",
        keys=("burn_s", "body_axis", "fuel_kg"),
        flies=True,
        elsewhere="tests/workflows/test_burn.py",
    ),
    _command(
        "compare",
        keys=("variants", "controller_path"),
        folder="compare",
        flies=True,
        # On the gallery it flies the paper's controller with --allow-mismatch, as
        # simulate, margins and burn do here by default.
        slow="gallery",
        elsewhere="tests/workflows/test_compare.py",
    ),
    _command(
        "deorbit",
        "--solar",
        "mean",
        "--no-minimum-swarm",
        "--workers",
        "1",
        keys=("cases", "deorbit_dv_m_s", "governing_case"),
        # The orbit sees a problem's mass and area only: the paper's cells run by default.
        slow="gallery",
        elsewhere="tests/workflows/test_deorbit.py",
    ),
    _command(
        "detumble",
        "--no-ocp",
        "--rate-rad-s",
        "0.01,0.01,0.01",
        keys=("duration_s", "final_rate_rad_s", "fuel_kg"),
        elsewhere="tests/workflows/test_detumble.py",
    ),
    _command(
        "failures",
        "--max-failed",
        "1",
        "--no-stages",
        "--no-closed-loop",
        "--corner-sets",
        "0",
        "--quick",
        "--workers",
        "1",
        keys=("baseline", "case_count", "cases"),
        flies=True,
        elsewhere="tests/workflows/test_failures.py",
    ),
    _command(
        "placement",
        "--count",
        "4",
        "--candidates",
        "1",
        "--time-limit",
        "60",
        keys=("problem", "chosen", "count", "objective"),
        elsewhere="tests/workflows/test_placement.py",
    ),
    _command(
        "montecarlo",
        "--max-cases",
        "1",
        "--workers",
        "1",
        keys=("cases", "nominal", "controller_path"),
        flies=True,
        # A campaign with --json --out, and its folder, by default in
        # tests/cli/test_simulation.py (the resumed campaign).
        slow="all",
    ),
    _command(
        "synthesize",
        "--max-iterations",
        "0",
        "--mu-points",
        "10",
        "--samples",
        "1",
        "--d-orders",
        "0",
        keys=("controller_path", "mu_peak", "order_reduced"),
        slow="long",
        elsewhere="tests/workflows/test_synthesize.py",
    ),
    _command(
        "transfer",
        keys=("edelbaum_dv_m_s", "available_dv_m_s"),
        slow="long",
        elsewhere="tests/workflows/test_transfer.py",
    ),
    _command(
        "mission",
        "--solar",
        "mean",
        keys=("deorbit_dv_m_s", "governing_case"),
        slow="long",
        elsewhere="tests/workflows/test_mission.py",
    ),
    _command(
        "worstcase",
        "--budget",
        "1",
        "--no-mu",
        keys=("problem", "search", "controller_path"),
        flies=True,
        slow="long",
        elsewhere="tests/workflows/test_worstcase.py",
    ),
    _command(
        "design",
        "--quick",
        "--method",
        "pd",
        "--workers",
        "1",
        keys=("problem",),
        slow="all",
        label="design-pd",
    ),
)


def _slow(command: Command, problem: str, mode: str) -> bool:
    """Whether a cell runs only under ``-m slow`` (module notes)."""
    if mode == "json" and command.elsewhere:
        return True
    return {
        "": False,
        "long": problem != "paper" or mode == "text",
        "gallery-json": problem != "paper" and mode == "json",
        "gallery": problem != "paper",
        "all": True,
    }[command.slow]


def _cases(mode: str) -> list[object]:
    """Every command on every problem, marked slow as ``_slow`` says."""
    cases = []
    for command in COMMANDS:
        for problem in PROBLEMS:
            slow = _slow(command, problem, mode)
            marks = [pytest.mark.slow] if slow else []
            cases.append(pytest.param(command, problem, marks=marks, id=f"{command.id}-{problem}"))
    return cases


def _invoke(args: list[str]) -> Result:
    result = CliRunner().invoke(main, args)
    assert result.exit_code != 3, f"internal error: {args}\n{result.output}"
    assert result.exit_code == 0, f"exit {result.exit_code}: {args}\n{result.output}"
    assert "Traceback" not in result.output, result.output
    return result


def _line(command: Command, problem: str) -> list[str]:
    line = [command.name, str(PROBLEMS[problem]), *command.args]
    if command.flies and problem != "paper":
        line += ["--controller", str(PAPER_CONTROLLER), "--allow-mismatch"]
    return line


def _summary(folder: Path) -> dict[str, object]:
    assert (folder / "summary.json").is_file(), sorted(p.name for p in folder.iterdir())
    summary = json.loads((folder / "summary.json").read_text())
    assert isinstance(summary, dict) and summary
    return summary


@pytest.mark.parametrize(("command", "problem"), _cases("text"))
def test_plain_text(command: Command, problem: str, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = _invoke(_line(command, problem))
    assert result.stdout.strip(), "no output"
    with pytest.raises(json.JSONDecodeError):
        json.loads(result.stdout)  # text for people, not JSON
    if command.folder is None:
        assert not (tmp_path / "runs").exists()
        return
    folder = tmp_path / "runs" / command.folder.format(command=command.name, problem=problem)
    _summary(folder)


@pytest.mark.parametrize(("command", "problem"), _cases("json"))
def test_json_and_out(command: Command, problem: str, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    line = [*_line(command, problem), "--json"]
    if command.out:
        line += ["--out", str(out)]
    result = _invoke(line)
    printed = json.loads(result.stdout)
    assert isinstance(printed, dict)
    assert command.keys <= set(printed), sorted(command.keys - set(printed))
    if "problem" in printed:
        assert printed["problem"] == problem
    if command.out:
        _summary(out)
        assert not (tmp_path / "runs").exists(), "wrote a default folder beside --out"


def test_problems_and_schema() -> None:
    listed = json.loads(_invoke(["problems", "--json"]).stdout)
    names = {p["name"] for p in listed["problems"]}
    assert "paper" in names
    assert "rigid_no_arrays" in _invoke(["problems"]).stdout
    schema = json.loads(_invoke(["schema"]).stdout)
    assert {"$schema", "properties"} <= set(schema)


@pytest.mark.parametrize("mode", [["--json"], []], ids=["json", "text"])
def test_reproduce_quick(mode: list[str], tmp_path: Path) -> None:
    """``reproduce`` has no problem argument: the paper's, quick."""
    pytest.importorskip("matplotlib")
    out = tmp_path / "reproduce"
    result = _invoke(["reproduce", "--quick", "--workers", "1", "--out", str(out), *mode])
    if mode:
        assert isinstance(json.loads(result.stdout), dict)
    _summary(out)


test_reproduce_quick = pytest.mark.slow(test_reproduce_quick)


def test_every_command_is_in_the_matrix() -> None:
    """A new command joins the matrix (or this list says why not)."""
    elsewhere = {"problems", "schema", "reproduce"}
    assert set(main.commands) == {c.name for c in COMMANDS} | elsewhere
