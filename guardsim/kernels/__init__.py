"""guardsim's kernel library: every compiled primitive, in one place.

Compiled code anywhere in guardsim is compiled by :func:`guardsim.kernels.compiler.jit` and calls
compiled code in another file only if that code lives here:

- :mod:`~guardsim.kernels.states`: the state numbering (a cell and one of four headings), plain Python;
- :mod:`~guardsim.kernels.steps`: its compiled form and the greedy step every walker takes;
- :mod:`~guardsim.kernels.distances`: breadth-first distance fills over cells and over states;
- :mod:`~guardsim.kernels.heap`: a binary min-heap of (key, item) pairs;
- :mod:`~guardsim.kernels.subsets`: the Held–Karp subset DP over a small distance matrix.

Importing this package loads no compiler; each module imports numba itself.
"""
