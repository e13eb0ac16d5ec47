"""The JIT-compiled step gives the virtual machine's numbers (where a C compiler exists)."""

from __future__ import annotations

import json
import os
from dataclasses import replace

import numpy as np
import pytest

from casadi_debris.allocation import Allocator
from casadi_debris.config import default_controller_path, default_problem_path, load_problem
from casadi_debris.model import build_model
from casadi_debris.robust.controller import ControllerRecord
from casadi_debris.simulation import scenario_reference, simulate
from casadi_debris.simulation.closed_loop import c_compiler

pytestmark = pytest.mark.skipif(c_compiler() is None, reason="no C compiler for CasADi's JIT")


def test_compiled_and_virtual_machine_runs_agree() -> None:
    problem = load_problem(default_problem_path().parent / "paper_slew.toml")
    problem = replace(problem, simulation=replace(problem.simulation, duration_s=150.0))
    model = build_model(problem)
    record = ControllerRecord.from_dict(json.loads(default_controller_path().read_text()))
    reference = scenario_reference(problem)
    corner = model.parameters(inertia_scale_z=1.17, array_angle_offset_rad=0.8)
    runs = [
        simulate(
            problem,
            model,
            record.reduced,
            reference,
            parameters=corner,
            # A fresh allocator each: a warm one reuses regions anchored elsewhere,
            # which moves the thrust within the QP's tolerance.
            allocator=Allocator.from_problem(problem, model.geometry),
            jit=jit,
        )
        for jit in (False, True)
    ]
    assert runs[1].info["compiled_step"] and not runs[0].info["compiled_step"]
    # Same operations in the same order: agreement to round-off.
    assert np.abs(runs[0].state - runs[1].state).max() < 1e-12
    assert np.abs(runs[0].thrust_N - runs[1].thrust_N).max() < 1e-15


def test_jit_folders_of_killed_processes_are_removed(tmp_path, monkeypatch) -> None:
    import subprocess
    import sys
    import tempfile

    from casadi_debris.simulation import closed_loop

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
