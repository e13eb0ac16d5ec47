"""The debris as an FMU, checked by an independent FMI importer (fmpy).

The reference is the toolkit's own model integrated without the FMU: its
``dynamics`` Function with the engines' torque and force maps, by CVODES at
tight tolerances (relative 1e-12, absolute 1e-18: the modal rates are of
order 1e-6, so an absolute tolerance of 1e-13 would let CVODES itself drift by
1e-4 of them); for the rigid debris, ``simulation.open_loop_rigid``. The FMU
integrates with RK4, whose error falls as the step to the fourth power: the
tolerance of each comparison is RK4's error at the step used (measured, and
checked to shrink as the theory says), never looser.
"""

from __future__ import annotations

import shutil
import subprocess
import zipfile
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.codegen import (
    FmuSettings,
    FmuSummary,
    engine_names,
    fmi_platform,
    fmu_layout,
    model_identifier,
    write_fmu,
)
from casadi_debris.dynamics import Model, build_model
from casadi_debris.errors import InputShapeError, OutputError

fmpy = pytest.importorskip("fmpy")
from fmpy.validation import validate_fmu  # noqa: E402

HAS_COMPILER = any(shutil.which(name) for name in ("gcc", "cc", "clang"))
needs_compiler = pytest.mark.skipif(not HAS_COMPILER, reason="no C compiler to build the FMU")

# The communication step of the runs and the held-thrust segments [s].
COMMUNICATION_S = 0.05
# RK4's global error at the 2 ms default step, against CVODES, as a fraction of each
# output's peak over the run: measured 2e-5 on the paper's fastest modal rate (second
# bending, 35 rad/s), 1e-9 on the attitude. The bound leaves a factor 5 for other
# thrust histories, not for a change of the method (which would show as 16x per halving).
RK4_RELATIVE_AT_DEFAULT = 1e-4


def held_input(names: tuple[str, ...], knots_s: np.ndarray, thrust_N: np.ndarray) -> np.ndarray:
    """fmpy's input table for a thrust held from each knot: a repeated time is a step."""
    rows = []
    for k, time in enumerate(knots_s):
        if k > 0:
            rows.append((time, *thrust_N[k - 1]))
        rows.append((time, *thrust_N[k]))
    return np.array(rows, dtype=[("time", float)] + [(n, float) for n in names])


def reference_states(
    model: Model,
    knots_s: np.ndarray,
    thrust_N: np.ndarray,
    grid: np.ndarray,
    parameters: np.ndarray | None = None,
    start: np.ndarray | None = None,
    disturbance_Nm: np.ndarray | tuple[float, ...] = (0.0, 0.0, 0.0),
) -> np.ndarray:
    """The model's dynamics with the engines' maps, by CVODES, sampled on ``grid``.

    Nominal parameters, at rest at the identity unless ``parameters`` and ``start`` say
    otherwise; the disturbance torque is constant.
    """
    geometry = model.geometry
    x = ca.SX.sym("x", model.layout.size)
    thrust = ca.SX.sym("thrust", thrust_N.shape[1])
    span = ca.SX.sym("span")
    loads = ca.vertcat(
        ca.DM(geometry.torque_map) @ thrust,
        ca.DM(disturbance_Nm),
        ca.DM(geometry.force_map) @ thrust,
    )
    p = model.nominal_parameters if parameters is None else parameters
    rate = model.dynamics(x, loads, p)
    options = {"abstol": 1e-18, "reltol": 1e-12, "max_num_steps": 1_000_000}
    step = ca.integrator(
        "reference", "cvodes", {"x": x, "p": ca.vertcat(thrust, span), "ode": span * rate}, 0.0,
        1.0, options,
    )  # fmt: skip
    states = np.zeros((len(grid), model.layout.size))
    states[0] = model.initial_state() if start is None else start
    for i in range(len(grid) - 1):
        held = thrust_N[np.searchsorted(knots_s, grid[i] + 1e-9, side="right") - 1]
        params = np.append(held, grid[i + 1] - grid[i])
        states[i + 1] = np.asarray(step(x0=states[i], p=params)["xf"]).ravel()
    return states


