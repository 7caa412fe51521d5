"""Vision: which cells a guard sees from each state, by one of the line-of-sight rules.

- :mod:`~guardsim.vision.rules`: the line-of-sight rules (:class:`LineOfSight`) and the vision-function type;
- :mod:`~guardsim.vision.cone`: the cone's cell offsets per heading (:class:`VisionCone`);
- :mod:`~guardsim.vision.rays`: the reference, one pymunk ray per cell (:func:`visible_cells`);
- :mod:`~guardsim.kernels.screen`: the compiled wall screen that settles most rays without pymunk;
- :mod:`~guardsim.kernels.targets`: the compiled twin of the cone's targets;
- :mod:`~guardsim.vision.bresenham`: the Bresenham rule of grid watchman-route solvers;
- :mod:`~guardsim.vision.cache`: every state's cells, computed once per level (:class:`VisionCache`);
- :mod:`~guardsim.vision.table`: the per-level view table, what each state sees and who sees each cell.
"""

from __future__ import annotations

from guardsim.vision.cone import VisionCone
from guardsim.vision.rays import visible_cells
from guardsim.vision.rules import LineOfSight, VisionFunction

# The cache, the table and the Bresenham rule are compiled with numba: import them from their modules,
# so that what only needs the cone and the rays (validation, previews) starts without the compiler.
__all__ = ["LineOfSight", "VisionCone", "VisionFunction", "visible_cells"]
