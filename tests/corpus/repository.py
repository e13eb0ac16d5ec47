"""Did the corpus write into the repository? ``git status`` before and after."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def git_status() -> set[str]:
    """``git status --porcelain`` lines of the repository (untracked files listed one by one)."""
    try:
        out = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=all"],
            cwd=REPO,
            capture_output=True,
            text=True,
            check=True,
            timeout=60,
        ).stdout
    except (OSError, subprocess.SubprocessError):
        return set()
    return set(out.splitlines())


def new_repo_files(before: set[str], after: set[str]) -> list[str]:
    """Status lines that appeared, less source edits and tool caches (others work in this tree)."""
    caches = re.compile(r"(^|/)(__pycache__|\.\w*cache|\.venv[\w-]*|\.hypothesis)/")
    new = sorted(after - before)
    return [
        line
        for line in new
        if not caches.search(line[3:])
        and (
            not re.search(r"\.(py|md|toml|cfg|txt|json|yml|yaml)$", line)
            or "runs/" in line
            or line.strip().endswith(("summary.json", "controller.json"))
        )
    ]
