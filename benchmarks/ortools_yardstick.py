"""How good is `tour`'s viewpoint ordering? The same open-tour problem solved by OR-tools' routing solver.

Usage::

    pip install ortools                      # the yardstick only; guardsim does not need it
    python benchmarks/ortools_yardstick.py                  # shipped levels, 5 starts each
    python benchmarks/ortools_yardstick.py --starts 10 --seconds 20

For each start (bench episodes 0, 1, ... of seed 0): the set-cover viewpoints that still see something
after the first look, and the asymmetric step counts between them and the start
(:func:`guardsim.planners.tour.route_costs`), exactly what `tour` orders. `tour`'s order
(:func:`guardsim.planners.team_routes.plan_routes`: nearest neighbour, 2-opt, Or-opt) against OR-tools'
(path cheapest arc, then guided local search for ``--seconds`` per start; an open path is a route
from the start to a dummy end reached from anywhere at no cost). Prints the two lengths per start and
their ratio; a time-limited search depends on the machine, which is why only this benchmark uses one.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
LEVELS = sorted((REPO / "levels").glob("*.json"))


def ortools_order(cost: np.ndarray, start: int, nodes: np.ndarray, seconds: float) -> int:
    """Length of OR-tools' open path from ``start`` through ``nodes``."""
    try:
        from ortools.constraint_solver import pywrapcp, routing_enums_pb2
    except ImportError:
        sys.exit("this benchmark needs OR-tools: pip install ortools")
    members = [start, *nodes.tolist()]
    end = len(members)
    manager = pywrapcp.RoutingIndexManager(end + 1, 1, [0], [end])
    routing = pywrapcp.RoutingModel(manager)

    def steps(from_index: int, to_index: int) -> int:
        a, b = manager.IndexToNode(from_index), manager.IndexToNode(to_index)
        if b == end or a == end:
            return 0
        return int(cost[members[a], members[b]])

    routing.SetArcCostEvaluatorOfAllVehicles(routing.RegisterTransitCallback(steps))
    parameters = pywrapcp.DefaultRoutingSearchParameters()
    parameters.first_solution_strategy = routing_enums_pb2.FirstSolutionStrategy.PATH_CHEAPEST_ARC
    parameters.local_search_metaheuristic = routing_enums_pb2.LocalSearchMetaheuristic.GUIDED_LOCAL_SEARCH
    parameters.time_limit.FromMilliseconds(int(seconds * 1000))
    solution = routing.SolveWithParameters(parameters)
    return int(solution.ObjectiveValue())


def main() -> None:
    from guardsim import load_level
    from guardsim.kernels.tours import tour_cost
    from guardsim.planners.team_routes import plan_routes
    from guardsim.planners.tour import route_costs
    from guardsim.planners.viewpoint_cover import greedy_cover
    from guardsim.simulation import Scene, choose_start, episode_generator
    from guardsim.vision.table import view_table

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=5, help="Starts per level.")
    parser.add_argument("--seconds", type=float, default=10.0, help="OR-tools' time per start.")
    arguments = parser.parse_args()
    print("| level | start | viewpoints | tour's order | OR-tools | tour / OR-tools | tour ms |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    ratios = []
    for path in LEVELS:
        scene = Scene.from_level(load_level(path))
        grid = scene.grid
        table = view_table(grid, scene.vision())
        for episode in range(arguments.starts):
            (col, row), heading = choose_start(scene, rng=episode_generator(0, episode))
            goal = grid.component(col, row).ravel()
            seen = np.zeros(grid.size, dtype=bool)
            seen[table.sees(grid.flat(col, row) * 4 + heading)] = True
            viewpoints = greedy_cover(table, goal)
            useful = np.array([(goal[table.sees(s)] & ~seen[table.sees(s)]).any() for s in viewpoints], dtype=bool)
            states = viewpoints[useful]
            team = ((grid.flat(col, row), heading),)
            cost = route_costs(grid.neighbours, table.entry, states, team)
            first = states.size
            began = time.perf_counter()
            (order,) = plan_routes(cost, np.array([first]), np.arange(states.size))
            planned = time.perf_counter() - began
            ours = int(tour_cost(cost, np.concatenate([[first], order])))
            theirs = ortools_order(cost, first, np.arange(states.size), arguments.seconds)
            ratios.append(ours / theirs)
            print(
                f"| {path.stem} | {episode} | {states.size} | {ours} | {theirs} | {ours / theirs:.3f} "
                f"| {planned * 1000:.1f} |",
                flush=True,
            )
    print(f"\nmedian tour / OR-tools {statistics.median(ratios):.3f}, worst {max(ratios):.3f}")


if __name__ == "__main__":
    main()
