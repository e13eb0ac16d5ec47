"""The result of every slew method, and its check on the flexible model.

A :class:`SlewProfile` is a feed-forward reference: attitude, rate and
acceleration of the hub, the torque (and thrust) that produce them, and the
model input ``u(t) = [tau, 0, F]`` as a CasADi Function of time, ready to be the
reference of a closed-loop simulation. Every method ends the same way
(:func:`finish_profile`): the input is integrated on the full flexible model
(all array modes, CVODES) from rest, then held at zero for a few periods of the
lowest array mode, which gives the residual vibration:

    e(t) = attitude_error(q_final, q(t)),  t in [T, T + window]
    residual_vibration_rad = max_t || e(t) - (a + b t) ||

(a + b t is the least-squares line through e, removing a constant offset and
any slow drift so that only the oscillation is left), and the vibration energy
left in the arrays

    E_vib = E(x_T) - 1/2 mu^T M_rr^-1 mu,   mu = M_r nu = [p; h] (body axes)

(total kinetic + strain energy less the least kinetic energy the rigid
momenta mu alone must carry; M is the model's mass matrix in nu = [v, omega,
eta_dot], M_rr its rigid 6 x 6 block).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, build_model, euler_angles_321
from casadi_debris.errors import InputShapeError
from casadi_debris.geometry import Geometry
from casadi_debris.records import FLATTENED, Record
from casadi_debris.slews._limits import LimitCheck, authority_use, check_limits, unchecked
from casadi_debris.slews._maneuver import SlewTarget, eigenaxis_duration_s
from casadi_debris.slews._propellant import fuel_weights, least_fuel_thrust, propellant_kg

RESIDUAL_WINDOW_PERIODS = 10.0
# The step cap is per output interval and only a cap (it changes no result that stays
# below it): 200,000 was too few for a random heavy debris's 28,000 s bang-bang slew
# about an axis within round-off of x, whose check then ended in CVODES' "too much work".
INTEGRATOR_OPTIONS = {"abstol": 1e-12, "reltol": 1e-10, "max_num_steps": 2_000_000}
# A second integration at tolerances a hundred times tighter: its difference from the
# first estimates the first's global error (CVODES bounds only each step's local error;
# over a slew's hundreds of steps and its switches the rate errs by up to ~1e-10 rad/s).
REFERENCE_INTEGRATOR_OPTIONS = {"abstol": 1e-14, "reltol": 1e-12, "max_num_steps": 4_000_000}
N_TORQUE = 3
N_DISTURBANCE = 3
N_FORCE = 3
MAX_PROFILE_SAMPLES = 10_000_000  # 2 GB of states and inputs at the bound


@dataclass(frozen=True, eq=False)
class SlewProfile:
    """A rest-to-rest slew reference, SI units, time along the first axis.

    Attributes
    ----------
    method : str
        ``"bang-bang"``, ``"time-optimal"`` or ``"fuel-optimal"``.
    target : SlewTarget
    flexible, thrusters : bool
        Array modes in the optimisation; thrust per engine as decision variable.
    time_s : ndarray, shape (n,)
    quaternion_BN : ndarray, shape (n, 4)
        Hub attitude, scalar first.
    rate_rad_s, acceleration_rad_s2 : ndarray, shape (n, 3)
        Body rate omega_BN_B and its derivative.
    torque_Nm : ndarray, shape (n, 3)
        Control torque in B (right-continuous at switches; zero at the end).
    thrust_N : ndarray, shape (n, n_engines)
        Thrust per engine: the OCP's when ``thrusters``, else the least-fuel
        thrust of the torque (see :mod:`casadi_debris.slews._propellant`).
    input_function : casadi.Function
        ``u(t) -> [tau (3) N m, 0 (3), F (3) N]``, the model input (no disturbance); zero
        before 0 and after the end.
    duration_s, fuel_kg : float
        Slew time; propellant.
    limit_duration_s : float
        2 sqrt(Theta / alpha_max), alpha_max sized on J e alone: the time scale of
        the OCPs. Neither achievable (off a principal axis the gyroscopic torque
        exceeds the authority) nor a lower bound (three axes beat the eigenaxis).
    solve_time_s : float
        Wall time of the generation (OCP solve, or evaluating the bang-bang profile).
    solver_status : str
    residual_vibration_rad, residual_energy_J : float
        Detrended attitude oscillation after the end and vibration energy left,
        both from the full flexible model (nan if not checked).
    settings : dict
        The parameters that define the profile, units in the keys.
    limits : LimitCheck
        The torque (and thrust) against the engines over the whole grid
        (:mod:`casadi_debris.slews._limits`).
    eigenaxis_duration_s : float
        The eigenaxis bang-bang time at the profile's torque fraction, gyroscopic
        torque included (:func:`~casadi_debris.slews._maneuver.eigenaxis_duration_s`):
        flyable, so the time-optimal slew at that authority is never longer.
    """

    method: str
    target: SlewTarget
    flexible: bool
    thrusters: bool
    time_s: np.ndarray
    quaternion_BN: np.ndarray
    rate_rad_s: np.ndarray
    acceleration_rad_s2: np.ndarray
    torque_Nm: np.ndarray
    thrust_N: np.ndarray
    input_function: ca.Function
    duration_s: float
    fuel_kg: float
    limit_duration_s: float
    solve_time_s: float
    solver_status: str
    residual_vibration_rad: float = math.nan
    residual_energy_J: float = math.nan
    settings: dict[str, Any] = field(default_factory=dict)
    limits: LimitCheck = field(default_factory=unchecked)
    eigenaxis_duration_s: float = math.nan

    @property
    def euler_angles_rad(self) -> np.ndarray:
        """3-2-1 angles [Phi, Theta, Psi], shape (n, 3)."""
        return euler_angles_321(self.quaternion_BN)

    @property
    def max_torque_Nm(self) -> np.ndarray:
        """Largest |torque| per body axis, shape (3,)."""
        return np.max(np.abs(self.torque_Nm), axis=0)

    def summary(self) -> ProfileSummary:
        """Figures of the profile, SI units in the names."""
        return ProfileSummary(
            method=self.method,
            flexible=self.flexible,
            thrusters=self.thrusters,
            axis_B=tuple(np.asarray(self.target.axis_B, dtype=float)),
            angle_rad=self.target.angle_rad,
            duration_s=self.duration_s,
            eigenaxis_duration_s=self.eigenaxis_duration_s,
            duration_over_eigenaxis=self.duration_s / self.eigenaxis_duration_s,
            limits_ok=self.limits.limits_ok,
            max_torque_Nm=tuple(self.max_torque_Nm),
            fuel_kg=self.fuel_kg,
            residual_vibration_rad=self.residual_vibration_rad,
            residual_energy_J=self.residual_energy_J,
            solve_time_s=self.solve_time_s,
            solver_status=self.solver_status,
            settings={**self.settings, **_limit_keys(self.limits)},
        )


def _limit_keys(check: LimitCheck) -> dict[str, Any]:
    """The check's figures other than its verdict, as summary keys."""
    keys = check.to_json()
    keys.pop("limits_ok")
    return keys


