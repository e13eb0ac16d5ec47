"""The JIT-compiled step gives the virtual machine's numbers (where a C compiler exists),
and is compiled once per machine: the library is cached on disk by content hash."""

from __future__ import annotations

import json
import logging
import os
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from casadi_debris.allocation import Allocator
from casadi_debris.config import default_controller_path, default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import (
    LoopSettings,
    build_loop_step,
    c_compiler,
    discretize_controller,
    simulate_closed_loop,
)
from casadi_debris.simulation import _closed_loop as closed_loop
from casadi_debris.simulation import _jit_cache as jit_cache

pytestmark = pytest.mark.skipif(c_compiler() is None, reason="no C compiler for CasADi's JIT")

# Builds the paper slew's compiled step in a process of its own and says how it went.
LOOP_STEP_SCRIPT = """
import json, logging, sys
logging.basicConfig(level=logging.INFO, stream=sys.stderr)
from casadi_debris.allocation import Allocator
from casadi_debris.config import default_controller_path, default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import build_loop_step, discretize_controller

problem = load_problem(default_problem_path().parent / "paper_slew.toml")
model = build_model(problem)
record = Controller.from_dict(json.loads(default_controller_path().read_text()))
period = 1.0 / problem.simulation.control_rate_hz
loop = build_loop_step(
    model,
    model.nominal_parameters,
    discretize_controller(record.reduced, period),
    Allocator.from_problem(problem, model.geometry).authority_polytope(),
    integrator_steps=problem.simulation.integrator_steps,
    jit=True,
)
print(json.dumps({"compiled": loop.compiled}))
"""

# Compiles a small Function into the cache once every racer is ready (so that
# their compiles overlap) and prints its value at 0.5.
RACER_SCRIPT = """
import pathlib, sys, time
import casadi as ca
from casadi_debris.simulation._jit_cache import compiled_function
gate, me, racers = pathlib.Path(sys.argv[1]), sys.argv[2], int(sys.argv[3])
(gate / me).touch()
while len(list(gate.iterdir())) < racers:
    time.sleep(0.001)
x = ca.SX.sym("x")
f = ca.Function("small", [x], [ca.sin(x) * x + 1.0])
print(float(compiled_function(f, {compiler!r})(0.5)))
"""


@pytest.fixture(scope="module")
def module_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("jit_cache")


@pytest.fixture(autouse=True)
def _private_cache(module_cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The tests neither read nor fill the user's cache folder."""
    monkeypatch.setenv(jit_cache.CACHE_ENV, str(module_cache))


def _small_function() -> ca.Function:
    x = ca.SX.sym("x", 3)
    return ca.Function("small", [x], [ca.sin(x) * x + ca.sqrt(ca.fabs(x)) / 3.0])


def _subprocess_environment(cache: Path, scratch: Path) -> dict[str, str]:
    """A child's environment: the cache given, and a temporary folder to check it leaves empty."""
    return {**os.environ, jit_cache.CACHE_ENV: str(cache), "TMPDIR": str(scratch)}


def test_compiled_and_virtual_machine_runs_agree() -> None:
    problem = load_problem(default_problem_path().parent / "paper_slew.toml")
    problem = replace(problem, simulation=replace(problem.simulation, duration_s=150.0))
    model = build_model(problem)
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    reference = scenario_reference(problem)
    corner = model.parameters(inertia_scale_z=1.17, array_angle_offset_rad=0.8)
    runs = [
        simulate_closed_loop(
            model,
            record.reduced,
            reference,
            parameters=corner,
            # A fresh allocator each: a warm one reuses regions anchored elsewhere,
            # which moves the thrust within the QP's tolerance.
            allocator=Allocator.from_problem(problem, model.geometry),
            settings=LoopSettings(jit=jit),
        )
        for jit in (False, True)
    ]
    assert runs[1].compiled_step and not runs[0].compiled_step
    # Same operations in the same order: agreement to round-off.
    assert np.abs(runs[0].state - runs[1].state).max() < 1e-12
    assert np.abs(runs[0].thrust_N - runs[1].thrust_N).max() < 1e-15


def test_jit_folders_of_killed_processes_are_removed(tmp_path, monkeypatch) -> None:
    import subprocess
    import sys
    import tempfile

    from casadi_debris.simulation import _closed_loop as closed_loop

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    finished = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    )
    dead = tmp_path / f"{closed_loop.JIT_PREFIX}{int(finished.stdout)}_x1"
    live = tmp_path / f"{closed_loop.JIT_PREFIX}{os.getpid()}_x2"
    other = tmp_path / "casadi_debris_jit_notapid_x3"
    for folder in (dead, live, other):
        folder.mkdir()
        (folder / "loop_step.c").write_text("int x;")
    closed_loop._remove_stale_jit_folders()
    assert not dead.exists() and live.exists() and other.exists()


def test_a_fresh_process_loads_the_compiled_step_from_the_cache(tmp_path: Path) -> None:
    cache, scratch = tmp_path / "cache", tmp_path / "scratch"
    scratch.mkdir()
    first, second = (
        subprocess.run(
            [sys.executable, "-c", LOOP_STEP_SCRIPT],
            capture_output=True,
            text=True,
            env=_subprocess_environment(cache, scratch),
        )
        for _ in range(2)
    )
    for finished in (first, second):
        assert finished.returncode == 0, finished.stderr
        assert json.loads(finished.stdout) == {"compiled": True}
    assert "JIT cache miss" in first.stderr and "JIT cache hit" not in first.stderr
    assert "JIT cache hit" in second.stderr and "JIT cache miss" not in second.stderr
    # One library and nothing else, in the cache folder only.
    assert [path.suffix for path in cache.iterdir()] == [".so"]
    assert list(scratch.iterdir()) == []


