"""The loop builder's compiled steps: one leg of a lap, and the cells a lap sees counted.

A lap is the concatenation of its legs, so a change to one viewpoint of a tour changes two or three legs
and leaves the rest alone: the builder keeps, per cell, how many of the lap's states see it
(:func:`add_sights`), and tries a change on those legs only, instead of walking and looking along the
whole lap again. A leg is found by a breadth-first search from its end that stops as soon as it reaches
the start (:func:`leg_states`), so a short leg costs its neighbourhood, not the level, and no distance
field is kept between legs.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.distances import spread
from guardsim.kernels.steps import state_of

__all__ = ["add_sights", "leg_states"]


@jit
def leg_states(
    neighbours: np.ndarray,
    start: int,
    heading: int,
    entry: int,
    target: int,
    far: int,
    distance: np.ndarray,
    queue: np.ndarray,
) -> np.ndarray:
    """The states after each tick from cell ``start`` facing ``heading`` to arriving in state ``target``
    through its entry cell ``entry``: a shortest walk to ``entry`` (where several steps are equally short
    the guard keeps its heading, then prefers right, down, left, up), then ``target``.

    ``distance`` (``int32 (cells,)``, all ``far``) and ``queue`` (``int64 (cells,)``) are scratch, left as
    found. An empty result when ``start`` cannot reach ``entry``.

    The search stops when ``start`` is reached, at ``d`` steps from ``entry``: every cell nearer than
    ``d`` then has its distance, and the walk down from ``start`` reads no other, so the walk is the one a
    full field gives.
    """
    distance[entry] = 0
    queue[0] = entry
    tail = 1
    if start != entry:
        tail = spread(neighbours, queue, 1, far, distance, start)
    steps = distance[start]
    if steps >= far:
        for index in range(tail):
            distance[queue[index]] = far
        return np.empty(0, dtype=np.int64)
    out = np.empty(steps + 1, dtype=np.int64)
    cell = start
    for tick in range(steps):
        here = distance[cell]
        for choice in range(5):
            direction = heading if choice == 0 else choice - 1
            other = neighbours[cell, direction]
            if other >= 0 and distance[other] == here - 1:
                cell = other
                heading = direction
                break
        out[tick] = state_of(cell, heading)
    out[steps] = target
    for index in range(tail):
        distance[queue[index]] = far
    return out


@jit
def add_sights(
    sight_start: np.ndarray, sight: np.ndarray, states: np.ndarray, delta: int, count: np.ndarray, goal: np.ndarray
) -> int:
    """Add ``delta`` (1 or -1) to ``count`` at every cell each of ``states`` sees (once per state, repeats
    counted); returns the change in the number of goal cells whose count is zero (unseen by the lap)."""
    change = 0
    for index in range(states.shape[0]):
        state = states[index]
        for at in range(sight_start[state], sight_start[state + 1]):
            cell = sight[at]
            was = count[cell]
            count[cell] = was + delta
            if goal[cell]:
                if was == 0:
                    change -= 1
                elif was + delta == 0:
                    change += 1
    return change
