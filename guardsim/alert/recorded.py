"""An alert episode read back from its trace (:func:`~guardsim.alert.alert_trace_data`, the JSON of
``guardsim alert --trace`` and of each file ``--out`` writes): what its page and GIF are drawn from, so
that ``guardsim view`` draws a saved episode without running it again.

A trace keeps the search area's size at each tick, not its cells: a recorded episode has no
contaminated cells (its pictures show no search-area dots, and the page still reads out the size). The
level's cameras are not replayed either.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from guardsim.alert.model import AlertEvent
from guardsim.errors import TraceError
from guardsim.grid import CoverageGrid

__all__ = ["RecordedEpisode", "recorded_episode"]


class _Named(NamedTuple):
    name: str


class _Goal(NamedTuple):
    cell: int
    """The intruder's last cell in the level."""
    goal: int
    """The flat cell it headed for (-1: none)."""


class _NoCameras(NamedTuple):
    watch: None = None


class RecordedEpisode(NamedTuple):
    """The parts of an :class:`~guardsim.alert.AlertEpisode` its pictures read, from a trace."""

    record: dict[str, Any]
    """Per tick, as the episode's :attr:`~guardsim.alert.AlertEpisode.record` (no contaminated cells)."""
    modes: list[str]
    """One entry per guard (its last state)."""
    events: list[AlertEvent]
    noises: list[tuple[int, int, float, str]]
    """``(tick, flat cell, radius, source)``."""
    intruder: _Goal
    search: _Named
    phase: int
    cameras: _NoCameras = _NoCameras()


def recorded_episode(data: dict[str, Any], grid: CoverageGrid, *, source: str = "trace") -> RecordedEpisode:
    """The episode of alert trace ``data`` on ``grid`` (the grid of the level it was played on); a
    :class:`~guardsim.errors.TraceError` naming ``source`` when the trace does not fit the grid."""
    try:
        return _recorded(data, grid)
    except (KeyError, TypeError, ValueError, IndexError) as error:
        raise TraceError(f"{source}: not an alert trace of this level ({type(error).__name__}: {error})") from None


def _recorded(data: dict[str, Any], grid: CoverageGrid) -> RecordedEpisode:
    rows, cols = grid.shape
    if list(data["shape"]) != [rows, cols]:
        raise ValueError(f"its grid is {data['shape'][0]} x {data['shape'][1]}, the level's {rows} x {cols}")

    def flat(pair: Sequence[int] | None, missing: int = -1) -> int:
        if pair is None:
            return missing
        col, row = int(pair[0]), int(pair[1])
        if not (0 <= col < cols and 0 <= row < rows):
            raise ValueError(f"cell [{col}, {row}] lies outside the grid")
        return grid.flat(col, row)

    paths = data["paths"]
    guards, ticks = len(paths), len(paths[0])
    cells: list[list[int]] = []
    for tick in range(ticks):
        # A body off the grid for a tick (continuous motion) is drawn where it last was.
        cells.append([flat(paths[g][tick], cells[-1][g] if cells else 0) for g in range(guards)])
    intruder = [None if pair is None else flat(pair) for pair in data["intruder_path"]]
    record: dict[str, Any] = {
        "cells": cells,
        "headings": [[int(data["headings"][g][tick]) for g in range(guards)] for tick in range(ticks)],
        "guard_states": [[str(data["guard_states"][g][tick]) for g in range(guards)] for tick in range(ticks)],
        "awareness": [[float(data["awareness"][g][tick]) for g in range(guards)] for tick in range(ticks)],
        "intruder": intruder,
        "contaminated": [int(count) for count in data["contaminated"]],
        "contaminated_cells": [np.zeros(0, dtype=np.int32) for _ in range(ticks)],
        "last_known": [flat(pair) for pair in data["last_known"]],
        "heard": [[bool(data["heard"][g][tick]) for g in range(guards)] for tick in range(ticks)]
        if "heard" in data
        else [[False] * guards for _ in range(ticks)],
    }
    if "poses" in data:
        record["poses"] = [[data["poses"][g][tick][1:] for g in range(guards)] for tick in range(ticks)]
    noises = []
    for noise in data.get("noises", []):
        at = grid.cell_of(tuple(noise["position"]))
        if at is not None:
            noises.append((int(noise["tick"]), grid.flat(*at), float(noise["radius"]), str(noise["source"])))
    goal = data.get("goal")
    at_goal = None if goal is None else grid.cell_of((float(goal[0]), float(goal[1])))
    last = next((cell for cell in reversed(intruder) if cell is not None), 0)
    return RecordedEpisode(
        record=record,
        modes=[str(states[-1]) for states in data["guard_states"]],
        events=[AlertEvent(int(e["tick"]), int(e["guard"]), str(e["event"])) for e in data["events"]],
        noises=noises,
        intruder=_Goal(last, -1 if at_goal is None else grid.flat(*at_goal)),
        search=_Named(str(data["search"])),
        phase=int(data.get("phase", 0)),
    )
