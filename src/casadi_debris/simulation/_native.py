"""Call a compiled CasADi Function's C directly, on numpy arrays, without copies.

CasADi's generated C (:mod:`~casadi_debris.simulation._jit_cache`) exports one
entry point per Function, ``int name(const double** arg, double** res,
casadi_int* iw, double* w, int mem)``, with ``name_work`` giving the sizes of
the four work vectors and ``name_checkout`` / ``name_release`` a memory slot
(CasADi's documented interface of generated code). :class:`NativeFunction`
calls it through ``ctypes`` with pointers to numpy arrays: no conversion of
the inputs to CasADi matrices nor of the results back, which for a long
roll-out costs more than the arithmetic.

Every input and output must be dense. CasADi stores a matrix column by
column, so an ``(rows, columns)`` CasADi matrix is a C-ordered numpy array of
shape ``(columns, rows)``: :meth:`NativeFunction.call` takes and gives arrays
in that (transposed) layout.
"""

from __future__ import annotations

import ctypes
import threading
from collections.abc import Sequence
from pathlib import Path

import casadi as ca
import numpy as np

from casadi_debris.errors import CompileError

_INT = ctypes.c_longlong  # casadi_int of CasADi's generated code
_REAL_POINTER = ctypes.POINTER(ctypes.c_double)


class NativeFunction:
    """A dense CasADi Function compiled into ``library``, called on numpy arrays.

    Parameters
    ----------
    function : casadi.Function
        The Function the library was generated from (for its name and shapes).
    library : Path
        The shared library (see :func:`~casadi_debris.simulation._jit_cache.compiled_library`).

    Raises
    ------
    CompileError
        An input or output is sparse, or the library lacks the entry points.

    Examples
    --------
    >>> import casadi as ca, numpy as np
    >>> from casadi_debris.simulation._jit_cache import compiled_library
    >>> from casadi_debris.processes import c_compiler
    >>> x = ca.SX.sym("x", 2, 3)
    >>> f = ca.Function("twice", [x], [2 * x])
    >>> native = NativeFunction(f, compiled_library(f, c_compiler()))  # doctest: +SKIP
    >>> native.call([np.arange(6.0).reshape(3, 2)])[0].T  # doctest: +SKIP
    array([[ 0.,  4.,  8.],
           [ 2.,  6., 10.]])
    """

    def __init__(self, function: ca.Function, library: Path) -> None:
        name = function.name()
        self.name = name
        self.input_shapes = [_dense_shape(function.sparsity_in(i)) for i in range(function.n_in())]
        self.output_shapes = [
            _dense_shape(function.sparsity_out(i)) for i in range(function.n_out())
        ]
        try:
            self._library = ctypes.CDLL(str(library))
            entry = getattr(self._library, name)
            work = getattr(self._library, f"{name}_work")
        except (OSError, AttributeError) as exc:
            raise CompileError(f"{library} does not export {name!r}: {exc}") from exc
        sizes = [_INT() for _ in range(4)]
        work(*(ctypes.byref(size) for size in sizes))
        n_arg, n_res, n_iw, n_w = (int(size.value) for size in sizes)
        self._entry = entry
        self._entry.restype = ctypes.c_int
        self._args = (_REAL_POINTER * max(n_arg, 1))()
        self._results = (_REAL_POINTER * max(n_res, 1))()
        self._iw = np.zeros(max(n_iw, 1), dtype=np.int64)
        self._w = np.zeros(max(n_w, 1))
        self._memory = self._optional(f"{name}_checkout", 0)
        # One set of work vectors: threads (a Dask worker's) take turns.
        self._lock = threading.Lock()
        self._optional(f"{name}_incref", None)

    def _optional(self, entry: str, default: int | None) -> int | None:
        """Call an optional entry point without arguments (absent: ``default``)."""
        function = getattr(self._library, entry, None)
        return default if function is None else int(function() or 0)

    def call(self, inputs: Sequence[np.ndarray]) -> list[np.ndarray]:
        """Evaluate on ``inputs`` (column-major: shape ``(columns, rows)``); the outputs likewise.

        Raises
        ------
        ValueError
            An input of the wrong size, or the C returned an error status.
        """
        if len(inputs) != len(self.input_shapes):
            raise ValueError(f"{self.name} takes {len(self.input_shapes)} inputs")
        with self._lock:
            return self._call(inputs)

    def _call(self, inputs: Sequence[np.ndarray]) -> list[np.ndarray]:
        kept = []
        for i, (given, (rows, columns)) in enumerate(zip(inputs, self.input_shapes, strict=True)):
            array = np.ascontiguousarray(given, dtype=np.float64)
            if array.size != rows * columns:
                raise ValueError(
                    f"{self.name}: input {i} has {array.size} values, expected {rows} x {columns}"
                )
            kept.append(array)  # alive until the call returns
            self._args[i] = array.ctypes.data_as(_REAL_POINTER)
        outputs = [np.empty((columns, rows)) for rows, columns in self.output_shapes]
        for i, array in enumerate(outputs):
            self._results[i] = array.ctypes.data_as(_REAL_POINTER)
        status = self._entry(
            self._args,
            self._results,
            self._iw.ctypes.data_as(ctypes.POINTER(_INT)),
            self._w.ctypes.data_as(_REAL_POINTER),
            ctypes.c_int(self._memory or 0),
        )
        if status != 0:
            raise ValueError(f"{self.name} returned error status {status}")
        return outputs


def _dense_shape(sparsity: ca.Sparsity) -> tuple[int, int]:
    if not sparsity.is_dense():
        raise CompileError("a natively called Function must have dense inputs and outputs")
    return int(sparsity.size1()), int(sparsity.size2())
