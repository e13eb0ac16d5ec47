"""Facts about operating-system processes that several layers need."""

from __future__ import annotations

import os


def process_alive(pid: int) -> bool:
    """Whether a process of that id exists (a zombie counts as alive).

    Parameters
    ----------
    pid : int
        Process id.
    """
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
