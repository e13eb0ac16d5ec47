"""Problem files on disk: regular files only, bounded size, bounded ``extends`` chains.

And through the command line: a bad file ends with exit status 2 and one line
``error: <file>: <key>: <message>``, never an internal error or a hang.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.config import limits
from casadi_debris.errors import ProblemFileError

PAPER = Path(__file__).parents[2] / "problems" / "paper.toml"
HANG_S = 20

unix_only = pytest.mark.skipif(sys.platform == "win32", reason="FIFOs and /dev are Unix")


@contextlib.contextmanager
def no_hang(seconds: int = HANG_S) -> Iterator[None]:
    """Fail instead of blocking for ever (a FIFO open, a read of /dev/zero)."""

    def expire(*_: object) -> None:
        raise TimeoutError(f"still running after {seconds} s")

    if not hasattr(signal, "SIGALRM"):
        yield
        return
    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _child(tmp_path: Path, extends: str, name: str = "child.toml") -> Path:
    path = tmp_path / name
    path.write_text(f'extends = "{extends}"\nname = "child"\n')
    return path


def _refused(path: Path, key: str, words: str) -> str:
    with no_hang(), pytest.raises(ProblemFileError) as caught:
        load_problem(path)
    message = str(caught.value)
    assert caught.value.field == key, message
    assert words in message, message
    assert "\n" not in message
    return message


@unix_only
def test_extends_to_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    _refused(_child(tmp_path, str(fifo)), "extends", "not a regular file")


@unix_only
@pytest.mark.parametrize("device", ["/dev/zero", "/dev/stdin", "/dev/null"])
def test_extends_to_a_device_is_refused(tmp_path, device):
    if not os.path.exists(device):
        pytest.skip(f"no {device} here")
    _refused(_child(tmp_path, device), "extends", "not a regular file")


def test_extends_to_a_folder_is_refused(tmp_path):
    _refused(_child(tmp_path, str(tmp_path)), "extends", "not a regular file")


@unix_only
def test_a_fifo_or_device_as_the_problem_file_is_refused(tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    _refused(fifo, "", "not a regular file")
    _refused(Path("/dev/zero"), "", "not a regular file")


def test_extends_must_be_a_path_string(tmp_path):
    path = tmp_path / "child.toml"
    for value in ("5", '""', "[]", "{a = 1}", '"a\\u0000b"'):
        path.write_text(f"extends = {value}\n")
        _refused(path, "extends", "")


def test_missing_parent_names_extends(tmp_path):
    message = _refused(_child(tmp_path, "absent.toml"), "extends", "does not exist")
    assert "absent.toml" in message
    assert "nor a shipped problem" in _refused(_child(tmp_path, "papr"), "extends", "papr")


def test_oversized_files_are_refused(tmp_path):
    big = tmp_path / "big.toml"
    big.write_text(f'description = "{"x" * limits.MAX_FILE_BYTES}"\n')
    _refused(big, "", f"larger than {limits.MAX_FILE_BYTES} bytes")
    _refused(_child(tmp_path, str(big)), "extends", "larger than")


def test_extends_chains_are_bounded(tmp_path):
    depth = limits.MAX_EXTENDS_DEPTH
    (tmp_path / f"level{depth + 1}.toml").write_text(PAPER.read_text())
    for level in range(depth + 1):
        _child(tmp_path, f"level{level + 1}.toml", f"level{level}.toml")
    _refused(tmp_path / "level0.toml", "extends", f"at most {depth} files")
    assert load_problem(tmp_path / "level1.toml").name == "child"  # depth files below it


def test_circular_extends_names_the_chain(tmp_path):
    _child(tmp_path, "b.toml", "a.toml")
    _child(tmp_path, "a.toml", "b.toml")
    _refused(tmp_path / "a.toml", "extends", "circular")
    _refused(_child(tmp_path, "self.toml", "self.toml"), "extends", "circular")


@unix_only
def test_symlink_loops_are_refused(tmp_path):
    (tmp_path / "loop1").symlink_to(tmp_path / "loop2")
    (tmp_path / "loop2").symlink_to(tmp_path / "loop1")
    _refused(_child(tmp_path, "loop1"), "extends", "")


@pytest.mark.parametrize(
    ("content", "words"),
    [
        (b"a = " + b"[" * 5000 + b"]" * 5000 + b"\n", "nested too deeply"),
        (b"a = " + b"1" * 5000 + b"\n", "not valid TOML"),
        (b"name = \xff\n", "not valid TOML"),
        (b"[hub\n", "not valid TOML"),
    ],
    ids=["deep", "long-integer", "not-utf8", "syntax"],
)
def test_unparsable_files_name_the_file(tmp_path, content, words):
    path = tmp_path / "bad.toml"
    path.write_bytes(content)
    _refused(path, "", words)
    _refused(_child(tmp_path, str(path)), "extends", words)


def test_parent_errors_name_extends_in_the_child(tmp_path):
    (tmp_path / "parent.toml").write_text("[hub\n")
    child = _child(tmp_path, "parent.toml")
    message = _refused(child, "extends", "parent.toml is not valid TOML")
    assert message.startswith(f"{child}: extends: ")


# ----------------------------------------------------------------------- command line


def _cli(*args: str) -> tuple[int, str]:
    with no_hang():
        result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.stderr


ONE_ARRAY = (
    "[[arrays]]\nhinge_corner_m = [0.4, 1.4, 0.0]\ndirection = '-z'\nmass_kg = 42.0\n"
    "length_m = 2.5\nwidth_m = 2.0\ninertia_kgm2 = [17.0, 62.0, 80.0]\nangle_deg = 0.0\n"
    "damping_ratio = 0.005\n"
)
MODE_ORDER_9 = (
    ONE_ARRAY + "[[arrays.modes]]\nname = 'b9'\nkind = 'bending'\norder = 9\nomega_rad_s = 50.0\n"
)
BAD_FILES = {
    "numeric-string": ('[cubesat_layout]\nmass_kg = "5"\n', "cubesat_layout.mass_kg"),
    "bool": ("[hub]\nmass_kg = true\n", "hub.mass_kg"),
    "nan": ("[hub]\nmass_kg = nan\n", "hub.mass_kg"),
    "inf-array": ("[hub]\nsize_m = [0.75, inf, 1.0]\n", "hub.size_m"),
    "huge-int": ("[hub]\nmass_kg = " + "9" * 400 + "\n", "hub.mass_kg"),
    "1e308-mass": ("[hub]\nmass_kg = 1e308\n", "hub.mass_kg"),
    "steps": ("[simulation]\nintegrator_steps = 1000000000\n", "simulation.integrator_steps"),
    "rate": ("[simulation]\ncontrol_rate_hz = 1e-9\n", "simulation.control_rate_hz"),
    "propellant": ("[engine]\nstage_life_h = 1e5\n", "engine.stage_life_h"),
    "corners": ("[montecarlo]\ncorner_array_angles = 100000\n", "montecarlo.corner_array_angles"),
    "seed": ("[montecarlo]\nseed = 99999999999\n", "montecarlo.seed"),
    "zero-hub": ("[hub]\nsize_m = [0.0, 0.0, 0.0]\n", "hub.size_m"),
    "empty-hinge": (ONE_ARRAY.replace("[0.4, 1.4, 0.0]", "[]"), "arrays[0].hinge_corner_m"),
    "old-arrays-table": ("[arrays]\nmass_kg = 42.0\n", "arrays"),
    "mode-order": (MODE_ORDER_9, "arrays[0].modes[0].order"),
    "nesting": ("hub = 5\n", "hub"),
    "name-path": ('name = "../../somewhere"\n', "name"),
}


@pytest.mark.parametrize("command", ["model", "budget"])
@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_files_exit_2_with_one_line_naming_the_key(tmp_path, command, case):
    body, key = BAD_FILES[case]
    path = tmp_path / "bad.toml"
    path.write_text(f'extends = "{PAPER}"\n{body}')
    code, stderr = _cli(command, str(path))
    assert code == 2, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, stderr
    assert lines[0].startswith(f"error: {path}: {key}"), stderr


@unix_only
@pytest.mark.parametrize("command", ["model", "budget"])
def test_a_fifo_on_the_command_line_exits_2(tmp_path, command):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    code, stderr = _cli(command, str(fifo))
    assert code == 2 and stderr.strip() == f"error: {fifo}: is not a regular file"
    code, stderr = _cli(command, str(_child(tmp_path, str(fifo))))
    assert code == 2 and "extends: " in stderr


def test_the_shipped_problems_still_run(tmp_path):
    for name in ("paper.toml", "paper_slew.toml", "paper_pointing.toml"):
        code, stderr = _cli("budget", str(PAPER.parent / name))
        assert code == 0, stderr
