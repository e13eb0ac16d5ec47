"""Typed results and their one JSON form.

Every result a user gets (a closed-loop run, a campaign case, a slew, a
synthesis, a reproduction row) is a frozen dataclass deriving from
:class:`Record`. Its fields are what the user reads, in the units and the
numbering (CubeSats, engines and stages from 1) of the JSON it becomes, so that
``to_json`` is the fields themselves and ``from_json`` reads them back:

>>> from dataclasses import dataclass
>>> @dataclass(frozen=True)
... class Verdict(Record):
...     name: str
...     error_deg: float | None
...     met: bool
>>> Verdict("slew", 0.45, True).to_json()
{'name': 'slew', 'error_deg': 0.45, 'met': True}
>>> Verdict.from_json({"name": "slew", "error_deg": None, "met": False})
Verdict(name='slew', error_deg=None, met=False)

A field declared ``field(metadata=FLATTENED)`` holds another record whose keys are written into
its parent's (a campaign case is its identity and its run's figures, in one
flat row); a flattened ``dict`` field holds the keys no other field claims
(settings that differ from one method to another). A field declared
``field(default=None, metadata=OPTIONAL)`` is left out of the JSON when None and
None when its key is missing (a stage that did not run). Non-finite floats become
``null``, numpy values plain numbers and lists.
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from typing import Any, Self, TypeVar, Union

import numpy as np

T = TypeVar("T")
FLATTEN = "records.flatten"
# ``field(metadata=FLATTENED)``: the field's record writes its keys into its parent's object.
FLATTENED = types.MappingProxyType({FLATTEN: True})
OMIT = "records.omit_none"
# ``field(default=None, metadata=OPTIONAL)``: no key at all when the value is None.
OPTIONAL = types.MappingProxyType({OMIT: True})


class Record:
    """A result with one JSON form: :meth:`to_json` and :meth:`from_json`."""

    def to_json(self) -> dict[str, Any]:
        """The record as JSON-ready builtins (dict, list, str, float, int, bool, None)."""
        value = to_jsonable(self)
        assert isinstance(value, dict)
        return value

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Self:
        """The record ``to_json`` wrote (extra keys are an error)."""
        return from_jsonable(cls, data)


def to_jsonable(value: Any) -> Any:
    """``value`` as JSON-ready builtins: dataclasses by field, numpy as lists and numbers."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        out: dict[str, Any] = {}
        for field in dataclasses.fields(value):
            if field.metadata.get(OMIT) and getattr(value, field.name) is None:
                continue
            item = to_jsonable(getattr(value, field.name))
            if field.metadata.get(FLATTEN):
                out.update(item)
            else:
                out[field.name] = item
        return out
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    return value


def from_jsonable(kind: type[T], data: Any) -> T:
    """Rebuild a value of type ``kind`` from what :func:`to_jsonable` made of it."""
    return typing.cast(T, _convert(kind, data))


def _convert(kind: Any, data: Any) -> Any:
    origin = typing.get_origin(kind)
    if kind is Any:
        return data
    if origin in (Union, types.UnionType):
        options = [a for a in typing.get_args(kind) if a is not type(None)]
        if data is None:
            return None
        return _convert(options[0], data) if len(options) == 1 else data
    if origin is typing.Literal:
        return data
    if isinstance(kind, type) and dataclasses.is_dataclass(kind):
        return kind(**_fields_of(kind, data))
    if origin is tuple:
        args = typing.get_args(kind)
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_convert(args[0], v) for v in data)
        return tuple(_convert(a, v) for a, v in zip(args, data, strict=True))
    if origin is list:
        return [_convert(typing.get_args(kind)[0], v) for v in data]
    if origin is dict:
        value_kind = typing.get_args(kind)[1]
        return {k: _convert(value_kind, v) for k, v in data.items()}
    if kind is np.ndarray:
        return np.asarray(data, dtype=float)
    if kind is float:
        return math.nan if data is None else float(data)
    return data


def _fields_of(kind: Any, data: dict[str, Any]) -> dict[str, Any]:
    """Constructor arguments of dataclass ``kind`` from its (possibly flattened) JSON.

    A flattened field of type ``dict`` takes every key no other field claims.
    """
    hints = typing.get_type_hints(kind)
    values: dict[str, Any] = {}
    used: set[str] = set()
    rest: str | None = None
    for field in dataclasses.fields(kind):
        inner = hints[field.name]
        if field.metadata.get(FLATTEN) and typing.get_origin(inner) is dict:
            rest = field.name
        elif field.metadata.get(FLATTEN):
            names = _json_keys(inner)
            values[field.name] = _convert(inner, {k: data[k] for k in names if k in data})
            used |= names
        elif field.name in data:
            values[field.name] = _convert(inner, data[field.name])
            used.add(field.name)
    extra = {k: v for k, v in data.items() if k not in used}
    if rest is not None:
        values[rest] = _convert(hints[rest], extra)
    elif extra:
        raise ValueError(f"{kind.__name__}: unknown field(s) {', '.join(sorted(extra))}")
    return values


def _json_keys(kind: Any) -> set[str]:
    """The keys a dataclass's JSON object has (flattened fields' keys included)."""
    hints = typing.get_type_hints(kind)
    keys: set[str] = set()
    for field in dataclasses.fields(kind):
        if field.metadata.get(FLATTEN) and typing.get_origin(hints[field.name]) is not dict:
            keys |= _json_keys(hints[field.name])
        elif not field.metadata.get(FLATTEN):
            keys.add(field.name)
    return keys
