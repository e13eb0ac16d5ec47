"""Campaigns: many closed-loop runs over the uncertainty set, their statistics and the
worst case.

- Cases: :func:`nominal_case`, :func:`corner_cases` / :func:`corner_case` (the corners
  of the uncertainty box), :func:`sample_cases` / :func:`sample_case` (seeded samples)
  and :func:`varied_cases` / :func:`varied_case` (the quantities of
  ``[[montecarlo.vary]]``); every :class:`Case` carries what re-runs it alone.
- :func:`run_campaign`: the cases on local processes or Dask, each a
  :class:`CaseResult` (its :class:`CaseSummary` and :class:`Bands`), with an
  :class:`Envelope` over them; a case that raises is a :class:`CaseFailure` and the
  campaign goes on.
- :func:`campaign_statistics`: pass rate, moments, percentiles and what drives the worst
  cases (:class:`CampaignStatistics`).
- :func:`campaign_dataset`: every case as labelled arrays (an xarray Dataset, the
  ``campaign.nc`` that :mod:`casadi_debris.store` writes and opens).
- :func:`worst_case_search`: a search of the uncertainty box for the loop's largest
  pointing error (:class:`WorstCaseSearch`).

This layer sits on the closed loop (:mod:`casadi_debris.simulation`) and uses only its
public names; nothing below imports it. Nothing here writes files: the campaign folder
and its dataset on disk are :mod:`casadi_debris.store`'s.
"""

from casadi_debris.campaigns._cases import (
    Case,
    CaseBatch,
    CaseIdentity,
    batches,
    corner_case,
    corner_cases,
    nominal_case,
    sample_case,
    sample_cases,
)
from casadi_debris.campaigns._dataset import campaign_dataset
from casadi_debris.campaigns._monte_carlo import (
    DEFAULT_BATCH_CASES,
    Bands,
    CampaignSetup,
    CaseFailure,
    CaseFailureSummary,
    CaseResult,
    CaseRunner,
    CaseSummary,
    Envelope,
    Extremes,
    bin_bands,
    fly_case,
    run_campaign,
    run_case,
)
from casadi_debris.campaigns._sampling import (
    varied_case,
    varied_cases,
    varied_count,
)
from casadi_debris.campaigns._statistics import (
    FIGURES,
    CampaignStatistics,
    Driver,
    FigureStatistics,
    Sensitivity,
    campaign_statistics,
    case_figures,
    case_quantities,
    first_order_index,
    requirement_of,
    requirement_shortfalls,
    statistics_of,
)
from casadi_debris.campaigns._worst_case import (
    Evaluation,
    WorstCaseSearch,
    WorstCaseSettings,
    linear_screen,
    worst_case_search,
)

__all__ = [
    "DEFAULT_BATCH_CASES",
    "FIGURES",
    "Bands",
    "CampaignSetup",
    "CampaignStatistics",
    "Case",
    "CaseBatch",
    "CaseFailure",
    "CaseFailureSummary",
    "CaseIdentity",
    "CaseResult",
    "CaseRunner",
    "CaseSummary",
    "Driver",
    "Envelope",
    "Evaluation",
    "Extremes",
    "FigureStatistics",
    "Sensitivity",
    "WorstCaseSearch",
    "WorstCaseSettings",
    "batches",
    "bin_bands",
    "campaign_dataset",
    "campaign_statistics",
    "case_figures",
    "case_quantities",
    "corner_case",
    "corner_cases",
    "first_order_index",
    "fly_case",
    "linear_screen",
    "nominal_case",
    "requirement_of",
    "requirement_shortfalls",
    "run_campaign",
    "run_case",
    "sample_case",
    "sample_cases",
    "statistics_of",
    "varied_case",
    "varied_cases",
    "varied_count",
    "worst_case_search",
]
