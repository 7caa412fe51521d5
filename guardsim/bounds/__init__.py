"""Lower bounds on the steps any guard with a given vision needs to see every reachable cell.

A guard's state is its cell and heading; one step goes from ``(c, h)`` to ``(neighbours[c, d], d)`` for
each connected direction ``d``, and the start state is free (what it sees is seen at step 0). The
*watchers* of a cell are the states that see it. A walk sees every goal cell only if it passes through
a watcher of each, which gives two bounds (why each is a lower bound: ``docs/bounds.md``):

- the **eccentricity** bound: the largest, over goal cells, of the distance from the start state to the
  cell's nearest watcher;
- the **cluster** bound (after Skyler, Atzmon, Yaffe and Felner, "Watchman routes on grids", JAIR
  2022): for goal cells with pairwise disjoint watcher sets, the distance from the start to the nearest
  of them plus a minimum spanning tree over them, weighted by the distances between watcher sets.

Who sees each cell depends only on the level and the vision: it is the level's
:class:`~guardsim.vision.table.ViewTable`, built once per grid and vision and shared with the planners.
Per start, :mod:`~guardsim.bounds.watchers` finds state distances, :mod:`~guardsim.bounds.clusters`
chooses the cells and :mod:`~guardsim.kernels.trees` weighs spanning trees over their watchers, all in a
few linear passes over the state graph in compiled code.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, NamedTuple

from guardsim.bounds.area import area_watchers
from guardsim.bounds.clusters import SPREAD_CANDIDATES, cluster_bound
from guardsim.bounds.watchers import nearest_watchers, state_distances
from guardsim.kernels.states import state_of
from guardsim.vision.rules import VisionFunction
from guardsim.vision.table import view_table

if TYPE_CHECKING:
    from guardsim.simulation import Scene

__all__ = ["Bounds", "cluster_bound", "lower_bounds", "nearest_watchers", "state_distances"]


class Bounds(NamedTuple):
    """Lower bounds on the steps of any walk from one start state that sees every reachable cell."""

    eccentricity: int
    """Largest distance from the start state to the nearest watcher of a goal cell."""
    cluster: int
    """Distance from the start to the nearest cluster plus a minimum spanning tree over the clusters."""
    clusters: int
    """How many clusters (cells with disjoint watcher sets) the cluster bound used."""
    best: int
    """The largest of the bounds."""
    seconds: float
    """Wall time of the call (building the level's view table too, when it was not cached)."""
    path: int = 0
    """Distance from the start through some clusters in the best order (the path bound)."""


def lower_bounds(scene: Scene, start: tuple[int, int], heading: int, vision: VisionFunction | None = None) -> Bounds:
    """Lower bounds on the steps any guard seeing by ``vision`` needs to see every cell reachable from ``start``.

    Parameters
    ----------
    scene
        The level, its grid and its vision.
    start
        ``(col, row)`` of the start cell.
    heading
        First heading number (0 right, 1 down, 2 left, 3 up).
    vision
        Which cells a state sees: :meth:`Scene.vision` by default. Only this function is asked, so any
        line-of-sight rule works. Its view table is cached per grid and vision object, so pass the same
        object every time (``scene.vision()`` always returns the scene's one cache).

    Returns
    -------
    Bounds
        Both bounds and the best. Goal cells that no reachable state sees (impossible with a vision that
        always sees the guard's own cell) are left out.

    Examples
    --------
    A corridor of 7 cells, a guard seeing its cell and the next, starting in the middle facing right: it
    must reach cell 5 facing right and cell 1 facing left, 2 + 4 steps whichever it does first.

    >>> from guardsim.level import parse_level
    >>> from guardsim.simulation import Scene
    >>> corridor = parse_level({"outer": [[0, 0], [7, 0], [7, 1], [0, 1]], "guard": {"view_range": 1.0}})
    >>> bounds = lower_bounds(Scene.from_level(corridor), (3, 0), 0)
    >>> bounds.eccentricity, bounds.cluster, bounds.clusters, bounds.best
    (2, 6, 2, 6)
    """
    began = time.perf_counter()
    grid = scene.grid
    vision = scene.vision() if vision is None else vision
    table = view_table(grid, vision)
    start_cell = grid.flat(*start)
    area = area_watchers(grid, vision, table, start_cell, SPREAD_CANDIDATES)
    eccentricity, cluster, clusters, path = cluster_bound(grid.neighbours, table, area, state_of(start_cell, heading))
    best = max(eccentricity, cluster, path)
    return Bounds(eccentricity, cluster, clusters, best, time.perf_counter() - began, path)
