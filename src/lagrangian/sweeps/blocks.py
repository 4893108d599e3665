"""The blocks of a sweep: rectangular pieces of the grid, each one task and one Zarr chunk.

A block takes whole trailing dimensions while they fit in ``chunk_size`` members, then as
many rows of the next dimension as fit, and one along the rest; the blocks tile the grid and
line up with the chunks of every array in the store, so each block is written on its own.

>>> block_shape((200, 200), 512)
(2, 200)
>>> [tuple((s.start, s.stop) for s in r) for r in regions((3, 2), (2, 2))]
[((0, 2), (0, 2)), ((2, 3), (0, 2))]
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator

from lagrangian.sweeps.grid import Region

#: Members per block unless asked otherwise: enough to keep a vectorized batch busy, few
#: enough that a resumed sweep loses little.
DEFAULT_CHUNK_SIZE = 512
#: Members per block where each member is one simulate call (constrained systems), each
#: far slower than a member of a compiled batch.
MEMBER_CHUNK_SIZE = 32


def block_shape(shape: tuple[int, ...], chunk_size: int) -> tuple[int, ...]:
    """The shape of a block of at most ``chunk_size`` members (at least one) of ``shape``."""
    budget = max(int(chunk_size), 1)
    block = []
    for size in reversed(shape):
        take = min(size, budget)
        block.append(max(take, 1))
        budget = budget // size if size <= budget else 1
    return tuple(reversed(block))


def regions(shape: tuple[int, ...], block: tuple[int, ...]) -> Iterator[Region]:
    """Every block of ``shape``, in C order, as slices."""
    starts = [range(0, size, step) for size, step in zip(shape, block)]
    for corner in itertools.product(*starts):
        yield tuple(
            slice(start, min(start + step, size)) for start, step, size in zip(corner, block, shape)
        )


def region_size(region: Region) -> int:
    """The number of members in ``region``."""
    return math.prod(s.stop - s.start for s in region)
