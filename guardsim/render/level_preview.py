"""``guardsim render``'s picture of a level: the preview (:mod:`guardsim.render.preview`) with what a guard
at a point sees, and the level's cameras and light (:mod:`guardsim.render.watchers`) over it."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from guardsim.level import Level
from guardsim.render.preview import draw_cone_overlay, render_preview, tight_cells, with_legend

__all__ = ["write_level_preview"]


def write_level_preview(
    path: str | Path,
    level: Level,
    *,
    start: tuple[float, float] | None = None,
    cone: tuple[tuple[float, float], str] | None = None,
    size: int | None = None,
    level_name: str = "level",
) -> str:
    """Write ``guardsim render``'s preview of ``level`` as a PNG at ``path``: walls, grid, the cells
    reachable from ``start`` (default the guard's; without one, the largest area) and the rest, rulers
    and a legend; ``cone`` (an eye in world units and a heading name) draws what a guard there sees;
    cameras and light when the level has them. Returns the counts in a line: ``"12 x 20 cells, ..."``.
    An eye where the guard cannot stand is a :class:`~guardsim.errors.LevelError` naming ``level_name``."""
    import imageio.v3 as iio

    from guardsim.errors import LevelError
    from guardsim.files.output import atomic_path
    from guardsim.level import HEADINGS
    from guardsim.scene import Scene
    from guardsim.starts import choose_start

    scene = Scene.from_level(level)
    point = start or level.guard.start
    cell = None
    if point is not None:
        cell, _ = choose_start(scene, rng=np.random.default_rng(0), point=point, heading="right")
        reachable = scene.grid.component(*cell)
    else:
        reachable = scene.grid.largest_component()
    image = render_preview(level, scene.grid.traversable, reachable, scene.grid.origin, start=cell, size=size)
    cone_note = ""
    if cone is not None:
        (eye_x, eye_y), heading_name = cone
        eye = scene.grid.cell_of((eye_x, eye_y))
        if eye is None or not scene.grid.traversable[eye[1], eye[0]]:
            raise LevelError(
                f"{level_name}: --cone ({eye_x:g}, {eye_y:g}) is not in a cell where the guard "
                f"(radius {level.guard.radius:g}) can stand"
            )
        heading = HEADINGS[heading_name] // 90
        seen = np.zeros(scene.grid.size, dtype=bool)
        seen[scene.vision()(eye[0], eye[1], heading)] = True
        image = draw_cone_overlay(
            image, level, scene.grid.shape, seen.reshape(scene.grid.shape), eye, heading, size=size
        )
        cone_note = f", a guard at ({eye_x:g}, {eye_y:g}) facing {heading_name} sees {int(seen.sum())} cells"
    light = None
    if level.cameras or not level.lit:
        from guardsim.detection.light import light_map
        from guardsim.render.watchers import draw_watch_overlay

        light = None if level.lit else light_map(scene)
        # Only floor is shaded: a wall is no darker for the dark.
        floor_light = None if light is None else np.where(scene.grid.traversable, light, 1.0)
        image = draw_watch_overlay(image, level, scene.grid.shape, floor_light, size=size)
        floor = light[scene.grid.traversable] if light is not None else None
        lit = "" if floor is None or not floor.size else f", light {floor.min():.2f} to {floor.max():.2f}"
        cone_note += f", {len(level.cameras)} camera(s), {len(level.lights)} light(s){lit}"
    image = with_legend(
        image,
        unreachable=bool((scene.grid.traversable & ~reachable).any()),
        tight=bool(tight_cells(level, scene.grid.traversable, scene.grid.origin).any()),
        start=cell is not None or cone is not None,
        cone=cone is not None,
        cameras=bool(level.cameras),
    )
    if light is not None:
        from guardsim.render.watchers import light_bar

        image = np.concatenate([image, light_bar(image.shape[1])])
    with atomic_path(path) as temporary:
        iio.imwrite(temporary, image, extension=".png")
    traversable = int(scene.grid.traversable.sum())
    rows, cols = scene.grid.shape
    return (
        f"{rows} x {cols} cells, {traversable} traversable, {int(reachable.sum())} reachable, "
        f"{traversable - int(reachable.sum())} unreachable{cone_note}"
    )
