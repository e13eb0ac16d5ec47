"""MkDocs hook: the API reference pages, generated from the navigation.

Every ``reference/<name>.md`` entry of ``nav`` in ``mkdocs.yml`` that has no file
in ``docs/`` becomes a page documenting ``casadi_debris.<name>``: the package's
docstring and the names its ``__init__`` exports (``__all__``, or the explicit
``from x import A as A`` re-exports where there is no ``__all__``), then each public
module and subpackage in it (names not starting with ``_``), found on disk, so a new
module appears without editing anything. Implementation modules are private
(``_name.py``): what they define reaches the page only through the names a package
exports, under the name a user imports. A name is documented once, in the highest
package on the page that exports it; a module or subpackage below lists it by link.
``reference/index.md``, if listed and missing, becomes a table of the listed packages
with the first line of each docstring. The list in ``nav`` is the only list.

Nothing is imported from the package and nothing is written to ``docs/``: the
pages exist only in the build (``File.generated``).
"""

from __future__ import annotations

import ast
import json
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


def _exports(folder: Path) -> dict[str, str] | None:
    """The names a package's ``__init__.py`` exports, each with the module it comes from.

    ``__all__`` when the package has one, else its redundant-alias re-exports
    (``from x import A as A``); None when it has neither (it exports nothing by name).
    A name defined in the ``__init__`` itself comes from the package.
    """
    dotted = ".".join((PACKAGE, *folder.relative_to(SOURCE).parts))
    tree = ast.parse((folder / "__init__.py").read_text(encoding="utf-8"))
    origins: dict[str, str] = {}
    redundant: list[str] = []
    listed: list[str] | None = None
    # Imports anywhere at module level, those of a lazy package under TYPE_CHECKING too.
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                origins[alias.asname or alias.name] = node.module
                if alias.asname == alias.name:
                    redundant.append(alias.name)
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef):
            origins[node.name] = dotted
        elif isinstance(node, ast.Assign) and any(
            isinstance(target, ast.Name) and target.id == "__all__" for target in node.targets
        ):
            listed = list(ast.literal_eval(node.value))
    names = listed if listed is not None else redundant or None
    if names is None:
        return None
    return {name: origins.get(name, dotted) for name in names}


def _yaml(value: object) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, list):
        return json.dumps(value)
    return str(value)


def _directive(identifier: str, **options: object) -> str:
    lines = [f"::: {identifier}"]
    if options:
        lines.append("    options:")
        lines.extend(f"      {key}: {_yaml(value)}" for key, value in options.items())
    return "\n".join(lines) + "\n"


def _below(origin: str, dotted: str) -> bool:
    """Whether a name that comes from ``origin`` is defined in ``dotted`` or below it."""
    return origin == dotted or origin.startswith(f"{dotted}.")


# A page's documented names: name -> (the module it comes from, the package documenting it).
Documented = dict[str, tuple[str, str]]


def _section(dotted: str, documented: Documented, **options: object) -> str:
    """One package or module of a page, without the names documented above it."""
    path = SOURCE.joinpath(*dotted.split(".")[1:])
    above = {name: where for name, (origin, where) in documented.items() if _below(origin, dotted)}
    if path.is_dir():
        exports = _exports(path)
        if exports is not None:
            # The exported names, under the name a user imports, in the order listed.
            options["members"] = [name for name in exports if name not in above]
            documented.update(
                {name: (origin, dotted) for name, origin in exports.items() if name not in above}
            )
        elif not _defines(path):
            # A package that neither defines nor exports anything shows only its docstring
            # and, below, its public modules.
            options["members"] = False
    elif above:
        options["filters"] = ["!^_[^_]", *(f"!^{name}$" for name in sorted(above))]
    text = _directive(dotted, **options)
    if above:
        links = ", ".join(f"[`{name}`][{where}.{name}]" for name, where in sorted(above.items()))
        text += f"\nAlso in `{dotted}`, documented above: {links}.\n"
    return text


def package_page(name: str) -> str:
    """Markdown of the reference page of ``casadi_debris.<name>``."""
    path = _source(name)
    dotted = f"{PACKAGE}.{name}"
    parts = [f"# `{dotted}`\n"]
    if path.is_dir():
        documented: Documented = {}
        parts.append(_section(dotted, documented))
        parts.extend(
            _section(module, documented, show_root_heading=True, heading_level=2)
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
