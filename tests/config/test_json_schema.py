"""The problem files' JSON Schema: valid, true to the shipped files, and as strict as the loader."""

from __future__ import annotations

import copy
import json
import tomllib
from typing import Any

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import default_problem_path, problem_from_dict, problem_schema
from casadi_debris.errors import ProblemFileError

jsonschema = pytest.importorskip("jsonschema")
SHIPPED = sorted(default_problem_path().parent.glob("**/*.toml"))


@pytest.fixture(scope="module")
def validator() -> Any:
    schema = problem_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_the_command_prints_the_schema() -> None:
    result = CliRunner().invoke(main, ["schema"])
    assert result.exit_code == 0, result.output
    printed = json.loads(result.stdout)
    assert printed == json.loads(json.dumps(problem_schema()))
    assert printed["properties"]["hub"]["additionalProperties"] is False


@pytest.mark.parametrize("path", SHIPPED, ids=[p.name for p in SHIPPED])
def test_every_shipped_problem_is_valid(validator: Any, path: Any) -> None:
    with path.open("rb") as file:
        errors = [e.message for e in validator.iter_errors(tomllib.load(file))]
    assert not errors


def _set(data: dict[str, Any], path: tuple[Any, ...], value: Any) -> None:
    for part in path[:-1]:
        data = data[part]
    data[path[-1]] = value


# Each mutation is refused by the loader; the schema must refuse it too.
REFUSED = [
    (("hub", "mass_kg"), "500"),
    (("hub", "mass_kg"), True),
    (("hub", "mass_kg"), 1e308),
    (("hub", "mass_kg"), 0.0),
    (("hub", "size_m"), [0.75, 3.0]),
    (("hub", "colour"), "red"),
    (("arrays", 0, "direction"), "+w"),
    (("arrays", 0, "angle_deg"), 400.0),
    (("arrays", 1, "modes", 0, "kind"), "breathing"),
    (("arrays", 1, "modes", 0, "order"), 7),
    (("cubesat_layout", "kind"), "ring"),
    (("cubesat_layout", "side_engines"), 5),
    (("cubesat_layout", "faces"), ["+x", "+w"]),
    (("engine", "stages"), 2.5),
    (("engine", "stages"), 17),
    (("uncertainty", "inertia_fraction"), 1.0),
    (("name",), "../x"),
    (("description",), "x" * 1001),
]


@pytest.mark.parametrize(("path", "value"), REFUSED, ids=[str(p) for p, _ in REFUSED])
def test_what_the_loader_refuses_the_schema_refuses(
    validator: Any, paper_data: dict[str, Any], path: tuple[Any, ...], value: Any
) -> None:
    data = copy.deepcopy(paper_data)
    _set(data, path, value)
    with pytest.raises(ProblemFileError):
        problem_from_dict(data)
    assert not validator.is_valid(data)


@pytest.mark.parametrize(
    ("path", "value"),
    [
        (("hub", "mass_kg"), 600),
        (("arrays",), []),
        (("arrays", 0, "direction"), [0, 0, -1.0]),
        (("uncertainty", "independent_array_angles"), False),
        (("cubesat_layout", "side_engines"), 4),
    ],
)
def test_what_the_loader_accepts_the_schema_accepts(
    validator: Any, paper_data: dict[str, Any], path: tuple[Any, ...], value: Any
) -> None:
    data = copy.deepcopy(paper_data)
    _set(data, path, value)
    problem_from_dict(data)
    assert validator.is_valid(data), [e.message for e in validator.iter_errors(data)]


def _schema_keys(schema: Any) -> set[str]:
    keys: set[str] = set()
    if isinstance(schema, dict):
        keys |= set(schema.get("properties", {}))
        for value in schema.values():
            keys |= _schema_keys(value)
    elif isinstance(schema, list):
        for value in schema:
            keys |= _schema_keys(value)
    return keys


def test_every_optional_key_a_reader_takes_is_in_the_schema() -> None:
    # The schema is read from example problems: an optional key no example sets would
    # be missing, and tables allow no other keys, so such a file would be refused.
    import re
    from pathlib import Path

    import casadi_debris.config

    sources = Path(casadi_debris.config.__file__).parent.glob("*.py")
    optional = {
        name
        for source in sources
        for name in re.findall(r'\b(?:t|top)\.has\("([a-z_]+)"\)', source.read_text())
    }
    assert optional >= {"independent_array_angles", "side_engines", "modes"}
    assert optional <= _schema_keys(problem_schema())
