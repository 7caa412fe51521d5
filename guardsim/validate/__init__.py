"""What ``guardsim validate`` adds to the level check: diagnostics of the built scene (cells the guard
cannot reach, passages too tight to stand in, walls that touch) and repairs of level geometry.

- :mod:`~guardsim.validate.diagnostics`: what a level's scene shows a designer should know;
- :mod:`~guardsim.validate.repair`: ``validate --fix``, level geometry made valid.
"""
