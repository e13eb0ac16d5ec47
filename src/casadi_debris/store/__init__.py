"""Results on disk, written so that a kill at any moment loses nothing of the user's.

It sits at the bottom of the layers: it knows files and folders, not what is in them, and imports
nothing above the errors, records and process facts, so that whatever writes as it runs
can use it.

- Run folders: :func:`check_output_folder` / :func:`check_output_file` before the work
  (an existing result is replaced only with ``overwrite``, and only if this toolkit wrote
  it), :class:`RunFolder` to stage a run and move it into place atomically,
  :func:`default_run_folder` for ``runs/<kind>-<label>``.
- Files: :func:`write_json_atomic`, :func:`write_atomically` (whole or absent),
  :func:`write_csv`, :func:`json_ready`.
- Campaign folders: :class:`CampaignFolder`, the ``<out>.partial`` folder a campaign
  is written into case by case (:func:`write_case`, :func:`write_failure`), locked,
  checked against its :class:`CampaignIdentity`, and resumed from.
- Campaign datasets: every case of a Monte-Carlo campaign, its binned error and
  torque and its figures, as labelled arrays in one netCDF-4 file, ``campaign.nc``
  (written with h5netcdf, :func:`write_campaign_dataset`, beside ``cases.csv``; read
  with :func:`open_campaign`):

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

  The dataset is built from a campaign's outcomes by
  :func:`casadi_debris.campaigns.campaign_dataset`.

Example
-------
>>> from casadi_debris.store import open_campaign
>>> ds = open_campaign("runs/slew-mc")  # doctest: +SKIP
>>> worst = ds.max_error_deg.idxmax().item()  # doctest: +SKIP
>>> ds.error_rad.sel(case=worst, bound="max").plot.line(x="time")  # doctest: +SKIP
"""

from casadi_debris.store._campaign_dataset import (
    BAND_DIMS,
    BAND_QUANTITIES,
    BOUNDS,
    CASE_FIGURES,
    DATASET_FORMAT_VERSION,
    DATASET_NAME,
    FORMAT_ATTRIBUTE,
    NO_SEED,
    open_campaign,
    write_campaign_dataset,
)
from casadi_debris.store._campaign_folder import (
    LOCK_NAME,
    PARTIAL_SUFFIX,
    RECORD_NAME,
    CampaignFolder,
    CampaignIdentity,
    partial_folder,
    write_case,
    write_failure,
)
from casadi_debris.store._files import json_ready, write_atomically, write_csv, write_json_atomic
from casadi_debris.store._folders import (
    MARKER_NAME,
    RunFolder,
    check_output_file,
    check_output_folder,
    clean_stale_folder,
    clean_stale_temporaries,
    default_run_folder,
    foreign_entries,
    move_into_place,
    slug,
    temporary_path,
    write_marker,
)

__all__ = [
    "BAND_DIMS",
    "BAND_QUANTITIES",
    "BOUNDS",
    "CASE_FIGURES",
    "DATASET_FORMAT_VERSION",
    "DATASET_NAME",
    "FORMAT_ATTRIBUTE",
    "LOCK_NAME",
    "MARKER_NAME",
    "NO_SEED",
    "PARTIAL_SUFFIX",
    "RECORD_NAME",
    "CampaignFolder",
    "CampaignIdentity",
    "RunFolder",
    "check_output_file",
    "check_output_folder",
    "clean_stale_folder",
    "clean_stale_temporaries",
    "default_run_folder",
    "foreign_entries",
    "json_ready",
    "move_into_place",
    "open_campaign",
    "partial_folder",
    "slug",
    "temporary_path",
    "write_atomically",
    "write_campaign_dataset",
    "write_case",
    "write_csv",
    "write_failure",
    "write_json_atomic",
    "write_marker",
]
