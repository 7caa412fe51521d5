"""``guardsim regress``: re-play levels and compare them with stored references, for a studio's CI."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from guardsim.cli.common import limit_options, load, one_line, reports_errors, with_options
from guardsim.cli.map_options import MapImport, map_options
from guardsim.cli.motion import motion_override_options
from guardsim.errors import GuardsimError, LevelError, OutputError
from guardsim.files.reading import display_path
from guardsim.regress import regress_level
from guardsim.regress.references import DEFAULT_MAX_FRAME_SIZE, MotionOverride

__all__ = ["level_files", "regress"]

#: Exit status when a level differs from its references or has none.
DIFFERS = 1
#: Exit status for bad input: a level or reference that cannot be read.
BAD_INPUT = 2


def level_files(paths: tuple[str, ...]) -> list[Path]:
    """The level files named: files as given, folders as their ``*.json`` files in name order.

    Raises
    ------
    LevelError
        If a path does not exist, a folder holds no ``.json`` file, or two levels share a file stem
        (their references would share a folder).
    """
    files: list[Path] = []
    for given in paths:
        path = Path(given)
        if path.is_dir():
            found = sorted(path.glob("*.json"))
            if not found:
                raise LevelError(f"{display_path(path)}: folder holds no .json level files")
            files += found
        elif path.exists():
            files.append(path)
        else:
            raise LevelError(f"{display_path(path)}: no such file or folder")
    by_stem: dict[str, Path] = {}
    for path in files:
        other = by_stem.setdefault(path.stem, path)
        if other != path:
            raise LevelError(
                f"{display_path(path)}: same file name as {display_path(other)}; their references would share a folder"
            )
    return files


@click.command()
@click.argument("level_paths", metavar="LEVELS...", nargs=-1, required=True, type=click.Path())
@click.option(
    "--renders",
    type=click.Path(file_okay=False),
    default="renders",
    show_default=True,
    help="Folder of references, one sub-folder per level.",
)
@click.option("--update", is_flag=True, help="Rewrite the references from the current code and levels.")
@click.option(
    "--diff-dir",
    type=click.Path(file_okay=False),
    help="Write diff images here as LEVEL.diff.png [default: diff.png in each level's reference folder].",
)
@motion_override_options
@map_options
@click.option(
    "--max-frame-size",
    type=click.IntRange(min=16),
    default=DEFAULT_MAX_FRAME_SIZE,
    show_default=True,
    help="Largest frame_size (pixels a side) a reference manifest may ask for.",
)
@limit_options
@reports_errors
def regress(
    level_paths: tuple[str, ...],
    renders: str,
    update: bool,
    diff_dir: str | None,
    max_frame_size: int,
    motion: str | None,
    move_speed: float | None,
    turn_speed: float | None,
    tick_hz: float | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
    map_import: MapImport,
) -> None:
    """Re-play each level (files, or folders of *.json) and compare it with its references.

    Compares the trace exactly and the key frames within a tolerance; prints one line per level.
    Exit status: 0 all match, 1 some level differs or has no references (a diff image is written),
    2 bad input. Each episode is re-played in the motion its manifest names (grid when it names none);
    --motion and the speeds re-play every episode another way (with --update: rewrite them so).
    """
    if motion == "grid" and (move_speed, turn_speed, tick_hz) != (None, None, None):
        raise click.BadParameter("the speeds are continuous-motion parameters", param_hint="--motion grid")
    override = None
    if (motion, move_speed, turn_speed, tick_hz) != (None, None, None, None):
        override = MotionOverride(motion, move_speed, turn_speed, tick_hz)
    files = level_files(level_paths)
    renders_folder = Path(renders)
    if not renders_folder.is_dir():
        if not update:
            raise OutputError(f"{renders_folder}: no such folder of references (create it with --update)")
        _make_folder(renders_folder)
    diff_folder = None
    if diff_dir is not None:
        diff_folder = Path(diff_dir)
        _make_folder(diff_folder)
    differing = invalid = 0
    for path in files:
        try:
            level = load(str(path), max_cells, max_vertices, max_file_bytes, map_import)
            result = regress_level(
                level,
                renders_folder,
                update=update,
                diff_dir=diff_folder,
                max_frame_size=max_frame_size,
                max_cells=max_cells,
                max_file_bytes=max_file_bytes,
                override=override,
            )
        except GuardsimError as error:
            # One bad level must not hide the results of the others: report it and go on.
            click.echo(f"guardsim: error: {one_line(with_options(str(error)))}", err=True)
            invalid += 1
            continue
        click.echo(result.line())
        differing += result.status in ("differs", "missing")
    if invalid or differing:
        if len(files) > 1:
            parts = [f"{count} {what}" for count, what in ((differing, "differ"), (invalid, "invalid")) if count]
            click.echo(f"guardsim regress: {' and '.join(parts)} of {len(files)} levels", err=True)
        sys.exit(BAD_INPUT if invalid else DIFFERS)


def _make_folder(folder: Path) -> None:
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"{folder}: cannot create folder: {error.strerror or error}") from None
