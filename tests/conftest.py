"""Test-session settings shared by every test file."""

from __future__ import annotations

import os

# A fresh machine compiles the kernels during the first tests; their one-line notice on standard error
# is tested on its own (test_kernels.py) and must not add a line to the messages other tests read.
os.environ.setdefault("GUARDSIM_COMPILE_NOTICE", "0")
# Likewise a long command's progress lines (guardsim.cli.progress), tested in test_patrol_scaling.py.
os.environ.setdefault("GUARDSIM_PROGRESS", "0")
