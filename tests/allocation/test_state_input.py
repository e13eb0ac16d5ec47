"""``allocate --stage-state`` with a malformed file: exit 2 and one line naming the key."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.allocation import PropulsionState
from casadi_debris.cli import main

N_CUBESATS = 24  # the paper's swarm: one engine each, three stages
FULL = np.full((N_CUBESATS, 3), 0.0).tolist()


@pytest.mark.parametrize(
    ("content", "named"),
    [
        ('{"failed_cubesats": 5}', "failed_cubesats"),
        ('{"failed_cubesats": null}', "failed_cubesats"),
        ('{"failed_cubesats": {"4": true}}', "failed_cubesats"),
        ('{"failed_cubesats": [0]}', "failed_cubesats"),  # a 0-based id
        ('{"failed_cubesats": [25]}', "failed_cubesats"),
        ('{"failed_cubesats": [1.5]}', "failed_cubesats"),
        ('{"failed_cubesats": [true]}', "failed_cubesats"),
        ('{"failed_stages": 3}', "failed_stages"),
        ('{"failed_stages": [3]}', "failed_stages"),
        ('{"failed_stages": [[1]]}', "failed_stages"),
        ('{"failed_stages": [[1, 0]]}', "failed_stages"),
        ('{"failed_stages": [[1, 4]]}', "failed_stages"),
        ('{"failed_stages": [["1", 2]]}', "failed_stages"),
        ('{"failed_engines": "1,1"}', "failed_engines"),
        ('{"failed_engines": [5]}', "failed_engines"),
        ('{"failed_engines": [[1, 2]]}', "failed_engines"),  # one engine per CubeSat
        ('{"failed_engines": [[0, 1]]}', "failed_engines"),
        ('{"propellant_kg": "x"}', "propellant_kg"),
        ('{"propellant_kg": null}', "propellant_kg"),
        ('{"propellant_kg": [[1, 2]]}', "propellant_kg"),
        (json.dumps({"propellant_kg": [[-1.0, 0.0, 0.0]] * N_CUBESATS}), "propellant_kg"),
        (json.dumps({"firing_time_s": [[float("nan")] * 3] * N_CUBESATS}), "firing_time_s"),
        ('{"failed_cubesat": [1]}', "failed_cubesat"),  # unknown key
        ("[1, 2]", "JSON object"),
        ('{"failed_cubesats": [1', "JSON"),
        ("", "JSON"),
    ],
)
def test_a_malformed_stage_state_exits_2_with_one_line_naming_the_key(
    tmp_path, content: str, named: str
) -> None:
    state = tmp_path / "state.json"
    state.write_text(content)
    result = CliRunner().invoke(
        main, ["allocate", "--torque-mNm", "1", "0", "0", "--stage-state", str(state)]
    )
    assert result.exit_code == 2, result.output
    assert result.output.count("\n") == 1 and result.output.startswith("error:"), result.output
    assert "--stage-state" in result.output and named in result.output
    assert "Traceback" not in result.output


def test_a_zero_id_is_said_to_count_from_1(tmp_path) -> None:
    state = tmp_path / "state.json"
    state.write_text('{"failed_cubesats": [0]}')
    result = CliRunner().invoke(
        main, ["allocate", "--torque-mNm", "1", "0", "0", "--stage-state", str(state)]
    )
    assert "ids count from 1" in result.output


def test_a_well_formed_state_reads_back_what_it_wrote() -> None:
    """The checks refuse only what is malformed: a state's own ``to_dict`` reads back."""
    template = PropulsionState.from_problem(load_problem())
    state = template.copy()
    state.fail_cubesat(3)
    state.fail_stage(4, 0)
    read = template.updated_from_dict(json.loads(json.dumps(state.to_dict())))
    assert read.to_dict() == state.to_dict()
    assert read.to_dict()["failed_cubesats"] == [4] and read.to_dict()["failed_stages"] == [[5, 1]]
