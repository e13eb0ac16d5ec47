"""A campaign as labelled arrays: the xarray Dataset of ``campaign.nc``.

Every case of a Monte-Carlo campaign, its binned error and torque and its
figures, in one netCDF-4 file (written with h5netcdf) beside ``cases.csv``:

- dimensions ``case`` (the case ids, ``"corner-0017"``), ``time`` (start of
  each envelope bin [s]), ``bound`` (``"min"``, ``"max"``), ``axis`` (``"x"``,
  ``"y"``, ``"z"`` of the body frame B), ``parameter`` (the uncertain model
  parameters), ``cubesat`` (numbered from 1) and ``varied`` (what the campaign
  varies);
- ``error_rad`` and ``torque_Nm`` (case, time, bound, axis): the smallest and
  largest attitude error [rad] and torque [N m] in each bin. One variable per
  quantity because their units differ; ``ds[["error_rad", "torque_Nm"]]
  .to_dataarray("quantity")`` stacks them along a ``quantity`` dimension;
- one variable per figure of the case table (``max_error_deg``, ``fuel_kg``,
  ... as in ``cases.csv``), ``max_torque_mNm`` (case, axis) and
  ``fuel_per_cubesat_kg`` (case, cubesat);
- coordinates of every case: ``kind``, ``index``, ``seed`` (-1 for a case
  that is not a random sample) and ``normalized`` (case, parameter), the
  case's place in the uncertainty box (-1 .. 1 per parameter), so that a case
  sliced out keeps what re-runs it;
- ``varied_value`` (case, varied): the value of every varied quantity in
  each case, the dimension ``varied`` labelled by their names (the paths of
  ``[[montecarlo.vary]]``, in their units, or the model parameters for a
  campaign over the uncertainty set);
- attributes: problem name and sha256, controller sha256, case kind, seed,
  bin width [s], toolkit version.

Every number is the float64 of the per-case files, bit for bit, so a resumed
campaign writes the same data as an uninterrupted one.

Example
-------
>>> from casadi_debris.report.campaign_dataset import open_campaign
>>> ds = open_campaign("runs/slew-mc")  # doctest: +SKIP
>>> worst = ds.max_error_deg.idxmax().item()  # doctest: +SKIP
>>> ds.error_rad.sel(case=worst, bound="max").plot.line(x="time")  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from casadi_debris.config import AXIS_NAMES
from casadi_debris.report.campaign_folder import CampaignRecord, write_atomically
from casadi_debris.simulation import CaseOutcome
from casadi_debris.simulation.statistics import case_quantities

if TYPE_CHECKING:
    import xarray as xr

DATASET_NAME = "campaign.nc"
ENGINE: Final = "h5netcdf"
FORMAT_ATTRIBUTE = "casadi_debris_campaign_format"
FORMAT_VERSION = 1
NO_SEED = -1
BOUNDS = ("min", "max")
BAND_DIMS = ("case", "time", "bound", "axis")

# Binned quantities (fields of Bands): SI unit and description.
BAND_QUANTITIES: dict[str, tuple[str, str]] = {
    "error_rad": ("rad", "attitude error (doubled vector part of the error quaternion)"),
    "torque_Nm": ("N m", "torque applied by the engines"),
}

# The case table's figures (columns of cases.csv after the case's identity): unit, description.
CASE_FIGURES: dict[str, tuple[str, str]] = {
    "max_error_deg": ("deg", "largest attitude error over the run, any axis"),
    "max_error_arcsec": ("arcsec", "largest attitude error over the run, any axis"),
    "settle_time_s": ("s", "time from which the error stays in the settling band (NaN: never)"),
    "fuel_kg": ("kg", "propellant burnt by all CubeSats"),
    "fuel_worst_cubesat_kg": ("kg", "propellant burnt by the CubeSat that burnt the most"),
    "dv_used_m_s": ("m s-1", "velocity change of the propellant burnt (rocket equation)"),
    "torque_saturated_s": ("s", "time during which the torque demand was scaled down"),
    "min_scale": ("1", "smallest scale applied to the torque demand (1: never saturated)"),
}

# Compressed and chunked by case: reading one case reads one chunk.
_BAND_ENCODING = {"zlib": True, "complevel": 4, "shuffle": True}


def campaign_dataset(
    record: CampaignRecord,
    bin_start_s: np.ndarray,
    outcomes: Sequence[CaseOutcome],
    parameter_names: Sequence[str],
) -> xr.Dataset:
    """Every case of a campaign as one labelled dataset.

    Parameters
    ----------
    record : CampaignRecord
        What identifies the campaign (becomes the attributes).
    bin_start_s : ndarray, shape (n_bins,)
        Start of every time bin [s].
    outcomes : sequence of CaseOutcome
        The cases, in campaign order; each summary holds the figures of
        :data:`CASE_FIGURES` (None or missing: NaN), ``max_torque_mNm`` (3)
        and ``fuel_per_cubesat_kg`` (n_cubesats).
    parameter_names : sequence of str
        Names of the uncertain parameters, in the order of ``Case.normalized``.

    Returns
    -------
    xarray.Dataset
        Dimensions (case, time, bound, axis, parameter, cubesat, varied); see the
        module's description.
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


