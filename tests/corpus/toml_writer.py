"""A small TOML writer for parsed TOML data (``tomllib`` only reads)."""

from __future__ import annotations

import math
import re
from typing import Any

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def toml_key(key: str) -> str:
    return key if _BARE_KEY.fullmatch(key) else toml_string(key)


def toml_string(text: str) -> str:
    """A basic TOML string of ``text`` (control characters escaped)."""
    out = ['"']
    for ch in text:
        code = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\t":
            out.append("\\t")
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04x}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        inner = ", ".join(f"{toml_key(k)} = {toml_value(v)}" for k, v in value.items())
        return "{ " + inner + " }" if inner else "{}"
    raise TypeError(f"no TOML for {value!r}")


def is_table_array(value: Any) -> bool:
    """A non-empty list of tables (written as ``[[...]]``)."""
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def toml_dumps(data: dict[str, Any]) -> str:
    """TOML text for parsed TOML data (tables as headers, arrays of tables as [[...]]).

    An entry of an array of tables is written like a table, its own tables and
    arrays of tables under it (``[[arrays]]`` then ``[[arrays.modes]]``).
    """
    lines: list[str] = []

    def table(prefix: tuple[str, ...], body: dict[str, Any], header: str = "[{}]") -> None:
        if prefix:
            lines.append("")
            lines.append(header.format(".".join(toml_key(k) for k in prefix)))
        for key, value in body.items():
            if not isinstance(value, dict) and not is_table_array(value):
                lines.append(f"{toml_key(key)} = {toml_value(value)}")
        for key, value in body.items():
            if isinstance(value, dict):
                table((*prefix, key), value)
        for key, value in body.items():
            if is_table_array(value):
                for item in value:
                    table((*prefix, key), item, "[[{}]]")

    table((), data)
    return "\n".join(lines) + "\n"
