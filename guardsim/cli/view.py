"""``guardsim view``: a saved trace as the interactive HTML page that ``play --html`` (or ``alert --html``)
writes."""

from __future__ import annotations

from pathlib import Path

import click

from guardsim.cli.common import limit_options, load, reports_errors

__all__ = ["view"]


@click.command()
@click.argument("trace_path", metavar="TRACE")
@click.option("--html", "html_path", required=True, type=str, help="Where to write the page.")
@click.option(
    "--level",
    "level_path",
    type=str,
    help="The level the trace was played on, for its real walls (without it, walls come from the grid; "
    "an alert trace needs it).",
)
@click.option(
    "--patrol",
    "patrol_path",
    type=str,
    help="An alert trace's patrol.json, to draw the guards' routes; a sneak.json's patrol [default: the one it records].",
)
@limit_options
@reports_errors
def view(
    trace_path: str,
    html_path: str,
    level_path: str | None,
    patrol_path: str | None,
    max_cells: int,
    max_vertices: int,
    max_file_bytes: int,
) -> None:
    """Write TRACE (from `guardsim play --trace`; with --level, `guardsim alert --trace` or a sneak.json of
    `guardsim sneak --out`) as one self-contained HTML page to open in a browser.

    The page works offline: open it from disk; add #tick=N to its address to open it at tick N.
    """
    from guardsim.errors import LevelError
    from guardsim.files.reading import read_json_file
    from guardsim.regress.stored_trace import trace_from_stored
    from guardsim.viewer import write_viewer

    data = read_json_file(trace_path, max_file_bytes=max_file_bytes, kind="trace file", error=LevelError)
    if isinstance(data, dict) and "longest_unseen" in data and "rule" in data:
        from guardsim.errors import TraceError
        from guardsim.pictures import write_sneak_json_page

        if level_path is None:
            raise TraceError(f"{trace_path}: a sneak check's sneak.json: give --level LEVEL, the level it checked")
        sneak_level = load(level_path, max_cells, max_vertices, max_file_bytes)
        result = write_sneak_json_page(Path(html_path), sneak_level, data, patrol_path=patrol_path, source=trace_path)
        path = result.path
        assert path is not None
        click.echo(f"{sneak_level.name}: sneak from lap tick {path.start_tick}, {path.ticks} ticks -> {html_path}")
        return
    if isinstance(data, dict) and "guard_states" in data and "planner" not in data:
        from guardsim.errors import TraceError
        from guardsim.viewer.alerts import write_alert_trace_page

        if level_path is None:
            raise TraceError(f"{trace_path}: an alert episode's trace: give --level LEVEL, the level it was played on")
        alert_level = load(level_path, max_cells, max_vertices, max_file_bytes)
        episode = write_alert_trace_page(html_path, alert_level, data, patrol_path=patrol_path, source=trace_path)
        ticks, guards = len(episode.record["cells"]) - 1, len(episode.modes)
        click.echo(
            f"{alert_level.name}: alert episode, {episode.search.name} search, {ticks} ticks, {guards} guard(s) -> {html_path}"
        )
        return
    trace = trace_from_stored(data, source=trace_path, max_cells=max_cells)
    level = None
    note = "walls rebuilt from the trace's grid (give --level for the real walls)"
    if level_path is not None:
        level = load(level_path, max_cells, max_vertices, max_file_bytes)
        note = f"walls from {level_path}"
        if (level.grid_shape(), level.name) != (trace.shape, trace.level):
            raise LevelError(
                f"{level_path}: level {level.name!r} with a {level.grid_shape()[0]} x {level.grid_shape()[1]} grid "
                f"is not the one {trace_path} was played on ({trace.level!r}, {trace.shape[0]} x {trace.shape[1]})"
            )
    write_viewer(html_path, level, trace)
    click.echo(f"{trace.level}: {trace.steps} ticks, {trace.guards} guard(s), {note} -> {html_path}")
