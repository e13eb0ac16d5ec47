"""The sampled-data closed loop as one compiled CasADi graph.

One control period ``h = 1 / control_rate`` of the loop, from the state
``z_k = [x_k, xc_k]`` (plant, controller) and the reference ``q_ref,k``:

1. star tracker: ``e_k = attitude_error(q_ref,k, q_ST,k)`` (rad, attitude
   minus reference, short way round; the model's own function);
2. controller (the reduced mu controller, zero-order-hold discretised):
   ``u_k = Cd xc_k + Dd (-e_k) [deg -> mNm]``, ``xc_k+1 = Ad xc_k + Bd (-e_k)``;
3. saturation, as the allocator does it: the largest ``alpha <= 1`` with
   ``alpha u_k`` reachable by the engines at zero net force, from the facets
   of the authority polytope (:mod:`casadi_debris.allocation`);
4. plant: the model's ``dynamics`` with torque ``alpha u_k`` held and the
   disturbance ``d(t)``, integrated over the period by ``integrator_steps``
   classical Runge-Kutta steps (or CVODES, for reference). The environment
   torques the problem switches on (:mod:`~casadi_debris.simulation._disturbance`)
   are evaluated once per period from ``t_k`` and the attitude of ``x_k`` and
   held with ``alpha u_k``: they change over minutes, the period is 0.1 s.

With realistic sensors, estimator, delay or engines (the problem's
``[sensors.*]``, ``[estimation]``, ``[controller]``, ``[actuators]``) steps 1 and
3 are those of :mod:`~casadi_debris.simulation._realism`, with their extra state
after the controller's and their noise as extra rows of ``s``.

The whole period is one ``casadi.Function`` (expanded to scalar operations,
the parameter vector folded in as constants), rolled out over many periods
with ``mapaccum``: no Python per step. The engines' thrust for the applied
torques is the allocator's least-fuel answer, computed for each stretch of
periods at once by :meth:`~casadi_debris.allocation.Allocator.allocate_series`;
its torque equals ``alpha u_k`` to 1e-9 (checked on every run and reported),
so computing it after the stretch changes nothing in the loop.
"""

from __future__ import annotations

import gc
import hashlib
import logging
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import casadi as ca
import control
import numpy as np

from casadi_debris.allocation import AuthorityPolytope
from casadi_debris.dynamics import Model
from casadi_debris.errors import CompileError, SimulationError
from casadi_debris.processes import c_compiler, process_alive
from casadi_debris.simulation._disturbance import environment_function
from casadi_debris.simulation._jit_cache import compiled_function
from casadi_debris.simulation._realism import EngineBasis, Realism, realistic_law
from casadi_debris.units import DEG_PER_RAD, NM_PER_MNM

# Relative pull-in of a saturated torque so that it lies strictly inside the
# reachable set (the allocator promises alpha to 1e-9).
SATURATION_BACKOFF = 1e-10
INTEGRATORS = ("rk4", "cvodes")
MODAL_CONDITION_MAX = 1e6


class StepInput:
    """Rows of the step's input ``s`` (one column per control period)."""

    TIME_S = 0
    REFERENCE_BN = slice(1, 5)
    FEEDFORWARD_NM = slice(5, 8)
    SIZE = 8


class StepOutput:
    """Rows of the step's output ``y``.

    The ideal loop's ``y`` has the first ``SIZE``; the realistic one adds the
    torque and force applied over the period and, with engine-level effects,
    the (delayed) torque command and each engine's thrust change
    (:mod:`~casadi_debris.simulation._realism`).
    """

    DEMAND_NM = slice(0, 3)
    SCALE = 3
    MEASURED_ERROR_RAD = slice(4, 7)
    SIZE = 7
    APPLIED_NM = slice(7, 10)
    FORCE_N = slice(10, 13)
    COMMAND_NM = slice(13, 16)
    THRUST_CHANGE_START = 16


JIT_FLAGS = ("-O2",)
# Older versions compiled each campaign's step into a folder with this prefix in the
# system's temporary folder (then the owner's process id); the step now goes to the
# machine's cache (jit_cache), and stale folders of those versions are still removed.
JIT_PREFIX = "casadi_debris_jit_"
MODAL_ROUND_OFF = 1e-13
CVODES_OPTIONS = {"abstol": 1e-12, "reltol": 1e-10, "max_num_steps": 100000}

