"""``guardsim render``: a level preview for designers, optionally with what a guard sees from one spot."""

from __future__ import annotations

import click
import numpy as np

from guardsim.cli.common import limit_options, load, parse_point, reports_errors
from guardsim.cli.map_options import MapImport, map_options
from guardsim.errors import LevelError
from guardsim.files.output import atomic_path
from guardsim.level import HEADINGS
from guardsim.render import draw_cone_overlay, render_preview
from guardsim.render.preview import tight_cells, with_legend
from guardsim.scene import Scene
from guardsim.starts import choose_start

__all__ = ["render"]


def parse_cone(
    _ctx: click.Context, param: click.Parameter, value: str | None
) -> tuple[tuple[float, float], str] | None:
    """Click callback: ``X,Y,HEADING`` into a point and a heading name."""
    if value is None:
        return None
    parts = value.split(",")
    if len(parts) != 3 or parts[2].strip() not in HEADINGS:
        raise click.BadParameter(
            f"expected X,Y,HEADING with HEADING one of {', '.join(HEADINGS)}, got {value!r}", param=param
        )
    point = parse_point(_ctx, param, ",".join(parts[:2]))
    assert point is not None  # parse_point returns a point for any string it accepts
    return point, parts[2].strip()


@click.command()
@click.argument("level_path", metavar="LEVEL")
@click.option("--png", "png_path", required=True, type=str, help="Where to write the preview.")
@click.option("--start", callback=parse_point, metavar="X,Y", help="Start position (default: the level's).")
@click.option(
    "--cone",
    callback=parse_cone,
    metavar="X,Y,HEADING",
    help="Overlay what a guard standing at X,Y facing HEADING (right, down, left, up) sees.",
)
@click.option(
    "--size",
    type=click.IntRange(min=64, max=8192),
    metavar="PX",
    help="Longest side of the map in pixels [default: 640, or 6 pixels a cell if more, up to 1600].",
)
@map_options
@limit_options
@reports_errors
def render(
    level_path: str,
    png_path: str,
    start: tuple[float, float] | None,
    cone: tuple[tuple[float, float], str] | None,
    size: int | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
    map_import: MapImport,
) -> None:
    """Draw a preview of LEVEL: walls, grid, reachable and unreachable cells, coordinate rulers, a legend.

    Reachable means reachable from the start; with no start, from the largest connected area.
    """
    import imageio.v3 as iio

    level = load(level_path, max_cells, max_vertices, max_file_bytes, map_import)
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
                f"{level_path}: --cone ({eye_x:g}, {eye_y:g}) is not in a cell where the guard "
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
    with atomic_path(png_path) as temporary:
        iio.imwrite(temporary, image, extension=".png")
    traversable = int(scene.grid.traversable.sum())
    rows, cols = scene.grid.shape
    click.echo(
        f"{level.name}: {rows} x {cols} cells, {traversable} traversable, {int(reachable.sum())} reachable, "
        f"{traversable - int(reachable.sum())} unreachable{cone_note} -> {png_path}"
    )
