"""A campaign's cases as one labelled dataset (the ``campaign.nc`` of
:mod:`casadi_debris.store`): its format (dimensions, variables, attributes) is described
there, with the writer and :func:`~casadi_debris.store.open_campaign`."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.campaigns._monte_carlo import CaseResult
from casadi_debris.campaigns._statistics import case_quantities
from casadi_debris.config import AXIS_NAMES
from casadi_debris.store import (
    BAND_DIMS,
    BAND_QUANTITIES,
    BOUNDS,
    CASE_FIGURES,
    DATASET_FORMAT_VERSION,
    FORMAT_ATTRIBUTE,
    NO_SEED,
    CampaignIdentity,
)

if TYPE_CHECKING:
    import xarray as xr


def campaign_dataset(
    record: CampaignIdentity,
    bin_start_s: np.ndarray,
    outcomes: Sequence[CaseResult],
    parameter_names: Sequence[str],
) -> xr.Dataset:
    """Every case of a campaign as one labelled dataset.

    Parameters
    ----------
    record : CampaignIdentity
        What identifies the campaign (becomes the attributes).
    bin_start_s : ndarray, shape (n_bins,)
        Start of every time bin [s].
    outcomes : sequence of CaseResult
        The cases, in campaign order; each summary holds the figures of
        :data:`CASE_FIGURES` (None or missing: NaN), ``max_torque_mNm`` (3)
        and ``fuel_per_cubesat_kg`` (n_cubesats).
    parameter_names : sequence of str
        Names of the uncertain parameters, in the order of ``Case.normalized``.

    Returns
    -------
    xarray.Dataset
        Dimensions (case, time, bound, axis, parameter, cubesat, varied); see the
        description in :mod:`casadi_debris.store`.
    """
    # Imported here: a single run reaches this module through report.simulation and
    # needs neither xarray nor pandas (about a second of imports).
    import xarray as xr

    if not outcomes:
        raise ValueError("a campaign dataset needs at least one case")
    data_vars: dict[str, Any] = {
        name: (BAND_DIMS, _stacked_bands(outcomes, name), {"units": units, "long_name": text})
        for name, (units, text) in BAND_QUANTITIES.items()
    }
    for name, (units, text) in CASE_FIGURES.items():
        values = np.array(
            [_number(getattr(o.summary.run, name)) for o in outcomes], dtype=np.float64
        )
        data_vars[name] = ("case", values, {"units": units, "long_name": text})
    data_vars["max_torque_mNm"] = (
        ("case", "axis"),
        np.array([o.summary.run.max_torque_mNm for o in outcomes], dtype=np.float64),
        {"units": "mN m", "long_name": "largest torque magnitude over the run, per axis"},
    )
    fuel = np.array([o.summary.run.fuel_per_cubesat_kg for o in outcomes], dtype=np.float64)
    data_vars["fuel_per_cubesat_kg"] = (
        ("case", "cubesat"),
        fuel,
        {"units": "kg", "long_name": "propellant burnt by each CubeSat"},
    )
    coords = _coordinates(outcomes, np.asarray(bin_start_s, dtype=np.float64), parameter_names)
    coords["cubesat"] = ("cubesat", np.arange(1, fuel.shape[1] + 1), {"long_name": "CubeSat"})
    quantities = case_quantities(outcomes, parameter_names)
    coords["varied"] = ("varied", list(quantities), {"long_name": "varied quantity"})
    data_vars["varied_value"] = (
        ("case", "varied"),
        np.stack(list(quantities.values()), axis=1).astype(np.float64),
        {
            "units": "as in the quantity's name",
            "long_name": "value of each varied quantity in the case",
        },
    )
    return xr.Dataset(data_vars, coords, _attributes(record))


def _stacked_bands(outcomes: Sequence[CaseResult], name: str) -> np.ndarray:
    """One binned quantity of every case, shape (n_cases, n_bins, 2, 3)."""
    per_case = []
    for outcome in outcomes:
        extremes = outcome.bands.quantities()[name]
        per_case.append(np.stack([getattr(extremes, bound) for bound in BOUNDS], axis=1))
    return np.stack(per_case).astype(np.float64, copy=False)


def _number(value: Any) -> float:
    return np.nan if value is None else float(value)


def _coordinates(
    outcomes: Sequence[CaseResult], bin_start_s: np.ndarray, parameter_names: Sequence[str]
) -> dict[str, Any]:
    cases = [o.case for o in outcomes]
    return {
        "case": ("case", [c.case_id for c in cases], {"long_name": "case id"}),
        "time": ("time", bin_start_s, {"units": "s", "long_name": "start of the time bin"}),
        "bound": ("bound", list(BOUNDS), {"long_name": "smallest or largest value in the bin"}),
        "axis": ("axis", list(AXIS_NAMES), {"long_name": "body axis (frame B)"}),
        "parameter": ("parameter", list(parameter_names), {"long_name": "uncertain parameter"}),
        "kind": ("case", [c.kind for c in cases], {"long_name": "nominal, corner or sample"}),
        "index": ("case", np.array([c.index for c in cases], dtype=np.int64)),
        "seed": (
            "case",
            np.array([NO_SEED if c.seed is None else c.seed for c in cases], dtype=np.int64),
            {"long_name": "seed of a random sample", "comment": f"{NO_SEED}: not a sample"},
        ),
        "normalized": (
            ("case", "parameter"),
            np.array([c.normalized for c in cases], dtype=np.float64),
            {"units": "1", "long_name": "place in the uncertainty box, -1 .. 1"},
        ),
    }


def _attributes(record: CampaignIdentity) -> dict[str, Any]:
    return {
        "title": f"Monte-Carlo campaign of {record.problem_name}",
        "problem": record.problem_name,
        "problem_sha256": record.problem_sha256,
        "controller_sha256": record.controller_sha256,
        "case_kind": record.case_kind,
        "seed": NO_SEED if record.seed is None else record.seed,
        "bin_width_s": record.envelope_bin_s,
        "toolkit": "casadi_debris",
        "toolkit_version": record.toolkit_version,
        FORMAT_ATTRIBUTE: DATASET_FORMAT_VERSION,
    }
