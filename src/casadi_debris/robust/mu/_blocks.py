"""Block structures of the structured singular value.

A structure is a sequence of blocks, each ``("complex", k)`` (a full complex
k x k block) or ``("real", k)`` (a real scalar repeated k times, delta I_k);
a bare integer k means ``("complex", k)``. The closed loop's inputs and
outputs are ordered as the blocks.

SLICOT AB13MD, which bounds mu, takes full complex blocks and real scalars,
not repeated ones: a repeated real scalar is bounded as k independent real
scalars. That set of perturbations contains delta I_k, so the bound stays an
upper bound of mu (possibly a conservative one).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from casadi_debris.errors import SynthesisError

BlockKind = Literal["complex", "real"]


@dataclass(frozen=True)
class Block:
    """One block of an uncertainty structure.

    Attributes
    ----------
    kind : {"complex", "real"}
        Full complex block, or a real scalar repeated ``size`` times.
    size : int
        Number of closed-loop inputs (and outputs) the block takes.
    """

    kind: BlockKind
    size: int


BlockLike = Block | tuple[str, int] | int


def block_structure(blocks: Sequence[BlockLike]) -> tuple[Block, ...]:
    """Normalise a block list: ``Block``, ``(kind, size)`` or a bare size (full complex).

    Parameters
    ----------
    blocks : sequence
        For example ``[("complex", 1), ("complex", 1), ("complex", 2)]``.

    Returns
    -------
    tuple of Block

    Raises
    ------
    SynthesisError
        An empty structure, an unknown kind or a size that is not a positive integer.
    """
    if isinstance(blocks, str | bytes) or len(blocks) == 0:
        raise SynthesisError(f"blocks: a non-empty list of blocks, got {blocks!r}")
    structure = []
    for index, block in enumerate(blocks):
        kind, size = (
            (block.kind, block.size)
            if isinstance(block, Block)
            else ("complex", block)
            if isinstance(block, int | np.integer) and not isinstance(block, bool)
            else _pair(block, index)
        )
        if kind not in ("complex", "real"):
            raise SynthesisError(f"blocks[{index}]: kind must be 'complex' or 'real', got {kind!r}")
        if isinstance(size, bool) or not isinstance(size, int | np.integer) or size < 1:
            raise SynthesisError(f"blocks[{index}]: size must be a positive integer, got {size!r}")
        structure.append(Block(kind, int(size)))
    return tuple(structure)


def _pair(block: object, index: int) -> tuple[object, object]:
    if isinstance(block, tuple | list) and len(block) == 2:
        return block[0], block[1]
    raise SynthesisError(
        f"blocks[{index}]: expected ('complex', k), ('real', k) or an integer, got {block!r}"
    )


def expanded(structure: Sequence[Block]) -> tuple[np.ndarray, np.ndarray]:
    """AB13MD's block sizes and types (2 complex, 1 real) for a structure.

    Parameters
    ----------
    structure : sequence of Block

    Returns
    -------
    sizes, types : ndarray of int, shape (n_scalar_blocks,)
        A repeated real scalar becomes ``size`` real scalars of size 1.
    """
    sizes: list[int] = []
    types: list[int] = []
    for block in structure:
        if block.kind == "complex":
            sizes.append(block.size)
            types.append(2)
        else:
            sizes += [1] * block.size
            types += [1] * block.size
    return np.array(sizes, dtype=int), np.array(types, dtype=int)


def total_size(structure: Sequence[Block]) -> int:
    """Number of closed-loop inputs (and outputs) the structure takes."""
    return sum(block.size for block in structure)
