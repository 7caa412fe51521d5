"""What a walk cost in game terms: seconds, distance, turning.

A *turn* is a run of consecutive ticks over which the heading changes in one direction; its size is the
angle it adds up to. A *U-turn* is a turn of at least :data:`U_TURN_DEGREES`. On the grid a turn is a
tick whose heading differs from the previous one (90 or 180 degrees), and distance is moves times the
cell size: the steps-based subset.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from guardsim.trace import Trace

__all__ = [
    "FRACTIONS",
    "RECORD_COLUMNS",
    "U_TURN_DEGREES",
    "continuous_measures",
    "grid_measures",
    "measures_of",
    "record_columns",
    "summary_text",
]

#: Coverage fractions reported as T50, T90, T99.
FRACTIONS = (0.5, 0.9, 0.99)
#: A turn of at least this many degrees is a U-turn.
U_TURN_DEGREES = 135.0
# Below these a tick neither moved nor turned (float noise of the physics step).
_STILL = 1e-9
_NO_TURN = 1e-7


def continuous_measures(poses: np.ndarray, tick_hz: float, ticks_to: Mapping[str, int | None]) -> dict[str, Any]:
    """Measures of ``poses`` (``[t, x, y, heading_degrees]`` per tick).

    ``ticks_to`` maps ``"cover"``, ``"t50"``, ``"t90"``, ``"t99"`` to the tick each was reached (or
    ``None``); they are reported in seconds.
    """
    ticks = max(0, len(poses) - 1)
    seconds = ticks / tick_hz
    moved = np.hypot(np.diff(poses[:, 1]), np.diff(poses[:, 2])) if ticks else np.zeros(0)
    turned = (np.diff(poses[:, 3]) + 180.0) % 360.0 - 180.0 if ticks else np.zeros(0)
    turning = np.abs(turned) > _NO_TURN
    in_place = turning & (moved <= _STILL)
    sizes = _turn_sizes(turned, turning)
    turns = len(sizes)
    return {
        "seconds": round(seconds, 6),
        **{f"{name}_s": None if tick is None else round(tick / tick_hz, 6) for name, tick in ticks_to.items()},
        "distance": round(float(moved.sum()), 6),
        "turning_degrees": round(float(np.abs(turned).sum()), 3),
        "in_place_s": round(int(in_place.sum()) / tick_hz, 6),
        "turns": turns,
        "u_turns": int(sum(size >= U_TURN_DEGREES - 1e-6 for size in sizes)),
        "turns_per_minute": round(60.0 * turns / seconds, 3) if seconds else None,
    }


def _turn_sizes(turned: np.ndarray, turning: np.ndarray) -> list[float]:
    """Sizes of the runs of same-signed rotation."""
    sizes: list[float] = []
    current, sign = 0.0, 0
    for angle, active in zip(turned.tolist(), turning.tolist()):
        now = (1 if angle > 0 else -1) if active else 0
        if now != sign and sign != 0:
            sizes.append(abs(current))
            current = 0.0
        if now:
            current += angle
        sign = now
    if sign != 0:
        sizes.append(abs(current))
    return sizes


def grid_measures(trace: Trace) -> dict[str, Any]:
    """The steps-based subset for a grid trace: turns, U-turns, turning, distance (each guard summed)."""
    turns = u_turns = 0
    degrees = 0.0
    for headings, path in zip(trace.team_headings(), trace.team_paths()):
        for before, after, cell_before, cell_after in zip(headings, headings[1:], path, path[1:]):
            if before != after and cell_before != cell_after:
                quarter = (after - before) % 4
                turns += 1
                degrees += 180.0 if quarter == 2 else 90.0
                u_turns += quarter == 2
    steps = trace.steps
    return {
        "steps": steps,
        **{f"t{round(100 * f)}": trace.steps_to_fraction(f) for f in FRACTIONS},
        "distance": trace.total_moves * trace.cell_size,
        "turning_degrees": degrees,
        "turns": turns,
        "u_turns": u_turns,
        "turns_per_100_steps": round(100.0 * turns / steps, 3) if steps else None,
    }


def measures_of(trace: Trace) -> dict[str, Any]:
    """The trace's own measures (continuous motion) or the steps-based subset (grid)."""
    if trace.motion == "continuous" and trace.measures:
        return dict(trace.measures)
    return grid_measures(trace)


def summary_text(trace: Trace) -> str:
    """The motion figures of ``guardsim play``'s summary line."""
    m = measures_of(trace)
    if trace.motion == "continuous":
        t90 = m.get("t90_s")
        return (
            f"{m['seconds']:.1f} s of game time ({trace.steps} ticks at {trace.tick_hz:g} Hz), "
            f"T90 {'-' if t90 is None else f'{t90:.1f} s'}, walked {m['distance']:.1f}, "
            f"turned {m['turning_degrees']:.0f} deg ({m['in_place_s']:.1f} s in place), "
            f"{m['turns']} turns ({_per(m['turns_per_minute'])}/min), {m['u_turns']} U-turns"
        )
    return f"{m['turns']} turns ({_per(m['turns_per_100_steps'])} per 100 steps), {m['u_turns']} U-turns"


def _per(value: float | None) -> str:
    return "-" if value is None or math.isnan(value) else f"{value:.1f}"


#: The motion columns of ``guardsim bench``'s results, in order (see :func:`record_columns`).
RECORD_COLUMNS = ("motion", "game_seconds", "t50_s", "t90_s", "t99_s", "distance", "turning_degrees", "in_place_s",
                  "turns", "u_turns", "turns_per_minute")  # fmt: skip


def record_columns(trace: Trace) -> dict[str, Any]:
    """The values of :data:`RECORD_COLUMNS` for one episode: all of them in continuous motion, the
    steps-based subset (distance, turning, turns, U-turns) on the grid, ``None`` for the rest."""
    m = measures_of(trace)
    continuous = trace.motion == "continuous"
    values: dict[str, Any] = dict.fromkeys(RECORD_COLUMNS)
    values["motion"] = trace.motion
    for name in ("distance", "turning_degrees", "turns", "u_turns"):
        values[name] = m.get(name)
    if continuous:
        values["game_seconds"] = m["seconds"]
        for name in ("t50_s", "t90_s", "t99_s", "in_place_s", "turns_per_minute"):
            values[name] = m.get(name)
    return values
