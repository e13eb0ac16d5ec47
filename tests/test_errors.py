"""Every error class of the toolkit is in ``errors.py``, under ``CasadiDebrisError``, and
also a builtin it refines (``ValueError``, ``OSError``, ``RuntimeError``), so that a
caller's ``except ValueError`` keeps working and the command line can tell a user's
mistake (exit 2) from a bug (exit 3)."""

from __future__ import annotations

import ast
import builtins
import inspect
from pathlib import Path

import casadi_debris
from casadi_debris import errors

SOURCE = Path(casadi_debris.__file__).parent
BUILTIN_ERRORS = {
    name
    for name, value in vars(builtins).items()
    if isinstance(value, type) and issubclass(value, BaseException)
}


def _raises_or_defines_errors(path: Path) -> list[str]:
    """Classes in ``path`` whose bases look like exceptions (a builtin or a name ending
    in Error/Exception)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ClassDef):
            names = [ast.unparse(base).rsplit(".", 1)[-1] for base in node.bases]
            if any(n in BUILTIN_ERRORS or n.endswith(("Error", "Exception")) for n in names):
                found.append(f"{path.relative_to(SOURCE)}: {node.name}")
    return found


def test_no_error_class_outside_errors_py() -> None:
    elsewhere = [
        found
        for path in sorted(SOURCE.rglob("*.py"))
        if path.name != "errors.py"
        for found in _raises_or_defines_errors(path)
    ]
    assert not elsewhere, elsewhere


def test_every_error_is_the_toolkits_and_a_builtins() -> None:
    classes = [
        value
        for value in vars(errors).values()
        if inspect.isclass(value)
        and issubclass(value, Exception)
        and value.__module__ == errors.__name__
    ]
    assert len(classes) > 20
    # Ctrl-C stays a KeyboardInterrupt (not an Exception): the user stopped the run.
    assert issubclass(errors.CampaignInterrupted, KeyboardInterrupt)
    for cls in classes:
        assert issubclass(cls, errors.CasadiDebrisError), cls
        if cls is errors.CasadiDebrisError or cls is errors.AllocationError:
            continue
        refined = [
            base
            for base in cls.__mro__
            if base.__module__ == "builtins" and base not in (Exception, BaseException, object)
        ]
        assert refined, f"{cls.__name__} refines no builtin error"


def test_an_internal_error_is_a_bug_and_exits_3() -> None:
    import click
    import pytest

    from casadi_debris.cli.common import EXIT_BAD_INPUT, EXIT_INTERNAL, friendly_errors

    def fails(error: Exception) -> None:
        raise error

    command = friendly_errors(fails)
    with pytest.raises(SystemExit) as internal:
        command(errors.AllocationInternalError("no finite thrust"))
    with pytest.raises(SystemExit) as user:
        command(errors.InputShapeError("torque_mNm: 3 numbers"))
    assert (internal.value.code, user.value.code) == (EXIT_INTERNAL, EXIT_BAD_INPUT)
    assert click  # the wrapper writes through click.echo
