"""The model's uncertain parameters by name: layout of the vector ``p`` and a named value type.

CasADi Functions take the parameters as one vector ``p``; everything else reads
and writes them by name through :class:`ParameterLayout` (which entry is which)
and :class:`Parameters` (the values, named). The layout follows the debris: a
rigid debris has no array angle and no bending frequency.

Entries, in order:

- ``inertia_scale_x``, ``inertia_scale_y``, ``inertia_scale_z``: factors on the
  hub-and-CubeSats inertia about each body axis (the diagonal scales by them, a
  product of inertia by the square root of the two factors), 1 nominal;
- ``mass_kg``: total mass [kg];
- ``array_angle_offset_rad``: turn of every array about its hinge axis away from
  its nominal angle [rad] (the paper's theta_SA, whose nominal is 0), one for
  all arrays, present when the debris has arrays; or, when the uncertainty set
  asks for independent array angles, ``array1_angle_offset_rad``,
  ``array2_angle_offset_rad``, ... one per array;
- ``bending_frequency_scale``: factor on every array's first bending frequency,
  1 nominal, present when the model keeps a first bending mode.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.dynamics import build_model
>>> model = build_model(load_problem())
>>> corner = model.nominal.replace(mass_kg=700.0, array_angle_offset_rad=0.5)
>>> p = corner.to_vector()  # for model.dynamics(x, u, p)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError, ModelError

INERTIA_SCALE_NAMES = ("inertia_scale_x", "inertia_scale_y", "inertia_scale_z")


class Indexable(Protocol):
    """A numeric vector or a CasADi symbol: the layout only indexes it."""

    def __getitem__(self, key: Any, /) -> Any: ...


@dataclass(frozen=True)
class ParameterLayout:
    """Which entry of the parameter vector ``p`` is which.

    Attributes
    ----------
    array_angles : int
        How many array-angle entries ``p`` holds: 0 (no arrays), 1 (one offset for
        every array, the default) or one per array (``per_array``).
    has_bending_scale : bool
        Whether ``p`` holds the first-bending frequency factor.
    per_array : bool
        One angle entry per array (``array1_angle_offset_rad``, ...), when the
        uncertainty set asks for independent array angles.
    """

    array_angles: int = 1
    has_bending_scale: bool = True
    per_array: bool = False

    @classmethod
    def for_problem(cls, problem: Problem) -> ParameterLayout:
        """The layout of every model of ``problem``, whichever modes it keeps.

        It depends on the problem only, so that one parameter vector (a Monte
        Carlo case, say) fits both the design model and the simulation model.
        """
        n_arrays = len(problem.arrays)
        per_array = n_arrays > 0 and problem.uncertainty.independent_array_angles
        bending = any(
            (m.kind, m.order) == ("bending", 1) for array in problem.arrays for m in array.modes
        )
        return cls(
            array_angles=n_arrays if per_array else min(n_arrays, 1),
            has_bending_scale=bending,
            per_array=per_array,
        )

    @property
    def has_array_angle(self) -> bool:
        """Whether ``p`` holds array angles at all (the debris has arrays)."""
        return self.array_angles > 0

    @property
    def angle_names(self) -> tuple[str, ...]:
        """The array-angle entries' names, in vector order."""
        if self.per_array:
            return tuple(f"array{k}_angle_offset_rad" for k in range(1, self.array_angles + 1))
        return ("array_angle_offset_rad",) * min(self.array_angles, 1)

    @property
    def names(self) -> tuple[str, ...]:
        """Entry names, in vector order."""
        names = [*INERTIA_SCALE_NAMES, "mass_kg", *self.angle_names]
        if self.has_bending_scale:
            names.append("bending_frequency_scale")
        return tuple(names)

    @property
    def size(self) -> int:
        """Length of ``p``."""
        return len(self.names)

    def index(self, name: str) -> int:
        """Position of entry ``name`` in ``p``; a ModelError names the known entries."""
        try:
            return self.names.index(name)
        except ValueError:
            raise ModelError(
                f"unknown parameter {name!r}; this model has {', '.join(self.names)}"
            ) from None

    def inertia_scale(self, p: Indexable) -> Any:
        """The three inertia factors of ``p`` (a slice of it)."""
        return p[0:3]

    def mass_kg(self, p: Indexable) -> Any:
        """Total mass entry of ``p`` [kg]."""
        return p[3]

    def array_angle_offset_rad(self, p: Indexable, array: int = 0) -> Any:
        """Angle offset of array ``array`` (0-based) in ``p`` [rad]; the shared one by default."""
        return p[4 + (array if self.per_array else 0)]

    def bending_frequency_scale(self, p: Indexable) -> Any:
        """First-bending frequency factor of ``p``."""
        return p[self.index("bending_frequency_scale")]


