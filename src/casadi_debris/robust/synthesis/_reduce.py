"""Controller order reduction by balanced truncation (stable/unstable split).

The H-infinity controllers come out badly scaled (entries of A up to ~1e7);
they are first brought to a minimal, diagonally balanced realisation, then
reduced with ``control.balred`` (SLICOT AB09MD/AB09ND: unstable poles are
kept, the stable part is balanced and truncated; Hsu and Hou 1991).
"""

from __future__ import annotations

import logging
import warnings

import control

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.synthesis._hinf import well_conditioned

LOGGER = logging.getLogger(__name__)


def reduce_controller(controller: control.StateSpace, order: int) -> control.StateSpace:
    """Balanced truncation of a controller to at most ``order`` states.

    Parameters
    ----------
    controller : control.StateSpace
    order : int
        Wanted number of states; a controller already that small is only
        made minimal. Unstable poles are never truncated, so a controller with
        more unstable poles than ``order`` keeps them all.

    Returns
    -------
    control.StateSpace

    Raises
    ------
    SynthesisError
        If SLICOT cannot reduce it (e.g. more unstable poles than ``order``).
    """
    conditioned = well_conditioned(controller)
    if conditioned.nstates <= order:
        return conditioned
    try:
        # SLICOT warns when the stable part's minimal order is below ``order`` (it then
        # keeps that order): worth a log line, not a warning on the user's terminal.
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            reduced = control.balred(conditioned, order, method="truncate")
    except (ValueError, ArithmeticError) as exc:
        raise SynthesisError(f"balanced truncation to {order} states failed: {exc}") from exc
    for warning in caught:
        LOGGER.info("balanced truncation: %s", " ".join(str(warning.message).split()))
    return reduced
