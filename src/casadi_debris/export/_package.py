"""The package ``casadi_debris.export`` is also the front door's job of that name.

``casadi_debris.export(problem, ...)`` is the job (:func:`casadi_debris.workflows.export`),
and ``casadi_debris.export`` the package of the flight code. Once the package is imported,
Python binds the name ``casadi_debris.export`` to it, so the package object itself is made
callable: calling it runs the job, and :func:`inspect.signature` shows the job's. The job
lives a layer above this package; it is found through the import system at call time, so
that nothing here imports ``casadi_debris.workflows``.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import Any


def _job() -> Any:
    return importlib.import_module("casadi_debris.workflows").export


class ExportPackage(types.ModuleType):
    """``casadi_debris.export``: the flight-code package, which calls as the export job."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        """Run :func:`casadi_debris.workflows.export`."""
        return _job()(*args, **kwargs)

    @property
    def __wrapped__(self) -> Any:
        """The job (what :func:`inspect.signature` and :func:`inspect.unwrap` follow)."""
        return _job()


def callable_package(name: str) -> None:
    """Make the package ``name`` (already in ``sys.modules``) an :class:`ExportPackage`."""
    sys.modules[name].__class__ = ExportPackage
