"""Reports: results in display units, paper-vs-toolkit comparisons, tables, the files of
each job's folder.

This is an edge package: it turns SI results into fields whose names carry
their display unit (``torque_max_mNm``), holds the paper's published figures
and tolerances (:mod:`casadi_debris.report._paper`) and lays out what each job's
folder holds; the writing itself (atomic files, run and campaign folders) is
:mod:`casadi_debris.store`'s.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from casadi_debris.report._alternatives import (
        AlternativesSummary,
        alternatives_figures,
        write_alternatives,
    )
    from casadi_debris.report._burn import (
        BurnSummary,
        burn_figures,
        write_burn,
    )
    from casadi_debris.report._common import format_figure, format_table, verdict_text
    from casadi_debris.report._compare import (
        COLUMNS,
        CompareSummary,
        VariantRow,
        cell,
        comparison_figures,
        write_comparison,
    )
    from casadi_debris.report._deorbit import (
        DeorbitSummary,
        deorbit_figures,
        write_deorbit,
    )
    from casadi_debris.report._describe import (
        BudgetSummary,
        ModelSummary,
        Thruster,
        budget_summary,
        budget_text,
        describe_model,
        model_text,
    )
    from casadi_debris.report._design import (
        DesignFigures,
        DesignSummary,
        RequirementRow,
        VerificationSummary,
        binding_lines,
        body_lines,
        classical_markdown,
        design_markdown,
        requirement_rows,
        verification_rows,
    )
    from casadi_debris.report._detumble import (
        DetumbleSummary,
        detumble_figures,
        write_detumble,
    )
    from casadi_debris.report._failures import (
        HEATMAP,
        failure_figures,
        pointing_window,
        write_failures,
    )
    from casadi_debris.report._mission import (
        mission_figures,
        mission_text,
        write_mission,
    )
    from casadi_debris.report._paper import (
        load_paper_reference,
        paper_figure,
        paper_figures,
        table_figures,
    )
    from casadi_debris.report._placement import (
        PLACEMENT_FILE,
        placement_figures,
        write_placement,
    )
    from casadi_debris.report._reproduce import (
        ControllerSummary,
        ReproductionRow,
        ReproductionSummary,
        report_markdown,
        reproduction_rows,
    )
    from casadi_debris.report._robust import (
        DiskMargin,
        Margins,
        MarginsSummary,
        margin_figures,
        margins_summary,
        write_margins,
    )
    from casadi_debris.report._simulation import (
        CampaignRun,
        CampaignSummary,
        FailedCase,
        WorstValueSummary,
        campaign_envelope,
        campaign_figures,
        campaign_summary,
        engine_groups,
        figure_title,
        normalized_column,
        run_figures,
        series_columns,
        torque_limits_mNm,
        write_campaign,
        write_run,
    )
    from casadi_debris.report._slew import (
        write_profile_csv,
        write_reference_csv,
    )
    from casadi_debris.report._transfer import (
        transfer_figures,
        write_transfer,
    )
    from casadi_debris.report._worstcase import (
        ParameterFile,
        WorstCaseIdentity,
        WorstCaseSummary,
        corner_campaign_envelope,
        parameter_file,
        worst_case_figure,
        worst_case_summary,
        write_worst_case_files,
        write_worst_cases,
    )

__all__ = [
    "COLUMNS",
    "HEATMAP",
    "PLACEMENT_FILE",
    "AlternativesSummary",
    "BudgetSummary",
    "BurnSummary",
    "CampaignRun",
    "CampaignSummary",
    "CompareSummary",
    "ControllerSummary",
    "DeorbitSummary",
    "DesignFigures",
    "DesignSummary",
    "DetumbleSummary",
    "DiskMargin",
    "FailedCase",
    "Margins",
    "MarginsSummary",
    "ModelSummary",
    "ParameterFile",
    "ReproductionRow",
    "ReproductionSummary",
    "RequirementRow",
    "Thruster",
    "VariantRow",
    "VerificationSummary",
    "WorstCaseIdentity",
    "WorstCaseSummary",
    "WorstValueSummary",
    "alternatives_figures",
    "binding_lines",
    "body_lines",
    "budget_summary",
    "budget_text",
    "burn_figures",
    "campaign_envelope",
    "campaign_figures",
    "campaign_summary",
    "cell",
    "classical_markdown",
    "comparison_figures",
    "corner_campaign_envelope",
    "deorbit_figures",
    "describe_model",
    "design_markdown",
    "detumble_figures",
    "engine_groups",
    "failure_figures",
    "figure_title",
    "format_figure",
    "format_table",
    "load_paper_reference",
    "margin_figures",
    "margins_summary",
    "mission_figures",
    "mission_text",
    "model_text",
    "normalized_column",
    "paper_figure",
    "paper_figures",
    "parameter_file",
    "placement_figures",
    "pointing_window",
    "report_markdown",
    "reproduction_rows",
    "requirement_rows",
    "run_figures",
    "series_columns",
    "table_figures",
    "torque_limits_mNm",
    "transfer_figures",
    "verdict_text",
    "verification_rows",
    "worst_case_figure",
    "worst_case_summary",
    "write_alternatives",
    "write_burn",
    "write_campaign",
    "write_comparison",
    "write_deorbit",
    "write_detumble",
    "write_failures",
    "write_margins",
    "write_mission",
    "write_placement",
    "write_profile_csv",
    "write_reference_csv",
    "write_run",
    "write_transfer",
    "write_worst_case_files",
    "write_worst_cases",
]

# Imported on first use: the commands import this package for a few helpers, and the
# modules behind the rest bring in matplotlib, the studies and the simulation.
_LAZY = {
    "AlternativesSummary": "casadi_debris.report._alternatives",
    "alternatives_figures": "casadi_debris.report._alternatives",
    "write_alternatives": "casadi_debris.report._alternatives",
    "BurnSummary": "casadi_debris.report._burn",
    "burn_figures": "casadi_debris.report._burn",
    "write_burn": "casadi_debris.report._burn",
    "format_figure": "casadi_debris.report._common",
    "format_table": "casadi_debris.report._common",
    "verdict_text": "casadi_debris.report._common",
    "COLUMNS": "casadi_debris.report._compare",
    "CompareSummary": "casadi_debris.report._compare",
    "VariantRow": "casadi_debris.report._compare",
    "cell": "casadi_debris.report._compare",
    "comparison_figures": "casadi_debris.report._compare",
    "write_comparison": "casadi_debris.report._compare",
    "DeorbitSummary": "casadi_debris.report._deorbit",
    "deorbit_figures": "casadi_debris.report._deorbit",
    "write_deorbit": "casadi_debris.report._deorbit",
    "BudgetSummary": "casadi_debris.report._describe",
    "ModelSummary": "casadi_debris.report._describe",
    "Thruster": "casadi_debris.report._describe",
    "budget_summary": "casadi_debris.report._describe",
    "budget_text": "casadi_debris.report._describe",
    "describe_model": "casadi_debris.report._describe",
    "model_text": "casadi_debris.report._describe",
    "VerificationSummary": "casadi_debris.report._design",
    "DesignFigures": "casadi_debris.report._design",
    "DesignSummary": "casadi_debris.report._design",
    "RequirementRow": "casadi_debris.report._design",
    "binding_lines": "casadi_debris.report._design",
    "body_lines": "casadi_debris.report._design",
    "classical_markdown": "casadi_debris.report._design",
    "design_markdown": "casadi_debris.report._design",
    "requirement_rows": "casadi_debris.report._design",
    "verification_rows": "casadi_debris.report._design",
    "DetumbleSummary": "casadi_debris.report._detumble",
    "detumble_figures": "casadi_debris.report._detumble",
    "write_detumble": "casadi_debris.report._detumble",
    "HEATMAP": "casadi_debris.report._failures",
    "failure_figures": "casadi_debris.report._failures",
    "pointing_window": "casadi_debris.report._failures",
    "write_failures": "casadi_debris.report._failures",
    "mission_figures": "casadi_debris.report._mission",
    "mission_text": "casadi_debris.report._mission",
    "write_mission": "casadi_debris.report._mission",
    "load_paper_reference": "casadi_debris.report._paper",
    "paper_figure": "casadi_debris.report._paper",
    "paper_figures": "casadi_debris.report._paper",
    "table_figures": "casadi_debris.report._paper",
    "PLACEMENT_FILE": "casadi_debris.report._placement",
    "placement_figures": "casadi_debris.report._placement",
    "write_placement": "casadi_debris.report._placement",
    "ControllerSummary": "casadi_debris.report._reproduce",
    "ReproductionRow": "casadi_debris.report._reproduce",
    "ReproductionSummary": "casadi_debris.report._reproduce",
    "report_markdown": "casadi_debris.report._reproduce",
    "reproduction_rows": "casadi_debris.report._reproduce",
    "DiskMargin": "casadi_debris.report._robust",
    "Margins": "casadi_debris.report._robust",
    "MarginsSummary": "casadi_debris.report._robust",
    "margin_figures": "casadi_debris.report._robust",
    "margins_summary": "casadi_debris.report._robust",
    "write_margins": "casadi_debris.report._robust",
    "CampaignRun": "casadi_debris.report._simulation",
    "CampaignSummary": "casadi_debris.report._simulation",
    "FailedCase": "casadi_debris.report._simulation",
    "WorstValueSummary": "casadi_debris.report._simulation",
    "campaign_envelope": "casadi_debris.report._simulation",
    "campaign_figures": "casadi_debris.report._simulation",
    "campaign_summary": "casadi_debris.report._simulation",
    "engine_groups": "casadi_debris.report._simulation",
    "figure_title": "casadi_debris.report._simulation",
    "normalized_column": "casadi_debris.report._simulation",
    "run_figures": "casadi_debris.report._simulation",
    "series_columns": "casadi_debris.report._simulation",
    "torque_limits_mNm": "casadi_debris.report._simulation",
    "write_campaign": "casadi_debris.report._simulation",
    "write_run": "casadi_debris.report._simulation",
    "write_profile_csv": "casadi_debris.report._slew",
    "write_reference_csv": "casadi_debris.report._slew",
    "transfer_figures": "casadi_debris.report._transfer",
    "write_transfer": "casadi_debris.report._transfer",
    "ParameterFile": "casadi_debris.report._worstcase",
    "WorstCaseIdentity": "casadi_debris.report._worstcase",
    "WorstCaseSummary": "casadi_debris.report._worstcase",
    "corner_campaign_envelope": "casadi_debris.report._worstcase",
    "parameter_file": "casadi_debris.report._worstcase",
    "worst_case_figure": "casadi_debris.report._worstcase",
    "worst_case_summary": "casadi_debris.report._worstcase",
    "write_worst_case_files": "casadi_debris.report._worstcase",
    "write_worst_cases": "casadi_debris.report._worstcase",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
