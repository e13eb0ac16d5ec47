"""The TOML table reader: typed, bounded values, each error naming its dotted key."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from casadi_debris.errors import ProblemFileError


def frozen_array(values: Any) -> np.ndarray:
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


class Table:
    """Reads one TOML table, naming the dotted key in every error.

    Every key must be taken exactly once; :meth:`done` rejects the rest.
    """

    def __init__(self, data: Any, path: str, source: str | None) -> None:
        self.path = path
        self.source = source
        if not isinstance(data, Mapping):
            raise self.error(path or "<top level>", "must be a table")
        self.data = data
        self.taken: set[str] = set()

    def key(self, name: str) -> str:
        return f"{self.path}.{name}" if self.path else name

    def error(self, key: str, message: str) -> ProblemFileError:
        return ProblemFileError(key, message, self.source)

    def raw(self, name: str) -> Any:
        self.taken.add(name)
        if name not in self.data:
            raise self.error(self.key(name), "missing")
        return self.data[name]

    def table(self, name: str) -> Table:
        return Table(self.raw(name), self.key(name), self.source)

    def tables(self, name: str) -> list[Table]:
        value = self.raw(name)
        if not isinstance(value, list) or not value:
            raise self.error(self.key(name), "must be a non-empty array of tables")
        return [Table(v, f"{self.key(name)}[{i}]", self.source) for i, v in enumerate(value)]

    def text(self, name: str, choices: tuple[str, ...] | None = None) -> str:
        value = self.raw(name)
        if not isinstance(value, str):
            raise self.error(self.key(name), f"must be a string, got {value!r}")
        if choices is not None and value not in choices:
            raise self.error(self.key(name), f"must be one of {', '.join(choices)}; got {value!r}")
        return value

    def texts(self, name: str, choices: tuple[str, ...]) -> tuple[str, ...]:
        value = self.raw(name)
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise self.error(self.key(name), "must be an array of strings")
        for v in value:
            if v not in choices:
                raise self.error(self.key(name), f"entries must be among {', '.join(choices)}")
        return tuple(value)

    def boolean(self, name: str) -> bool:
        value = self.raw(name)
        if not isinstance(value, bool):
            raise self.error(self.key(name), f"must be true or false, got {value!r}")
        return value

    def integer(self, name: str, minimum: int | None = None) -> int:
        value = self.raw(name)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(self.key(name), f"must be an integer, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.error(self.key(name), f"must be at least {minimum}, got {value}")
        return value

    def number(
        self,
        name: str,
        *,
        positive: bool = False,
        nonnegative: bool = False,
        below: float | None = None,
        at_most: float | None = None,
    ) -> float:
        return float(
            self.array(
                name,
                (),
                positive=positive,
                nonnegative=nonnegative,
                below=below,
                at_most=at_most,
            )
        )

    def array(
        self,
        name: str,
        shape: tuple[int | None, ...],
        *,
        positive: bool = False,
        nonnegative: bool = False,
        below: float | None = None,
        at_most: float | None = None,
    ) -> np.ndarray:
        """A number (shape ``()``) or nested list of numbers of the given shape."""
        key = self.key(name)
        value = self.raw(name)
        try:
            array = np.array(value, dtype=float)
        except (TypeError, ValueError):
            raise self.error(key, f"must be numbers of shape {shape}, got {value!r}") from None
        if isinstance(value, bool) or _has_bool(value):
            raise self.error(key, "must be numbers, not true/false")
        if array.ndim != len(shape) or any(
            s is not None and s != n for s, n in zip(shape, array.shape, strict=True)
        ):
            want = "a number" if not shape else f"shape {tuple(s or 'n' for s in shape)}"
            raise self.error(key, f"must be {want}, got shape {array.shape}")
        if not np.all(np.isfinite(array)):
            raise self.error(key, "must be finite (no NaN or inf)")
        if positive and np.any(array <= 0):
            raise self.error(key, f"must be positive, got {value!r}")
        if nonnegative and np.any(array < 0):
            raise self.error(key, f"must not be negative, got {value!r}")
        if below is not None and np.any(array >= below):
            raise self.error(key, f"must be below {below}, got {value!r}")
        if at_most is not None and np.any(array > at_most):
            raise self.error(key, f"must be at most {at_most}, got {value!r}")
        return frozen_array(array)

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.taken)
        if unknown:
            raise self.error(self.key(unknown[0]), "unknown key")


def _has_bool(value: Any) -> bool:
    if isinstance(value, bool):
        return True
    if isinstance(value, list):
        return any(_has_bool(v) for v in value)
    return False
