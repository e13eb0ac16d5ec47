"""The TOML table reader: typed, bounded values, each error naming its dotted key.

Types are strict: a number is a TOML integer or float (never a string, never
true/false), an integer is a TOML integer, and every number lies in a
:class:`~casadi_debris.config.limits.Range`. Messages stay on one line and
short, whatever the file holds.
"""

from __future__ import annotations

import difflib
import json
import math
import re
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, TypeVar, overload

import numpy as np

from casadi_debris.config.limits import MAX_DESCRIPTION_CHARS, NAME_PATTERN, Range
from casadi_debris.errors import ProblemFileError

# One of a closed set of strings (a Literal type's values): what a checked choice is typed as.
Choice = TypeVar("Choice", bound=str)

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]{1,64}")
# What the readers asked of each key, while :func:`recording` is on (for the JSON Schema).
_RECORDER: ContextVar[list[tuple[str, dict[str, Any]]] | None] = ContextVar(
    "casadi_debris_table_recorder", default=None
)


@contextmanager
def recording() -> Iterator[list[tuple[str, dict[str, Any]]]]:
    """Collect (dotted key, what was asked of it) for every key the readers take meanwhile.

    ``kind`` is one of table, tables, text, label, prose, texts, boolean, integer, array,
    with the range, shape, choices or count the reader checked.
    """
    calls: list[tuple[str, dict[str, Any]]] = []
    token = _RECORDER.set(calls)
    try:
        yield calls
    finally:
        _RECORDER.reset(token)


_SHOWN_CHARS = 60
_ALLOWED_CONTROL = "\n\t"


def frozen_array(values: Any) -> np.ndarray:
    """A read-only float array of ``values``."""
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


def show(value: Any) -> str:
    """``repr(value)`` cut to a few dozen characters, for one-line messages."""
    try:
        text = repr(value)
    except ValueError:  # an integer too long to print (Python's digit limit)
        return "<an integer of thousands of digits>"
    except RecursionError:
        return "<arrays nested too deeply>"
    return text if len(text) <= _SHOWN_CHARS else text[: _SHOWN_CHARS - 3] + "..."


def _shape_text(shape: tuple[int | None, ...]) -> str:
    if not shape:
        return "a number"
    return f"an array of shape {tuple(s or 'n' for s in shape)}"