@pytest.mark.parametrize("damage", ["truncated", "overwritten", "not_a_library"])
def test_a_damaged_library_in_the_cache_is_compiled_again(
    damage: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    monkeypatch.setenv(jit_cache.CACHE_ENV, str(tmp_path))
    function = _small_function()
    point = np.array([0.3, -1.2, 2.5])
    expected = np.asarray(function(point))
    compiler = c_compiler()
    assert compiler is not None
    np.testing.assert_array_equal(jit_cache.compiled_function(function, compiler)(point), expected)
    (library,) = tmp_path.iterdir()
    data = library.read_bytes()
    if damage == "truncated":
        library.write_bytes(data[: len(data) // 2])
    elif damage == "overwritten":
        library.write_bytes(data[:4096] + bytes(len(data) - 4096))
    else:  # its name matches its bytes, but they are not a library
        library.unlink()
        garbage = b"not a shared library"
        digest = jit_cache._content_digest(garbage)
        library = library.with_name(f"{library.name.split('.')[0]}.{digest}.so")
        library.write_bytes(garbage)
    with caplog.at_level(logging.INFO, logger=jit_cache.__name__):
        rebuilt = jit_cache.compiled_function(function, compiler)
    assert "is damaged" in caplog.text and "JIT cache miss" in caplog.text
    np.testing.assert_array_equal(rebuilt(point), expected)
    (replacement,) = tmp_path.iterdir()
    assert replacement.name.split(".")[1] == jit_cache._content_digest(replacement.read_bytes())


def test_processes_compiling_one_function_at_once_each_get_a_library(tmp_path: Path) -> None:
    cache, scratch, gate = tmp_path / "cache", tmp_path / "scratch", tmp_path / "gate"
    scratch.mkdir()
    gate.mkdir()
    script = RACER_SCRIPT.format(compiler=c_compiler())
    racers = [
        subprocess.Popen(
            [sys.executable, "-c", script, str(gate), str(i), "2"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=_subprocess_environment(cache, scratch),
        )
        for i in range(2)
    ]
    answers = [racer.communicate(timeout=600) for racer in racers]
    assert [racer.returncode for racer in racers] == [0, 0], answers
    assert {float(out) for out, _ in answers} == {float(np.sin(0.5) * 0.5 + 1.0)}
    # Whole libraries only (one, or one each if the compiler is not deterministic).
    for library in cache.iterdir():
        assert library.suffix == ".so"
        assert library.name.split(".")[1] == jit_cache._content_digest(library.read_bytes())
    assert list(scratch.iterdir()) == []


def test_a_failing_compiler_leaves_the_step_on_the_virtual_machine(
    model, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    failing = shutil.which("false")
    if failing is None:
        pytest.skip("no `false` command")
    monkeypatch.setattr(closed_loop, "c_compiler", lambda: failing)
    monkeypatch.setattr(closed_loop, "_JIT_STEPS", {})
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    problem = model.problem
    with caplog.at_level(logging.WARNING, logger=closed_loop.__name__):
        loop = build_loop_step(
            model,
            model.nominal_parameters,
            discretize_controller(record.reduced, 1.0 / problem.simulation.control_rate_hz),
            Allocator.from_problem(problem, model.geometry).authority_polytope(),
            jit=True,
        )
    assert not loop.compiled
    assert "virtual machine" in caplog.text and "failed" in caplog.text


@pytest.mark.slow
def test_the_cached_library_computes_what_casadis_own_jit_computes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Bit for bit: the cache compiles the C that CasADi's JIT compiled, with the same flags."""
    monkeypatch.setenv(jit_cache.CACHE_ENV, str(tmp_path / "cache"))
    monkeypatch.setattr(closed_loop, "_JIT_STEPS", {})
    problem = load_problem(default_problem_path().parent / "paper_slew.toml")
    model = build_model(problem)
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    reference = scenario_reference(problem)
    controller = discretize_controller(record.reduced, 1.0 / problem.simulation.control_rate_hz)
    polytope = Allocator.from_problem(problem, model.geometry).authority_polytope()
    cached = build_loop_step(
        model, model.nominal_parameters, controller, polytope, chunk_steps=500, jit=True
    )
    assert cached.compiled
    step = closed_loop._loop_step(model, None, controller, polytope, 4, "rk4")
    inputs = [ca.SX.sym(step.name_in(i), step.sparsity_in(i)) for i in range(step.n_in())]
    options = {
        "jit": True,
        "compiler": "shell",
        "jit_options": {
            "compiler": c_compiler(),
            "flags": list(closed_loop.JIT_FLAGS),
            "directory": f"{tmp_path}{os.sep}",
        },
    }
    own = ca.Function("loop_step_c", inputs, step.call(inputs), options)
    own_loop = closed_loop.LoopStep.of(own, model, controller, 500, compiled=True)
    z0 = np.concatenate([model.initial_state(), np.zeros(controller.n_states)])
    rows = np.vstack([reference.time_s[:500], reference.quaternion_BN[:500].T, np.zeros((3, 500))])
    for a, b in zip(
        cached.roll(z0, rows, model.nominal_parameters),
        own_loop.roll(z0, rows, model.nominal_parameters),
        strict=True,
    ):
        np.testing.assert_array_equal(a, b)
