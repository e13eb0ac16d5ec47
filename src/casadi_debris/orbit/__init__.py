"""Orbits of the debris: low-thrust transfers, the atmosphere and orbital lifetime.

Algorithms only (no file I/O, no simulation loop): each is usable on its own from
Python, like ``slew`` and ``allocation``. The Earth's constants come from the
problem (``problem.constants``) or from :mod:`casadi_debris.environment`.
"""

from casadi_debris.orbit.deorbit import DeorbitSettings as DeorbitSettings
from casadi_debris.orbit.plan import DeorbitPlan as DeorbitPlan
from casadi_debris.orbit.plan import plan_deorbit as plan_deorbit
from casadi_debris.orbit.transfer import TransferPlan as TransferPlan
from casadi_debris.orbit.transfer import TransferSummary as TransferSummary
from casadi_debris.orbit.transfer import plan_transfer as plan_transfer
