"""The awareness meter over two crossings of a guard's view, drawn to docs/images/detection/meter.png.

A guard with the default detection keys (0.25 s near, 1.5 s at the edge of its 8-unit range, 4 s to
forget) stands still; a player crosses its view 6 units away at the grid tick (0.5 s: one cell at the
guard's walking speed of 2 units/s). A two-tick dash leaves the meter at 0.84; a third tick in view
detects. Run from the repository root; needs matplotlib (``pip install guardsim[test]``).

    python examples/detection_meter.py
"""

from __future__ import annotations

from pathlib import Path

from guardsim.detection import AwarenessMeter, DetectionModel

OUT = Path(__file__).resolve().parent.parent / "docs" / "images" / "detection" / "meter.png"


def crossing(ticks_in_view: int, *, before: int = 2, after: int = 10, distance: float = 6.0) -> list[float]:
    """The meter at each tick of a crossing: ``before`` ticks out of view, then in view, then out."""
    meter = AwarenessMeter(DetectionModel(), view_range=8.0)
    sight = [False] * before + [True] * ticks_in_view + [False] * after
    return [0.0] + [meter.update(0.5, seen, distance) for seen in sight]


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 3.2), dpi=100)
    for ticks, colour in ((2, "tab:blue"), (3, "tab:red")):
        levels = crossing(ticks)
        label = f"{ticks} ticks in view at 6 units: peak {max(levels):.2f}" + (
            " (detected)" if max(levels) >= 1 else ""
        )
        axes.step([0.5 * tick for tick in range(len(levels))], levels, where="pre", color=colour, label=label)
    axes.axhline(0.5, color="orange", linestyle="--", linewidth=1, label="suspicious (0.5)")
    axes.axhline(1.0, color="black", linewidth=1)
    axes.axvspan(1.0, 2.0, color="gold", alpha=0.3, label="in view (both)")
    axes.axvspan(2.0, 2.5, color="salmon", alpha=0.2, label="in view (red only)")
    axes.set_xlabel("seconds")
    axes.set_ylabel("awareness")
    axes.set_ylim(0, 1.05)
    axes.legend(loc="upper right", fontsize=8)
    axes.set_title("A guard's meter as a player crosses its view")
    figure.tight_layout()
    OUT.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(OUT)
    print(OUT)


if __name__ == "__main__":
    main()
