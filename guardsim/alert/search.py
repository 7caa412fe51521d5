"""Search strategies: where guards go once they have lost sight of the intruder.

Every strategy sees the same picture: the *contaminated* set (cells the intruder may be in now: the last
known cell, grown each tick by the intruder's reach and cleared by every guard's sight; kept by the
episode, :class:`Contamination`), the last known cell and the searching guards' cells. Each tick it gives
each searching guard a distance field to walk down, or ``None`` when that guard's search is over. The
cells at the bottom of a field (distance 0) are where the strategy wants that guard to look; the episode
commits each searcher to one of them, leaning the way the intruder was last seen going and away from
the other searchers' choices (see :mod:`guardsim.alert.episode`). The strategies are told that
direction of travel when a search starts (``diffuse`` spreads its mass that way).

- ``ripple``: RippleFront over the contaminated set: the distance to the nearest cell the intruder may be
  in, one compiled fill per tick (a 60 x 60 level: about 20 microseconds).
- ``diffuse``: a probability grid seeded at the last known cell, diffusing each tick (more of it along
  the intruder's last seen direction of travel: :data:`LEAN`) and losing the mass in view
  (Stealth-Simulator's grid search); a guard heads for the cell with the most probability per step of
  distance.
- ``team``: the contaminated set split into one part per searcher (grown from centres spread over the
  set); each walks RippleFront over its own part.
- ``last-known``: walk to the last known cell, look around once, give up (what most games ship); a
  second guard that finds a teammate already there looks around from within two cells of it.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from guardsim.errors import ArgumentError
from guardsim.kernels.distances import FAR, distance_fields, distances_from

__all__ = ["SEARCHES", "Contamination", "SearchStrategy", "make_search"]

#: The strategies, by the name ``guardsim alert --search`` takes.
SEARCHES = ("ripple", "diffuse", "team", "last-known")

#: Ticks a ``last-known`` guard turns in place at the last known cell (a full turn) before giving up.
LOOK_AROUND_TICKS = 4

#: ``diffuse``: how much the spread leans along the intruder's last seen direction of travel: a cell
#: passes ``rate * (1 + LEAN * cos(angle)) / 4`` of its mass to the neighbour at that angle from the
#: direction (the four shares add up to ``rate``).
LEAN = 0.6

#: Heading numbers' steps (column, row): right, down, left, up.
DIRECTIONS = ((1, 0), (0, 1), (-1, 0), (0, -1))


class Contamination:
    """Cells the intruder may occupy: grown by its reach each tick, cleared by sight.

    >>> neighbours = np.array([[1, -1, -1, -1], [2, -1, 0, -1], [-1, -1, 1, -1]])
    >>> field = Contamination(neighbours)
    >>> field.seed(0); field.spread(1); field.cells.tolist()
    [True, True, False]
    >>> field.clear(np.array([0])); field.count
    1
    """

    def __init__(self, neighbours: np.ndarray) -> None:
        self.neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
        self.cells = np.zeros(self.neighbours.shape[0], dtype=bool)
        self._padded = np.zeros(self.neighbours.shape[0] + 1, dtype=bool)

    def seed(self, cell: int) -> None:
        """Only ``cell``: the intruder was seen there."""
        self.cells[:] = False
        self.cells[cell] = True

    def spread(self, steps: int) -> None:
        """Grow by ``steps`` 4-connected moves (the intruder's reach this tick)."""
        padded = self._padded
        for _ in range(steps):
            padded[:-1] = self.cells
            # Index -1 (no neighbour) reads the padding's last entry, which stays False.
            self.cells |= padded[self.neighbours].any(axis=1)

    def clear(self, seen: np.ndarray) -> None:
        """Remove the cells in view (flat indices)."""
        self.cells[seen] = False

    @property
    def count(self) -> int:
        """Cells the intruder may be in."""
        return int(np.count_nonzero(self.cells))


class SearchStrategy(Protocol):
    """A search strategy (see the module's list)."""

    name: str

    def start(self, last_known: int, travel: int = -1) -> None:
        """A search starts (or restarts after a loss of sight) from the last known cell; ``travel`` is the
        heading number of the intruder's last seen direction of travel (-1: not known)."""

    def observe(self, contaminated: Contamination, seen: np.ndarray) -> None:
        """The tick's picture after spreading and clearing; ``seen`` is every guard's view (flat cells)."""

    def fields(self, searchers: dict[int, int]) -> dict[int, np.ndarray | None]:
        """Each searching guard's field (``{guard: cell}`` in, ``{guard: field or None}`` out)."""


class _Base:
    name = ""

    def __init__(self, neighbours: np.ndarray) -> None:
        self.neighbours = np.ascontiguousarray(neighbours, dtype=np.int64)
        self.contaminated = np.zeros(self.neighbours.shape[0], dtype=bool)
        self.last_known = -1
        self.travel = -1

    def start(self, last_known: int, travel: int = -1) -> None:
        self.last_known = int(last_known)
        self.travel = int(travel)
        self.contaminated = np.zeros(self.neighbours.shape[0], dtype=bool)
        self.contaminated[last_known] = True

    def observe(self, contaminated: Contamination, seen: np.ndarray) -> None:
        self.contaminated = contaminated.cells

    def fields(self, searchers: dict[int, int]) -> dict[int, np.ndarray | None]:
        raise NotImplementedError


class RippleSearch(_Base):
    """RippleFront over the contaminated set, shared by every searcher."""

    name = "ripple"

    def fields(self, searchers: dict[int, int]) -> dict[int, np.ndarray | None]:
        if not self.contaminated.any():
            return dict.fromkeys(searchers)
        field = distances_from(self.neighbours, self.contaminated)
        return dict.fromkeys(searchers, field)


class TeamSearch(_Base):
    """The contaminated set split into one part per searcher, each walking RippleFront over its own.

    The parts grow from centres spread over the set (the first contaminated cell in row order, then each
    next centre the cell farthest from those chosen); every cell joins its nearest centre, and the
    searchers take the parts nearest to them, closest pair first. A split by nearest *searcher* would
    leave every searcher but one with nothing when the set lies to one side of them all.
    """

    name = "team"

    def fields(self, searchers: dict[int, int]) -> dict[int, np.ndarray | None]:
        cells = np.flatnonzero(self.contaminated)
        if cells.size == 0:
            return dict.fromkeys(searchers)
        guards = sorted(searchers)
        parts = min(len(guards), int(cells.size))
        if parts == 1:
            return dict.fromkeys(guards, distances_from(self.neighbours, cells))
        centres = [int(cells[0])]
        nearest = distances_from(self.neighbours, np.array(centres, dtype=np.int64))
        while len(centres) < parts:
            centres.append(int(cells[int(np.argmax(nearest[cells]))]))
            nearest = np.minimum(nearest, distances_from(self.neighbours, np.array(centres[-1:], dtype=np.int64)))
        owner = np.argmin(distance_fields(self.neighbours, np.array(centres, dtype=np.int64))[:, cells], axis=0)
        to_guard = distance_fields(self.neighbours, np.array([searchers[g] for g in guards], dtype=np.int64))
        pairs = sorted((int(to_guard[i, centre]), i, k) for i in range(len(guards)) for k, centre in enumerate(centres))
        taken_guards: set[int] = set()
        taken_parts: set[int] = set()
        out: dict[int, np.ndarray | None] = {}
        for _, index, part in pairs:
            if index in taken_guards or part in taken_parts:
                continue
            taken_guards.add(index)
            taken_parts.add(part)
            out[guards[index]] = distances_from(self.neighbours, cells[owner == part])
        whole = distances_from(self.neighbours, cells)
        for guard in guards:
            out.setdefault(guard, whole)  # more searchers than cells: the rest sweep the whole set
        return out


class DiffuseSearch(_Base):
    """A probability grid: each tick every cell passes ``rate / 4`` of its mass to each neighbour, the mass
    in view is dropped and the rest renormalised; a guard heads for the cell with the most mass per step
    of distance (``mass / (1 + steps)``)."""

    name = "diffuse"

    def __init__(self, neighbours: np.ndarray, rate: float = 0.5) -> None:
        super().__init__(neighbours)
        self.rate = rate
        self.mass = np.zeros(self.neighbours.shape[0], dtype=np.float64)
        self._degree = (self.neighbours >= 0).sum(axis=1)
        self._padded = np.zeros(self.neighbours.shape[0] + 1, dtype=np.float64)
        self._share = np.full(4, 0.25)

    def start(self, last_known: int, travel: int = -1) -> None:
        super().start(last_known, travel)
        self.mass[:] = 0.0
        self.mass[last_known] = 1.0
        # share[d]: the part of ``rate`` a cell passes to its neighbour in direction d.
        self._share = np.full(4, 0.25)
        if travel >= 0:
            self._share = np.array([(1.0 + LEAN * _cos(travel, d)) / 4.0 for d in range(4)])

    def observe(self, contaminated: Contamination, seen: np.ndarray) -> None:
        super().observe(contaminated, seen)
        padded = self._padded
        padded[:-1] = self.mass
        share = self._share
        has = self.neighbours >= 0
        # A cell receives from its neighbour in direction d what that neighbour sends the opposite way.
        inflow = (padded[self.neighbours] * share[[2, 3, 0, 1]]).sum(axis=1)
        outflow = (has * share).sum(axis=1) * self.mass
        self.mass += self.rate * (inflow - outflow)
        self.mass[seen] = 0.0
        total = self.mass.sum()
        if total > 0:
            self.mass /= total

    def fields(self, searchers: dict[int, int]) -> dict[int, np.ndarray | None]:
        if not (self.mass > 0).any():
            return dict.fromkeys(searchers)
        out: dict[int, np.ndarray | None] = {}
        for guard, cell in sorted(searchers.items()):
            steps = distances_from(self.neighbours, np.array([cell], dtype=np.int64)).astype(np.float64)
            steps[steps >= FAR] = np.inf
            target = int(np.argmax(self.mass / (1.0 + steps)))
            out[guard] = distances_from(self.neighbours, np.array([target], dtype=np.int64))
        return out


class LastKnownSearch(_Base):
    """Walk to the last known cell, turn around once there, then give up."""

    name = "last-known"

    def __init__(self, neighbours: np.ndarray) -> None:
        super().__init__(neighbours)
        self._looked: dict[int, int] = {}
        self._field: np.ndarray | None = None

    def start(self, last_known: int, travel: int = -1) -> None:
        super().start(last_known, travel)
        self._looked = {}
        self._field = distances_from(self.neighbours, np.array([last_known], dtype=np.int64))

    def fields(self, searchers: dict[int, int]) -> dict[int, np.ndarray | None]:
        out: dict[int, np.ndarray | None] = {}
        there = [g for g, c in searchers.items() if c == self.last_known]
        for guard, cell in searchers.items():
            if cell == self.last_known or (there and self._within_two(cell) and guard not in there):
                self._looked[guard] = self._looked.get(guard, 0) + 1
            done = self._looked.get(guard, 0) > LOOK_AROUND_TICKS
            out[guard] = None if done or self._field is None else self._field
        return out

    def _within_two(self, cell: int) -> bool:
        return self._field is not None and int(self._field[cell]) <= 2


def _cos(travel: int, direction: int) -> float:
    """Cosine of the angle between two heading numbers."""
    (ax, ay), (bx, by) = DIRECTIONS[travel], DIRECTIONS[direction]
    return float(ax * bx + ay * by)


def make_search(name: str, neighbours: np.ndarray) -> SearchStrategy:
    """The strategy called ``name`` (one of :data:`SEARCHES`).

    >>> make_search("ripple", np.array([[-1, -1, -1, -1]])).name
    'ripple'
    """
    kinds: dict[str, type[_Base]] = {
        "ripple": RippleSearch,
        "diffuse": DiffuseSearch,
        "team": TeamSearch,
        "last-known": LastKnownSearch,
    }
    if name not in kinds:
        raise ArgumentError(f"unknown search strategy {name!r}; choose from {', '.join(SEARCHES)}")
    return kinds[name](neighbours)