def _stacked_bands(outcomes: Sequence[CaseOutcome], name: str) -> np.ndarray:
    """One binned quantity of every case, shape (n_cases, n_bins, 2, 3)."""
    per_case = []
    for outcome in outcomes:
        extremes = outcome.bands.quantities()[name]
        per_case.append(np.stack([getattr(extremes, bound) for bound in BOUNDS], axis=1))
    return np.stack(per_case).astype(np.float64, copy=False)


def _number(value: Any) -> float:
    return np.nan if value is None else float(value)


def _coordinates(
    outcomes: Sequence[CaseOutcome], bin_start_s: np.ndarray, parameter_names: Sequence[str]
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


def _attributes(record: CampaignRecord) -> dict[str, Any]:
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
        FORMAT_ATTRIBUTE: FORMAT_VERSION,
    }


def write_campaign_dataset(path: Path, dataset: xr.Dataset) -> Path:
    """Write ``dataset`` as netCDF-4 (h5netcdf), whole or not at all.

    Parameters
    ----------
    path : Path
        The file, usually ``<campaign>/campaign.nc``.
    dataset : xarray.Dataset
        From :func:`campaign_dataset`.

    Returns
    -------
    Path
        ``path``.
    """
    n_bins = dataset.sizes["time"]
    encoding = {
        name: {**_BAND_ENCODING, "chunksizes": (1, n_bins, len(BOUNDS), len(AXIS_NAMES))}
        for name in BAND_QUANTITIES
    }

    def write(temporary: Path) -> None:
        dataset.to_netcdf(temporary, engine=ENGINE, encoding=encoding)

    return write_atomically(path, write)


def open_campaign(folder: str | Path) -> xr.Dataset:
    """Open a finished campaign's ``campaign.nc`` (a labelled dataset, read lazily).

    Parameters
    ----------
    folder : str or Path
        The campaign folder (``--out`` of ``casadi-debris montecarlo``, or the
        ``out`` of :func:`~casadi_debris.workflows._montecarlo.montecarlo`),
        or its ``campaign.nc``.

    Returns
    -------
    xarray.Dataset
        As described in :mod:`casadi_debris.report.campaign_dataset`. Values
        are read when used; ``.load()`` reads them all, and ``with
        open_campaign(...) as ds:`` closes the file at the end of the block.

    Raises
    ------
    FileNotFoundError
        No ``campaign.nc`` there (a campaign still running, or interrupted,
        has none until it completes).
    ValueError
        The file is not a campaign of this toolkit.

    Example
    -------
    >>> from casadi_debris.report.campaign_dataset import open_campaign
    >>> ds = open_campaign("runs/slew-mc")  # doctest: +SKIP
    >>> ds.fuel_kg.to_pandas().describe()  # doctest: +SKIP
    >>> ds.error_rad.sel(case="corner-0128", bound="max", axis="z").plot()  # doctest: +SKIP
    """
    import xarray as xr

    path = Path(folder)
    if path.is_dir():
        path = path / DATASET_NAME
    if not path.is_file():
        raise FileNotFoundError(
            f"{path}: no campaign dataset; it is written when every case of a campaign is done"
        )
    dataset = xr.open_dataset(path, engine=ENGINE)
    if FORMAT_ATTRIBUTE not in dataset.attrs:
        dataset.close()
        raise ValueError(f"{path} is not a casadi_debris campaign (no {FORMAT_ATTRIBUTE})")
    return dataset
