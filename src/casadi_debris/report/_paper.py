"""The reference paper's figures and the tolerances within which ours reproduce them.

One data file, ``casadi_debris/data/paper_reference.toml``, holds every figure
the paper publishes that this toolkit reproduces: the report of
``casadi-debris reproduce``, the paper columns of ``casadi-debris model`` and
``casadi-debris budget``, and the tests read it here, so a tolerance changed in
the file changes everywhere. The file is read once and checked as a whole; a
malformed entry is refused with its key named.

Example
-------
>>> from casadi_debris.report._paper import paper_figure
>>> mass = paper_figure("mass_kg")
>>> mass.value, mass.accepted
(668.0, '±0.5')
>>> mass.accepts(668.4), mass.accepts(668.6)
(True, False)
>>> paper_figure("margins_sampled").accepts([14.1, 52.0, 4.0])  # delay below 5 s
False
"""

from __future__ import annotations

import functools
import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any, Literal, cast

from casadi_debris.errors import InputShapeError, PaperReferenceError

PAPER_REFERENCE_FILE = "paper_reference.toml"
"""Name of the data file in the package's ``data`` folder."""

ToleranceKind = Literal["abs", "rel", "range", "at_most", "at_least", "below"]
TOLERANCE_KINDS: tuple[ToleranceKind, ...] = (
    "abs",
    "rel",
    "range",
    "at_most",
    "at_least",
    "below",
)
ENTRY_FIELDS = ("title", "paper", "accepted", "value", "components", "tolerance", "table")


@dataclass(frozen=True)
class Tolerance:
    """How far a figure of ours may be from the paper's and still reproduce it.

    Parameters
    ----------
    kind : {"abs", "rel", "range", "at_most", "at_least", "below"}
        ``abs``: ``|ours - paper| <= bound``; ``rel``: ``|ours - paper| <=
        bound |paper|``; ``range``: ``bound[0] <= ours <= bound[1]``;
        ``at_most``: ``ours <= bound``; ``at_least``: ``ours >= bound``;
        ``below``: ``ours < bound``.
    bound : float or (float, float)
        In the figure's unit (``rel``: a fraction, 0.05 for 5 %).
    """

    kind: ToleranceKind
    bound: float | tuple[float, float]

    def accepts(self, ours: float | None, paper: float) -> bool:
        """Whether ``ours`` is accepted for the paper's ``paper`` (None or NaN never is)."""
        if ours is None or math.isnan(ours):
            return False
        if self.kind == "range":
            low, high = cast(tuple[float, float], self.bound)
            return low <= ours <= high
        bound = cast(float, self.bound)
        if self.kind == "abs":
            return abs(ours - paper) <= bound
        if self.kind == "rel":
            return abs(ours - paper) <= bound * abs(paper)
        if self.kind == "at_most":
            return ours <= bound
        if self.kind == "at_least":
            return ours >= bound
        return ours < bound


@dataclass(frozen=True)
class Component:
    """One number of a figure (a figure such as the inertia diagonal has several).

    Parameters
    ----------
    name : str
        ``"zz"``, ``"gain_margin_db"``; the figure's key for a single number.
    value : float
        The paper's number, in the figure's unit.
    tolerance : Tolerance or None
        None: shown beside ours, not judged.
    """

    name: str
    value: float
    tolerance: Tolerance | None

    def accepts(self, ours: float | None) -> bool | None:
        """Whether ``ours`` reproduces this number (None: not judged)."""
        return None if self.tolerance is None else self.tolerance.accepts(ours, self.value)


