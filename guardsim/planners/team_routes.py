"""Splitting viewpoints among guards: one open tour per guard, balanced so the longest is short.

Each viewpoint first goes to the guard whose start is nearest to it (ties to the lowest number), and
each guard's viewpoints are ordered into an open tour (:mod:`guardsim.kernels.tours`). Then, as
long as it helps, one viewpoint moves from the longest tour to the place in another guard's tour where
it costs least, provided both tours end up shorter than the longest was; both tours are then improved
again. This is the min-max multiple-TSP heuristic of moving nodes off the critical tour (after the
insertion moves of Frederickson, Hecht and Kim 1978, "Approximation algorithms for some routing
problems", and its later local-search variants); its aim is the team's makespan, not the total steps.
"""

from __future__ import annotations

import numpy as np

from guardsim.kernels.compiler import jit
from guardsim.kernels.tours import improve_tour, nearest_neighbour_tour, tour_cost

__all__ = ["plan_routes"]


@jit
def _best_transfer(cost: np.ndarray, nodes: np.ndarray, offsets: np.ndarray, longest: int) -> tuple[int, int, int]:
    """The move of one viewpoint off tour ``longest`` that most shortens the longer of the two tours.

    Tour ``g`` is ``nodes[offsets[g]:offsets[g + 1]]``. Returns ``(position in longest, other guard,
    gap in other)``, or ``(-1, -1, -1)`` when no move makes both tours shorter than ``longest`` is now.
    """
    source = nodes[offsets[longest] : offsets[longest + 1]]
    source_cost = tour_cost(cost, source)
    best = (-1, -1, -1)
    best_worst = source_cost
    for position in range(1, source.shape[0]):
        node = source[position]
        saved = cost[source[position - 1], node]
        if position + 1 < source.shape[0]:
            saved += cost[node, source[position + 1]] - cost[source[position - 1], source[position + 1]]
        remaining = source_cost - saved
        for guard in range(offsets.shape[0] - 1):
            if guard == longest:
                continue
            target = nodes[offsets[guard] : offsets[guard + 1]]
            target_cost = tour_cost(cost, target)
            for gap in range(target.shape[0]):
                added = cost[target[gap], node]
                if gap + 1 < target.shape[0]:
                    added += cost[node, target[gap + 1]] - cost[target[gap], target[gap + 1]]
                worst = max(remaining, target_cost + added)
                if worst < best_worst:
                    best, best_worst = (position, guard, gap), worst
    return best


def plan_routes(cost: np.ndarray, starts: np.ndarray, viewpoints: np.ndarray) -> list[np.ndarray]:
    """One open tour per guard covering every viewpoint once.

    Parameters
    ----------
    cost
        ``int64 (nodes, nodes)``: steps from one node to another.
    starts
        ``int64 (guards,)``: each guard's start node.
    viewpoints
        ``int64``: the nodes to visit.

    Returns
    -------
    list of numpy.ndarray
        Per guard, its viewpoints in walking order (its start left out).
    """
    guards = starts.size
    if guards == 1:
        owner = np.zeros(viewpoints.size, dtype=np.int64)
    else:
        owner = np.argmin(cost[np.ix_(starts, viewpoints)], axis=0)
    tours = [improve_tour(cost, nearest_neighbour_tour(cost, starts[g], viewpoints[owner == g])) for g in range(guards)]
    for _ in range(4 * viewpoints.size if guards > 1 else 0):
        longest = int(np.argmax([tour_cost(cost, tour) for tour in tours]))
        offsets = np.cumsum([0] + [tour.size for tour in tours])
        position, other, gap = _best_transfer(cost, np.concatenate(tours), offsets, longest)
        if position < 0:
            break
        node = tours[longest][position]
        tours[longest] = improve_tour(cost, np.delete(tours[longest], position))
        tours[other] = improve_tour(cost, np.insert(tours[other], gap + 1, node))
    return [tour[1:].copy() for tour in tours]
