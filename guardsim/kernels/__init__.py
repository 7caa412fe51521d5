"""guardsim's kernel library: the compiled primitives, each in one place.

Every compiled function in guardsim is compiled by :func:`guardsim.kernels.compiler.jit`, and compiled
code calls compiled code in another file only if that code lives here. Importing this package loads no
compiler; each module imports numba itself.

- :mod:`~guardsim.kernels.compiler`: the decorator, the cache folder named after a digest of every
  compiled source (never stale), and the one-line notice while compiling;
- :mod:`~guardsim.kernels.ahead`: a command's kernels compiled ahead on two processes, from ``plan.json``;
- :mod:`~guardsim.kernels.states`: the state numbering (a cell and one of four headings), plain Python;
- :mod:`~guardsim.kernels.steps`: the numbering for compiled code, and the greedy step every walker takes;
- :mod:`~guardsim.kernels.distances`: breadth-first fills over cells and over states;
- :mod:`~guardsim.kernels.heap`: a binary min-heap of (key, item) pairs;
- :mod:`~guardsim.kernels.subsets`: the Held–Karp subset DP of the path bounds;
- :mod:`~guardsim.kernels.trees`: spanning trees over clusters of states;
- :mod:`~guardsim.kernels.picks`: the cluster bound's farthest-first picks;
- :mod:`~guardsim.kernels.tours`: open tours (nearest neighbour, 2-opt, Or-opt);
- :mod:`~guardsim.kernels.walk`: a team walking its viewpoint routes, simulated with the view table;
- :mod:`~guardsim.kernels.estimate` and :mod:`~guardsim.kernels.frontier`: the exact search's lower
  bound and macro moves, shared with its beam seed;
- :mod:`~guardsim.kernels.targets`, :mod:`~guardsim.kernels.screen` and :mod:`~guardsim.kernels.fill`:
  a cone's cells, the wall screen and the compiled vision fill;
- :mod:`~guardsim.kernels.arrays`: copying into a slice by a plain loop;
- :mod:`~guardsim.kernels.noise`: how far a noise carries along the grid (hearing).
- :mod:`~guardsim.kernels.meter`: the awareness meter's rules (a tick's gain, visibility in the light, the
  meter after a tick), for plain Python and compiled code alike.
"""
