"""``casadi-debris reproduce``: the whole paper, end to end, with a report."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import click

from casadi_debris.cli.common import echo_json, folder_option, main, output_options, workers_option
from casadi_debris.cli.simulate import stage_progress
from casadi_debris.records import Record
from casadi_debris.report import format_table

TABLE_KEYS = ("result", "paper", "accepted", "ours", "verdict")


@main.command()
@folder_option("Report folder.", default=Path("runs") / "reproduce")
@click.option("--quick", is_flag=True, help="Fewer samples and corners, shorter pointing run (CI).")
@click.option("--resynthesize", is_flag=True, help="Design the controller anew (≈1 min).")
@workers_option
@output_options
def reproduce(
    out: Path, quick: bool, resynthesize: bool, workers: int, overwrite: bool, as_json: bool
) -> None:
    """Reproduce the paper: model, budgets, controller, margins, slew and pointing
    with their Monte-Carlo envelopes; writes report.md with every figure of the
    paper next to ours."""
    from casadi_debris.store import check_output_folder
    from casadi_debris.workflows import reproduce as reproduce_job

    check_output_folder(out, overwrite=overwrite)
    paper = reproduce_job(
        out,
        quick=quick,
        resynthesize=resynthesize,
        workers=workers,
        overwrite=overwrite,
        progress=stage_progress(as_json),
    )
    summary = paper.summary
    echo_verdicts(
        summary,
        summary.table,
        TABLE_KEYS,
        f"{summary.reproduced} of {summary.rows} rows reproduced; "
        f"report: {out.absolute() / 'report.md'} ({summary.time_s:.0f} s)",
        as_json=as_json,
    )


def echo_verdicts(
    summary: Record,
    rows: Sequence[Record],
    keys: tuple[str, ...],
    closing: str,
    *,
    as_json: bool,
) -> None:
    """A checked run's summary as JSON, or its table of verdicts (columns ``keys`` of
    ``rows``' JSON) and a closing line."""
    if as_json:
        echo_json(summary)
        return
    table = [[row.to_json()[key] for key in keys] for row in rows]
    click.echo(format_table(list(keys), table))
    click.echo(closing)