@dataclass(frozen=True)
class Parameters:
    """Values of a model's parameters, by name.

    Attributes
    ----------
    layout : ParameterLayout
    inertia_scale : tuple of float
        Factors on the hub-and-CubeSats inertia about x, y, z.
    mass_kg : float
        Total mass [kg].
    array_angle_offsets_rad : tuple of float
        Turn of the arrays about their hinge axes from their nominal angles [rad]:
        none without arrays, one shared by every array, or one per array.
    bending_frequency_scale : float or None
        Factor on the first bending frequencies; None without a bending mode.
    """

    layout: ParameterLayout
    inertia_scale: tuple[float, float, float]
    mass_kg: float
    array_angle_offsets_rad: tuple[float, ...] = ()
    bending_frequency_scale: float | None = None

    def __post_init__(self) -> None:
        for name, value in self.items():
            if not math.isfinite(value):
                raise ModelError(f"parameter {name} must be finite, got {value}")
        if self.mass_kg <= 0.0 or min(self.inertia_scale) <= 0.0:
            raise ModelError("parameters mass_kg and inertia_scale_* must be positive")

    @property
    def array_angle_offset_rad(self) -> float:
        """The arrays' shared angle offset [rad] (a ModelError when there is none)."""
        if self.layout.per_array or not self.array_angle_offsets_rad:
            raise ModelError("this model has no single array angle offset")
        return self.array_angle_offsets_rad[0]

    def items(self) -> list[tuple[str, float]]:
        """(name, value) pairs in vector order."""
        values = [*self.inertia_scale, self.mass_kg, *self.array_angle_offsets_rad]
        if self.bending_frequency_scale is not None:
            values.append(self.bending_frequency_scale)
        names = self.layout.names
        if len(values) != len(names):
            raise ModelError(f"parameters: expected {', '.join(names)}, got {len(values)} values")
        return list(zip(names, map(float, values), strict=True))

    def to_dict(self) -> dict[str, float]:
        """Values by name (for JSON)."""
        return dict(self.items())

    def to_vector(self) -> np.ndarray:
        """The vector ``p`` the model's Functions take, shape (layout.size,)."""
        return np.array([value for _, value in self.items()])

    @classmethod
    def from_vector(cls, layout: ParameterLayout, vector: npt.ArrayLike) -> Parameters:
        """Named values of a parameter vector laid out as ``layout``."""
        p = np.asarray(vector, dtype=float)
        if p.shape != (layout.size,):
            raise InputShapeError(
                f"parameters: expected {layout.size} numbers ({', '.join(layout.names)}), "
                f"got shape {p.shape}"
            )
        return cls.from_mapping(layout, dict(zip(layout.names, p.tolist(), strict=True)))

    @classmethod
    def from_mapping(cls, layout: ParameterLayout, values: Mapping[str, float]) -> Parameters:
        """From a complete name -> value mapping (unknown or missing names are errors)."""
        unknown = sorted(set(values) - set(layout.names))
        missing = [name for name in layout.names if name not in values]
        if unknown or missing:
            raise ModelError(
                f"parameters: unknown {unknown}, missing {missing}; "
                f"this model has {', '.join(layout.names)}"
            )
        scale = tuple(float(values[name]) for name in INERTIA_SCALE_NAMES)
        bending = values.get("bending_frequency_scale")
        return cls(
            layout=layout,
            inertia_scale=(scale[0], scale[1], scale[2]),
            mass_kg=float(values["mass_kg"]),
            array_angle_offsets_rad=tuple(float(values[n]) for n in layout.angle_names),
            bending_frequency_scale=None if bending is None else float(bending),
        )

    def replace(self, **values: float) -> Parameters:
        """A copy with the named entries replaced (``inertia_scale_x=1.17``, ``mass_kg=700``)."""
        merged = self.to_dict()
        for name, value in values.items():
            self.layout.index(name)  # names the known entries if ``name`` is not one
            merged[name] = float(value)
        return Parameters.from_mapping(self.layout, merged)