LOGGER = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class DiscreteController:
    """Controller ``x+ = A x + B e, u = C x + D e`` (e [deg] -> u [mNm]) at period ``period_s``."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    period_s: float

    @property
    def n_states(self) -> int:
        return self.A.shape[0]


def discretize_controller(controller: control.StateSpace, period_s: float) -> DiscreteController:
    """Zero-order-hold discretisation of a continuous controller, in real modal form.

    Parameters
    ----------
    controller : control.StateSpace
        Continuous, 3 inputs (attitude error, deg) and 3 outputs (torque, mNm).
    period_s : float
        Sample period [s].

    Raises
    ------
    SimulationError
        Not 3 x 3, or the discrete controller is not stable while the
        continuous one is (period too long for its poles).
    """
    if controller.ninputs != 3 or controller.noutputs != 3:
        raise SimulationError(
            f"the controller must map 3 attitude errors to 3 torques, "
            f"got {controller.ninputs} inputs and {controller.noutputs} outputs"
        )
    if not period_s > 0:
        raise SimulationError(f"control period must be positive, got {period_s}")
    discrete = control.sample_system(controller, period_s, method="zoh")
    # The real modal form (2 x 2 blocks) has the same input-output behaviour with a
    # nearly diagonal A: about a quarter of the operations per step. Kept only when
    # the change of basis is well conditioned.
    modal, basis = control.modal_form(discrete)
    a = np.asarray(discrete.A)
    if np.linalg.cond(basis) < MODAL_CONDITION_MAX:
        discrete = modal
        # Entries off the 2 x 2 blocks are round-off of the change of basis.
        a = np.where(np.abs(modal.A) > MODAL_ROUND_OFF * np.abs(modal.A).max(), modal.A, 0.0)
    return DiscreteController(
        A=a,
        B=np.asarray(discrete.B),
        C=np.asarray(discrete.C),
        D=np.asarray(discrete.D),
        period_s=float(period_s),
    )


def saturation_scale(torque: ca.SX, polytope: AuthorityPolytope) -> ca.SX:
    """alpha = min(1, min over facets with n.tau > 0 of b / (n.tau)), symbolic."""
    return _saturation(torque, ca.DM(polytope.normals), ca.DM(polytope.offsets))


def _saturation(torque: ca.SX, normals: ca.SX | ca.DM, offsets: ca.SX | ca.DM) -> ca.SX:
    """:func:`saturation_scale` with the facets given as constants or as symbols."""
    reach = normals @ torque
    tiny = np.finfo(float).tiny
    ratios = ca.if_else(reach > 0, offsets / ca.fmax(reach, tiny), ca.DM.inf(reach.shape))
    return ca.fmin(1.0, ca.mmin(ratios))


def applied_torque(demand_Nm: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """The torque the loop applies for demands (k, 3) and their saturation factors (k,).

    The numeric twin of the step's own ``applied`` (same back-off).
    """
    shrink = np.where(scale < 1.0, scale * (1.0 - SATURATION_BACKOFF), 1.0)
    return demand_Nm * shrink[:, None]


def _rk4_step(
    model: Model, parameters: np.ndarray | None, period_s: float, steps: int
) -> ca.Function:
    """``plant(x, t, u, p) -> x(t + h)``: RK4 on the model with the torque/force input u held.

    With ``parameters`` given they are folded in as constants (p is then unused).
    """
    x = ca.SX.sym("x", model.layout.size)
    t = ca.SX.sym("t")
    u = ca.SX.sym("u", 6)  # torque (3) N m, force (3) N
    p_in = ca.SX.sym("p", len(model.parameter_names))
    p = p_in if parameters is None else ca.DM(parameters)
    h = period_s / steps

    def rate(state: ca.SX, time: ca.SX) -> ca.SX:
        inputs = ca.vertcat(u[0:3], model.disturbance(time), u[3:6])
        return model.dynamics(state, inputs, p)

    state = x
    for i in range(steps):
        start = t + i * h
        k1 = rate(state, start)
        k2 = rate(state + h / 2 * k1, start + h / 2)
        k3 = rate(state + h / 2 * k2, start + h / 2)
        k4 = rate(state + h * k3, start + h)
        state = state + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return ca.Function(
        "plant_rk4", [x, t, u, p_in], [state], ["x", "t", "u", "p"], ["x_next"]
    ).expand()


def _cvodes_step(model: Model, parameters: np.ndarray, period_s: float) -> ca.Function:
    """``plant(x, t, u, p) -> x(t + h)`` by CVODES (time as an extra state for the disturbance).

    The parameters are folded in; p is unused.
    """
    x = ca.SX.sym("x", model.layout.size)
    clock = ca.SX.sym("clock")
    u = ca.SX.sym("u", 6)
    inputs = ca.vertcat(u[0:3], model.disturbance(clock), u[3:6])
    ode = ca.vertcat(model.dynamics(x, inputs, ca.DM(parameters)), 1.0)
    dae = {"x": ca.vertcat(x, clock), "p": u, "ode": ode}
    integrator = ca.integrator("plant_cvodes", "cvodes", dae, 0.0, period_s, CVODES_OPTIONS)
    xs = ca.MX.sym("x", model.layout.size)
    ts = ca.MX.sym("t")
    us = ca.MX.sym("u", 6)
    ps = ca.MX.sym("p", len(model.parameter_names))
    final = integrator(x0=ca.vertcat(xs, ts), p=us)["xf"]
    return ca.Function(
        "plant_cvodes",
        [xs, ts, us, ps],
        [final[: model.layout.size]],
        ["x", "t", "u", "p"],
        ["x_next"],
    )


@dataclass(frozen=True, eq=False)
class LoopStep:
    """One control period as a CasADi Function and its roll-out.

    ``step(z, s, p) -> (z_next, y)`` with z = [x (plant), xc (controller)],
    s = [t_k, q_ref,k (4), feedforward torque (3) N m], p the model
    parameters (unused when folded in), y = [u_k (3) N m demanded, alpha_k,
    e_k (3) rad measured]. ``rollout`` is ``step.mapaccum`` over
    ``chunk_steps`` periods; ``compiled`` says it runs as JIT-compiled C.
    """

    step: ca.Function
    rollout: ca.Function
    chunk_steps: int
    n_plant: int
    n_controller: int
    compiled: bool = False
    realism: Realism | None = None

    @classmethod
    def of(
        cls,
        step: ca.Function,
        model: Model,
        controller: DiscreteController,
        chunk_steps: int,
        *,
        compiled: bool = False,
        realism: Realism | None = None,
    ) -> LoopStep:
        """Wrap a step Function with its ``mapaccum`` roll-out."""
        return cls(
            step=step,
            rollout=step.mapaccum(f"{step.name()}_rollout", chunk_steps),
            chunk_steps=chunk_steps,
            n_plant=model.layout.size,
            n_controller=controller.n_states,
            compiled=compiled,
            realism=realism,
        )

    @property
    def n_inputs(self) -> int:
        """Rows of the step's input ``s``."""
        return StepInput.SIZE if self.realism is None else self.realism.inputs.size

    def roll(self, z: np.ndarray, inputs: np.ndarray, parameters: np.ndarray) -> tuple:
        """``chunk_steps`` periods from ``z``: (states after each, outputs of each), arrays.

        The arrays are handed to the roll-out in place (CasADi's function
        buffer): converting them to and from CasADi matrices element by element
        cost more than the steps themselves for wide inputs.
        """
        p = np.asarray(parameters, dtype=float)
        chunk = self.chunk_steps
        tiled = np.repeat(p[:, None], chunk, axis=1)
        rollout = self.rollout
        dense = all(rollout.sparsity_in(i).is_dense() for i in range(3)) and all(
            rollout.sparsity_out(i).is_dense() for i in range(2)
        )
        if not dense:
            z_all, y_all = rollout(z, inputs, tiled)
            return np.asarray(z_all), np.asarray(y_all)
        # Column-major matrices: each period's column is contiguous.
        arguments = [
            np.ascontiguousarray(z, dtype=float).ravel(),
            np.ascontiguousarray(np.asarray(inputs, dtype=float).T).ravel(),
            np.ascontiguousarray(tiled.T).ravel(),
        ]
        n_z, n_y = rollout.size1_out(0), rollout.size1_out(1)
        results = [np.empty(n_z * chunk), np.empty(n_y * chunk)]
        buffer, trigger = rollout.buffer()
        # CasADi's Python binding takes (index, buffer); its type stubs say otherwise.
        set_arg: Any = buffer.set_arg
        set_res: Any = buffer.set_res
        for i, argument in enumerate(arguments):
            set_arg(i, argument.data)
        for i, result in enumerate(results):
            set_res(i, result.data)
        trigger()
        return results[0].reshape(chunk, n_z).T, results[1].reshape(chunk, n_y).T