@dataclass(frozen=True)
class PaperFigure:
    """A figure of the paper, as the reproduction table shows and judges it.

    Parameters
    ----------
    key : str
        Its name, with its unit (``"torque_max_mNm"``).
    title : str
        The row's title in the report; ``{samples}`` is a field the caller fills.
    paper : str
        The paper's figure as printed (``"246 / 66 / 242"``).
    accepted : str
        The tolerance as printed (``"within 6 %"``); ``"—"`` when not judged.
    components : tuple of Component
        Its numbers, in the order ours are given.
    table : bool
        Whether it is a row of the reproduction table.
    """

    key: str
    title: str
    paper: str
    accepted: str
    components: tuple[Component, ...]
    table: bool = True

    @property
    def values(self) -> tuple[float, ...]:
        """The paper's numbers, one per component."""
        return tuple(c.value for c in self.components)

    @property
    def value(self) -> float:
        """The paper's number of a single-number figure."""
        if len(self.components) != 1:
            raise ValueError(f"{self.key} has {len(self.components)} numbers: use .values")
        return self.components[0].value

    @property
    def tolerance(self) -> Tolerance | None:
        """The tolerance shared by every component."""
        tolerances = {c.tolerance for c in self.components}
        if len(tolerances) != 1:
            raise ValueError(f"{self.key} has a tolerance per component: use .component(name)")
        return tolerances.pop()

    @property
    def judged(self) -> bool:
        """Whether any of its numbers has a tolerance."""
        return any(c.tolerance is not None for c in self.components)

    def component(self, name: str) -> Component:
        """The component called ``name``."""
        for component in self.components:
            if component.name == name:
                return component
        names = ", ".join(c.name for c in self.components)
        raise KeyError(f"{self.key} has no component {name!r} (it has {names})")

    def accepts(self, ours: float | Sequence[float | None] | None) -> bool | None:
        """Whether our numbers reproduce the figure.

        Parameters
        ----------
        ours : float or sequence of float
            One number per component, in the figure's unit; a missing number
            (None) or NaN fails its component.

        Returns
        -------
        bool or None
            True when every judged component is within its tolerance; None for
            a figure without tolerance.
        """
        if not self.judged:
            return None
        numbers = _as_numbers(ours)
        if len(numbers) != len(self.components):
            raise InputShapeError(
                f"{self.key}: {len(self.components)} number(s) expected, got {len(numbers)}"
            )
        verdicts = [c.accepts(x) for c, x in zip(self.components, numbers, strict=True)]
        return all(v for v in verdicts if v is not None)


def _as_numbers(ours: Any) -> tuple[float | None, ...]:
    if ours is None or isinstance(ours, int | float) or getattr(ours, "ndim", None) == 0:
        items = [ours]
    else:
        items = list(ours)
    return tuple(None if x is None else float(x) for x in items)


# ----------------------------------------------------------------------------- loading


def default_reference_path() -> Path:
    """Path of the shipped ``paper_reference.toml``."""
    return Path(str(resources.files("casadi_debris") / "data" / PAPER_REFERENCE_FILE))


@functools.cache
def paper_figures() -> Mapping[str, PaperFigure]:
    """Every figure of the shipped file by key, in the file's order (read once)."""
    return MappingProxyType(load_paper_reference())


def paper_figure(key: str) -> PaperFigure:
    """The shipped figure ``key`` (e.g. ``"mass_kg"``)."""
    figures = paper_figures()
    if key not in figures:
        raise KeyError(f"no paper figure {key!r}; known: {', '.join(figures)}")
    return figures[key]


def table_figures() -> tuple[PaperFigure, ...]:
    """The figures that are rows of the reproduction table, in the file's order."""
    return tuple(f for f in paper_figures().values() if f.table)


