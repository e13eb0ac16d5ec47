"""``K…`` entries for where a command writes: ``--out`` folders and files, ``--overwrite``.

Existing files and folders of the user's, unwritable places (``/proc``), a
folder under a file: refused, with the user's files left as they were.
"""

from __future__ import annotations

from .invocations import BASE, Invocations, replace_option

DIR_OUT = [
    ("existing.txt", "an existing file"),
    ("existing.txt/sub", "a folder under a file"),
    ("/proc/casadi-debris-corpus", "an unwritable place (/proc)"),
    (".", "the working folder (not empty)"),
    ("full", "an existing non-empty folder"),
    ("", "empty string"),
]


def out_folder_options(inv: Invocations, command: str) -> None:
    """``command --out`` each of :data:`DIR_OUT`."""
    for value, desc in DIR_OUT:
        inv.option(command, "--out", [value], f"--out {desc}")


def overwrite_entries(inv: Invocations) -> None:
    """``--overwrite`` on a folder casadi-debris did not write: refused, its file kept."""
    for command in ("slew", "simulate", "margins", "compare"):
        inv.add(
            command,
            [*replace_option(BASE[command], "--out", ["full"]), "--overwrite"],
            "--out an existing folder of the user's with --overwrite",
            ("--out", "--overwrite", "full"),
            category="overwrite-foreign",
        )


def out_checked_first_entries(inv: Invocations) -> None:
    """An unwritable ``--out`` with the full default work: refused before the work starts."""
    for command, args in (
        ("margins", ["--no-plots", "--out", "/proc/casadi-debris-corpus"]),
        ("montecarlo", ["--out", "/proc/casadi-debris-corpus"]),
        ("synthesize", ["--out", "/proc/casadi-debris-corpus"]),
        ("simulate", ["--out", "/proc/casadi-debris-corpus"]),
    ):
        inv.add(
            command,
            args,
            "an unwritable --out with the full default work (checked before it starts)",
            ("--out",),
            category="out-checked-late",
        )