@dataclass(frozen=True, kw_only=True)
class ProfileSummary(Record):
    """Figures of a slew profile, SI units in the names.

    Attributes
    ----------
    method : str
    flexible, thrusters : bool
    axis_B : tuple of 3 float
        Unit slew axis in the body frame.
    angle_rad, duration_s : float
        Slew angle and slew time.
    eigenaxis_duration_s : float
        The eigenaxis bang-bang time at this torque fraction, gyroscopic torque
        included: flyable, so the time-optimal slew is never longer (a bound above).
    duration_over_eigenaxis : float
    limits_ok : bool
        The profile is within the engines' authority over its whole grid (the
        check's figures are in the settings keys: ``worst_axis_ratio``, ...).
    max_torque_Nm : tuple of 3 float
        Largest |torque| per body axis.
    fuel_kg, residual_vibration_rad, residual_energy_J, solve_time_s : float
    solver_status : str
    settings : dict
        What defines the profile and what its method reports (starts, local
        optima, the flexible method, ...), written beside the other keys.
    """

    method: str
    flexible: bool
    thrusters: bool
    axis_B: tuple[float, ...]
    angle_rad: float
    duration_s: float
    eigenaxis_duration_s: float
    duration_over_eigenaxis: float
    limits_ok: bool
    max_torque_Nm: tuple[float, ...]
    fuel_kg: float
    residual_vibration_rad: float
    residual_energy_J: float
    solve_time_s: float
    solver_status: str
    settings: dict[str, Any] = field(default_factory=dict, metadata=FLATTENED)


