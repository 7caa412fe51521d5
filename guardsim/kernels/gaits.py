"""The intruder's step under gaits, for the exact sneak searches: one transition every search calls.

A walking step lands the tick after it starts; a sneaking step from ``a`` to ``b`` takes ``sneak_ticks``
ticks, the intruder in ``a`` for all but the last and in ``b`` at the last. The searches need no state
for a step under way: the ticks of a sneaking step before it lands are the same as waiting in ``a``, so
a sneaking step is a landing allowed once the intruder has stood ``sneak_ticks - 1`` ticks in ``a``.
Their state is (lap tick, cell, ``still``): the ticks stood in the cell since arriving, capped at
``sneak_ticks - 1``. Waiting is silent; a step makes its noise where and when it lands.

Moves are numbered 0-3 (walk in that direction), 4 (wait) and 5-8 (sneak in direction ``move - 5``).
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["GAIT_MOVES", "SILENT", "SNEAK_MOVE", "WAIT_MOVE", "WALK_MOVES", "gait_move"]

#: Moves with gaits (walking and sneaking steps and waiting).
GAIT_MOVES = 9
#: Moves without gaits: the four walking steps and waiting (``cap`` 0, ``heard`` :data:`SILENT`).
WALK_MOVES = 5
#: ``heard`` when no step is heard anywhere: the searches without ears.
SILENT = np.zeros((2, 1, 1), dtype=np.bool_)
#: The wait move.
WAIT_MOVE = 4
#: The first sneaking move (direction 0).
SNEAK_MOVE = 5


# Inlined: the searches call it for every move of every node, and a call passing an array costs more
# than the move itself.
@jit(inline="always")
def gait_move(
    neighbours: np.ndarray, heard: np.ndarray, after: int, cell: int, still: int, cap: int, move: int
) -> tuple[int, int, bool]:
    """Move ``move`` from ``cell`` after standing there ``still`` ticks (capped at ``cap``), landing at lap
    tick ``after``: the cell it is in then (-1: no such move), its ``still`` then, and whether a guard
    hears the landing (``heard``: ``bool (2, period, cells)``, a walking then a sneaking step's noise
    heard there and then; shape ``(2, 1, 1)`` when nothing is heard anywhere)."""
    if move == WAIT_MOVE:
        return cell, min(still + 1, cap), False
    sneaking = move >= SNEAK_MOVE
    if sneaking and still < cap:
        return -1, 0, False
    other = neighbours[cell, move - SNEAK_MOVE if sneaking else move]
    if other < 0:
        return -1, 0, False
    loud = False
    if heard.shape[1] > 1 or heard.shape[2] > 1:
        loud = heard[1 if sneaking else 0, after, other]
    return other, 0, loud