def fmu_states(path: Path, model: Model, signal: np.ndarray, stop_s: float, **start: float):
    """The FMU's state outputs, simulated by fmpy, and its time grid."""
    result = fmpy.simulate_fmu(
        str(path),
        stop_time=stop_s,
        output_interval=COMMUNICATION_S,
        input=signal,
        start_values=start,
    )
    layout = fmu_layout(model, 1.0)
    names = [v.name for v in layout.variables[layout.state : layout.state + layout.n_states]]
    return result["time"], np.column_stack([result[n] for n in names]), result


def bang_bang(model: Model, axis: int, level: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Two engines pushing about +axis, then two about -axis, then a mixed pair, then none."""
    torque = model.geometry.torque_map[axis]
    limit = np.array([e.max_thrust_N for e in model.geometry.engines])
    plus, minus = np.argsort(-torque)[:2], np.argsort(torque)[:2]
    thrust = np.zeros((4, len(limit)))
    thrust[0, plus] = level * limit[plus]
    thrust[1, minus] = level * limit[minus]
    thrust[2, plus[0]], thrust[2, minus[1]] = 0.5 * limit[plus[0]], 0.8 * limit[minus[1]]
    return np.array([0.0, 6.0, 12.0, 18.0]), thrust


def modal_excitation(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Pulses near the first bending period (1.1 s): about z, flipping every 0.55 s for 11 s."""
    torque = model.geometry.torque_map[2]
    plus, minus = np.argmax(torque), np.argmin(torque)
    knots = np.arange(0.0, 11.0, 0.55)
    thrust = np.zeros((len(knots) + 1, len(torque)))
    for k in range(len(knots)):
        engine = plus if k % 2 == 0 else minus
        thrust[k, engine] = model.geometry.engines[engine].max_thrust_N
    return np.append(knots, 11.0), thrust


def relative_error(fmu: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Largest |difference| of each output over the run, over that output's peak."""
    peak = np.abs(reference).max(axis=0)
    return np.abs(fmu - reference).max(axis=0) / np.where(peak > 0.0, peak, 1.0)


@pytest.fixture(scope="module")
def paper_model() -> Model:
    return build_model(load_problem("paper"))


@pytest.fixture(scope="module")
def paper_fmu(paper_model: Model, tmp_path_factory: pytest.TempPathFactory) -> FmuSummary:
    if not HAS_COMPILER:
        pytest.skip("no C compiler to build the FMU")
    return write_fmu(paper_model, tmp_path_factory.mktemp("fmu") / "paper.fmu")


def test_fmpy_finds_no_problem(paper_fmu: FmuSummary):
    assert validate_fmu(paper_fmu.path) == []
    description = fmpy.read_model_description(paper_fmu.path)
    assert description.fmiVersion == "2.0"
    assert description.coSimulation is not None and description.modelExchange is None
    with zipfile.ZipFile(paper_fmu.path) as archive:
        names = set(archive.namelist())
    folder, suffix = fmi_platform()
    library = f"binaries/{folder}/{paper_fmu.model_identifier}{suffix}"
    assert {"modelDescription.xml", "sources/fmu.c", "sources/plant.c", library} <= names


def test_variables_name_engines_from_one(paper_model: Model, paper_fmu: FmuSummary):
    engines = len(paper_model.geometry.engines)
    assert paper_fmu.inputs[0] == "thrust_cs01_e1_N"
    assert paper_fmu.inputs[engines - 1] == f"thrust_cs{engines:02d}_e1_N"
    assert paper_fmu.inputs[engines:] == [
        "disturbance_x_Nm",
        "disturbance_y_Nm",
        "disturbance_z_Nm",
    ]
    assert paper_fmu.outputs[:7] == [
        "q0_BN", "q1_BN", "q2_BN", "q3_BN", "omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s"
    ]  # fmt: skip
    assert "eta_array1_bending1" in paper_fmu.outputs
    assert paper_fmu.parameters["mass_kg"] == pytest.approx(paper_model.geometry.mass_kg)


def test_side_engines_are_named_by_cubesat_and_engine():
    """Five engines per CubeSat: each CubeSat's are e1..e5, in the model's engine order."""
    model = build_model(load_problem("side_engines_12"))
    names = engine_names(model)
    assert len(set(names)) == len(names) == len(model.geometry.engines)
    for engine, name in zip(model.geometry.engines, names, strict=True):
        own = model.geometry.cubesats[engine.cubesat].engines
        assert name == f"thrust_cs{engine.cubesat + 1:02d}_e{own.index(engine.index) + 1}_N"
    assert {name[-4:] for name in names} == {f"e{k}_N" for k in range(1, 6)}


@needs_compiler
def test_bang_bang_agrees_with_cvodes(paper_model: Model, paper_fmu: FmuSummary):
    knots, thrust = bang_bang(paper_model, axis=2)
    signal = held_input(tuple(paper_fmu.inputs[: thrust.shape[1]]), knots, thrust)
    grid, states, _ = fmu_states(Path(paper_fmu.path), paper_model, signal, 24.0)
    reference = reference_states(paper_model, knots, thrust, grid)
    # The slew moved: the comparison is not one of zeros.
    assert np.abs(reference[:, 6]).max() > 1e-5
    error = relative_error(states, reference)
    assert error.max() < RK4_RELATIVE_AT_DEFAULT, dict(
        zip(paper_fmu.outputs, error.round(12), strict=False)
    )
    assert error[:7].max() < 1e-7  # attitude and rate


@needs_compiler
def test_engine_limits_and_loads(paper_model: Model, paper_fmu: FmuSummary):
    """Thrust is limited to [0, one stage]; torque and force outputs are the maps of it."""
    n = len(paper_model.geometry.engines)
    limit = np.array([e.max_thrust_N for e in paper_model.geometry.engines])
    rng = np.random.default_rng(7)
    asked = rng.uniform(-1.0, 2.0, n) * limit
    signal = held_input(tuple(paper_fmu.inputs[:n]), np.array([0.0]), asked[None, :])
    _, _, result = fmu_states(Path(paper_fmu.path), paper_model, signal, 2 * COMMUNICATION_S)
    applied = np.clip(asked, 0.0, limit)
    torque = np.array([result[f"torque_{a}_Nm"][-1] for a in "xyz"])
    force = np.array([result[f"force_{a}_N"][-1] for a in "xyz"])
    np.testing.assert_allclose(torque, paper_model.geometry.torque_map @ applied, rtol=1e-12)
    np.testing.assert_allclose(force, paper_model.geometry.force_map @ applied, rtol=1e-12)


@needs_compiler
def test_parameters_start_and_disturbance_reach_the_plant(
    paper_model: Model, paper_fmu: FmuSummary
):
    """Off-nominal parameters, a tilted, turning start and a held disturbance torque."""
    corner = {
        "inertia_scale_x": 1.17,
        "inertia_scale_z": 0.83,
        "mass_kg": 600.0,
        "array_angle_offset_rad": 0.5,
        "bending_frequency_scale": 0.8,
    }
    quaternion = np.array([0.9, 0.1, -0.3, 0.2])
    rate = np.array([1e-3, -2e-3, 5e-4])
    disturbance = np.array([2e-3, -1e-3, 3e-3])
    start = {
        **corner,
        **{f"initial_q{i}_BN": float(v) for i, v in enumerate(quaternion)},
        **{f"initial_omega_{a}_rad_s": float(v) for a, v in zip("xyz", rate, strict=True)},
    }
    knots, thrust = bang_bang(paper_model, axis=1)
    names = (*paper_fmu.inputs[: thrust.shape[1]], *paper_fmu.inputs[-3:])
    table = np.hstack([thrust, np.tile(disturbance, (len(knots), 1))])
    signal = held_input(names, knots, table)
    grid, states, _ = fmu_states(Path(paper_fmu.path), paper_model, signal, 12.0, **start)
    reference = reference_states(
        paper_model,
        knots,
        thrust,
        grid,
        parameters=paper_model.parameters(**corner),
        start=paper_model.initial_state(quaternion, rate),
        disturbance_Nm=disturbance,
    )
    error = relative_error(states, reference)
    assert error.max() < RK4_RELATIVE_AT_DEFAULT, error
    # The nominal plant from the same start is far off: the parameters did reach it.
    nominal = reference_states(
        paper_model, knots, thrust, grid, start=paper_model.initial_state(quaternion, rate),
        disturbance_Nm=disturbance,
    )  # fmt: skip
    assert relative_error(states, nominal)[4:7].max() > 100 * RK4_RELATIVE_AT_DEFAULT


def instantiated(summary: FmuSummary, folder: Path):
    """An fmpy co-simulation slave of the FMU, instantiated, and its value references."""
    from fmpy.fmi2 import FMU2Slave

    description = fmpy.read_model_description(summary.path)
    slave = FMU2Slave(
        guid=description.guid,
        unzipDirectory=fmpy.extract(summary.path, str(folder)),
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName="check",
    )
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    return slave, {v.name: v.valueReference for v in description.modelVariables}


@needs_compiler
def test_saved_state_replays_the_same_step(paper_fmu: FmuSummary, tmp_path: Path):
    """fmi2GetFMUstate / fmi2SetFMUstate: a restored instance steps to the same outputs."""
    slave, references = instantiated(paper_fmu, tmp_path)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    outputs = [references[n] for n in paper_fmu.outputs]
    slave.setReal([references["thrust_cs01_e1_N"]], [6.4e-4])
    slave.doStep(0.0, 0.5)
    saved = slave.getFMUstate()
    slave.doStep(0.5, 0.5)
    first = slave.getReal(outputs)
    slave.setFMUstate(saved)
    slave.doStep(0.5, 0.5)
    assert slave.getReal(outputs) == first
    assert any(value != 0.0 for value in first[4:7])  # the engine turned the debris
    slave.freeFMUstate(saved)
    slave.terminate()
    slave.freeInstance()


@needs_compiler
def test_bad_values_are_refused_by_name(paper_fmu: FmuSummary, tmp_path: Path, capfd):
    """The unit refuses a non-positive mass, a non-finite input and a late parameter."""
    from fmpy.fmi1 import FMICallException

    slave, references = instantiated(paper_fmu, tmp_path)
    slave.setReal([references["mass_kg"]], [-1.0])
    slave.enterInitializationMode()
    with pytest.raises(FMICallException):
        slave.exitInitializationMode()
    slave.setReal([references["mass_kg"]], [600.0])
    slave.exitInitializationMode()
    with pytest.raises(FMICallException):
        slave.setReal([references["thrust_cs02_e1_N"]], [float("nan")])
    with pytest.raises(FMICallException):
        slave.setReal([references["inertia_scale_x"]], [1.1])
    with pytest.raises(FMICallException):
        slave.setReal([references["q0_BN"]], [1.0])
    slave.terminate()
    slave.freeInstance()
    messages = capfd.readouterr().out
    for expected in (
        "mass_kg must be positive",
        "thrust_cs02_e1_N must be finite",
        "inertia_scale_x: a parameter is fixed",
        "q0_BN: an output cannot be set",
    ):
        assert expected in messages, messages


@needs_compiler
def test_same_problem_same_bytes(paper_model: Model, paper_fmu: FmuSummary, tmp_path: Path):
    again = write_fmu(paper_model, tmp_path / "again.fmu")
    assert Path(again.path).read_bytes() == Path(paper_fmu.path).read_bytes()


COMPILERS = [name for name in ("gcc", "clang") if shutil.which(name)]


@pytest.mark.parametrize("compiler", COMPILERS or [pytest.param("cc", marks=needs_compiler)])
def test_sources_build_against_the_standard_headers(
    compiler: str, paper_fmu: FmuSummary, tmp_path: Path
):
    """The wrapper compiles warning-free against fmi2Functions.h (every signature checked)."""
    headers = Path(fmpy.__file__).parent / "c-code"
    with zipfile.ZipFile(paper_fmu.path) as archive:
        archive.extractall(tmp_path)
    # Only CasADi's generated plant.c has unused work-array parameters.
    command = [compiler, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
               "-Wno-unused-parameter", "-DCDB_FMI2_HEADERS", f"-I{headers}", "-fPIC",
               "-shared", "-o", str(tmp_path / "rebuilt.so"), "fmu.c", "-lm"]  # fmt: skip
    built = subprocess.run(command, cwd=tmp_path / "sources", capture_output=True, text=True)
    assert built.returncode == 0, built.stderr


def test_summary_is_a_record(paper_fmu: FmuSummary):
    data = paper_fmu.to_json()
    assert FmuSummary.from_json(data) == paper_fmu
    assert data["fmi_version"] == "2.0" and data["platform"] == fmi_platform()[0]
    assert data["size_bytes"] == Path(paper_fmu.path).stat().st_size
    assert model_identifier("my debris-1 (v2)") == "casadi_debris_my_debris_1_v2"


def test_bad_requests_are_named(paper_model: Model, tmp_path: Path):
    with pytest.raises(InputShapeError, match="path"):
        write_fmu(paper_model, tmp_path / "plant.zip")
    (tmp_path / "there.fmu").write_bytes(b"")
    with pytest.raises(OutputError, match="overwrite"):
        write_fmu(paper_model, tmp_path / "there.fmu")
    assert (tmp_path / "there.fmu").read_bytes() == b""
    with pytest.raises(InputShapeError, match="max_step_s"):
        FmuSettings(max_step_s=0.0)


def test_sources_only_without_compiler(paper_model: Model, tmp_path: Path):
    summary = write_fmu(paper_model, tmp_path / "sources.fmu", FmuSettings(compile=False))
    assert summary.platform is None
    assert validate_fmu(summary.path) == []
    with zipfile.ZipFile(summary.path) as archive:
        assert not any(name.startswith("binaries/") for name in archive.namelist())


@pytest.mark.slow
@needs_compiler
def test_modal_excitation_agrees_and_converges(paper_model: Model, paper_fmu: FmuSummary):
    """Pulses at the first bending period; halving the step cuts the error about 16 times."""
    knots, thrust = modal_excitation(paper_model)
    signal = held_input(tuple(paper_fmu.inputs[: thrust.shape[1]]), knots, thrust)
    path = Path(paper_fmu.path)
    grid, coarse, _ = fmu_states(path, paper_model, signal, 15.0, max_step_s=0.004)
    _, fine, _ = fmu_states(path, paper_model, signal, 15.0, max_step_s=0.002)
    reference = reference_states(paper_model, knots, thrust, grid)
    modal = paper_model.layout.eta_dot
    assert np.abs(reference[:, modal]).max() > 1e-6  # the arrays ring
    error_coarse = relative_error(coarse, reference)
    error_fine = relative_error(fine, reference)
    assert error_fine.max() < RK4_RELATIVE_AT_DEFAULT
    # Fourth order: 16 in theory; 10 leaves room for the reference's own error.
    ratio = error_coarse[modal] / error_fine[modal]
    assert ratio.min() > 10.0, ratio


@pytest.mark.slow
@needs_compiler
def test_rigid_gallery_agrees_with_open_loop_rigid(tmp_path: Path):
    """A debris without arrays against the toolkit's own open-loop simulation."""
    from casadi_debris.simulation import open_loop_rigid

    problem = load_problem("rigid_no_arrays")
    model = build_model(problem)
    assert model.layout.n_eta == 0
    summary = write_fmu(model, tmp_path / "rigid.fmu")
    assert validate_fmu(summary.path) == []
    knots, thrust = bang_bang(model, axis=0)
    signal = held_input(tuple(summary.inputs[: thrust.shape[1]]), knots, thrust)
    grid, states, _ = fmu_states(Path(summary.path), model, signal, 24.0)
    torque = thrust @ model.geometry.torque_map.T
    expected = open_loop_rigid(problem, knots, torque, duration_s=24.0)
    at = np.searchsorted(grid, expected.time_s)
    assert np.allclose(grid[at], expected.time_s)
    fmu_q, fmu_rate = states[at, model.layout.q], states[at, model.layout.omega]
    peak = np.abs(expected.rate_rad_s).max()
    assert peak > 1e-5
    # open_loop_rigid's CVODES runs at an absolute tolerance of 1e-13 rad/s, 1e-8 of these
    # rates per step: that, not RK4, bounds the agreement (measured 8e-9 of the peak).
    assert np.abs(fmu_rate - expected.rate_rad_s).max() < 1e-7 * peak
    assert np.abs(fmu_q - expected.quaternion_BN).max() < 1e-9