def sample_grid(duration_s: float, sample_s: float, knots_s: np.ndarray) -> np.ndarray:
    """Output instants of a profile: every ``sample_s`` and every knot, sorted [s].

    Raises
    ------
    InputShapeError
        Naming ``sample_s`` when the profile would hold more than
        ``MAX_PROFILE_SAMPLES`` samples.
    """
    count = duration_s / sample_s
    if not count <= MAX_PROFILE_SAMPLES:
        raise InputShapeError(
            f"sample_s: {sample_s:g} s over a {duration_s:.6g} s slew is {count:.3g} samples; "
            f"a profile holds at most {MAX_PROFILE_SAMPLES:.0e}"
        )
    return np.unique(np.concatenate([np.arange(0.0, duration_s, sample_s), knots_s]))


def input_vector(torque: ca.SX, force: ca.SX | None = None) -> ca.SX:
    """Model input [tau, 0 (disturbance), F] from torque and optional force."""
    force = ca.SX.zeros(N_FORCE) if force is None else force
    return ca.vertcat(torque, ca.SX.zeros(N_DISTURBANCE), force)


def simulate_open_loop(
    model: Model,
    input_function: ca.Function,
    time_s: np.ndarray,
    x0: np.ndarray | None = None,
    parameters: np.ndarray | None = None,
    *,
    options: dict[str, float] | None = None,
) -> np.ndarray:
    """Integrate ``model.dynamics(x, u(t), p)`` with CVODES; states at ``time_s``, shape (n, nx).

    ``time_s`` should hold the input's switching times, so that the integrator
    restarts there instead of stepping across a jump. ``options``: CVODES' tolerances
    (default ``INTEGRATOR_OPTIONS``).
    """
    p = model.nominal_parameters if parameters is None else parameters
    x = ca.SX.sym("x", model.layout.size)
    t = ca.SX.sym("t")
    ode = model.dynamics(x, input_function(t), p)
    grid = np.asarray(time_s, dtype=float)
    integrator = ca.integrator(
        "slew_check",
        "cvodes",
        {"x": x, "t": t, "ode": ode},
        grid[0],
        grid,
        INTEGRATOR_OPTIONS if options is None else options,
    )
    start = model.initial_state() if x0 is None else x0
    return np.array(integrator(x0=start)["xf"]).T


def vibration_energy(model: Model, state: np.ndarray, parameters: np.ndarray) -> float:
    """Energy in the array modes, J: E(x) - 1/2 mu^T M_rr^-1 mu (see module notes)."""
    lay = model.layout
    mass = np.array(model.mass_matrix(parameters))
    nu = np.concatenate([state[lay.v], state[lay.omega], state[lay.eta_dot]])
    momenta = mass[:6] @ nu
    rigid = 0.5 * momenta @ np.linalg.solve(mass[:6, :6], momenta)
    return float(model.energy(state, parameters)) - rigid


def residual_vibration(
    problem: Problem | Model,
    target: SlewTarget,
    input_function: ca.Function,
    knots_s: np.ndarray,
    duration_s: float,
    parameters: np.ndarray | None = None,
) -> tuple[float, float]:
    """(residual_vibration_rad, residual_energy_J) of an input on the full flexible model.

    Parameters
    ----------
    problem : Problem or Model
        The problem, or its full flexible model already built (every array mode).
    knots_s : ndarray
        Switching times of the input (integration restarts there).
    """
    model = problem if isinstance(problem, Model) else build_model(problem, "all")
    p = model.nominal_parameters if parameters is None else parameters
    arrays = model.problem.arrays
    frequencies = [mode.omega_rad_s for array in arrays for mode in array.modes]
    if not frequencies:  # a rigid debris: nothing rings after the slew
        frequencies = [math.inf]
    window = RESIDUAL_WINDOW_PERIODS * 2.0 * math.pi / min(frequencies)
    after = duration_s + np.linspace(0.0, window, 401)
    grid = np.unique(np.concatenate([[0.0], knots_s[knots_s < duration_s], after]))
    states = simulate_open_loop(
        model, input_function, grid, model.initial_state(target.q_initial_BN), p
    )
    tail = states[grid >= duration_s]
    errors = np.array(
        [np.array(model.attitude_error(target.q_final_BN, s[model.layout.q])).ravel() for s in tail]
    )
    times = grid[grid >= duration_s] - duration_s
    basis = np.column_stack([np.ones_like(times), times])
    coefficients, *_ = np.linalg.lstsq(basis, errors, rcond=None)
    oscillation = errors - basis @ coefficients
    amplitude = float(np.max(np.linalg.norm(oscillation, axis=1)))
    return amplitude, vibration_energy(model, tail[0], p)


