"""Click parameter types the commands share (below :mod:`guardsim.cli.common` and
:mod:`guardsim.cli.map_options`, which both use them)."""

from __future__ import annotations

import math
from typing import Any

import click

__all__ = ["FiniteFloatRange"]


class FiniteFloatRange(click.FloatRange):
    """A float option within a range that also refuses ``nan`` and ``inf`` (every comparison with NaN is
    false, so a plain :class:`click.FloatRange` lets it through)."""

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        number = super().convert(value, param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number.", param, ctx)
        return number
