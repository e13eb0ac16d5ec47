"""Griffe extension: Sphinx cross-reference roles in docstrings become links.

The docstrings are numpydoc and cite other objects the Sphinx way
(``:func:`load_problem```, ``:class:`~casadi_debris.slews.OptimalSlewSettings```,
``:mod:`.mu```). mkdocstrings reads Markdown, where such a role would show as
literal text, so before the docstrings are parsed each role is rewritten into a
mkdocstrings cross-reference to the object's full path, resolved in the scope of
the object that carries the docstring (its members, its module's imports, its
parents), as Sphinx would:

- a name of this package becomes ``[`name`][casadi_debris.full.path]``: a link,
  and a warning (so an error under ``mkdocs build --strict``) if the page that
  documents it does not exist;
- a name defined in a private module links to the public name it is exported
  under (``casadi_debris.robust.musyn``, not ``...synthesis._musyn.musyn``);
- a private name (``_helper``) or a name outside the package (``logging``,
  ``qpsolvers.solve_problem``) becomes plain code: nothing to link to here;
- a name that resolves to nothing is reported as a warning naming the
  docstring's owner, so a stale reference fails the strict build.

An undocumented attribute (a dataclass field described in its class's
``Attributes`` section, a module constant) has no entry of its own in the
reference, so its link goes to the nearest documented parent. A numpydoc
``Example`` heading is read as ``Examples``, so its ``>>>`` lines show as code.
"""

from __future__ import annotations

import importlib.util
import re
from typing import Any

import griffe

ROLE = re.compile(r":(?:py:)?(func|meth|class|mod|data|attr|exc|obj|const):`([^`]+)`")
TITLED = re.compile(r"^(.*?)\s*<([^>]+)>$")
CALLABLE_ROLES = {"func", "meth"}
EXAMPLE_HEADING = re.compile(r"^(\s*)Example\n(\s*)-------$", re.MULTILINE)
logger = griffe.get_logger("casadi_debris.docs.sphinx_roles")


def _module_of(obj: griffe.Object) -> griffe.Module:
    while not obj.is_module:
        obj = obj.parent
    return obj


def _relative(obj: griffe.Object, target: str) -> str:
    """``.mu`` or ``..slew.options`` against the package of ``obj``'s module."""
    module = _module_of(obj)
    base = module if module.is_package else module.parent
    dots = len(target) - len(target.lstrip("."))
    for _ in range(dots - 1):
        base = base.parent
    return f"{base.path}.{target.lstrip('.')}"


def _canonical(root: griffe.Module, path: str) -> str:
    """The path where an object is defined (re-exports followed), if known."""
    try:
        obj = root[path.removeprefix(f"{root.path}.")] if path != root.path else root
        return obj.final_target.path if obj.is_alias else obj.path
    except (KeyError, griffe.AliasResolutionError, griffe.CyclicAliasError):
        return path


def _documented(root: griffe.Module, path: str) -> str:
    """``path``, or its nearest parent with a docstring (what the reference shows)."""
    while path != root.path:
        try:
            obj = root[path.removeprefix(f"{root.path}.")]
        except KeyError:
            return path
        if obj.docstring is not None:
            return path
        path = path.rsplit(".", 1)[0]
    return path


def _resolve(obj: griffe.Object, root: griffe.Module, target: str) -> str | None:
    if target.startswith("."):
        return _canonical(root, _relative(obj, target))
    if target == root.path or target.startswith(f"{root.path}."):
        return _canonical(root, target)
    head, _, tail = target.partition(".")
    try:
        resolved = obj.resolve(head)
    except griffe.NameResolutionError:
        return target if importlib.util.find_spec(head) is not None else None
    path = f"{resolved}.{tail}" if tail else resolved
    return _canonical(root, path) if path.startswith(f"{root.path}.") else path


def _is_private(path: str) -> bool:
    return any(part.startswith("_") and not part.endswith("__") for part in path.split("."))


def public_paths(root: griffe.Module) -> dict[str, str]:
    """Where each object defined in a private module is documented: the shortest public
    path that exports it (``casadi_debris.robust.synthesis._musyn.musyn`` ->
    ``casadi_debris.robust.musyn``), the package root itself left out (it has no page)."""
    found: dict[str, str] = {}

    def visit(module: griffe.Module) -> None:
        for member in list(module.members.values()):
            if member.is_alias:
                if module.path == root.path or member.name.startswith("_"):
                    continue
                try:
                    target = member.final_target.path
                except (griffe.AliasResolutionError, griffe.CyclicAliasError):
                    continue
                if _is_private(target) and (
                    target not in found or len(member.path) < len(found[target])
                ):
                    found[target] = member.path
            elif member.is_module and not _is_private(member.path):
                visit(member)

    visit(root)
    return found


def rewrite(
    text: str, obj: griffe.Object, root: griffe.Module, public: dict[str, str] | None = None
) -> str:
    """``text`` with every Sphinx role replaced by a link or plain code.

    A role naming an object of a private module links to the public name it is
    documented under (``public``, from :func:`public_paths`).
    """
    public = public or {}

    def replace(match: re.Match[str]) -> str:
        role, body = match.groups()
        titled = TITLED.match(body)
        title, target = titled.groups() if titled else (None, body)
        short = target.startswith("~")
        target = target.lstrip("~")
        shown = title or (target.rsplit(".", 1)[-1] if short else target.lstrip("."))
        if role in CALLABLE_ROLES and not title:
            shown += "()"
        path = _resolve(obj, root, target)
        if path is None:
            logger.warning("%s: cannot resolve :%s:`%s`", obj.path, role, body)
            return f"`{shown}`"
        inside = path == root.path or path.startswith(f"{root.path}.")
        path = public.get(path, path)
        if not inside or _is_private(path):
            return f"`{shown}`"
        return f"[`{shown}`][{_documented(root, path)}]"

    text = EXAMPLE_HEADING.sub(r"\1Examples\n\2--------", text)
    return ROLE.sub(replace, text)


def _walk(obj: griffe.Object) -> Any:
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from _walk(member)


class SphinxRoles(griffe.Extension):
    """Rewrite Sphinx roles in every docstring of the loaded package."""

    def on_package(self, *, pkg: griffe.Module, **kwargs: Any) -> None:
        public = public_paths(pkg)
        for obj in _walk(pkg):
            if obj.docstring is not None:
                obj.docstring.value = rewrite(obj.docstring.value, obj, pkg, public)
