"""guardsim: coverage path planning for guards in games."""

__version__ = "0.1.0"