def zoh_input_function(
    knots_s: np.ndarray, torque_Nm: np.ndarray, force_N: np.ndarray | None = None
) -> ca.Function:
    """u(t) holding torque (and force) k on [t_k, t_k+1), zero outside [t_0, t_n)."""
    t = ca.SX.sym("t")
    n = torque_Nm.shape[0]
    force = np.zeros((n, N_FORCE)) if force_N is None else force_N
    values = np.vstack([np.zeros((1, 6)), np.hstack([torque_Nm, force]), np.zeros((1, 6))])
    columns = [ca.pw_const(t, ca.DM(knots_s), ca.DM(values[:, j])) for j in range(6)]
    u = input_vector(ca.vertcat(*columns[:3]), ca.vertcat(*columns[3:]))
    return ca.Function("slew_input", [t], [u], ["t"], ["u"])


@dataclass(frozen=True, eq=False, kw_only=True)
class ProfileRequest:
    """What a slew method hands :func:`finish_profile`: the sampled hub motion and the
    input that produces it, SI units, time along the first axis.

    Attributes
    ----------
    method, target, flexible, thrusters
        As :class:`SlewProfile`.
    time_s : ndarray, shape (n,)
    quaternion_BN : ndarray, shape (n, 4)
    rate_rad_s, acceleration_rad_s2 : ndarray, shape (n, 3)
    input_function : casadi.Function
        ``u(t)``, the model input (see :class:`SlewProfile`).
    knots_s : ndarray, shape (m + 1,)
        Knots of the input, s.
    interval_thrust_N : ndarray, shape (m, n_engines), optional
        Thrust held on each knot interval (a thruster-level slew), N; None: the
        least-fuel thrust of the torque.
    duration_s, limit_duration_s, solve_time_s, solver_status
        As :class:`SlewProfile`.
    figures : mapping
        The method's own figures, units in the keys: they become the profile's
        ``settings`` record after ``torque_fraction`` (the JSON written).
    """

    method: str
    target: SlewTarget
    flexible: bool
    thrusters: bool
    time_s: np.ndarray
    quaternion_BN: np.ndarray
    rate_rad_s: np.ndarray
    acceleration_rad_s2: np.ndarray
    input_function: ca.Function
    knots_s: np.ndarray
    interval_thrust_N: np.ndarray | None = None
    duration_s: float
    limit_duration_s: float
    solve_time_s: float
    solver_status: str
    figures: Mapping[str, object] = field(default_factory=dict)


@dataclass(frozen=True)
class ProfileSettings:
    """How :func:`finish_profile` checks a profile.

    Attributes
    ----------
    torque_fraction : float
        Share of the engines' authority the profile was sized to (in (0, 1]); the
        eigenaxis time is taken at it.
    check_vibration : bool
        Integrate the input on the full flexible model for the residual vibration.
    zero_net_force : bool
        The net-force rule of the limit check (the closed loop's allocator keeps the
        net force zero; a thruster-level profile is checked with its own rule).
    """

    torque_fraction: float = 1.0
    check_vibration: bool = True
    zero_net_force: bool = True


