"""Import every shared map, validate it, and optionally play it: one table row per map.

Usage: ``python benchmarks/import_maps.py [--maps DIR] [--play] [--max-steps N] [--seed S] [--only NAME ...]``,
``python benchmarks/import_maps.py --corpus [--maps DIR]`` or ``python benchmarks/import_maps.py --robustness``.

``--corpus`` prints one row per Tiled map under ``DIR/tiled`` (the sneaktime levels and ``real/``): the
walls the import found, the floor cells the guard can reach, the spawns, the warnings, and the outcome
of ``guardsim play MAP --gif`` run as a real process (exit status, steps, coverage, seconds).

``--robustness`` writes the importer inputs of the issue-16 fuzzing campaign to a scratch folder, runs
``guardsim import`` on each as a real process and prints exit status, stderr lines, seconds and peak
memory: every one must end with status 2 and one line, well inside 20 s and 2 GB.

For each Moving AI map (``DIR/movingai/*.map``) and Tiled map (``DIR/tiled/*.json`` and ``*.tmx``; the
sneaktime guard tiles 50 and 51 are the spawns) the script imports the map at cell size 1, loads the
written level back, builds its grid and prints: grid (cols x rows), cells, traversable, reachable (from
the level's start, or the largest connected area), holes, vertices and the import time (import, write
and reload; not the grid). With ``--play`` it also runs one RippleFront episode (start and heading drawn
from ``--seed`` as ``guardsim play --episode 0`` does, or the level's start when it has one) and adds
the steps, whether every reachable cell was seen, and the grid-plus-episode time.
"""

from __future__ import annotations

import argparse
import base64
import io
import os
import subprocess
import sys
import tempfile
import time
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np

from guardsim import ImportedLevel, load_level
from guardsim.motion import run_episode
from guardsim.planners import RippleFront
from guardsim.simulation import Scene, choose_start, episode_generator

MAPS = Path(__file__).resolve().parents[2] / "shared" / "maps"
SNEAKTIME_GUARD_TILES = (50, 51)


def sources(folder: Path, only: list[str]) -> list[Path]:
    found = sorted((folder / "movingai").glob("*.map")) + sorted((folder / "tiled").glob("sneaktime_*.*"))
    found = [path for path in found if path.suffix in (".map", ".json", ".tmx")]
    return [path for path in found if not only or path.stem in only or path.name in only]


def tiled_corpus(folder: Path) -> list[Path]:
    """Every Tiled map under ``folder/tiled``, the sneaktime levels first."""
    tiled = folder / "tiled"
    found = [path for pattern in ("*.tmx", "*.json", "*.tmj") for path in tiled.rglob(pattern)]
    return sorted(found, key=lambda path: (path.parent != tiled, str(path)))


def run_cli(args: list[str]) -> tuple[int, list[str], str, float, float]:
    """``guardsim ARGS`` in a real process: exit status, stderr lines, stdout, seconds, peak memory (MB)."""
    began = time.perf_counter()
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        process = subprocess.Popen([sys.executable, "-m", "guardsim.cli", *args], stdout=out, stderr=err, text=True)
        # wait4 gives this child's own peak memory, not the largest of all children so far.
        _, status, usage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(status)
        seconds = time.perf_counter() - began
        out.seek(0)
        err.seek(0)
        return process.returncode, err.read().splitlines(), out.read().strip(), seconds, usage.ru_maxrss / 1024


def corpus_table(folder: Path) -> None:
    """The Tiled corpus: what each map imports into, and what `guardsim play MAP` does with it."""
    print(f"{'map':<58} {'walls found':<62} {'reachable':>9} {'spawns':>6} {'warn':>4}  play")
    with tempfile.TemporaryDirectory() as scratch:
        for path in tiled_corpus(folder):
            name = str(path.relative_to(folder / "tiled"))
            records: list[ImportedLevel] = []
            level = load_level(path, report=records.append)
            imported = records[0]
            walls = next((change for change in imported.changes if change.startswith("walls from")), "")
            scene = Scene.from_level(level)
            if level.guard.start is not None:
                cell = scene.grid.cell_of(level.guard.start)
                reachable = int(scene.grid.component(*cell).sum()) if cell else 0
            else:
                reachable = int(scene.grid.largest_component().sum())
            status, _, stdout, seconds, _ = run_cli(["play", str(path), "--gif", str(Path(scratch) / "out.gif")])
            outcome = stdout.split(": ", 1)[-1].split(" -> ")[0] if status == 0 else f"exit {status}"
            print(
                f"{name:<58} {walls[11:73]:<62} {reachable:>9} {len(level.starts):>6} {len(imported.warnings):>4}  "
                f"exit {status}, {outcome} ({seconds:.1f} s)",
                flush=True,
            )


