"""What a Monte-Carlo campaign varies: ``[[montecarlo.vary]]``, checked against the problem.

Each entry names a quantity and a distribution::

    [[montecarlo.vary]]
    path = "environment.density_kg_m3"       # any real-valued key of the problem file
    distribution = "uniform"
    low = 1e-13
    high = 5e-12

    [[montecarlo.vary]]
    path = "mass_kg"                         # a model parameter (varied in the compiled step)
    distribution = "normal"
    mean = 668.0
    sigma = 20.0                             # truncated to [low, high] when given

A path without a dot is a model parameter (checked against the model when a
campaign builds its cases). Any other path is a key of the problem file,
written as the loader's messages write it (``arrays[0].modes[0].omega_rad_s``,
``disturbance.amplitude_mNm[2]`` for one element of an array; indices from
0). Such a key is checked here by reading the problem again with the key set
to the distribution's bounds, so whatever the readers accept (their ranges,
their checks across tables) is what a campaign may vary, with no list of
keys to keep up to date: a key added to a reader can be varied at once.
Every case of a campaign that varies file keys rebuilds its problem the same
way (:func:`problem_with_values`), and its model.
"""

from __future__ import annotations

import copy
import dataclasses
import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from casadi_debris.config import limits
from casadi_debris.config._schema import DISTRIBUTIONS, Problem, VariedQuantity
from casadi_debris.config._table import Table, recording, show
from casadi_debris.errors import ProblemFileError

ProblemReader = Callable[[Mapping[str, Any], str | None], Problem]
"""Reads a problem from its TOML tables and the file's name (``problem_from_dict``)."""

_SEGMENT = re.compile(r"([A-Za-z_][A-Za-z0-9_]{0,63})((?:\[\d{1,6}\])*)")
_INDEX = re.compile(r"\[(\d+)\]")
PathPart = str | int
NORMAL_CHECKED_SIGMAS = 4.0
# A path without a dot names a model parameter (see casadi_debris.dynamics.ParameterLayout).
_PARAMETER = re.compile(
    r"inertia_scale_[xyz]|mass_kg|array\d{0,3}_angle_offset_rad|bending_frequency_scale"
)


def read_vary(t: Table) -> tuple[VariedQuantity, ...]:
    """The ``[[montecarlo.vary]]`` entries, each checked on its own (not yet against the keys)."""
    entries = tuple(_read_entry(e) for e in t.tables("vary", limits.MAX_VARIED_QUANTITIES))
    seen: set[str] = set()
    for i, entry in enumerate(entries):
        if entry.path in seen:
            raise t.error(f"{t.key('vary')}[{i}].path", f"{entry.path} is varied twice")
        seen.add(entry.path)
    corners = sum(e.distribution == "corners" for e in entries)
    if corners > limits.MAX_VARIED_CORNERS:
        raise t.error(
            t.key("vary"),
            f"{corners} quantities with corners make 2^{corners} cases; "
            f"at most {limits.MAX_VARIED_CORNERS}",
        )
    return entries


def _read_entry(t: Table) -> VariedQuantity:
    path = t.text("path")
    try:
        parts = parse_path(path)
    except ValueError as exc:
        raise t.error(t.key("path"), str(exc)) from None
    if len(parts) == 1 and not _PARAMETER.fullmatch(path):
        raise t.error(
            t.key("path"),
            f"{show(path)} is neither a model parameter (inertia_scale_x, _y, _z, mass_kg, "
            "array_angle_offset_rad, bending_frequency_scale) nor a dotted key of the problem",
        )
    distribution = t.text("distribution", DISTRIBUTIONS)
    bounds = limits.VARIED_VALUE
    low = t.number("low", bounds) if t.has("low") or distribution != "normal" else None
    high = t.number("high", bounds) if t.has("high") or distribution != "normal" else None
    mean = sigma = None
    if distribution == "normal":
        mean = t.number("mean", bounds)
        sigma = t.number("sigma", limits.Range(0.0, bounds.high, low_open=True))
        if low is not None and mean < low:
            raise t.error(t.key("mean"), f"must be at least low = {low:g}, got {mean:g}")
        if high is not None and mean > high:
            raise t.error(t.key("mean"), f"must be at most high = {high:g}, got {mean:g}")
    if low is not None and high is not None and not low < high:
        raise t.error(t.key("high"), f"must be above low = {low:g}, got {high:g}")
    t.done()
    return VariedQuantity(path, distribution, low, high, mean, sigma)


