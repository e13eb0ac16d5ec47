"""The folder a Monte-Carlo campaign is written into, case by case, and resumed from.

While it runs, a campaign lives in ``<out>.partial/``:

- ``campaign.json``: what the campaign is (problem and controller hashes, case
  kind, seed, the case list, envelope bins, toolkit version). A resume with
  anything different is refused with a line that says what differs.
- ``.lock``: the id of the process writing the folder; a second campaign on
  the same folder is refused while that process lives.
- ``cases/<id>.npz`` (the case's arrays, :class:`~casadi_debris.campaigns.Bands`
  as named float64 arrays ``error_rad_min``, ..., so that a resumed campaign
  is bit-exact) then ``cases/<id>.json`` (the summary, written last: the
  marker of a whole case).
- ``cases/<id>.failed.json``: a case that raised (its identity, the
  exception and the worker's traceback). A resume runs it again, and a case
  that then finishes drops the file; a finished campaign keeps the others.
- ``.jit/``: the compiled control step of every worker, removed at the end.

When every case is in, the tables and ``campaign.nc`` (every case as labelled
arrays, see :func:`~casadi_debris.store.open_campaign`) are written and the
folder is moved to ``<out>`` (see :func:`~casadi_debris.store.move_into_place`).

This module knows files, not campaigns: a case is its id, its named arrays and its
summary (a record or a dict), and what reads a case back is given by the caller
(:mod:`casadi_debris.campaigns` builds its outcomes from them).
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Iterable, Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from types import TracebackType
from typing import Any, TypeVar

import numpy as np

from casadi_debris._version import __version__
from casadi_debris.errors import OutputError
from casadi_debris.processes import process_alive
from casadi_debris.records import Record
from casadi_debris.store._files import write_atomically, write_json_atomic
from casadi_debris.store._folders import (
    check_output_folder,
    clean_stale_folder,
    move_into_place,
    write_marker,
)

PARTIAL_SUFFIX = ".partial"
RECORD_NAME = "campaign.json"
LOCK_NAME = ".lock"

T = TypeVar("T")


def partial_folder(out: Path) -> Path:
    """Where the campaign for ``out`` is written while it runs."""
    return out.with_name(out.name + PARTIAL_SUFFIX)


@dataclass(frozen=True)
class CampaignIdentity:
    """What identifies a campaign: a resume must match every field.

    Attributes
    ----------
    problem_name : str
    problem_sha256 : str
        Hash of the problem file's bytes (and the files it extends).
    controller_sha256 : str
        Hash of the controller file's bytes.
    case_kind : str
        ``"corner"`` or ``"sample"``.
    seed : int or None
        Seed of sampled cases.
    case_ids : tuple of str
        Every case of the campaign, in order.
    envelope_bin_s : float
        Width of the envelope's time bins [s].
    toolkit_version : str
    """

    problem_name: str
    problem_sha256: str
    controller_sha256: str
    case_kind: str
    seed: int | None
    case_ids: tuple[str, ...]
    envelope_bin_s: float
    toolkit_version: str = __version__

    def to_dict(self) -> dict[str, Any]:
        return {**asdict(self), "case_ids": list(self.case_ids)}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> CampaignIdentity:
        return cls(**{**data, "case_ids": tuple(data["case_ids"])})

    def differences(self, other: CampaignIdentity) -> list[str]:
        """Human-readable fields in which ``other`` differs from this record."""
        found = []
        for name, mine in self.to_dict().items():
            theirs = other.to_dict()[name]
            if mine == theirs:
                continue
            if name == "case_ids":
                found.append(f"case list ({len(theirs)} cases there, {len(mine)} here)")
            elif name.endswith("sha256"):
                found.append(f"{name.removesuffix('_sha256')} file (sha256 {theirs[:12]}...)")
            else:
                found.append(f"{name} ({theirs} there, {mine} here)")
        return found


def _lock(folder: Path, option: str) -> None:
    lock = folder / LOCK_NAME
    for _ in range(2):
        try:
            handle = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            text = lock.read_text().strip() if lock.exists() else ""
            owner = int(text) if text.isdigit() else None
            if owner is not None and owner != os.getpid() and process_alive(owner):
                raise OutputError(
                    f"{option}: {folder} is in use by process {owner} (another campaign); "
                    f"wait for it, or remove {lock} if that process is not a casadi-debris run"
                ) from None
            lock.unlink(missing_ok=True)  # left by a run that was killed
            continue
        with os.fdopen(handle, "w") as stream:
            stream.write(f"{os.getpid()}\n")
        return
    raise OutputError(f"{option}: cannot take the lock {lock}")


def write_case(
    folder: Path,
    case_id: str,
    arrays: Mapping[str, np.ndarray],
    summary: Record | dict[str, Any],
) -> None:
    """One finished case into ``folder``: ``cases/<id>.npz`` (its named arrays) then
    ``cases/<id>.json`` (its summary, written last: the marker of a whole case); a
    ``cases/<id>.failed.json`` of an earlier try goes."""
    cases = folder / "cases"
    cases.mkdir(exist_ok=True)
    # Any: numpy's stubs take ** entries for its own keywords (allow_pickle).
    named: dict[str, Any] = dict(arrays)

    def save(path: Path) -> None:
        # A stream, not a name: savez would add ".npz" to the temporary's name.
        with path.open("xb") as stream:
            np.savez_compressed(stream, **named)

    write_atomically(cases / f"{case_id}.npz", save)
    write_json_atomic(cases / f"{case_id}.json", summary)
    (cases / f"{case_id}.failed.json").unlink(missing_ok=True)


def write_failure(folder: Path, case_id: str, summary: Record | dict[str, Any]) -> Path:
    """A case that raised, as ``cases/<id>.failed.json`` in ``folder``."""
    cases = folder / "cases"
    cases.mkdir(exist_ok=True)
    path = cases / f"{case_id}.failed.json"
    write_json_atomic(path, summary)
    return path


class CampaignFolder:
    """A campaign's ``<out>.partial`` folder: locked, checked against its record, resumable.

    Use :meth:`open` before any work; it is a context manager that releases
    the lock when the block ends (the folder itself stays for a resume unless
    :meth:`finish` moved it into place).
    """

    def __init__(self, out: Path, partial: Path, overwrite: bool) -> None:
        self.out = out
        self.partial = partial
        self.overwrite = overwrite

    @classmethod
    def open(
        cls,
        out: str | Path,
        record: CampaignIdentity,
        *,
        overwrite: bool = False,
        option: str = "--out",
        expected_bytes: int | None = None,
    ) -> CampaignFolder:
        """Check ``out``, lock ``<out>.partial`` and check (or write) its record.

        Raises
        ------
        OutputError
            ``out`` cannot be written (see
            :func:`~casadi_debris.store.check_output_folder`), the
            partial folder is in use, or it holds another campaign.
        """
        target = check_output_folder(
            out, overwrite=overwrite, option=option, expected_bytes=expected_bytes
        )
        partial = partial_folder(target)
        if partial.exists() and not partial.is_dir():
            raise OutputError(f"{option}: {partial} exists and is not a folder")
        partial.mkdir(parents=True, exist_ok=True)
        _lock(partial, option)
        folder = cls(target, partial, overwrite)
        try:
            folder._check_record(record, option)
        except BaseException:
            folder.release()
            raise
        folder._clean()
        return folder

    def _check_record(self, record: CampaignIdentity, option: str) -> None:
        path = self.partial / RECORD_NAME
        if not path.exists():
            if (self.partial / "cases").exists():
                raise OutputError(
                    f"{option}: {self.partial} holds cases but no {RECORD_NAME}; "
                    "it cannot be checked, remove it to start afresh"
                )
            write_json_atomic(path, record.to_dict())
            return
        try:
            found = CampaignIdentity.from_dict(json.loads(path.read_text()))
        except (OSError, ValueError, TypeError, KeyError) as exc:
            raise OutputError(f"{option}: {path} is damaged ({exc}); remove the folder") from None
        differences = record.differences(found)
        if differences:
            raise OutputError(
                f"{option}: {self.partial} holds another campaign (differs in "
                f"{'; '.join(differences)}); resume with the same inputs, or choose another --out"
            )

    def _clean(self) -> None:
        clean_stale_folder(self.partial)
        clean_stale_folder(self.partial / "cases")

    def write_case(
        self, case_id: str, arrays: Mapping[str, np.ndarray], summary: Record | dict[str, Any]
    ) -> None:
        """One finished case: ``cases/<id>.npz`` (arrays) then ``cases/<id>.json`` (the marker)."""
        write_case(self.partial, case_id, arrays, summary)

    def write_failure(self, case_id: str, summary: Record | dict[str, Any]) -> Path:
        """A case that raised, as ``cases/<id>.failed.json`` (a resume runs it again)."""
        return write_failure(self.partial, case_id, summary)

    def finished_cases(
        self,
        case_ids: Iterable[str],
        read: Callable[[str, dict[str, Any], Mapping[str, np.ndarray]], T],
    ) -> dict[str, T]:
        """Cases of ``case_ids`` already written (both files present and readable).

        ``read(case_id, summary, arrays)`` turns a case's JSON summary and its arrays
        into what the caller keeps; a case whose files or ``read`` fail (ValueError,
        KeyError, TypeError: damaged, or of an older layout) is left out, to run again.
        """
        found: dict[str, T] = {}
        for case_id in case_ids:
            summary_path = self.partial / "cases" / f"{case_id}.json"
            arrays_path = self.partial / "cases" / f"{case_id}.npz"
            if not (summary_path.exists() and arrays_path.exists()):
                continue
            try:
                summary = json.loads(summary_path.read_text())
                with np.load(arrays_path) as data:
                    found[case_id] = read(case_id, summary, data)
            except (OSError, ValueError, KeyError, TypeError):
                continue  # a damaged case (or one of an older layout) is simply run again
        return found

    def finish(self, command: str = "montecarlo") -> Path:
        """Move the complete campaign to ``out`` (replacing an old one only with overwrite)."""
        (self.partial / LOCK_NAME).unlink(missing_ok=True)
        write_marker(self.partial, command)
        return move_into_place(self.partial, self.out, overwrite=self.overwrite)

    def release(self) -> None:
        """Give up the lock; the cases stay for a resume."""
        lock = self.partial / LOCK_NAME
        if lock.exists() and lock.read_text().strip() == str(os.getpid()):
            lock.unlink()

    def __enter__(self) -> CampaignFolder:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        if self.partial.exists():
            self.release()
