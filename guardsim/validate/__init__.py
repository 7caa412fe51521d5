"""Judging a level: what ``guardsim validate`` adds to the level check, and the gates of ``guardsim check``.

- :mod:`~guardsim.validate.diagnostics`: what a level's scene shows a designer should know (cells the
  guard cannot reach, passages too tight to stand in, walls that touch);
- :mod:`~guardsim.validate.repair`: ``validate --fix``, level geometry made valid;
- :mod:`~guardsim.validate.checks`: ``guardsim check``, a level's patrol and sneak gates for CI.
"""
