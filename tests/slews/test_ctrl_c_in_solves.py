"""Ctrl-C during an IPOPT solve outside a map stops the job.

CasADi turns a Ctrl-C that comes while IPOPT iterates into a failed solve; the slews,
the transfer and the detumble OCPs then went on to their next start or fallback as if
the solve had not converged. Each solve is wrapped in ``keep_ctrl_c``; here a real
IPOPT solve is interrupted from its own iteration callback (the signal arrives while
IPOPT runs, as a user's would), with no clock involved.
"""

from __future__ import annotations

import signal

import casadi as ca
import pytest

from casadi_debris.errors import SlewNotConvergedError
from casadi_debris.parallel import keep_ctrl_c
from casadi_debris.slews import solve_with_ipopt

# Each Ctrl-C of these tests raises KeyboardInterrupt however the run was started.
pytestmark = pytest.mark.usefixtures("ctrl_c_raises")


def _rosenbrock(interrupt_at: int | None) -> tuple[ca.Opti, ca.MX]:
    """A small NLP (least at 1, 1) whose iteration callback sends SIGINT to this process
    at iteration ``interrupt_at`` (None: never); the NLP and its variable."""
    opti = ca.Opti()
    x = opti.variable(2)
    opti.minimize((1 - x[0]) ** 2 + 100 * (x[1] - x[0] ** 2) ** 2)
    opti.set_initial(x, [-1.2, 1.0])

    def callback(iteration: int) -> None:
        if iteration == interrupt_at:
            signal.raise_signal(signal.SIGINT)

    opti.callback(callback)
    return opti, x


def test_a_solve_interrupted_in_ipopt_raises_keyboard_interrupt() -> None:
    with pytest.raises(KeyboardInterrupt):
        solve_with_ipopt(_rosenbrock(interrupt_at=2)[0], {})


def test_an_uninterrupted_solve_is_unchanged() -> None:
    opti, x = _rosenbrock(interrupt_at=None)
    value, status = solve_with_ipopt(opti, {})
    assert status == "Solve_Succeeded"
    assert [float(v) for v in value(x)] == pytest.approx([1.0, 1.0], abs=1e-6)


def test_without_the_guard_the_interrupt_was_a_failed_solve() -> None:
    """What the guard is for: CasADi's own answer to the same Ctrl-C is an error that
    the solvers' fallbacks catch (here a RuntimeError or a non-converged solve), not a
    KeyboardInterrupt."""
    opti, _ = _rosenbrock(interrupt_at=2)
    opti.solver("ipopt", {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes"})
    try:
        opti.solve()
        caught: BaseException | None = None
    except BaseException as error:
        caught = error
    assert caught is None or not isinstance(caught, KeyboardInterrupt)


def test_the_guard_passes_other_errors_through() -> None:
    with pytest.raises(SlewNotConvergedError), keep_ctrl_c():
        raise SlewNotConvergedError("not interrupted")
