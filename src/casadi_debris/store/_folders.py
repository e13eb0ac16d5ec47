"""Output folders and files that never lose a user's data.

Every command that writes results goes through this module:

- :func:`check_output_folder` / :func:`check_output_file` run *before* the work:
  an existing non-empty folder (or an existing file) is refused unless the
  user asked to overwrite it, the place must be writable and have room.
- :class:`RunFolder` stages a run in a hidden folder beside the target and
  moves it into place only when it is complete. Replacing an old result swaps
  the two folders in one atomic ``renameat2(RENAME_EXCHANGE)`` where Linux
  offers it (two renames elsewhere), then removes the old one, so that a kill
  at any moment leaves either the old or the new result whole.
- Only folders this toolkit wrote (they hold :data:`MARKER_NAME`, which lists
  every file the run wrote) are ever replaced, even with ``overwrite``, and only
  while they hold nothing else: a folder or file of the user's is never deleted.
- Temporaries carry their writer's process id in their name. A run that finds
  temporaries of a dead process beside its target cleans them up (and puts back
  an old result that a killed swap left aside).

Example
-------
>>> with RunFolder.claim("runs/slew", overwrite=False) as folder:  # doctest: +SKIP
...     (folder / "summary.json").write_text("{}")
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import json
import logging
import os
import re
import secrets
import shutil
import time
from pathlib import Path
from types import TracebackType

from casadi_debris._version import __version__
from casadi_debris.errors import OutputError
from casadi_debris.processes import process_alive

LOGGER = logging.getLogger(__name__)

MARKER_NAME = ".casadi-debris-run.json"
TEMPORARY_TAG = "casadi-debris"
# Room kept free beyond what a run says it will write: plots and logs are not counted.
FREE_SPACE_MARGIN_BYTES = 16 * 2**20
SLUG_LENGTH = 64
_TEMPORARY = re.compile(rf"^\.(?P<name>.+)\.{TEMPORARY_TAG}-(?P<pid>\d+)-[0-9a-f]+\.(?P<kind>\w+)$")
_RENAME_EXCHANGE = 2


# ----------------------------------------------------------------------------- names


def slug(label: str) -> str:
    """A label made safe as one path component: ``[A-Za-z0-9._-]``, no leading dot.

    Parameters
    ----------
    label : str
        Any text, e.g. a problem's name.

    Returns
    -------
    str
        At most ``SLUG_LENGTH`` characters; ``"run"`` if nothing usable is left.
    """
    cleaned = re.sub(r"[^A-Za-z0-9._-]+", "-", label).strip(".-")[:SLUG_LENGTH].strip(".-")
    return cleaned or "run"


def default_run_folder(kind: str, label: str) -> Path:
    """``runs/<kind>-<slug(label)>``: always a child of ``runs/`` in the working folder."""
    return Path("runs") / f"{kind}-{slug(label)}"


def temporary_path(target: Path, kind: str) -> Path:
    """A hidden sibling of ``target`` that names this process (for stale detection)."""
    return target.with_name(
        f".{target.name}.{TEMPORARY_TAG}-{os.getpid()}-{secrets.token_hex(4)}.{kind}"
    )


def clean_stale_temporaries(target: Path) -> list[Path]:
    """Remove what killed runs left beside ``target``; put back a result left aside.

    A swap killed between its two renames leaves the old result under an
    ``.old`` name and no ``target``: it is renamed back. Everything else of a
    dead process (``.new`` staging folders, ``.old`` leftovers, ``.tmp``
    files) is deleted. Temporaries of live processes are left alone.

    Returns
    -------
    list of Path
        What was removed or restored.
    """
    return _clean_stale(target.parent, target.name)


def clean_stale_folder(folder: Path) -> list[Path]:
    """:func:`clean_stale_temporaries` for every name in ``folder``."""
    return _clean_stale(folder, None)


def _clean_stale(parent: Path, name: str | None) -> list[Path]:
    if not parent.is_dir():
        return []
    handled = []
    for entry in sorted(parent.iterdir()):
        match = _TEMPORARY.match(entry.name)
        if not match or name not in (None, match["name"]) or process_alive(int(match["pid"])):
            continue
        target = parent / match["name"]
        if match["kind"] == "old" and not target.exists() and entry.is_dir():
            entry.rename(target)
            LOGGER.warning("restored %s, left aside by a killed run", target)
        elif entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            entry.unlink(missing_ok=True)
        handled.append(entry)
    return handled


# ----------------------------------------------------------------------------- checks


def _is_ours(folder: Path) -> bool:
    return (folder / MARKER_NAME).is_file()


def _entries(folder: Path) -> list[str]:
    """Every file and folder below ``folder`` but the marker, as sorted relative paths."""
    found = []
    for root, folders, files in os.walk(folder):
        for name in [*folders, *files]:
            found.append((Path(root) / name).relative_to(folder).as_posix())
    return sorted(entry for entry in found if entry != MARKER_NAME)


def foreign_entries(folder: Path) -> list[str] | None:
    """What in a result folder its run did not write (a user's files), or None if unknown.

    The marker lists what the run wrote; a marker without that list (an older
    version's, or damaged) says nothing about the rest, so None.
    """
    try:
        written = json.loads((folder / MARKER_NAME).read_text()).get("files")
    except (OSError, ValueError, AttributeError):
        return None
    if not isinstance(written, list):
        return None
    known = set(written)
    return [entry for entry in _entries(folder) if entry not in known]


def _check_replaceable(folder: Path, shown: str | Path, option: str) -> None:
    """Refuse to replace a result folder that holds anything its run did not write."""
    if not _is_ours(folder):
        raise OutputError(
            f"{option}: {shown} was not written by casadi-debris (no {MARKER_NAME}); "
            "it is never replaced, choose another folder"
        )
    foreign = foreign_entries(folder)
    if foreign is None:
        raise OutputError(
            f"{option}: {shown} does not list the files its run wrote (an older result); "
            "it is not replaced, choose another folder"
        )
    if foreign:
        more = f" and {len(foreign) - 1} more" if len(foreign) > 1 else ""
        raise OutputError(
            f"{option}: {shown} holds {foreign[0]}{more}, not written by casadi-debris; "
            "it is never replaced, move it out or choose another folder"
        )


def _check_room(parent: Path, expected_bytes: int | None, option: str) -> None:
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"{option}: cannot write in {parent} (permission denied)")
    free = shutil.disk_usage(parent).free
    needed = (expected_bytes or 0) + FREE_SPACE_MARGIN_BYTES
    if free < needed:
        raise OutputError(
            f"{option}: only {free / 2**20:.1f} MiB free in {parent}, "
            f"the run needs about {needed / 2**20:.1f} MiB"
        )


def _existing_parent(path: Path, option: str) -> Path:
    """The nearest existing ancestor of ``path``, which must be a folder."""
    for ancestor in path.parents:
        if ancestor.exists():
            if not ancestor.is_dir():
                raise OutputError(f"{option}: {ancestor} is a file, not a folder")
            return ancestor
    raise OutputError(f"{option}: no existing folder above {path}")


def check_output_folder(
    path: str | Path,
    *,
    overwrite: bool = False,
    option: str = "--out",
    expected_bytes: int | None = None,
) -> Path:
    """Check, before any work, that a run may write its folder at ``path``.

    Parameters
    ----------
    path : str or Path
        The results folder.
    overwrite : bool
        Allow replacing an existing result folder written by this toolkit.
    option : str
        Name of the option or key, for messages.
    expected_bytes : int, optional
        What the run will write, when known [bytes].

    Returns
    -------
    Path
        The absolute target.

    Raises
    ------
    OutputError
        The target is a file, a non-empty folder without ``overwrite``, a
        folder this toolkit did not write, the folder the command runs in (or
        one above it), not writable, or on a file system without room.
    """
    target = Path(path).absolute()
    clean_stale_temporaries(target)
    if target.exists() or target.is_symlink():
        if not target.is_dir() or target.is_symlink():
            raise OutputError(f"{option}: {path} exists and is not a folder")
        if any(target.iterdir()):
            if not overwrite:
                raise OutputError(
                    f"{option}: {path} exists and is not empty; "
                    "pass --overwrite to replace a previous result"
                )
            _check_replaceable(target, path, option)
            if Path.cwd().resolve().is_relative_to(target.resolve()):
                raise OutputError(f"{option}: {path} holds the working folder; run from elsewhere")
    _check_room(_existing_parent(target, option), expected_bytes, option)
    return target


def check_output_file(
    path: str | Path,
    *,
    overwrite: bool = False,
    option: str = "--out",
    expected_bytes: int | None = None,
) -> Path:
    """Check, before any work, that a run may write the file ``path``.

    An existing file is refused unless ``overwrite``; a folder is always refused.
    """
    target = Path(path).absolute()
    clean_stale_temporaries(target)
    if target.is_dir():
        raise OutputError(f"{option}: {path} is a folder, a file is needed")
    if (target.exists() or target.is_symlink()) and not overwrite:
        raise OutputError(f"{option}: {path} exists; pass --overwrite to replace it")
    _check_room(_existing_parent(target, option), expected_bytes, option)
    return target


# ----------------------------------------------------------------------------- writing


def write_marker(folder: Path, command: str) -> None:
    """Mark ``folder`` as a result this toolkit wrote (what may be replaced later)."""
    record = {
        "toolkit": "casadi_debris",
        "version": __version__,
        "command": command,
        "written_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        # What may be replaced later: anything else found there is the user's.
        "files": _entries(folder),
    }
    (folder / MARKER_NAME).write_text(json.dumps(record, indent=1) + "\n")


def _libc_exchange() -> object | None:
    name = ctypes.util.find_library("c")
    if name is None:
        return None
    try:
        function = ctypes.CDLL(name, use_errno=True).renameat2
    except (OSError, AttributeError):
        return None
    function.argtypes = [
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_uint,
    ]
    return function


_AT_FDCWD = -100
_EXCHANGE = _libc_exchange()


def _exchange(first: Path, second: Path) -> bool:
    """Swap two paths atomically; False where the system cannot."""
    if _EXCHANGE is None:
        return False
    result = _EXCHANGE(  # type: ignore[operator]
        _AT_FDCWD, os.fsencode(first), _AT_FDCWD, os.fsencode(second), _RENAME_EXCHANGE
    )
    if result == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP):
        return False
    raise OSError(code, os.strerror(code), str(second))


def move_into_place(staged: Path, target: Path, *, overwrite: bool = False) -> Path:
    """Move a complete folder ``staged`` to ``target``, replacing an old result atomically.

    Parameters
    ----------
    staged : Path
        The finished folder (same file system as ``target``).
    target : Path
    overwrite : bool
        Whether an existing non-empty ``target`` may be replaced (it must then be
        a folder this toolkit wrote; see :func:`check_output_folder`).

    Returns
    -------
    Path
        ``target``.
    """
    target = Path(target).absolute()
    if not (target.exists() and any(target.iterdir())):
        # A missing or empty folder is replaced by rename(2) in one step.
        os.rename(staged, target)
        return target
    if not overwrite:
        raise OutputError(
            f"{target} appeared while the run was working; the new result is in {staged}"
        )
    try:
        _check_replaceable(target, target, "--out")
    except OutputError as error:
        raise OutputError(f"{error}; the new result is in {staged}") from None
    if _exchange(staged, target):
        shutil.rmtree(staged)
        return target
    aside = temporary_path(target, "old")
    os.rename(target, aside)
    os.rename(staged, target)
    shutil.rmtree(aside)
    return target


class RunFolder:
    """A results folder claimed for one run: checked first, staged, then moved into place.

    Use :meth:`claim` before the work starts and write into the yielded staging
    folder; on success the folder is marked and moved to its target, on any
    error (Ctrl-C included) the staging folder is deleted and the target is
    left as it was.
    """

    def __init__(self, target: Path, staging: Path, overwrite: bool, command: str) -> None:
        self.target = target
        self.staging = staging
        self.overwrite = overwrite
        self.command = command

    @classmethod
    def claim(
        cls,
        path: str | Path,
        *,
        overwrite: bool = False,
        option: str = "--out",
        expected_bytes: int | None = None,
        command: str = "",
    ) -> RunFolder:
        """Check ``path`` (see :func:`check_output_folder`) and create the staging folder."""
        target = check_output_folder(
            path, overwrite=overwrite, option=option, expected_bytes=expected_bytes
        )
        target.parent.mkdir(parents=True, exist_ok=True)
        staging = temporary_path(target, "new")
        staging.mkdir()
        return cls(target, staging, overwrite, command)

    def commit(self) -> Path:
        """Mark the staged folder and move it into place."""
        write_marker(self.staging, self.command)
        return move_into_place(self.staging, self.target, overwrite=self.overwrite)

    def discard(self) -> None:
        shutil.rmtree(self.staging, ignore_errors=True)

    def __enter__(self) -> Path:
        return self.staging

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        if kind is None:
            self.commit()
        else:
            self.discard()
