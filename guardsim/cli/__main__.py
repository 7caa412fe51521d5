"""``python -m guardsim.cli``: the same command line as ``guardsim``, as a plain Python program (its
interpreter tears down as usual, so ``python -m cProfile -m guardsim.cli ...`` prints its profile)."""

from guardsim.cli import main

main()