def build_loop_step(
    model: Model,
    parameters: np.ndarray,
    controller: DiscreteController,
    polytope: AuthorityPolytope,
    *,
    integrator_steps: int = 4,
    integrator: str = "rk4",
    chunk_steps: int = 1000,
    jit: bool = False,
    realism: Realism | None = None,
    basis: EngineBasis | None = None,
    force_N: np.ndarray | None = None,
) -> LoopStep:
    """Compile one control period of the closed loop for one parameter set.

    Parameters
    ----------
    model : Model
    parameters : ndarray, shape (6,)
        Model parameters, folded into the graph as constants (CasADi's virtual
        machine then does a third of the work). With ``jit`` they stay an
        input instead, so that one compiled step serves every parameter set.
    controller : DiscreteController
    polytope : AuthorityPolytope
        Reachable torques with the current engine limits.
    integrator_steps : int
        RK4 steps per control period.
    integrator : {"rk4", "cvodes"}
    chunk_steps : int
        Periods per ``rollout`` call.
    jit : bool
        Run the step as C compiled by the system's C compiler (RK4 only):
        about ten times faster per step. The library is compiled once per
        machine (a few seconds) and kept in the cache folder of
        :mod:`~casadi_debris.simulation._jit_cache`; other processes load it
        from there, and each process keeps it for a given model, controller
        and authority. Falls back to the virtual machine, with a logged
        warning, when no compiler is found or compiling fails.
    realism : Realism, optional
        Realistic sensors, estimator, delay and engines (None: the paper's loop).
    basis : EngineBasis, optional
        The allocator's thrust per unit torque, needed when an effect acts per engine.
    force_N : ndarray, shape (3,), optional
        Net force in body axes held on the plant every period (a burn's; ideal loop only).

    Returns
    -------
    LoopStep
    """
    if jit and integrator == "rk4":
        compiler = c_compiler()
        if compiler is not None:
            key = _jit_key(model, controller, polytope, integrator_steps, chunk_steps)
            key += _realism_key(realism, basis) + ("" if force_N is None else repr(list(force_N)))
            if key not in _JIT_STEPS:
                _JIT_STEPS[key] = _compiled(
                    _loop_step(
                        model,
                        None,
                        controller,
                        polytope,
                        integrator_steps,
                        "rk4",
                        realism=realism,
                        basis=basis,
                        force_N=force_N,
                    ),
                    compiler,
                    model,
                    controller,
                    chunk_steps,
                    realism,
                )
            cached = _JIT_STEPS[key]
            if cached is not None:
                return cached
    step = _loop_step(
        model,
        parameters,
        controller,
        polytope,
        integrator_steps,
        integrator,
        realism=realism,
        basis=basis,
        force_N=force_N,
    )
    return LoopStep.of(step, model, controller, chunk_steps, realism=realism)