def parse_path(path: str) -> list[PathPart]:
    """``"arrays[0].modes[1].omega_rad_s"`` -> ``["arrays", 0, "modes", 1, "omega_rad_s"]``.

    Raises
    ------
    ValueError
        Not a dotted key with optional ``[index]`` suffixes.
    """
    parts: list[PathPart] = []
    for segment in path.split("."):
        match = _SEGMENT.fullmatch(segment)
        if match is None:
            raise ValueError(
                f"{show(path)} is not a dotted key such as environment.density_kg_m3 or "
                "disturbance.amplitude_mNm[2] (nor a model parameter name)"
            )
        parts.append(match[1])
        parts.extend(int(i) for i in _INDEX.findall(match[2]))
    return parts


def key_of(parts: Sequence[PathPart]) -> str:
    """The dotted key of ``parts``, as the loader's messages write it."""
    text = ""
    for part in parts:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


def with_value(data: Mapping[str, Any], parts: Sequence[PathPart], value: float) -> dict[str, Any]:
    """A deep copy of ``data`` with the key at ``parts`` set to ``value`` (tables made as needed).

    Raises
    ------
    ValueError
        A part of the path is not a table, or an index past the end of its array.
    """
    root = copy.deepcopy(dict(data))
    node: Any = root
    for k, part in enumerate(parts):
        last = k == len(parts) - 1
        where = key_of(parts[:k]) or "the problem"
        if isinstance(part, int):
            if not isinstance(node, list) or part >= len(node):
                count = len(node) if isinstance(node, list) else 0
                raise ValueError(f"{where} has no entry [{part}] ({count} entries)")
            if last:
                node[part] = value
            else:
                node = node[part]
            continue
        if not isinstance(node, dict):
            raise ValueError(f"{where} is not a table, so it has no key {part}")
        if last:
            node[part] = value
        else:
            node = node.setdefault(part, {})
    return root


def without_vary(data: Mapping[str, Any]) -> dict[str, Any]:
    """``data`` without ``[[montecarlo.vary]]`` (a problem rebuilt for a case does not vary)."""
    trimmed = dict(data)
    montecarlo = trimmed.get("montecarlo")
    if isinstance(montecarlo, Mapping) and "vary" in montecarlo:
        trimmed["montecarlo"] = {k: v for k, v in montecarlo.items() if k != "vary"}
    return trimmed


def resolve_vary(t: Table, problem: Problem, read: ProblemReader) -> tuple[VariedQuantity, ...]:
    """Check every file key of ``problem.montecarlo.vary`` against the problem's readers.

    Each key must be a real number (or one element of an array of numbers) the
    readers take, and the problem must stay valid with the key at each bound
    of its distribution. A normal distribution without bounds is truncated to
    the key's allowed range.

    Parameters
    ----------
    t : Table
        The ``[montecarlo]`` table (errors name ``montecarlo.vary[i].<field>``).
    problem : Problem
        Validated, with its ``data``.
    read : callable
        The problem reader (``problem_from_dict``), passed in because it is the reader
        that calls this check.

    Returns
    -------
    tuple of VariedQuantity
        The entries, normal bounds filled in.
    """
    base = without_vary(problem.data)
    return tuple(
        entry
        if entry.is_parameter
        else _resolve(f"{t.key('vary')}[{i}]", entry, base, t.source, read)
        for i, entry in enumerate(problem.montecarlo.vary)
    )