def _tmx(layers: str, width: int, height: int) -> str:
    return (
        f'<map version="1.10" orientation="orthogonal" width="{width}" height="{height}" tilewidth="16" '
        f'tileheight="16" infinite="0">{layers}</map>'
    )


def _zlib_layer(gids: np.ndarray, width: int, height: int) -> str:
    data = base64.b64encode(zlib.compress(np.asarray(gids, dtype="<u4").tobytes(), 9)).decode("ascii")
    return f'<layer name="Ground" width="{width}" height="{height}"><data encoding="base64" compression="zlib">{data}</data></layer>'


def _noise_png() -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    noise = np.random.default_rng(0).integers(0, 2, size=(1000, 1000), dtype=np.uint8) * 255
    Image.fromarray(noise).save(buffer, format="PNG")
    return buffer.getvalue()


FLOOR = '<layer name="Ground" width="4" height="4"><data encoding="csv">' + ",".join(["1"] * 16) + "</data></layer>"
#: The importer inputs of the fuzzing campaign (issue 16): file name -> contents.
ROBUSTNESS: dict[str, Callable[[], str | bytes]] = {
    "height-superscript.map": lambda: "type octile\nheight ³\nwidth 2\nmap\n..\n",
    "width-9999999999999.map": lambda: "type octile\nheight 2\nwidth 9999999999999\nmap\n..\n..\n",
    "width-1000000000000.map": lambda: "type octile\nheight 1\nwidth 1000000000000\nmap\n.\n",
    "integer-5001-digits.json": lambda: '{"orientation": "orthogonal", "tilewidth": ' + "7" * 5001 + ', "layers": []}',
    "object-1e308.tmx": lambda: _tmx(
        FLOOR + '<objectgroup name="Walls"><object id="1" x="0" y="0" width="1e308" height="1e308"/></objectgroup>',
        4,
        4,
    ),
    "object-1e308.json": lambda: (
        '{"orientation": "orthogonal", "tilewidth": 16, "tileheight": 16, "layers": [{"type": "tilelayer", '
        '"name": "G", "width": 1, "height": 1, "data": [1]}, {"type": "objectgroup", "name": "Walls", "objects": '
        '[{"id": 1, "x": 1e308, "y": 0, "width": 1e308, "height": 1}]}]}'
    ),
    "object-nan.tmx": lambda: _tmx(
        FLOOR + '<objectgroup name="Walls"><object id="1" x="nan" y="0" width="4" height="4"/></objectgroup>', 4, 4
    ),
    "base64-as-list.json": lambda: (
        '{"orientation": "orthogonal", "tilewidth": 16, "tileheight": 16, "layers": [{"type": "tilelayer", '
        '"name": "G", "width": 2, "height": 1, "encoding": "base64", "data": [1, 1]}]}'
    ),
    "nested-3000-groups.tmx": lambda: _tmx("<group name='g'>" * 3000 + FLOOR + "</group>" * 3000, 4, 4),
    "encoding-hex.tmx": lambda: _tmx(
        '<layer name="G" width="4" height="3"><data encoding="hex">111111111111</data></layer>', 4, 3
    ),
    "walls-cover-floor.tmx": lambda: _tmx(
        FLOOR + '<objectgroup name="Walls"><object id="1" x="0" y="0" width="64" height="64"/></objectgroup>', 4, 4
    ),
    "noise-1000x1000.png": _noise_png,
    "checkerboard-1000x1000.tmx": lambda: _tmx(
        _zlib_layer((np.indices((1000, 1000)).sum(axis=0) % 2).ravel(), 1000, 1000), 1000, 1000
    ),
    "tiles-2048x2048.tmx": lambda: _tmx(_zlib_layer(np.ones(2048 * 2048), 2048, 2048), 2048, 2048),
}


