"""Readers of runs: ``[simulation]`` (with its slew and failures) and ``[montecarlo]``.

Besides each key's range, a run is bounded as a whole: its count of control
periods and of integration steps (so that no file can ask for a run of days
or of more memory than a workstation has), and its Runge-Kutta step against
the fastest dynamics the file gives (so that the integration cannot diverge to
NaN).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace

from casadi_debris.config import limits
from casadi_debris.config._schema import (
    REFERENCE_KINDS,
    FailureEvent,
    MonteCarlo,
    Problem,
    Simulation,
)
from casadi_debris.config._segments import (
    SLEW_METHODS,
    SlewRequest,
    Target,
    read_axis,
    read_segments,
    read_slew_request,
)
from casadi_debris.config._table import Table
from casadi_debris.config._varied import read_vary
from casadi_debris.errors import ProblemFileError


def read_slew(t: Table, run_duration_s: float) -> SlewRequest:
    """``[simulation.slew]``: a turn about a body axis, starting (default at 0) within the
    run of ``run_duration_s`` [s]."""
    axis = read_axis(t, "axis")
    angle_deg = t.number("angle_deg", limits.SLEW_ANGLE_DEG)

    def timing() -> tuple[float | None, float | None]:
        start_s = (
            t.number("start_s", limits.nonnegative(run_duration_s)) if t.has("start_s") else 0.0
        )
        duration_s = t.number("duration_s", limits.SLEW_DURATION_S) if t.has("duration_s") else None
        return start_s, duration_s

    target = Target("rotation", axis=axis, angle_deg=angle_deg)
    slew = read_slew_request(t, SLEW_METHODS, lambda: target, timing)
    t.done()
    return slew


def read_failure(t: Table, engines_per_cubesat: Sequence[int], n_stages: int) -> FailureEvent:
    """One ``[[simulation.failures]]`` entry; CubeSats, stages and engines numbered from 1.

    ``engine`` counts the CubeSat's own engines (1 to ``engines_per_cubesat[cubesat - 1]``).
    """
    cubesat = t.integer("cubesat", limits.Range(1, len(engines_per_cubesat)))
    stage = t.integer("stage", limits.Range(1, n_stages)) if t.has("stage") else None
    engine = None
    if t.has("engine"):
        # Recorded against the largest count any CubeSat may have (the JSON Schema's
        # bound); this CubeSat's own count is checked next.
        engine = t.integer("engine", limits.Range(1, limits.MAX_ENGINES_PER_CUBESAT))
        count = engines_per_cubesat[cubesat - 1]
        if engine > count:
            raise t.error(
                t.key("engine"),
                f"CubeSat {cubesat} has {count} engine(s), numbered 1..{count}; got {engine}",
            )
        if stage is not None:
            raise t.error(
                t.key("engine"), "give stage or engine, not both (a stage fails on every engine)"
            )
    event = FailureEvent(
        time_s=t.number("time_s", limits.Range(0.0, limits.DURATION_S.high)),
        cubesat=cubesat - 1,
        stage=None if stage is None else stage - 1,
        engine=None if engine is None else engine - 1,
    )
    t.done()
    return event


def run_length_violation(
    duration_s: float, control_rate_hz: float, integrator_steps: int
) -> tuple[str, str] | None:
    """What makes a run too short or too long, as (key, message), or None.

    A run holds 1 to :data:`~casadi_debris.config.limits.MAX_CONTROL_PERIODS`
    control periods and at most
    :data:`~casadi_debris.config.limits.MAX_INTEGRATION_STEPS` integration steps.
    """
    periods = duration_s * control_rate_hz
    if not 1.0 <= periods <= limits.MAX_CONTROL_PERIODS:
        return "duration_s", (
            f"{duration_s:g} s at {control_rate_hz:g} Hz is {periods:.4g} control periods; "
            f"a run holds 1 to {limits.MAX_CONTROL_PERIODS}"
        )
    if periods * integrator_steps > limits.MAX_INTEGRATION_STEPS:
        return "integrator_steps", (
            f"{integrator_steps} steps x {periods:.4g} control periods exceeds the "
            f"{limits.MAX_INTEGRATION_STEPS:.0e} integration steps a run may take"
        )
    return None


def with_duration(problem: Problem, duration_s: float, field: str = "duration_s") -> Problem:
    """``problem`` with its closed-loop run lasting ``duration_s`` [s], checked as a file's.

    Raises
    ------
    ProblemFileError
        Naming ``field`` when the run would be outside the bounds of
        :func:`run_length_violation` or ``duration_s`` outside
        :data:`~casadi_debris.config.limits.DURATION_S`.
    """
    simulation = problem.simulation
    violation = (
        limits.DURATION_S.violation(duration_s) if math.isfinite(duration_s) else "must be finite"
    )
    if violation is None:
        found = run_length_violation(
            duration_s, simulation.control_rate_hz, simulation.integrator_steps
        )
        violation = None if found is None else found[1]
    if violation is not None:
        raise ProblemFileError(field, violation)
    return replace(problem, simulation=replace(simulation, duration_s=float(duration_s)))


def read_simulation(t: Table, engines_per_cubesat: Sequence[int], n_stages: int) -> Simulation:
    """``[simulation]``: length, sampling, reference and failures of a closed-loop run."""
    reference = t.text("reference", REFERENCE_KINDS)
    has_slew = t.has("slew")
    if reference == "slew" and not has_slew:
        raise t.error(t.key("slew"), 'missing: reference = "slew" needs a [simulation.slew] table')
    if reference != "slew" and has_slew:
        raise t.error(t.key("slew"), 'only allowed with reference = "slew"')
    if reference == "sequence" and not t.has("segments"):
        raise t.error(
            t.key("segments"), 'missing: reference = "sequence" needs [[simulation.segments]]'
        )
    if reference != "sequence" and t.has("segments"):
        raise t.error(t.key("segments"), 'only allowed with reference = "sequence"')
    duration_s = t.number("duration_s", limits.DURATION_S)
    rate_hz = t.number("control_rate_hz", limits.CONTROL_RATE_HZ)
    steps = t.integer("integrator_steps", limits.INTEGRATOR_STEPS)
    violation = run_length_violation(duration_s, rate_hz, steps)
    if violation is not None:
        raise t.error(t.key(violation[0]), violation[1])
    failures = (
        tuple(
            read_failure(f, engines_per_cubesat, n_stages)
            for f in t.tables("failures", limits.MAX_FAILURES)
        )
        if t.has("failures")
        else ()
    )
    simulation = Simulation(
        duration_s=duration_s,
        control_rate_hz=rate_hz,
        integrator_steps=steps,
        reference=reference,
        slew=read_slew(t.table("slew"), duration_s) if has_slew else None,
        failures=tuple(sorted(failures, key=lambda event: event.time_s)),
        segments=read_segments(t, SLEW_METHODS, duration_s) if t.has("segments") else (),
    )
    t.done()
    return simulation


def check_integration_step(t: Table, simulation: Simulation, rates: Mapping[str, float]) -> None:
    """Refuse Runge-Kutta steps too long for the fastest dynamics of the problem.

    One step lasts ``h = 1 / (control_rate_hz x integrator_steps)``; classical
    RK4 diverges when ``h x omega`` exceeds about 2.8, so ``h x omega <=``
    :data:`~casadi_debris.config.limits.RK4_STABLE_STEP` for every rate given.

    Parameters
    ----------
    t : Table
        The ``[simulation]`` table (the error names its ``integrator_steps``).
    simulation : Simulation
    rates : mapping of str to float
        Dotted key of each fast dynamic -> its rate [rad/s] (star tracker
        bandwidth, array mode frequencies).

    Raises
    ------
    ProblemFileError
        Naming ``simulation.integrator_steps``, with the count that would do.
    """
    key, omega = max(rates.items(), key=lambda item: item[1])
    step_s = 1.0 / (simulation.control_rate_hz * simulation.integrator_steps)
    if step_s * omega <= limits.RK4_STABLE_STEP:
        return
    needed = math.ceil(omega / (simulation.control_rate_hz * limits.RK4_STABLE_STEP))
    remedy = (
        f"give integrator_steps >= {needed}"
        if needed <= limits.INTEGRATOR_STEPS.high
        else "raise control_rate_hz"
    )
    raise t.error(
        t.key("integrator_steps"),
        f"Runge-Kutta steps of {step_s:.3g} s diverge on {key} = {omega:g} rad/s "
        f"(step x rate must be at most {limits.RK4_STABLE_STEP:g}); {remedy}",
    )


def read_montecarlo(t: Table) -> MonteCarlo:
    """``[montecarlo]``: the corner set, the random cases and what a campaign varies."""
    montecarlo = MonteCarlo(
        corner_array_angles=t.integer("corner_array_angles", limits.CORNER_ARRAY_ANGLES),
        samples=t.integer("samples", limits.MONTECARLO_SAMPLES),
        seed=t.integer("seed", limits.SEED),
        vary=read_vary(t) if t.has("vary") else (),
    )
    t.done()
    return montecarlo
