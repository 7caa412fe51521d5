"""Guards that notice: patrol, suspicious, investigate, chase, search and return, against an intruder.

- :mod:`~guardsim.alert.model`: states, events, the rules' numbers, an episode's outcome.
- :mod:`~guardsim.alert.search`: the contaminated set and the search strategies.
- :mod:`~guardsim.alert.intruders`: route, sneak, evader and still intruders.
- :mod:`~guardsim.alert.movement`: where the guards are and what they see: grid or continuous motion.
- :mod:`~guardsim.alert.episode`: the tick loop.
- :mod:`~guardsim.alert.run`: one episode from given points or many from seeded starts, traces, summaries.
- :mod:`~guardsim.alert.batch`: one episode of a batch as a task a worker runs, and its trace file.
- :mod:`~guardsim.alert.batch_run`: a batch as ``guardsim alert`` runs it: options checked, starts drawn,
  episodes on workers or Dask, traces written into a folder and resumed, ``alert.json``.
- :mod:`~guardsim.alert.player`: the game's own player as the intruder, a frame at a time.
- :mod:`~guardsim.alert.invariants`: what a designer expects of game guards, checked on traces.

See ``docs/alert.md``.
"""

from __future__ import annotations

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.intruders import Intruder, make_intruder
from guardsim.alert.invariants import Violation, check_alert_trace
from guardsim.alert.model import (
    EVENTS,
    GUARD_STATES,
    INTRUDERS,
    OUTCOMES,
    AlertEvent,
    AlertOutcome,
    AlertRules,
    Event,
    GuardState,
)
from guardsim.alert.player import GameGuards, GuardsFrame, PlayerIntruder
from guardsim.alert.run import DEFAULT_MAX_SECONDS, AlertSummary, alert_episode, alert_trace_data, run_alerts, summarise
from guardsim.alert.search import SEARCHES, Contamination, make_search

__all__ = [
    "DEFAULT_MAX_SECONDS",
    "EVENTS",
    "GUARD_STATES",
    "INTRUDERS",
    "OUTCOMES",
    "SEARCHES",
    "AlertEpisode",
    "AlertEvent",
    "AlertOutcome",
    "AlertRules",
    "AlertSummary",
    "Contamination",
    "Event",
    "GameGuards",
    "GuardState",
    "GuardsFrame",
    "Intruder",
    "PlayerIntruder",
    "Violation",
    "alert_episode",
    "alert_trace_data",
    "check_alert_trace",
    "make_intruder",
    "make_search",
    "run_alerts",
    "summarise",
]