def robustness_table() -> None:
    """Each fuzzing-campaign input through `guardsim import` in a real process."""
    print(f"{'input':<28} {'bytes':>8} {'exit':>4} {'lines':>5} {'seconds':>7} {'peak MB':>7}  stderr")
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        cases = {name: make() for name, make in ROBUSTNESS.items()}
        special = {"dev-zero.tmx": "/dev/zero", "dev-zero.map": "/dev/zero", "fifo.tmx": None}
        for name, content in cases.items():
            path = folder / name
            path.write_bytes(content.encode("utf-8") if isinstance(content, str) else content)
        for name, target in special.items():
            if target is None:
                os.mkfifo(folder / name)
            else:
                (folder / name).symlink_to(target)
        for name in [*cases, *special]:
            path = folder / name
            size = path.stat().st_size if name in cases else 0
            status, lines, _, seconds, peak = run_cli(["import", str(path), "--out", str(folder / "out.json")])
            shown = lines[-1].replace(str(folder) + "/", "")[:110] if lines else ""
            print(f"{name:<28} {size:>8} {status:>4} {len(lines):>5} {seconds:>7.2f} {peak:>7.0f}  {shown}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", type=Path, default=MAPS, help="The shared maps folder.")
    parser.add_argument("--corpus", action="store_true", help="The Tiled corpus table (with guardsim play).")
    parser.add_argument("--robustness", action="store_true", help="The fuzzing-campaign inputs through import.")
    parser.add_argument("--play", action="store_true", help="Also play one episode per map.")
    parser.add_argument("--max-steps", type=int, default=None, help="Step limit of each episode.")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--only", nargs="*", default=[], help="Map names (stem or file name) to run.")
    args = parser.parse_args()
    if args.corpus:
        corpus_table(args.maps)
        return
    if args.robustness:
        robustness_table()
        return
    header = (
        f"{'map':<26} {'grid':>9} {'cells':>7} {'traversable':>11} {'reachable':>9} {'holes':>5} "
        f"{'vertices':>8} {'import s':>8}"
    )
    print(header + (f" {'steps':>7} {'covered':>7} {'play s':>7}" if args.play else ""))
    with tempfile.TemporaryDirectory() as scratch:
        for path in sources(args.maps, args.only):
            began = time.perf_counter()
            found: list[ImportedLevel] = []
            load_level(path, spawn_tiles=SNEAKTIME_GUARD_TILES, report=found.append)
            imported = found[0]
            written = Path(scratch) / f"{path.stem}.json"
            written.write_text(imported.to_json(), encoding="utf-8")
            level = load_level(written)
            import_seconds = time.perf_counter() - began
            began = time.perf_counter()
            scene = Scene.from_level(level)
            grid = scene.grid
            if level.guard.start is not None:
                cell, heading = choose_start(scene, rng=np.random.default_rng(args.seed), point=level.guard.start)
                reachable = int(grid.component(*cell).sum())
            else:
                cell, heading = choose_start(scene, rng=episode_generator(args.seed, 0))
                reachable = int(grid.largest_component().sum())
            rows, cols = grid.shape
            row = (
                f"{path.name:<26} {f'{cols}x{rows}':>9} {grid.size:>7} {int(grid.traversable.sum()):>11} "
                f"{reachable:>9} {len(level.holes):>5} {imported.vertices:>8} {import_seconds:>8.2f}"
            )
            if args.play:
                trace = run_episode(
                    scene, RippleFront(), starts=[cell], headings=[heading], max_steps=args.max_steps, seed=args.seed
                )
                play_seconds = time.perf_counter() - began
                row += f" {trace.steps:>7} {'yes' if trace.covered else trace.outcome:>7} {play_seconds:>7.1f}"
            print(row, flush=True)


if __name__ == "__main__":
    main()