def _resolve(
    where: str,
    entry: VariedQuantity,
    base: Mapping[str, Any],
    source: str | None,
    read: ProblemReader,
) -> VariedQuantity:
    parts = parse_path(entry.path)
    if parts[0] == "montecarlo":
        raise ProblemFileError(f"{where}.path", "a campaign cannot vary its own settings", source)
    first = "low" if entry.distribution != "normal" else "mean"
    value = entry.low if first == "low" else entry.mean
    assert value is not None  # read_vary asks for it
    allowed = _probe(where, first, entry, parts, value, (base, source, read))
    for name in ("low", "high", "mean"):
        given = getattr(entry, name)
        problem_text = None if given is None else allowed.violation(given)
        if problem_text is not None:
            raise ProblemFileError(
                f"{where}.{name}", f"{entry.path} {problem_text}, got {given:g}", source
            )
    if entry.distribution == "normal":
        mean, sigma = float(entry.mean or 0.0), float(entry.sigma or 0.0)
        low = allowed.low if entry.low is None else entry.low
        high = allowed.high if entry.high is None else entry.high
        entry = dataclasses.replace(entry, low=low, high=high)
        # The problem must stay valid over mean +- 4 sigma (a case beyond, one in 16 000,
        # is recorded as failed if a check across tables refuses it).
        spread = NORMAL_CHECKED_SIGMAS * sigma
        checks = {"low": max(low, mean - spread), "high": min(high, mean + spread)}
    else:
        checks = {"high": float(entry.high or 0.0)}
    for name, bound in checks.items():
        if bound != value:
            _probe(where, name, entry, parts, bound, (base, source, read))
    return entry


def _probe(
    where: str,
    field: str,
    entry: VariedQuantity,
    parts: list[PathPart],
    value: float,
    problem: tuple[Mapping[str, Any], str | None, ProblemReader],
) -> limits.Range:
    """Read the problem with the key at ``value``; the key's allowed range.

    Raises
    ------
    ProblemFileError
        Naming ``<where>.path`` when the key is not a real number the readers take,
        ``<where>.<field>`` when the problem refuses ``value``.
    """
    base, source, problem_from_dict = problem
    try:
        data = with_value(base, parts, value)
    except ValueError as exc:
        raise ProblemFileError(f"{where}.path", f"{entry.path}: {exc}", source) from None
    with recording() as calls:
        try:
            problem_from_dict(data, source)
            refused = None
        except ProblemFileError as exc:
            refused = exc
    spec = _key_spec(where, entry.path, parts, dict(calls), source)
    if refused is not None:
        unknown = spec is None or "unknown key" in str(refused)
        raise ProblemFileError(
            f"{where}.{'path' if unknown else field}",
            f"{entry.path} = {value:g} is refused: {_bare(refused)}",
            source,
        )
    if spec is None:
        raise ProblemFileError(
            f"{where}.path", f"{entry.path} is not a key the problem reads", source
        )
    return spec


def _key_spec(
    where: str, path: str, parts: list[PathPart], recorded: dict[str, Any], source: str | None
) -> limits.Range | None:
    """The range of the real number at ``parts`` from what the readers asked of its key
    (None: the readers did not take it)."""
    for elements in range(len(parts)):
        if elements and not isinstance(parts[len(parts) - elements], int):
            break
        spec = recorded.get(key_of(parts[: len(parts) - elements]))
        if spec is None:
            continue
        kind, shape = spec.get("kind"), tuple(spec.get("shape", ()))
        if kind != "array":
            what = "an integer" if kind == "integer" else f"not a number ({kind})"
            raise ProblemFileError(
                f"{where}.path", f"{path} is {what}; only real-valued keys can vary", source
            )
        if len(shape) != elements:
            key = key_of(parts[: len(parts) - elements])
            what = f"an array of shape {shape}" if shape else "a number"
            hint = f"; vary one element, e.g. {key}{'[0]' * len(shape)}" if shape else ""
            raise ProblemFileError(f"{where}.path", f"{key} is {what}{hint}", source)
        bounds: limits.Range = spec["bounds"]
        return bounds
    return None


def _bare(error: ProblemFileError) -> str:
    """The error's key and message, without the file's name."""
    text = str(error)
    prefix = f"{error.source}: " if error.source else ""
    return text.removeprefix(prefix)
