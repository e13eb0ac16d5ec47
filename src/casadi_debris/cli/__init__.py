"""The ``casadi-debris`` command.

Every subcommand takes an optional problem file (default: the shipped paper
setup) and ``--json`` for scripts. Bad input ends with one line on stderr
naming the problem and exit status 2; never a traceback.

One module per group of subcommands; each registers itself on :data:`main`.
"""

from __future__ import annotations

# Importing a command module registers its commands on `main`.
from casadi_debris.cli import (  # noqa: F401
    allocate,  # allocate
    alternatives,  # alternatives
    burn,  # burn
    compare,  # compare
    deorbit,  # deorbit
    describe,  # model, budget, schema, problems
    design,  # design
    detumble,  # detumble
    export,  # export
    failures,  # failures
    mission,  # mission
    placement,  # placement
    reproduce,  # reproduce
    robust,  # synthesize, margins
    simulate,  # simulate, montecarlo
    slew,  # slew
    transfer,  # transfer
    worstcase,  # worstcase
)
from casadi_debris.cli.common import main

__all__ = ["main"]