def finish_profile(
    *,
    problem: Problem | Model,
    geometry: Geometry,
    request: ProfileRequest,
    settings: ProfileSettings,
    inertia_kgm2: np.ndarray,
) -> SlewProfile:
    """Assemble a :class:`SlewProfile` from the sampled hub motion and its input.

    Every profile is checked against the engines over its whole grid
    (:func:`~casadi_debris.slews._limits.check_limits`) with the net-force rule
    ``settings.zero_net_force``, its thrust too when ``request.thrusters``; and
    given the eigenaxis bang-bang time at its torque fraction (``inertia_kgm2`` the
    rigid inertia, kg m^2, shape (3, 3)). ``problem`` is the problem, or its full flexible
    model already built, on which the residual vibration is measured (else built from the
    problem with all modes).

    Propellant comes from ``request.interval_thrust_N`` (thrust held on each knot
    interval) when given, else from the least-fuel thrust of the torque at the
    midpoint of every interval of the merged sample/knot grid (exact for
    piecewise-constant torque, second order otherwise).
    """
    r = request
    own = problem.problem if isinstance(problem, Model) else problem
    torque = np.array(r.input_function.map(len(r.time_s))(r.time_s)).T[:, :N_TORQUE]
    thrust, fuel, extra = _thrust_and_fuel(
        own, geometry, r.input_function, r.time_s, r.knots_s, r.interval_thrust_N, torque
    )
    record = {"torque_fraction": settings.torque_fraction, **r.figures, **extra}
    limits = check_limits(
        geometry,
        r.time_s,
        torque,
        zero_net_force=settings.zero_net_force,
        thrust_N=thrust if r.thrusters else None,
    )
    eigenaxis = _eigenaxis_duration(
        geometry, r.target, inertia_kgm2, settings.zero_net_force, settings.torque_fraction
    )
    vibration, energy = (math.nan, math.nan)
    if settings.check_vibration:
        vibration, energy = residual_vibration(
            problem, r.target, r.input_function, r.knots_s, r.duration_s
        )
    return SlewProfile(
        method=r.method,
        target=r.target,
        flexible=r.flexible,
        thrusters=r.thrusters,
        time_s=r.time_s,
        quaternion_BN=r.quaternion_BN,
        rate_rad_s=r.rate_rad_s,
        acceleration_rad_s2=r.acceleration_rad_s2,
        torque_Nm=torque,
        thrust_N=thrust,
        input_function=r.input_function,
        duration_s=r.duration_s,
        fuel_kg=fuel,
        limit_duration_s=r.limit_duration_s,
        solve_time_s=r.solve_time_s,
        solver_status=r.solver_status,
        residual_vibration_rad=vibration,
        residual_energy_J=energy,
        settings=record,
        limits=limits,
        eigenaxis_duration_s=eigenaxis,
    )


def _thrust_and_fuel(
    problem: Problem,
    geometry: Geometry,
    input_function: ca.Function,
    time_s: np.ndarray,
    knots_s: np.ndarray,
    interval_thrust_N: np.ndarray | None,
    torque: np.ndarray,
) -> tuple[np.ndarray, float, dict[str, Any]]:
    """Thrust at the samples (N, shape (n, n_engines)), propellant (kg) and the settings
    they add (see :func:`finish_profile`)."""
    if interval_thrust_N is not None:
        fuel = propellant_kg(problem, interval_thrust_N, np.diff(knots_s))
        thrust = np.vstack([interval_thrust_N, np.zeros((1, interval_thrust_N.shape[1]))])[
            np.clip(np.searchsorted(knots_s, time_s, side="right") - 1, 0, len(knots_s) - 1)
        ]
        return thrust, fuel, {}
    edges = np.unique(np.concatenate([time_s, knots_s]))
    middles = 0.5 * (edges[:-1] + edges[1:])
    middle_torque = np.array(input_function.map(len(middles))(middles)).T[:, :N_TORQUE]
    weights = fuel_weights(problem)
    middle_thrust, shortfall = least_fuel_thrust(geometry, middle_torque, weights)
    fuel = propellant_kg(problem, middle_thrust, np.diff(edges))
    thrust = least_fuel_thrust(geometry, torque, weights)[0]
    return (
        thrust,
        fuel,
        {"engine_torque_shortfall_Nm": float(np.max(np.linalg.norm(shortfall, axis=1)))},
    )


def _eigenaxis_duration(
    geometry: Geometry,
    target: SlewTarget,
    inertia_kgm2: np.ndarray,
    zero_net_force: bool,
    fraction: float,
) -> float:
    """The eigenaxis bang-bang time at the profile's torque ``fraction``, s."""

    def use(torque_Nm: np.ndarray) -> np.ndarray:
        return authority_use(geometry, torque_Nm, zero_net_force) / fraction

    return eigenaxis_duration_s(target.angle_rad, inertia_kgm2, target.axis_B, use)
