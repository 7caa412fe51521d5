"""An alert episode's guards as a :class:`~guardsim.trace.Trace`, so the GIF renderer draws them."""

from __future__ import annotations

import numpy as np

from guardsim.alert.episode import AlertEpisode
from guardsim.alert.recorded import RecordedEpisode
from guardsim.kernels.steps import state_of
from guardsim.patrol.model import Patrol
from guardsim.patrol.replay import patrol_trace
from guardsim.scene import Scene
from guardsim.trace import Trace
from guardsim.vision.table import ViewTable

__all__ = ["guard_trace"]


def guard_trace(scene: Scene, table: ViewTable, episode: AlertEpisode | RecordedEpisode) -> Trace:
    """The guards' walk of ``episode`` (states as recorded, whatever their alert state) as a trace."""
    cells = np.asarray(episode.record["cells"], dtype=np.int64).T
    headings = np.asarray(episode.record["headings"], dtype=np.int64).T
    walked = Patrol(state_of(cells, headings), period=None, strategy="evaluate")
    grid = scene.grid
    first = int(cells[0, 0])
    goal = np.asarray(grid.component(*grid.unflat(first)).ravel())
    return patrol_trace(scene, table, walked, goal, ticks=walked.ticks - 1, label=f"alert: {episode.search.name}")