def _realism_key(realism: Realism | None, basis: EngineBasis | None) -> str:
    """What the realistic effects add to a compiled step's key (empty for the paper's loop)."""
    if realism is None:
        return ""
    digest = hashlib.sha256(repr(realism).encode())
    if basis is not None:
        for array in (basis.axis, basis.start_Nm, basis.length_Nm, basis.slope, basis.torque_map):
            digest.update(np.ascontiguousarray(array).tobytes())
    return "|" + digest.hexdigest()


# Compiled steps of this process, by model, controller, authority and sampling.
_JIT_STEPS: dict[str, LoopStep | None] = {}


def _jit_key(
    model: Model,
    controller: DiscreteController,
    polytope: AuthorityPolytope | None,
    integrator_steps: int,
    chunk_steps: int,
) -> str:
    """Hash of what a compiled step holds: problem, plant, controller, sampling (and authority)."""
    digest = hashlib.sha256()
    problem = model.problem
    digest.update(f"{problem.sha256}|{problem.name}|{model.layout.size}".encode())
    # Problems changed in memory keep their file's hash and name: the plant (with its
    # disturbance) and the environment torques, both part of the step, are hashed too.
    digest.update(f"{problem.plant_sha256}|{problem.environment!r}|{problem.orbit!r}".encode())
    digest.update(f"{problem.constants!r}".encode())
    for array in (controller.A, controller.B, controller.C, controller.D):
        digest.update(np.ascontiguousarray(array).tobytes())
    if polytope is not None:
        digest.update(np.ascontiguousarray(polytope.normals).tobytes())
        digest.update(np.ascontiguousarray(polytope.offsets).tobytes())
    digest.update(f"{controller.period_s}|{integrator_steps}|{chunk_steps}".encode())
    return digest.hexdigest()


