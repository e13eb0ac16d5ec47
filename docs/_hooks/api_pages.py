"""MkDocs hook: the API reference pages, generated from the navigation.

Every ``reference/<name>.md`` entry of ``nav`` in ``mkdocs.yml`` that has no file
in ``docs/`` becomes a page documenting ``casadi_debris.<name>``: the package's
docstring, then each public module in it (files not starting with ``_``), found on
disk, so a new module appears without editing anything. ``reference/index.md``,
if listed and missing, becomes a table of the listed packages with the first line
of each docstring. The list in ``nav`` is the only list.

Nothing is imported from the package and nothing is written to ``docs/``: the
pages exist only in the build (``File.generated``).
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Any

from mkdocs.config.defaults import MkDocsConfig
from mkdocs.structure.files import File, Files

PACKAGE = "casadi_debris"
SOURCE = Path(__file__).resolve().parents[2] / "src" / PACKAGE
PREFIX = "reference/"


def _nav_paths(nav: Any) -> list[str]:
    """Every page path in a ``nav`` value, depth first, in order."""
    if isinstance(nav, str):
        return [nav]
    if isinstance(nav, dict):
        return [path for value in nav.values() for path in _nav_paths(value)]
    if isinstance(nav, list):
        return [path for item in nav for path in _nav_paths(item)]
    return []


def _source(name: str) -> Path:
    """The package folder or module file of ``casadi_debris.<name>``."""
    folder = SOURCE / name
    if (folder / "__init__.py").is_file():
        return folder
    module = SOURCE / f"{name}.py"
    if module.is_file():
        return module
    raise FileNotFoundError(f"{PREFIX}{name}.md: no package or module {PACKAGE}.{name}")


def _summary(path: Path) -> str:
    """First line of a module's docstring."""
    file = path / "__init__.py" if path.is_dir() else path
    docstring = ast.get_docstring(ast.parse(file.read_text(encoding="utf-8"))) or ""
    return docstring.strip().splitlines()[0] if docstring.strip() else ""


def _modules(folder: Path, dotted: str) -> list[str]:
    """Public modules below a package folder, sorted, subpackages included."""
    found = []
    for path in sorted(folder.iterdir()):
        if path.name.startswith("_"):
            continue
        if path.suffix == ".py":
            found.append(f"{dotted}.{path.stem}")
        elif (path / "__init__.py").is_file():
            found.append(f"{dotted}.{path.name}")
            found.extend(_modules(path, f"{dotted}.{path.name}"))
    return found


def _defines(folder: Path) -> bool:
    """Whether a package's ``__init__.py`` defines functions or classes of its own."""
    tree = ast.parse((folder / "__init__.py").read_text(encoding="utf-8"))
    return any(isinstance(node, ast.FunctionDef | ast.ClassDef) for node in tree.body)


def _directive(identifier: str, **options: object) -> str:
    lines = [f"::: {identifier}"]
    if options:
        lines.append("    options:")
        lines.extend(f"      {key}: {str(value).lower()}" for key, value in options.items())
    return "\n".join(lines) + "\n"


def package_page(name: str) -> str:
    """Markdown of the reference page of ``casadi_debris.<name>``."""
    path = _source(name)
    dotted = f"{PACKAGE}.{name}"
    parts = [f"# `{dotted}`\n"]
    if path.is_dir():
        # A package that defines its API in __init__.py (parallel) shows it; one that only
        # re-exports shows its modules below instead of each name twice.
        parts.append(_directive(dotted) if _defines(path) else _directive(dotted, members=False))
        parts.extend(
            _directive(module, show_root_heading=True, heading_level=2)
            for module in _modules(path, dotted)
        )
    else:
        parts.append(_directive(dotted))
    return "\n".join(parts)


def index_page(names: list[str]) -> str:
    """Markdown of the reference index: one row per listed package."""
    rows = [f"| [`{PACKAGE}.{name}`]({name}.md) | {_summary(_source(name))} |" for name in names]
    return "\n".join(
        [
            "# API reference\n",
            "Generated from the docstrings (numpydoc). Quantities are SI unless their",
            "name carries another unit (`torque_mNm`, `error_arcsec`).\n",
            "| package | what it holds |",
            "| --- | --- |",
            *rows,
            "",
        ]
    )


def on_files(files: Files, config: MkDocsConfig) -> Files:
    """Add a generated page for each listed ``reference/*.md`` that has no file."""
    listed = [path for path in _nav_paths(config.nav) if path.startswith(PREFIX)]
    names = [path.removeprefix(PREFIX).removesuffix(".md") for path in listed]
    packages = [name for name in names if name != "index"]
    for path, name in zip(listed, names, strict=True):
        if files.get_file_from_path(path) is not None:
            continue
        content = index_page(packages) if name == "index" else package_page(name)
        files.append(File.generated(config, path, content=content))
    return files
