"""``K…`` entries for the files a command reads besides the problem file.

Controller files (``--controller``), stage states (``allocate --stage-state``)
and open-loop torque tables (``simulate --open-loop``): broken contents, and
paths that are no readable file.
"""

from __future__ import annotations

import copy
import json
import math
from collections.abc import Iterable

from .entry import FileSpec
from .invocations import SHORT_TOML, Invocations

STAGE_STATE_KEYS = ("propellant_kg", "firing_time_s", "failed_cubesats", "failed_stages")

_TORQUE_HEADER = "t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm\n"
OPEN_LOOP = {
    "not CSV": "torque please\n",
    "empty": "",
    "header only": _TORQUE_HEADER,
    "NaN torque": _TORQUE_HEADER + "0,nan,0,0\n1,0,0,0\n",
    "times going back": _TORQUE_HEADER + "0,1,0,0\n-5,0,0,0\n",
    "two columns": "t_s,tau_x_mNm\n0,1\n1,0\n",
    "1e308 torque": _TORQUE_HEADER + "0,1e308,0,0\n1,0,0,0\n",
}


def controller_files() -> dict[str, FileSpec]:
    """Broken copies of the shipped controller (``ctl.json``), by description."""
    from casadi_debris.config import default_controller_path

    shipped = json.loads(default_controller_path().read_text(encoding="utf-8"))
    nan_a = copy.deepcopy(shipped)
    nan_a["A"][0][0] = math.nan
    short_b = copy.deepcopy(shipped)
    short_b["B"] = short_b["B"][:-1]
    no_c = copy.deepcopy(shipped)
    del no_c["C"]
    string_d = copy.deepcopy(shipped)
    string_d["D"] = "zero"
    version = copy.deepcopy(shipped)
    version["format_version"] = 99
    huge = copy.deepcopy(shipped)
    huge["C"][0][0] = 1e308
    return {
        "NaN in A": FileSpec("ctl.json", content=json.dumps(nan_a)),
        "B one row short": FileSpec("ctl.json", content=json.dumps(short_b)),
        "C missing": FileSpec("ctl.json", content=json.dumps(no_c)),
        'D = "zero"': FileSpec("ctl.json", content=json.dumps(string_d)),
        "format_version 99": FileSpec("ctl.json", content=json.dumps(version)),
        "1e308 in C": FileSpec("ctl.json", content=json.dumps(huge)),
        "{}": FileSpec("ctl.json", content="{}"),
        "[]": FileSpec("ctl.json", content="[]"),
        "not JSON": FileSpec("ctl.json", content="controller, please\n"),
        "empty": FileSpec("ctl.json", content=""),
    }


def controller_options(inv: Invocations, command: str, descs: Iterable[str]) -> None:
    """``command --controller ctl.json`` with each broken controller of ``descs``."""
    controllers = controller_files()
    for desc in descs:
        inv.option(
            command,
            "--controller",
            ["ctl.json"],
            f"--controller: {desc}",
            files=(controllers[desc],),
            category="controller",
        )


def _stage_state_contents() -> list[tuple[str, str]]:
    def propellant(rows: list[list[float]]) -> str:
        return '{"propellant_kg": ' + json.dumps(rows) + "}"

    return [
        ("not JSON", "state\n"),
        ("a list", "[]"),
        ("propellant_kg a string", '{"propellant_kg": "a"}'),
        ("propellant_kg NaN", propellant([[math.nan] * 3] * 24)),
        ("negative propellant", propellant([[-1.0] * 3] * 24)),
        ("propellant_kg one CubeSat short", propellant([[0.1] * 3] * 23)),
        ("failed CubeSat 99", '{"failed_cubesats": [99]}'),
        ("unknown key", '{"bogus": 1}'),
    ]


def stage_state_options(inv: Invocations) -> None:
    """``allocate --stage-state``: broken contents, then paths that are no file."""
    for desc, content in _stage_state_contents():
        inv.option(
            "allocate",
            "--stage-state",
            ["state.json"],
            f"--stage-state {desc}",
            files=(FileSpec("state.json", content=content),),
            category="stage-state",
            names=("--stage-state", "state.json", *STAGE_STATE_KEYS),
        )
    paths = ("nope.json", "adir", "fifo", "/dev/zero")
    inv.file_options("allocate", "--stage-state", paths, category="stage-state")


def open_loop_options(inv: Invocations) -> None:
    """``simulate --rigid --open-loop``: broken tables, no ``--rigid``, a directory."""
    tail = ["--no-plots", "--out", "out", "--json"]
    for desc, content in OPEN_LOOP.items():
        inv.add(
            "simulate",
            [SHORT_TOML, "--rigid", "--open-loop", "ol.csv", *tail],
            f"--open-loop {desc}",
            ("--open-loop", "ol.csv"),
            files=(FileSpec("ol.csv", content=content),),
            category="open-loop",
        )
    inv.add(
        "simulate",
        [SHORT_TOML, "--open-loop", "ol.csv", *tail],
        "--open-loop without --rigid",
        ("--open-loop", "--rigid"),
        files=(FileSpec("ol.csv", content=_TORQUE_HEADER + "0,1,0,0\n"),),
        category="open-loop",
    )
    inv.add(
        "simulate",
        [SHORT_TOML, "--rigid", "--open-loop", "adir", *tail],
        "--open-loop a directory",
        ("--open-loop", "adir"),
        files=(FileSpec("adir", "dir"),),
        category="open-loop",
    )
