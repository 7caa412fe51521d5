"""The paper's figure: a box plot of steps per level, one box per planner, the median written on each.

matplotlib is optional (``pip install 'guardsim[plot]'``) and imported only when a figure is drawn.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import NamedTuple

from guardsim.errors import GuardsimError
from guardsim.output import atomic_path

__all__ = ["StepsBox", "plot_steps", "require_matplotlib"]


class StepsBox(NamedTuple):
    """The steps of the episodes of one level with one planner."""

    level: str
    """Level name, the label under its boxes."""
    planner: str
    steps: Sequence[int]


def require_matplotlib() -> None:
    """Raise a one-line :class:`GuardsimError` saying what to install if matplotlib is missing."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise GuardsimError("--plot needs matplotlib, which is not installed: pip install 'guardsim[plot]'") from None


def plot_steps(boxes: Sequence[StepsBox], targets: Sequence[str | os.PathLike[str]], *, title: str = "") -> None:
    """Draw the box plot and write it to each target (the format follows the suffix: ``.png``, ``.svg``).

    Levels appear left to right in the order of their first box; when there are several planners, each
    level gets one box per planner side by side, coloured by planner, with a legend. Boxes span the
    quartiles, whiskers reach 1.5 times the interquartile range, and points beyond are drawn as outliers.
    Output is deterministic: no timestamp in the SVG, a fixed SVG id salt.
    """
    require_matplotlib()
    from matplotlib import rc_context
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    levels = list(dict.fromkeys(box.level for box in boxes))
    planners = list(dict.fromkeys(box.planner for box in boxes))
    width = 0.8 / len(planners)
    colours = [f"C{index % 10}" for index in range(len(planners))]
    with rc_context({"svg.hashsalt": "guardsim", "svg.fonttype": "none"}):
        figure = Figure(figsize=(max(6.0, 1.6 * len(levels) * max(1, len(planners) / 2)), 4.5), layout="constrained")
        axes = figure.add_subplot()
        for box in boxes:
            if not box.steps:
                continue
            slot = planners.index(box.planner)
            position = levels.index(box.level) + (slot - (len(planners) - 1) / 2) * width
            drawn = axes.boxplot(
                [list(box.steps)],
                positions=[position],
                widths=width * 0.8,
                patch_artist=True,
                medianprops={"color": "black"},
                boxprops={"facecolor": colours[slot], "alpha": 0.6},
                flierprops={"markersize": 3},
            )
            median = drawn["medians"][0].get_ydata()[0]
            axes.annotate(
                f"{median:g}",
                (position, median),
                xytext=(0, 3),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize=8,
                fontweight="bold",
            )
        axes.set_xticks(range(len(levels)), levels)
        axes.set_xlim(-0.6, len(levels) - 0.4)
        axes.set_ylabel("steps to cover")
        axes.grid(axis="y", alpha=0.3)
        if title:
            axes.set_title(title)
        if len(planners) > 1:
            axes.legend(
                handles=[Patch(facecolor=colour, alpha=0.6, label=name) for colour, name in zip(colours, planners)]
            )
        for target in targets:
            with atomic_path(target) as temporary:
                figure.savefig(temporary, dpi=120, metadata={"Date": None} if str(target).endswith(".svg") else None)
