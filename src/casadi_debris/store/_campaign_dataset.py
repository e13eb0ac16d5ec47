"""The campaign dataset on disk (``campaign.nc``): its names, the writer and the reader.

The format is described in :mod:`casadi_debris.store`.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Final

from casadi_debris.store._files import write_atomically

if TYPE_CHECKING:
    import xarray as xr

DATASET_NAME = "campaign.nc"
ENGINE: Final = "h5netcdf"
FORMAT_ATTRIBUTE = "casadi_debris_campaign_format"
DATASET_FORMAT_VERSION = 1
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


def write_campaign_dataset(path: Path, dataset: xr.Dataset) -> Path:
    """Write ``dataset`` as netCDF-4 (h5netcdf), whole or not at all.

    Parameters
    ----------
    path : Path
        The file, usually ``<campaign>/campaign.nc``.
    dataset : xarray.Dataset
        From :func:`~casadi_debris.campaigns.campaign_dataset`.

    Returns
    -------
    Path
        ``path``.
    """
    n_bins = dataset.sizes["time"]
    encoding = {
        name: {**_BAND_ENCODING, "chunksizes": (1, n_bins, len(BOUNDS), dataset.sizes["axis"])}
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
        As described in :mod:`casadi_debris.store`. Values
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
    >>> from casadi_debris.store import open_campaign
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
