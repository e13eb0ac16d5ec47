"""The orbit transfer with the swarm's staged engines (``casadi-debris transfer``).

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.transfer import transfer_into
>>> result = transfer_into(load_problem(), "runs/transfer-paper")  # doctest: +SKIP
>>> round(result.transfer_dv_m_s), result.swarm_suffices  # doctest: +SKIP
(144, False)
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from casadi_debris.config import Problem
from casadi_debris.orbit import TransferResult, plan_transfer
from casadi_debris.orbit.transfer_ocp import Objective
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.report.transfer import write_transfer


def transfer_into(
    problem: Problem,
    out: str | Path,
    *,
    objective: Objective = "time",
    overwrite: bool = False,
) -> TransferResult:
    """Plan the problem's ``[transfer]`` and write it into the run folder ``out``.

    Parameters
    ----------
    problem : Problem
    out : str or Path
        Run folder: ``summary.json``, ``guidance.csv``, ``ocp.csv``, ``transfer.png``.
    objective : {"time", "propellant"}
        See :func:`~casadi_debris.orbit.plan_transfer`.
    overwrite : bool
        Replace a run folder this toolkit wrote.

    Returns
    -------
    TransferResult
        With ``out_dir`` set.
    """
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    plan = plan_transfer(problem, objective=objective)
    result = dataclasses.replace(plan.result, out_dir=str(out.absolute()))
    with RunFolder.claim(out, overwrite=overwrite, command="transfer") as staging:
        target = (problem.transfer.to_altitude_km, problem.transfer.to_inclination_deg)
        write_transfer(staging, plan, result, problem.constants.earth_radius_km, target)
    return result
