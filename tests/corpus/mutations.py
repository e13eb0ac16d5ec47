"""Mutations of a parsed problem: every node (table, list, number, string) changed or deleted.

Each mutation is ``(op, path, description, new value or DELETE, expectation)``.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Iterator
from typing import Any

from .expectations import (
    DELETE_EITHER,
    DELETE_OK,
    DROP_LAST_OK,
    DUPLICATE_ITEM,
    EMPTY_ARRAY_OK,
    EMPTY_TABLE_OK,
    FLIP_OK,
    HUGE_INT_EITHER,
    NEGATIVE_OK,
    TINY_REJECT,
    ZERO_EITHER,
    ZERO_OK,
    Path_,
    dotted,
    item_key,
    plain_key,
)
from .toml_writer import is_table_array

DELETE = object()

Change = tuple[str, str, Any, str]  # op, description, new value, expectation


def get_path(data: Any, path: Path_) -> Any:
    for part in path:
        data = data[part]
    return data


def set_path(data: Any, path: Path_, value: Any) -> None:
    get_path(data, path[:-1])[path[-1]] = value


def _delete(data: Any, path: Path_) -> None:
    del get_path(data, path[:-1])[path[-1]]


def apply_mutation(data: dict[str, Any], path: Path_, new: Any) -> dict[str, Any]:
    """A copy of ``data`` with ``path`` set to ``new`` (or deleted: :data:`DELETE`)."""
    out = copy.deepcopy(data)
    if new is DELETE:
        _delete(out, path)
    else:
        set_path(out, path, copy.deepcopy(new))
    return out


def same_value(a: Any, b: Any) -> bool:
    return type(a) is type(b) and a == b


def _leaves(data: Any, path: Path_ = ()) -> Iterator[tuple[Path_, Any]]:
    """Every node of the data: tables, lists and scalars, depth first."""
    yield path, data
    if isinstance(data, dict):
        for key, value in data.items():
            yield from _leaves(value, (*path, key))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from _leaves(value, (*path, i))


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _number_mutations(path: Path_, value: Any) -> Iterator[Change]:
    """(op, description, new value, expectation) for a number."""
    key = plain_key(path)
    is_int = isinstance(value, int)

    def zero_expect() -> str:
        if key in ZERO_OK:
            return "ok"
        return "either" if key in ZERO_EITHER else "reject"

    yield "zero", "0", (0 if is_int else 0.0), zero_expect()
    negative = -abs(value) if value != 0 else (-1 if is_int else -1.0)
    neg_expect = "ok" if key in NEGATIVE_OK else "reject"
    yield "negative", repr(negative), negative, neg_expect
    yield "nan", "nan", math.nan, "reject"
    yield "inf", "inf", math.inf, "reject"
    yield "-inf", "-inf", -math.inf, "reject"
    yield "1e308", "1e308", 1e308, "reject"
    yield "huge-int", "10**18", 10**18, "either" if key in HUGE_INT_EITHER else "reject"
    yield "numeric-string", f'"{value}"', str(value), "reject"
    yield "bool", "true", True, "reject"
    yield "table-for-number", f"{{ value = {value} }}", {"value": value}, "reject"
    if not isinstance(path[-1], int):
        yield "list-for-number", f"[{value}]", [value], "reject"
    if is_int:
        yield "float-for-int", f"{value + 0.5}", value + 0.5, "reject"
    else:
        tiny_expect = "reject" if key in TINY_REJECT else "either"
        yield "tiny", "1e-300", 1e-300, tiny_expect
        if float(value).is_integer() and abs(value) < 1e15:
            yield "int-for-float", f"{int(value)} (integer)", int(value), "ok"


def _list_mutations(path: Path_, value: list[Any]) -> Iterator[Change]:
    """Wrong lengths and nesting of a list of numbers or strings."""
    yield "empty-list", "[]", [], "reject"
    drop_expect = "ok" if plain_key(path) in DROP_LAST_OK else "reject"
    yield "drop-last", f"last of {len(value)} dropped", value[:-1], drop_expect
    yield "append", "one more element", [*value, copy.deepcopy(value[-1])], "reject"
    yield "scalar-for-list", f"{value[0]!r} (no list)", copy.deepcopy(value[0]), "reject"
    yield "extra-nesting", "[[...]]", [copy.deepcopy(value)], "reject"
    if all(_is_number(v) for v in value):
        yield "string-list", "elements as strings", [str(v) for v in value], "reject"
    if isinstance(value[0], list):
        ragged = copy.deepcopy(value)
        ragged[0] = ragged[0][:-1]
        yield "ragged", "first row one short", ragged, "reject"


_BAD_NAMES = (
    ("name-parent", '"../x"', "../x"),
    ("name-parent-deep", '"../../../../x"', "../../../../x"),
    ("name-parent-deeper", '"../../../../../../x"', "../../../../../../x"),
    ("name-slash", '"a/b"', "a/b"),
    ("name-empty", '""', ""),
    ("name-dot", '"."', "."),
    ("name-dotdot", '".."', ".."),
    ("name-long", "5000 characters", "n" * 5000),
    ("name-newline", '"a\\nb"', "a\nb"),
    ("name-nul", '"a\\u0000b"', "a\x00b"),
    ("name-absolute", "absolute path into the run folder", "{RUNDIR}/absolute"),
    ("name-backslash", '"a\\\\..\\\\b"', "a\\..\\b"),
)


def _string_mutations(path: Path_, value: str) -> Iterator[Change]:
    key = plain_key(path)
    if key == "name":
        for op, desc, new in _BAD_NAMES:
            yield op, desc, new, "reject"
        yield "name-valid", '"paper-variant_2"', "paper-variant_2", "ok"
        return
    if key == "description":
        yield "description-newline", '"a\\nb"', "a\nb", "either"
        yield "description-empty", '""', "", "either"
        yield "description-long", "100000 characters", "d" * 100_000, "either"
        yield "number-for-string", "5", 5, "reject"
        return
    if key.endswith(".name"):  # a mode's name: a label
        yield "empty-string", '""', "", "either"
        yield "number-for-string", "5", 5, "reject"
        return
    yield "junk-string", '"junk"', "junk", "reject"
    yield "empty-string", '""', "", "reject"
    yield "number-for-string", "5", 5, "reject"
    yield "bool-for-string", "true", True, "reject"
    yield "upper-case", repr(value.upper()), value.upper(), "either"
    if value in _SIGNED_AXES:
        yield "unsigned-axis", repr(value[1]), value[1], "reject"
    if value in _SIGNED_AXES and key.endswith(".direction"):  # an axis or a 3-vector
        yield "axis-as-vector", f"{_axis_vector(value)}", _axis_vector(value), "ok"
        yield "zero-vector", "[0.0, 0.0, 0.0]", [0.0, 0.0, 0.0], "reject"


_SIGNED_AXES = ("+x", "-x", "+y", "-y", "+z", "-z")


def _axis_vector(axis: str) -> list[float]:
    """``"-z"`` as ``[0.0, 0.0, -1.0]``."""
    vector = [0.0, 0.0, 0.0]
    vector["xyz".index(axis[1])] = 1.0 if axis[0] == "+" else -1.0
    return vector


def _bool_mutations(path: Path_, value: bool) -> Iterator[Change]:
    """A switch flipped, or given as a number or a string."""
    flipped = "true" if not value else "false"
    yield "flip-bool", flipped, not value, "ok" if plain_key(path) in FLIP_OK else "reject"
    yield "number-for-bool", "1", 1, "reject"
    yield "string-for-bool", f'"{str(value).lower()}"', str(value).lower(), "reject"


def _table_mutations(path: Path_, value: dict[str, Any]) -> Iterator[Change]:
    key = plain_key(path)
    yield "number-for-table", "1", 1, "reject"
    yield "string-for-table", '"x"', "x", "reject"
    yield "list-for-table", "[]", [], "reject"
    yield "empty-table", "{}", {}, "ok" if key in EMPTY_TABLE_OK else "reject"
    unknown = dict(value)
    unknown["bogus_key"] = 1.0
    yield "unknown-key", "bogus_key = 1.0 added", unknown, "reject"
    first = next((k for k, v in value.items() if not isinstance(v, dict | list)), None)
    if first is not None:
        renamed = {(k + "s" if k == first else k): v for k, v in value.items()}
        yield "misspelled-key", f"{first} -> {first}s", renamed, "reject"
        upper = {(k.upper() if k == first else k): v for k, v in value.items()}
        yield "upper-case-key", f"{first} -> {first.upper()}", upper, "reject"


def _is_item(path: Path_, data: dict[str, Any]) -> bool:
    """Is ``path`` an entry of an array of tables (``arrays[1]``, ``arrays[0].modes[2]``)?"""
    return isinstance(path[-1], int) and is_table_array(get_path(data, path[:-1]))


def _delete_expect(path: Path_, data: dict[str, Any]) -> str:
    key = item_key(path) if _is_item(path, data) else plain_key(path)
    if key in DELETE_OK:
        return "ok"
    if key in DELETE_EITHER:
        return "either"
    if key == "simulation.reference":
        return "reject" if "slew" in data.get("simulation", {}) else "ok"
    return "reject"


def _changes(path: Path_, value: Any) -> Iterator[tuple[str, str, Any, str]]:
    """(op, description with the key, new value, expectation) of one node, not deleted."""
    key = dotted(path)
    if _is_number(value):
        for op, desc, new, expect in _number_mutations(path, value):
            yield op, f"{key} = {desc}", new, expect
    elif isinstance(value, bool):
        for op, desc, new, expect in _bool_mutations(path, value):
            yield op, f"{key} = {desc}", new, expect
    elif isinstance(value, str):
        for op, desc, new, expect in _string_mutations(path, value):
            yield op, f"{key} = {desc}", new, expect
    elif isinstance(value, list) and value and not is_table_array(value):
        for op, desc, new, expect in _list_mutations(path, value):
            yield op, f"{key}: {desc}", new, expect
    elif is_table_array(value):
        plain = plain_key(path)
        yield "table-for-array", f"{key}: one table", copy.deepcopy(value[0]), "reject"
        empty_expect = "ok" if plain in EMPTY_ARRAY_OK else "reject"
        yield "empty-array", f"{key} = []", [], empty_expect
        dup = [*copy.deepcopy(value), copy.deepcopy(value[0])]
        dup_expect = DUPLICATE_ITEM.get(plain, "reject")
        yield "duplicate-item", f"{key}: first entry twice", dup, dup_expect
    elif isinstance(value, dict):
        for op, desc, new, expect in _table_mutations(path, value):
            yield op, f"[{key}] {desc}", new, expect


def mutations(
    data: dict[str, Any], under: Path_ = ()
) -> Iterator[tuple[str, Path_, str, Any, str]]:
    """(op, path, description, new value or DELETE, expectation) for every node.

    Keys and entries of arrays of tables are deleted too; with ``under``, only
    the nodes on that path and below it.
    """
    for path, value in _leaves(data):
        if not path or path[: len(under)] != under[: len(path)]:
            continue
        if isinstance(path[-1], str) or _is_item(path, data):
            desc = f"{dotted(path)} deleted"
            yield "delete", path, desc, DELETE, _delete_expect(path, data)
        for op, desc, new, expect in _changes(path, value):
            yield op, path, desc, new, expect
