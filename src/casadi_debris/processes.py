"""Facts about operating-system processes and tools that several layers need."""

from __future__ import annotations

import os
import shutil


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


def c_compiler() -> str | None:
    """Path of the C compiler to build generated code with (``$CC``, gcc, cc or clang),
    or None when there is none.

    One rule for every library the toolkit compiles (CasADi's JIT steps, the flight
    code, the FMU's binary), so that they are built by the same compiler.
    """
    for name in (os.environ.get("CC"), "gcc", "cc", "clang"):
        if name and shutil.which(name):
            return shutil.which(name)
    return None
