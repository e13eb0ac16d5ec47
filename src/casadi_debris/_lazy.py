"""Names a package exports but imports on first use (so importing it stays quick)."""

from __future__ import annotations

import ast
import importlib
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any


def lazy_exports(
    package: str, table: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module ``__getattr__`` and ``__dir__`` of ``package`` for the names of ``table``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    table : Mapping
        Each exported name and the module that defines it.

    Returns
    -------
    tuple
        ``(__getattr__, __dir__)``: the first imports the name's module on first use and
        keeps the value in the package's namespace, so it runs once per name.
    """
    namespace = vars(sys.modules[package])

    def __getattr__(name: str) -> Any:  # noqa: N807 (the module hook's name)
        if name in table:
            value = getattr(importlib.import_module(table[name]), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:  # noqa: N807
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__


def type_checking_imports(init_file: str) -> dict[str, str]:
    """Each name a package's ``if TYPE_CHECKING:`` block imports, and its module.

    The block (which type checkers read) is then the one list of where each exported
    name lives: the lazy table is derived from it, not written beside it.

    Parameters
    ----------
    init_file : str
        The package's ``__init__.py`` (its ``__file__``).

    Returns
    -------
    dict
        ``{name: module}`` in the block's order.
    """
    tree = ast.parse(Path(init_file).read_text(encoding="utf-8"))
    table: dict[str, str] = {}
    for node in tree.body:
        if isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING":
            for statement in node.body:
                if isinstance(statement, ast.ImportFrom) and statement.module:
                    for alias in statement.names:
                        table[alias.asname or alias.name] = statement.module
    return table