class Table:
    """Reads one TOML table, naming the dotted key in every error.

    Every key must be taken exactly once; :meth:`done` rejects the rest.

    Parameters
    ----------
    data : mapping
        The table as parsed; anything else is refused naming ``path``.
    path : str
        Dotted key of the table ("" for the top level).
    source : str or None
        The file, for messages.
    """

    def __init__(self, data: Any, path: str, source: str | None) -> None:
        self.path = path
        self.source = source
        if not isinstance(data, Mapping):
            raise self.error(path or "<top level>", f"must be a table, got {show(data)}")
        self.data = data
        self.taken: set[str] = set()

    def key(self, name: str) -> str:
        """Dotted key of ``name`` in this table; odd names quoted as TOML does."""
        shown = name if _BARE_KEY.fullmatch(str(name)) else json.dumps(str(name))[:_SHOWN_CHARS]
        return f"{self.path}.{shown}" if self.path else shown

    def error(self, key: str, message: str) -> ProblemFileError:
        """The error for ``key`` (dotted) in this table's file."""
        return ProblemFileError(key, message, self.source)

    def record(self, name: str, **spec: Any) -> None:
        """Note what a reader asks of ``name`` (only while :func:`recording` is on)."""
        calls = _RECORDER.get()
        if calls is not None:
            calls.append((self.key(name), spec))

    def has(self, name: str) -> bool:
        """Whether the (optional) key ``name`` is given."""
        return name in self.data

    def raw(self, name: str) -> Any:
        """The value of ``name`` unchecked; marks it taken; refuses a missing key."""
        self.taken.add(name)
        if name not in self.data:
            spare = [str(k) for k in self.data if k not in self.taken]
            close = difflib.get_close_matches(name, spare, n=1)
            hint = f" (is {close[0]} a misspelling of it?)" if close else ""
            raise self.error(self.key(name), f"missing{hint}")
        return self.data[name]

    def table(self, name: str) -> Table:
        """The sub-table ``name``."""
        self.record(name, kind="table")
        return Table(self.raw(name), self.key(name), self.source)

    def tables(self, name: str, max_count: int) -> list[Table]:
        """The array of tables ``name``: one to ``max_count`` of them."""
        self.record(name, kind="tables", max_count=max_count)
        value = self.raw(name)
        if not isinstance(value, list) or not value:
            raise self.error(self.key(name), "must be a non-empty array of tables")
        if len(value) > max_count:
            raise self.error(self.key(name), f"at most {max_count} tables, got {len(value)}")
        return [Table(v, f"{self.key(name)}[{i}]", self.source) for i, v in enumerate(value)]

    @overload
    def text(self, name: str, choices: None = None) -> str: ...
    @overload
    def text(self, name: str, choices: tuple[Choice, ...]) -> Choice: ...
    def text(self, name: str, choices: tuple[str, ...] | None = None) -> str:
        """A string, one of ``choices`` when given."""
        self.record(name, kind="text", choices=choices)
        value = self.raw(name)
        if not isinstance(value, str):
            raise self.error(self.key(name), f"must be a string, got {show(value)}")
        if choices is not None and value not in choices:
            raise self.error(
                self.key(name), f"must be one of {', '.join(choices)}; got {show(value)}"
            )
        return value

    def label(self, name: str) -> str:
        """A name used as a label (and in folder names): see ``limits.NAME_PATTERN``."""
        self.record(name, kind="label", pattern=NAME_PATTERN)
        value = self.text(name)
        if not re.fullmatch(NAME_PATTERN, value):
            raise self.error(
                self.key(name),
                "must be a label: a letter or digit, then at most 63 letters, digits, "
                f"'.', '_' or '-' (it names output folders, it is not a path); got {show(value)}",
            )
        return value

    def prose(self, name: str) -> str:
        """Free text of bounded length without control characters (tabs, newlines allowed)."""
        self.record(name, kind="prose", max_length=MAX_DESCRIPTION_CHARS)
        value = self.text(name)
        if len(value) > MAX_DESCRIPTION_CHARS:
            raise self.error(
                self.key(name),
                f"at most {MAX_DESCRIPTION_CHARS} characters, got {len(value)}",
            )
        if any((ord(c) < 32 and c not in _ALLOWED_CONTROL) or ord(c) == 127 for c in value):
            raise self.error(self.key(name), "must not hold control characters")
        return value

    def texts(self, name: str, choices: tuple[Choice, ...], max_count: int) -> tuple[Choice, ...]:
        """An array of one to ``max_count`` strings, each among ``choices``."""
        self.record(name, kind="texts", choices=choices, max_count=max_count)
        value = self.raw(name)
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise self.error(self.key(name), f"must be an array of strings, got {show(value)}")
        if not 1 <= len(value) <= max_count:
            raise self.error(
                self.key(name), f"must hold 1 to {max_count} entries, got {len(value)}"
            )
        for v in value:
            if v not in choices:
                raise self.error(self.key(name), f"entries must be among {', '.join(choices)}")
        return tuple(value)

    def boolean(self, name: str) -> bool:
        """true or false."""
        self.record(name, kind="boolean")
        value = self.raw(name)
        if not isinstance(value, bool):
            raise self.error(self.key(name), f"must be true or false, got {show(value)}")
        return value

    def integer(self, name: str, bounds: Range) -> int:
        """A TOML integer (not a float, not a string, not true/false) within ``bounds``."""
        self.record(name, kind="integer", bounds=bounds)
        value = self.raw(name)
        if isinstance(value, bool):
            raise self.error(self.key(name), "must be an integer, not true/false")
        if isinstance(value, str):
            raise self.error(self.key(name), f"must be an integer, not a string; got {show(value)}")
        if not isinstance(value, int):
            raise self.error(self.key(name), f"must be an integer, got {show(value)}")
        # Clamped first: a float conversion of an integer beyond 1.8e308 would overflow.
        problem = bounds.violation(max(min(value, 2**63), -(2**63)))
        if problem is not None:
            raise self.error(self.key(name), f"{problem}, got {show(value)}")
        return value

    def number(self, name: str, bounds: Range) -> float:
        """A TOML integer or float within ``bounds``."""
        return float(self.array(name, (), bounds))

    def array(
        self,
        name: str,
        shape: tuple[int | None, ...],
        bounds: Range,
        *,
        max_rows: int | None = None,
    ) -> np.ndarray:
        """A number (shape ``()``) or nested arrays of numbers of the given shape.

        Parameters
        ----------
        name : str
        shape : tuple of int or None
            Expected shape; None for a free length (1 to ``max_rows``).
        bounds : Range
            Every entry must lie in it.
        max_rows : int, optional
            Largest count of a free dimension.

        Returns
        -------
        ndarray
            Read-only floats.
        """
        self.record(name, kind="array", shape=shape, bounds=bounds, max_rows=max_rows)
        key = self.key(name)
        value = self.raw(name)
        self._check_structure(key, value, value, shape, max_rows)
        array = np.array(value, dtype=float)
        problem = bounds.violation(array)
        if problem is not None:
            raise self.error(key, f"{problem}, got {show(value)}")
        return frozen_array(array)

    def _check_structure(
        self,
        key: str,
        whole: Any,
        value: Any,
        shape: tuple[int | None, ...],
        max_rows: int | None,
        depth: int = 0,
    ) -> None:
        """Walk ``value`` along ``shape`` (so never deeper than the shape) checking each leaf."""
        want = _shape_text(shape)
        if depth == len(shape):
            scalar = value is whole
            if isinstance(value, bool):
                noun = "a number" if scalar else "numbers"
                raise self.error(key, f"must be {noun}, not true/false")
            if isinstance(value, str):
                nouns = "a number, not a string" if scalar else "numbers, not strings"
                raise self.error(key, f"must be {nouns}; got {show(whole)}")
            if not isinstance(value, int | float):
                raise self.error(key, f"must be {want}, got {show(whole)}")
            try:
                finite = math.isfinite(float(value))
            except OverflowError:  # an integer beyond 1.8e308
                finite = False
            if not finite:
                raise self.error(key, "must be finite (no NaN or inf, nothing beyond 1.8e308)")
            return
        if not isinstance(value, list):
            raise self.error(key, f"must be {want}, got {show(whole)}")
        length = shape[depth]
        if length is not None and len(value) != length:
            raise self.error(key, f"must be {want}, got {show(whole)}")
        if length is None and not 1 <= len(value) <= (max_rows or len(value)):
            raise self.error(key, f"must hold 1 to {max_rows} entries, got {len(value)}")
        for item in value:
            self._check_structure(key, whole, item, shape, max_rows, depth + 1)

    def done(self) -> None:
        """Refuse any key no reader took."""
        unknown = sorted(set(self.data) - self.taken, key=str)
        if unknown:
            close = difflib.get_close_matches(str(unknown[0]), sorted(self.taken), n=1)
            hint = f"; did you mean {close[0]}?" if close else ""
            raise self.error(self.key(unknown[0]), f"unknown key{hint}")
