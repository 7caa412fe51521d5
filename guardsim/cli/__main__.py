"""``python -m guardsim.cli``: the same command line as ``guardsim``."""

from guardsim.cli import run

run()