def _compiled(
    step: ca.Function,
    compiler: str,
    model: Model,
    controller: DiscreteController,
    chunk_steps: int,
    realism: Realism | None = None,
) -> LoopStep | None:
    """The step as C, from the machine's cache (compiled into it if needed); None if it fails."""
    _remove_stale_jit_folders()
    inputs = [ca.SX.sym(step.name_in(i), step.sparsity_in(i)) for i in range(step.n_in())]
    # The Function that CasADi's own JIT compiled before the cache: the same C
    # and flags, so the same numbers to the last bit.
    function = ca.Function("loop_step_c", inputs, step.call(inputs))
    try:
        compiled = compiled_function(function, compiler, JIT_FLAGS)
    except CompileError as exc:
        LOGGER.warning("the control step runs on CasADi's virtual machine: %s", exc)
        return None
    return LoopStep.of(compiled, model, controller, chunk_steps, compiled=True, realism=realism)


def release_compiled_steps() -> None:
    """Drop this process's compiled steps (their libraries stay in the cache)."""
    _JIT_STEPS.clear()
    gc.collect()


def _remove_stale_jit_folders() -> None:
    """Remove the JIT folders that killed processes left in the temporary folder.

    Older versions compiled there, and a killed campaign still leaves its
    (now empty) build folder.
    """
    for folder in Path(tempfile.gettempdir()).glob(f"{JIT_PREFIX}*_*"):
        owner = folder.name.removeprefix(JIT_PREFIX).split("_")[0]
        if owner.isdigit() and not process_alive(int(owner)) and folder.is_dir():
            shutil.rmtree(folder, ignore_errors=True)


