"""Noise: how far a sound carries over the grid, the one rule every hearing guard, search and map uses.

A noise of radius ``r`` world units made in cell ``a`` is heard in cell ``b`` when the shortest
4-connected path over traversable cells from ``a`` to ``b``, times the cell size, is at most ``r``: sound
goes round walls, not through them, and a cell the noise cannot reach by any path hears nothing.
"""

from __future__ import annotations

import math

import numpy as np

from guardsim.kernels.compiler import jit

__all__ = ["MAX_NOISE_STEPS", "heard_lap", "heard_within", "noise_reach", "noise_steps"]

#: Most steps a noise carries: more than any grid has cells (``reach`` holds them as ``int32``).
MAX_NOISE_STEPS = 2**31 - 2


def noise_steps(radius: float, cell_size: float) -> int:
    """Steps a noise of ``radius`` world units carries on a grid of ``cell_size`` (-1: none at all).

    >>> noise_steps(3.0, 1.0), noise_steps(2.9, 1.0), noise_steps(0.0, 1.0), noise_steps(1.0, 0.5)
    (3, 2, 0, 2)
    """
    if radius < 0:
        return -1
    steps = radius / cell_size + 1e-9
    # A noise heard farther than any grid's longest path is heard everywhere it can reach; the compiled
    # search takes a 32-bit count (a radius of 1e308 gave an integer of 309 digits).
    return MAX_NOISE_STEPS if steps >= MAX_NOISE_STEPS else math.floor(steps)


@jit
def noise_reach(neighbours: np.ndarray, source: int, steps: int, reach: np.ndarray) -> int:
    """Fill ``reach`` (``int32``, a cell each) with the steps from ``source`` of every cell within
    ``steps`` of it, -1 elsewhere; returns how many cells the noise reaches."""
    for cell in range(reach.shape[0]):
        reach[cell] = -1
    queue = np.empty(neighbours.shape[0], dtype=np.int64)
    sources = np.empty(1, dtype=np.int64)
    sources[0] = source
    return _spread(neighbours, sources, steps, reach, queue)


@jit
def _spread(neighbours: np.ndarray, sources: np.ndarray, steps: int, reach: np.ndarray, queue: np.ndarray) -> int:
    """The breadth-first fill behind every hearing rule: ``reach`` (all -1 on entry) gets the steps of
    every cell within ``steps`` of the nearest of ``sources``; the cells filled are ``queue[:returned]``.
    The grid's moves are symmetric, so the cells a noise made in one cell reaches are the cells from
    which a noise reaches it."""
    if steps < 0:
        return 0
    tail = 0
    for index in range(sources.shape[0]):
        source = sources[index]
        if source >= 0 and reach[source] < 0:
            reach[source] = 0
            queue[tail] = source
            tail += 1
    head = 0
    while head < tail:
        cell = queue[head]
        head += 1
        if reach[cell] >= steps:
            continue
        for direction in range(4):
            other = neighbours[cell, direction]
            if other >= 0 and reach[other] < 0:
                reach[other] = reach[cell] + 1
                queue[tail] = other
                tail += 1
    return tail


@jit
def _heard_lap(neighbours: np.ndarray, listeners: np.ndarray, steps: int) -> np.ndarray:
    period = listeners.shape[1]
    cells = neighbours.shape[0]
    heard = np.zeros((period, cells), dtype=np.bool_)
    reach = np.empty(cells, dtype=np.int32)
    reach[:] = -1
    queue = np.empty(cells, dtype=np.int64)
    sources = np.empty(listeners.shape[0], dtype=np.int64)
    for tick in range(period):
        for guard in range(listeners.shape[0]):
            sources[guard] = listeners[guard, tick]
        filled = _spread(neighbours, sources, steps, reach, queue)
        for index in range(filled):
            heard[tick, queue[index]] = True
            reach[queue[index]] = -1
    return heard


def heard_lap(neighbours: np.ndarray, listeners: np.ndarray, radius: float, cell_size: float) -> np.ndarray:
    """``bool (period, cells)``: whether a noise of ``radius`` world units made in each cell at each tick
    of a lap is heard by a listener, ``listeners`` (``int64 (guards, period)``) being each guard's cell
    at each tick (the rule of :func:`heard_within`, for every cell at once).

    >>> corridor = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]])
    >>> heard_lap(corridor, np.array([[0, 3]]), 1.0, 1.0).astype(int).tolist()
    [[1, 1, 0, 0], [0, 0, 1, 1]]
    """
    neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
    listeners = np.ascontiguousarray(np.asarray(listeners, dtype=np.int64).reshape(-1, np.shape(listeners)[-1]))
    return _heard_lap(neighbours, listeners, noise_steps(radius, cell_size))


def heard_within(
    neighbours: np.ndarray, source: int, radius: float, cell_size: float, listeners: np.ndarray
) -> np.ndarray:
    """``bool`` per listener cell: whether a noise of ``radius`` world units made in ``source`` reaches it.

    >>> corridor = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [3, -1, 1, -1], [-1, -1, 2, -1]])
    >>> heard_within(corridor, 0, 2.0, 1.0, np.array([1, 2, 3])).tolist()
    [True, True, False]
    """
    reach = np.empty(neighbours.shape[0], dtype=np.int32)
    noise_reach(np.ascontiguousarray(neighbours, dtype=np.int64), int(source), noise_steps(radius, cell_size), reach)
    cells = np.asarray(listeners, dtype=np.int64)
    return (cells >= 0) & (reach[np.maximum(cells, 0)] >= 0)
