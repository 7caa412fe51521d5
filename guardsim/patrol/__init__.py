"""Patrols: repeating guard routes that watch a level, scored by idleness, and routes for game editors.

- :mod:`~guardsim.patrol.model`: :class:`Patrol`, every guard's state per tick (one lap when it repeats).
- :mod:`~guardsim.patrol.scoring`: what each tick sees, and idleness (worst and mean unwatched time).
- :mod:`~guardsim.patrol.loops`: closed cover loops, for one guard or a team (shared cycle or split loops).
- :mod:`~guardsim.patrol.strategies`: the walked baselines (staleness, RippleFront for ever, random goals).
- :mod:`~guardsim.patrol.plan`: a patrol of a level by strategy name.
- :mod:`~guardsim.patrol.format`: patrol.json, written and read strictly.
- :mod:`~guardsim.patrol.export`: route.json waypoints; :mod:`~guardsim.patrol.tiled_export`: the Tiled
  object layer and a fresh map for a level drawn by hand.

See ``docs/patrols.md``.
"""

from __future__ import annotations

from guardsim.patrol.format import PatrolError, parse_patrol, patrol_data, read_patrol
from guardsim.patrol.model import STRATEGIES, Patrol
from guardsim.patrol.plan import PatrolPlan, PatrolSetup, patrol_setup, plan_loop, plan_patrol
from guardsim.patrol.scoring import PatrolScore, score_patrol, seen_timeline

__all__ = [
    "STRATEGIES",
    "Patrol",
    "PatrolError",
    "PatrolPlan",
    "PatrolScore",
    "PatrolSetup",
    "parse_patrol",
    "patrol_data",
    "patrol_setup",
    "plan_loop",
    "plan_patrol",
    "read_patrol",
    "score_patrol",
    "seen_timeline",
]