def _loop_step(
    model: Model,
    parameters: np.ndarray | None,
    controller: DiscreteController,
    polytope: AuthorityPolytope | int,
    integrator_steps: int,
    integrator: str,
    *,
    realism: Realism | None = None,
    basis: EngineBasis | None = None,
    force_N: np.ndarray | None = None,
) -> ca.Function:
    """The step Function (expanded to scalar operations for RK4, shared terms computed once).

    ``polytope`` is either the authority, folded in as constants, or a facet
    capacity: the step then takes a fourth input ``facets`` (capacity x 4, see
    :func:`~casadi_debris.simulation._batched.facet_rows`), so that one compiled
    step serves every authority.
    """
    if integrator not in INTEGRATORS:
        raise SimulationError(f"unknown integrator {integrator!r}; one of {', '.join(INTEGRATORS)}")
    period = controller.period_s
    n_plant, n_ctrl = model.layout.size, controller.n_states
    n_p = len(model.parameter_names)
    if integrator == "rk4":
        plant = _rk4_step(model, parameters, period, integrator_steps)
    elif parameters is None:  # only the JIT leaves them an input, and it is RK4 only
        raise ValueError("the CVODES step folds the parameters in: it needs them")
    else:
        plant = _cvodes_step(model, parameters, period)

    law, facets = _control_law(model, controller, polytope)
    if facets and realism is not None:
        raise SimulationError("the realistic effects need the authority folded in")
    n_aux = 0 if realism is None else realism.aux_size
    z = ca.MX.sym("z", n_plant + n_ctrl + n_aux)
    s = ca.MX.sym("s", StepInput.SIZE if realism is None else realism.inputs.size)
    p = ca.MX.sym("p", n_p)
    facets_in = [ca.MX.sym("facets", f.sparsity()) for f in facets]
    xz, xcz = z[:n_plant], z[n_plant : n_plant + n_ctrl]
    force: ca.DM | ca.MX
    if realism is None:
        torque, xc_next_z, demand_z, scale_z, error_z = law(
            xz[model.layout.q_st],
            xcz,
            s[StepInput.REFERENCE_BN],
            s[StepInput.FEEDFORWARD_NM],
            *facets_in,
        )
        force = ca.DM.zeros(3) if force_N is None else ca.DM(np.asarray(force_N, dtype=float))
        rest_next, y = xc_next_z, ca.vertcat(demand_z, scale_z, error_z)
    else:
        torque, force, rest_next, y = realistic_law(
            realism, model, law, basis, n_plant, n_ctrl, period
        )(z, s)
    environment = environment_function(model)
    if environment is not None:  # held over the period, as the applied torque
        torque = torque + environment(
            s[StepInput.TIME_S], xz, p if parameters is None else ca.DM(parameters)
        )
    x_next = plant(xz, s[StepInput.TIME_S], ca.vertcat(torque, force), p)
    names = ["z", "s", "p", *(["facets"] if facets else [])]
    outputs = [ca.vertcat(x_next, rest_next), y]
    step_mx = ca.Function("loop_step", [z, s, p, *facets_in], outputs, names, ["z_next", "y"])
    if integrator != "rk4":
        return step_mx
    expanded = step_mx.expand()
    # Common subexpressions (the RK4 stages share most of the model's terms) computed
    # once: half the operations, the same ones on the same values, so the same numbers.
    inputs = [ca.SX.sym(name, expanded.sparsity_in(i)) for i, name in enumerate(names)]
    return ca.Function(
        "loop_step", inputs, expanded.call(inputs), names, ["z_next", "y"], {"cse": True}
    )


def _control_law(
    model: Model, controller: DiscreteController, polytope: AuthorityPolytope | int
) -> tuple[ca.Function, list[ca.SX]]:
    """``law(q, xc, q_ref, feedforward[, facets]) -> (applied, xc_next, demand, scale, error)``
    and its facet input (see :func:`_loop_step` for ``polytope``).

    The controller on the attitude ``q`` it is told, and the saturation.
    """
    q = ca.SX.sym("q", 4)
    xc = ca.SX.sym("xc", controller.n_states)
    q_ref = ca.SX.sym("q_ref", 4)
    feedforward = ca.SX.sym("feedforward", 3)
    error = model.attitude_error(q_ref, q)
    command_deg = -DEG_PER_RAD * error  # e = reference - measured
    a, b, c, d = (
        ca.sparsify(ca.DM(m)) for m in (controller.A, controller.B, controller.C, controller.D)
    )
    demand = NM_PER_MNM * (c @ xc + d @ command_deg) + feedforward
    xc_next = a @ xc + b @ command_deg
    if isinstance(polytope, AuthorityPolytope):
        facets = []
        scale = saturation_scale(demand, polytope)
    else:
        facets = [ca.SX.sym("facets", polytope, 4)]
        scale = _saturation(demand, facets[0][:, :3], facets[0][:, 3])
    applied = ca.if_else(scale < 1.0, scale * (1.0 - SATURATION_BACKOFF), 1.0) * demand
    law = ca.Function(
        "control_law",
        [q, xc, q_ref, feedforward, *facets],
        [applied, xc_next, demand, scale, error],
    ).expand()
    return law, facets
