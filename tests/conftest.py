"""Shared fixtures: the paper's problem, its geometry and model, built once per session."""

from __future__ import annotations

import copy
import logging
import os
import shutil
import signal
import tempfile
import tomllib
from collections.abc import Iterator
from typing import Any

import pytest

from casadi_debris import load_problem
from casadi_debris.config import Problem, default_problem_path, problem_from_dict
from casadi_debris.dynamics import Model, build_model
from casadi_debris.geometry import Geometry, build_geometry
from shared_results import FOLDER_VARIABLE as SHARED_FOLDER


def pytest_configure(config: pytest.Config) -> None:
    """Keep the tests' compiled control steps (and shared results) out of the user's
    cache folder.

    One folder per test session (workers and subprocesses inherit it through the
    environment), removed when the session ends; a test that sets
    its own folder still wins.
    """
    if "CASADI_DEBRIS_JIT_CACHE" not in os.environ:
        folder = tempfile.mkdtemp(prefix="casadi_debris-test-jit-")
        os.environ["CASADI_DEBRIS_JIT_CACHE"] = folder
        config.add_cleanup(lambda: shutil.rmtree(folder, ignore_errors=True))
    # The results several files share (tests/shared_results.py), likewise one folder
    # per session, made before the workers start so that they all see it.
    if SHARED_FOLDER not in os.environ:
        shared = tempfile.mkdtemp(prefix="casadi_debris-test-shared-")
        os.environ[SHARED_FOLDER] = shared
        config.add_cleanup(lambda: shutil.rmtree(shared, ignore_errors=True))


@pytest.fixture(autouse=True)
def _toolkit_logger_restored() -> Iterator[None]:
    """Undo what a command run in-process does to the toolkit's logger.

    The command line gives the ``casadi_debris`` logger its own stderr handler and
    stops it propagating; a later test reading records through ``caplog`` (which
    listens at the root) would otherwise see none.
    """
    # Reset, not restored: a module- or session-scoped fixture that ran a command set
    # the logger up before this fixture could see it.
    _reset_toolkit_logger()
    yield
    _reset_toolkit_logger()


def _reset_toolkit_logger() -> None:
    """The ``casadi_debris`` logger as a library leaves it: no CLI handler, propagating."""
    logger = logging.getLogger("casadi_debris")
    logger.handlers[:] = [h for h in logger.handlers if h.get_name() != "casadi-debris-cli"]
    logger.propagate, logger.level = True, logging.NOTSET


@pytest.fixture
def ctrl_c_raises() -> Iterator[None]:
    """A Ctrl-C (SIGINT) raises ``KeyboardInterrupt`` in the test, as on a terminal, even
    when the test run was started with SIGINT ignored (a background job of a shell without
    job control, ``nohup``): Python then installs no handler of its own, and a test of what
    a Ctrl-C does would wait for what the Ctrl-C should have stopped."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@pytest.fixture(scope="session")
def paper_data() -> dict[str, Any]:
    """The paper's problem file as parsed TOML (copy before changing it)."""
    with default_problem_path().open("rb") as handle:
        return tomllib.load(handle)


@pytest.fixture
def fresh_data(paper_data: dict[str, Any]) -> dict[str, Any]:
    """A private, mutable copy of the paper's problem data."""
    return copy.deepcopy(paper_data)


@pytest.fixture(scope="session")
def problem() -> Problem:
    return load_problem()


@pytest.fixture(scope="session")
def geometry(problem: Problem) -> Geometry:
    return build_geometry(problem)


@pytest.fixture(scope="session")
def model(problem: Problem) -> Model:
    return build_model(problem)


@pytest.fixture(scope="session")
def undamped_problem(paper_data: dict[str, Any]) -> Problem:
    data = copy.deepcopy(paper_data)
    for array in data["arrays"]:
        array["damping_ratio"] = 0.0
    return problem_from_dict(data, "undamped")
