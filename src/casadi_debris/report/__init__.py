"""Reports: results in display units, paper-vs-toolkit comparisons, tables, the files of
each job's folder.

This is an edge package: it turns SI results into fields whose names carry
their display unit (``torque_max_mNm``), holds the paper's published figures
and tolerances (:mod:`casadi_debris.report._paper`) and lays out what each job's
folder holds; the writing itself (atomic files, run and campaign folders) is
:mod:`casadi_debris.store`'s.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from casadi_debris._lazy import lazy_exports, type_checking_imports

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
        failure_label,
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
    "failure_label",
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
# modules behind the rest bring in matplotlib, the studies and the simulation. Where each
# name lives is read from the TYPE_CHECKING imports above (one list, with __all__).
_LAZY = {
    name: module for name, module in type_checking_imports(__file__).items() if name in __all__
}
__getattr__, __dir__ = lazy_exports(__name__, _LAZY)
