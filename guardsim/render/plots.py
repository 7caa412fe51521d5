"""The paper's figure: a box plot of steps per level, one box per planner, the median written on each.

matplotlib is optional (``pip install 'guardsim[plot]'``) and imported only when a figure is drawn.
"""

from __future__ import annotations

import os
import statistics
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

from guardsim.errors import GuardsimError
from guardsim.files.output import atomic_path

if TYPE_CHECKING:
    from matplotlib.figure import Figure

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


def plot_steps(
    boxes: Sequence[StepsBox],
    targets: Sequence[str | os.PathLike[str]],
    *,
    title: str = "",
    ylabel: str = "steps to cover",
) -> Figure:
    """Draw the box plot and write it to each target (the format follows the suffix: ``.png``, ``.svg``).

    Levels appear left to right in the order of their first box; when there are several planners, each
    level gets one box per planner side by side, coloured by planner, with a legend below. When the
    medians differ more than tenfold the steps axis is logarithmic. Boxes span the
    quartiles, whiskers reach 1.5 times the interquartile range, and points beyond are drawn as outliers.
    ``ylabel`` names the steps axis (a team's steps are its makespan). The boxes' ``level`` is only their
    label: any grouping works, e.g. team sizes of one level. Output is deterministic: no timestamp in the
    SVG, a fixed SVG id salt. Returns the figure (a
    :class:`matplotlib.figure.Figure`, not attached to pyplot) for inspection.
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
        inches = min(16.0, max(6.4, 1.0 + len(levels) * (0.6 + 0.35 * len(planners))))
        figure = Figure(figsize=(inches, 4.8), layout="constrained")
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
                bbox={"boxstyle": "round,pad=0.1", "facecolor": "white", "alpha": 0.7, "linewidth": 0},
            )
        axes.set_xticks(range(len(levels)), levels)
        axes.set_xlim(-0.6, len(levels) - 0.4)
        medians = [statistics.median(box.steps) for box in boxes if box.steps]
        # Planners can differ by orders of magnitude (a random walk against a planner); a linear axis
        # would flatten all but the slowest box.
        logarithmic = bool(medians) and min(medians) > 0 and max(medians) / min(medians) > 10
        if logarithmic:
            axes.set_yscale("log")
        axes.set_ylabel(ylabel + (" (log scale)" if logarithmic else ""))
        axes.grid(axis="y", alpha=0.3)
        if title:
            axes.set_title(title)
        if len(planners) > 1:
            figure.legend(
                handles=[Patch(facecolor=colour, alpha=0.6, label=name) for colour, name in zip(colours, planners)],
                loc="outside lower center",
                # About two inches per entry, so that long planner names stay inside a narrow figure.
                ncols=min(len(planners), max(1, int(inches // 2))),
                frameon=False,
            )
        for target in targets:
            with atomic_path(target) as temporary:
                figure.savefig(temporary, dpi=120, metadata={"Date": None} if str(target).endswith(".svg") else None)
    return figure