def load_paper_reference(path: str | Path | None = None) -> dict[str, PaperFigure]:
    """Read and check a paper reference file.

    Parameters
    ----------
    path : str or Path, optional
        The file; the shipped one by default.

    Returns
    -------
    dict of str to PaperFigure
        In the file's order.

    Raises
    ------
    PaperReferenceError
        The file cannot be read or parsed, or an entry is malformed (the
        message names its key).
    """
    source = Path(path) if path is not None else default_reference_path()
    try:
        data = tomllib.loads(source.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as error:
        raise PaperReferenceError("", f"cannot read: {error}", str(source)) from error
    if not data:
        raise PaperReferenceError("", "no figures", str(source))
    return {key: _figure(key, entry, str(source)) for key, entry in data.items()}


def _figure(key: str, entry: Any, source: str) -> PaperFigure:
    def fail(field: str, message: str) -> PaperReferenceError:
        return PaperReferenceError(f"{key}.{field}" if field else key, message, source)

    if not isinstance(entry, dict):
        raise fail("", "must be a table of title, paper, accepted, value, tolerance")
    unknown = sorted(set(entry) - set(ENTRY_FIELDS))
    if unknown:
        raise fail(unknown[0], f"unknown field (allowed: {', '.join(ENTRY_FIELDS)})")
    for field in ("title", "paper"):
        if not isinstance(entry.get(field), str) or not entry[field].strip():
            raise fail(field, "must be a non-empty string")
    values = _values(entry.get("value"), fail)
    names = _names(entry.get("components"), key, len(values), fail)
    tolerances = _tolerances(entry.get("tolerance"), len(values), fail)
    judged = any(t is not None for t in tolerances)
    accepted = entry.get("accepted", "—")
    if not isinstance(accepted, str) or (judged and not accepted.strip()):
        raise fail("accepted", "must be a non-empty string")
    if judged and "accepted" not in entry:
        raise fail("accepted", "missing: a judged figure says what is accepted")
    table = entry.get("table", True)
    if not isinstance(table, bool):
        raise fail("table", "must be true or false")
    if table and not judged:
        raise fail("tolerance", "missing: a row of the reproduction table needs one")
    components = tuple(
        Component(n, v, t) for n, v, t in zip(names, values, tolerances, strict=True)
    )
    return PaperFigure(key, entry["title"], entry["paper"], accepted, components, table)


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value) if math.isfinite(value) else None


def _values(value: Any, fail: Any) -> list[float]:
    items = value if isinstance(value, list) else [value]
    numbers = [_number(v) for v in items]
    if not numbers or any(n is None for n in numbers):
        raise fail("value", "must be a finite number or a non-empty list of them")
    return cast(list[float], numbers)


def _names(components: Any, key: str, count: int, fail: Any) -> list[str]:
    if components is None:
        if count != 1:
            raise fail("components", f"missing: name the {count} numbers of `value`")
        return [key]
    if (
        not isinstance(components, list)
        or len(components) != count
        or not all(isinstance(c, str) and c for c in components)
        or len(set(components)) != count
    ):
        raise fail("components", f"must be {count} distinct names, one per number of `value`")
    return components


def _tolerances(tolerance: Any, count: int, fail: Any) -> list[Tolerance | None]:
    if tolerance is None:
        return [None] * count
    if isinstance(tolerance, dict):
        return [_tolerance(tolerance, fail)] * count
    if not isinstance(tolerance, list) or len(tolerance) != count:
        raise fail("tolerance", f"must be one table or a list of {count} (one per number)")
    return [_tolerance(t, fail) for t in tolerance]


def _tolerance(table: Any, fail: Any) -> Tolerance | None:
    kinds = ", ".join(TOLERANCE_KINDS)
    if not isinstance(table, dict):
        raise fail("tolerance", f"must be a table with one of {kinds}")
    if not table:
        return None
    if len(table) != 1 or next(iter(table)) not in TOLERANCE_KINDS:
        raise fail("tolerance", f"must have exactly one of {kinds}, got {', '.join(table)}")
    kind, bound = next(iter(table.items()))
    if kind == "range":
        pair = [_number(b) for b in bound] if isinstance(bound, list) else []
        if len(pair) != 2 or None in pair or cast(float, pair[0]) > cast(float, pair[1]):
            raise fail("tolerance", "range must be [low, high] with finite low <= high")
        return Tolerance("range", (cast(float, pair[0]), cast(float, pair[1])))
    number = _number(bound)
    if number is None:
        raise fail("tolerance", f"{kind} must be a finite number")
    if kind in ("abs", "rel") and number < 0:
        raise fail("tolerance", f"{kind} must be >= 0")
    return Tolerance(kind, number)
