"""Architecture and style: the import layers of DESIGN.md, and ruff."""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]


def _tool(name: str) -> str:
    beside_python = Path(sys.executable).parent / name
    found = str(beside_python) if beside_python.exists() else shutil.which(name)
    if found is None:
        pytest.fail(f"{name} is not installed; install the test extras: pip install -e '.[test]'")
    return found


def test_import_layers():
    result = subprocess.run(
        [_tool("lint-imports"), "--config", str(ROOT / "pyproject.toml"), "--no-cache"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=False,
    )
    assert result.returncode == 0, result.stdout + result.stderr


def test_ruff_clean():
    for args in (["check", "."], ["format", "--check", "."]):
        result = subprocess.run(
            [_tool("ruff"), *args], capture_output=True, text=True, cwd=ROOT, check=False
        )
        assert result.returncode == 0, result.stdout + result.stderr


# A module is one concept and a function one step. These are ceilings far above what
# reads well (most modules are a few hundred lines, most functions a screen), not targets:
# a module near its ceiling wants splitting along its concepts, not a sibling with a
# shared prefix.
MAX_MODULE_LINES = 800
MAX_FUNCTION_LINES = 100
# A signature takes at most eight parameters by position; more go into a settings
# object. Commands take their options (click passes each one), and the jobs of the front
# door take the same options as keyword-only parameters.
MAX_POSITIONAL_PARAMETERS = 8
MAX_PARAMETERS = 12
PACKAGE = ROOT / "src" / "casadi_debris"


def _functions() -> list[tuple[str, ast.FunctionDef | ast.AsyncFunctionDef]]:
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        name = str(path.relative_to(PACKAGE))
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                found.append((name, node))
    return found


def test_modules_and_functions_stay_readable():
    too_long = [
        f"{path.relative_to(PACKAGE)}: {lines} lines"
        for path in sorted(PACKAGE.rglob("*.py"))
        if (lines := path.read_text().count("\n")) > MAX_MODULE_LINES
    ]
    for name, node in _functions():
        length = (node.end_lineno or node.lineno) - node.lineno + 1
        if length > MAX_FUNCTION_LINES:
            too_long.append(f"{name}:{node.lineno} {node.name}: {length} lines")
    assert not too_long, too_long


def test_signatures_stay_narrow():
    import casadi_debris

    jobs = set(casadi_debris.__all__)
    wide = set()
    for name, node in _functions():
        if name.startswith("cli/"):
            continue
        args = node.args
        positional = [a.arg for a in args.posonlyargs + args.args if a.arg not in ("self", "cls")]
        keyword_only = [a.arg for a in args.kwonlyargs]
        everything = len(positional) + len(keyword_only)
        job = name.startswith("workflows/") and node.name in jobs
        if len(positional) > MAX_POSITIONAL_PARAMETERS or (everything > MAX_PARAMETERS and not job):
            wide.add(f"{name}:{node.name}")
    assert not wide, f"group these parameters into a settings object: {sorted(wide)}"


# A model knows its problem (``Model.problem``, ``DeorbitModel.problem``): a function that
# took both could be handed a model of another problem.
MODEL_PARAMETERS = ("model", "rigid", "rigid_model", "flexible_model")


def test_a_function_takes_a_model_or_a_problem_never_both():
    both = []
    for name, node in _functions():
        args = node.args
        names = {a.arg for a in args.posonlyargs + args.args + args.kwonlyargs}
        if "problem" in names and names & set(MODEL_PARAMETERS):
            both.append(f"{name}:{node.lineno} {node.name}")
    assert not both, f"take the model (it knows its problem) or the problem: {both}"


def _import_cycles() -> list[list[str]]:
    """Groups of modules that import each other at run time (type-checking imports left
    out), by Tarjan's strongly connected components."""
    import grimp

    graph = grimp.build_graph("casadi_debris", exclude_type_checking_imports=True)
    imports = {m: graph.find_modules_directly_imported_by(m) for m in graph.modules}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    cycles = []

    def visit(module: str) -> None:
        index[module] = low[module] = len(index)
        stack.append(module)
        for other in imports[module]:
            if other not in index:
                visit(other)
                low[module] = min(low[module], low[other])
            elif other in stack:
                low[module] = min(low[module], index[other])
        if low[module] == index[module]:
            group = []
            while True:
                member = stack.pop()
                group.append(member)
                if member == module:
                    break
            if len(group) > 1:
                cycles.append(sorted(group))

    for module in sorted(imports):
        if module not in index:
            visit(module)
    return cycles


def test_no_module_imports_itself_back():
    assert not _import_cycles()


def _private_imports() -> list[str]:
    """Imports of another package's private module or name (``casadi_debris.x._y``)."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        dotted = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        package = dotted.removesuffix(".__init__") if path.name == "__init__.py" else dotted
        package = package if path.name == "__init__.py" else package.rsplit(".", 1)[0]
        for node in ast.walk(ast.parse(path.read_text())):
            # (dotted path, whether its last part is a name rather than a module)
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                targets = [
                    (node.module, False),
                    *((f"{node.module}.{a.name}", True) for a in node.names),
                ]
            elif isinstance(node, ast.Import):
                targets = [(alias.name, False) for alias in node.names]
            else:
                continue
            for target, is_name in targets:
                parts = target.split(".")
                if parts[0] != "casadi_debris":
                    continue
                private = [i for i, part in enumerate(parts) if part.startswith("_")]
                if not private or parts[private[0]].startswith("__"):
                    continue
                # A private module belongs to its package; a private name to the package
                # of the module that defines it.
                i = private[0]
                owner = ".".join(parts[: i - 1] if is_name and i == len(parts) - 1 else parts[:i])
                if not (package == owner or package.startswith(f"{owner}.")):
                    found.append(f"{path.relative_to(PACKAGE)}:{node.lineno}: {target}")
    return found


def test_callers_import_from_the_package():
    """Implementation modules are private: what another package needs, the package exports
    from its __init__ (tests may still reach into a module to patch it)."""
    assert not _private_imports()


def test_the_report_package_lists_its_names_once():
    """``casadi_debris.report`` exports what its TYPE_CHECKING block imports (the lazy
    table is read from it): every name in ``__all__`` resolves, none is left out."""
    import casadi_debris.report as report
    from casadi_debris._lazy import type_checking_imports

    imported = type_checking_imports(report.__file__)
    assert set(imported) == set(report.__all__)
    for name in report.__all__:
        value = getattr(report, name)
        assert getattr(value, "__module__", imported[name]) == imported[name], name
