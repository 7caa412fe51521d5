"""The record of one episode, and its JSON form."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["OUTCOMES", "Trace"]

#: How an episode can end.
OUTCOMES = ("covered", "step_limit", "stuck")


@dataclass(frozen=True, eq=False)
class Trace:
    """Everything that happened in one episode; enough to redraw every frame."""

    level: str
    """Level name."""
    planner: str
    """Planner name."""
    seed: int | None
    """Seed the episode's generator came from, if any."""
    cell_size: float
    origin: tuple[float, float]
    """World position of the grid's top-left corner."""
    shape: tuple[int, int]
    """``(rows, cols)``."""
    path: tuple[tuple[int, int], ...]
    """``(col, row)`` of the guard at each tick, the start included."""
    headings: tuple[int, ...]
    """Heading number (0 right, 1 down, 2 left, 3 up) at each tick."""
    unseen_percent: tuple[float, ...]
    """Percentage of reachable cells still unseen at each tick."""
    outcome: str
    """One of :data:`OUTCOMES`."""
    reachable: int
    """Cells reachable from the start: the episode's goal."""
    unreachable: int
    """Traversable cells not reachable from the start (left out of the goal)."""
    first_seen: np.ndarray
    """``int (rows, cols)``: tick at which each cell was first seen, -1 if never."""
    goal: np.ndarray
    """``bool (rows, cols)``: the reachable cells."""
    traversable: np.ndarray
    """``bool (rows, cols)``: cells the guard could stand on."""

    @property
    def start(self) -> tuple[int, int]:
        """``(col, row)`` of the start cell."""
        return self.path[0]

    @property
    def steps(self) -> int:
        """Steps taken."""
        return len(self.path) - 1

    @property
    def covered(self) -> bool:
        """Whether every reachable cell was seen."""
        return self.outcome == "covered"

    def steps_to_fraction(self, fraction: float) -> int | None:
        """First tick at which at least ``fraction`` of the reachable cells had been seen, or ``None``."""
        ticks = np.sort(self.first_seen[self.goal & (self.first_seen >= 0)])
        needed = int(np.ceil(fraction * self.reachable - 1e-9))
        if needed <= 0:
            return 0
        if needed > ticks.size:
            return None
        return int(ticks[needed - 1])

    def to_data(self) -> dict[str, Any]:
        """The JSON-ready dictionary; see ``docs/trace-format.md``."""
        return {
            "level": self.level,
            "planner": self.planner,
            "seed": self.seed,
            "cell_size": self.cell_size,
            "origin": list(self.origin),
            "shape": list(self.shape),
            "start": list(self.start),
            "steps": self.steps,
            "covered": self.covered,
            "outcome": self.outcome,
            "reachable": self.reachable,
            "unreachable": self.unreachable,
            "path": [list(cell) for cell in self.path],
            "headings": list(self.headings),
            "unseen_percent": list(self.unseen_percent),
            "first_seen": self.first_seen.tolist(),
            "goal": self.goal.astype(int).tolist(),
            "traversable": self.traversable.astype(int).tolist(),
        }

    def to_json(self) -> str:
        """Stable JSON text: one top-level key per line, values compact, so traces diff well."""
        lines = [
            f"  {json.dumps(key)}: {json.dumps(value, separators=(',', ':'))}" for key, value in self.to_data().items()
        ]
        return "{\n" + ",\n".join(lines) + "\n}\n"

    @classmethod
    def from_data(cls, data: dict[str, Any]) -> Trace:
        """Rebuild a trace from :meth:`to_data` output."""
        return cls(
            level=data["level"],
            planner=data["planner"],
            seed=data["seed"],
            cell_size=float(data["cell_size"]),
            origin=(float(data["origin"][0]), float(data["origin"][1])),
            shape=(int(data["shape"][0]), int(data["shape"][1])),
            path=tuple((int(c), int(r)) for c, r in data["path"]),
            headings=tuple(int(h) for h in data["headings"]),
            unseen_percent=tuple(float(p) for p in data["unseen_percent"]),
            outcome=data["outcome"],
            reachable=int(data["reachable"]),
            unreachable=int(data["unreachable"]),
            first_seen=np.asarray(data["first_seen"], dtype=np.int64),
            goal=np.asarray(data["goal"], dtype=bool),
            traversable=np.asarray(data["traversable"], dtype=bool),
        )
