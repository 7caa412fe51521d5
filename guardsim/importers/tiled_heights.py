"""Which tiles of a Tiled map a walker meets: the top-most tile at its height decides each cell.

RPG engines that mark collision per tile (a boolean tile property such as ``collision``) let the
top-most tile under the walker decide: a bridge tile marked not colliding, drawn over water tiles marked
colliding, carries the walker across. Heights come from a ``z`` property, on the layer and on the tile,
added: tiles above the walker's height (roofs, tree tops: ``z`` above 0) never block, whatever they say.

So, cell by cell, from the top-most tile layer down, among the tiles at the walker's height: the first
tile whose own properties say whether it collides (true or false) decides the cell, and the tiles under
it are not walls there. Tiles that say nothing (decorations, flowers) do not decide. A map with no tile
that says it does not collide, and no ``z`` property, is read as before: every wall tile is a wall.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from guardsim.importers.imported import counted
from guardsim.importers.tiled_data import Properties, TiledMap, TileLayer
from guardsim.importers.tiled_roles import Guesses

__all__ = ["WALKER_Z", "walker_layers"]

#: The walker's height: tiles whose layer ``z`` plus tile ``z`` is above it are drawn over the walker.
WALKER_Z = 0.0


def _height(properties: Properties) -> float:
    value = properties.get("z")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        try:
            value = float(str(value)) if isinstance(value, str) else 0.0
        except ValueError:
            value = 0.0
    value = float(value)
    return value if value == value and abs(value) < 1e9 else 0.0


def walker_layers(tiled: TiledMap, roles: Guesses) -> tuple[list[TileLayer], str]:
    """The tile layers with the tiles a walker never meets taken out (those above its height, and those
    under a higher tile that decides the cell), in the same order; and a phrase saying what was taken out
    ("" when nothing was)."""
    layers = list(tiled.tile_layers)
    tile_heights = {gid: _height(info.properties) for gid, info in tiled.tiles.items() if "z" in info.properties}
    layer_heights = [_height(layer.properties) for layer in layers]
    if not roles.unmarked_gids and not tile_heights and not any(layer_heights):
        return layers, ""
    deciding = np.fromiter(roles.marked_gids | roles.unmarked_gids, dtype=np.int64)
    raised = np.fromiter(tile_heights, dtype=np.int64)
    raise_by = np.fromiter(tile_heights.values(), dtype=float)
    decided = np.zeros(0, dtype=np.int64)
    keeps: list[np.ndarray] = [np.ones(layer.gids.size, dtype=bool) for layer in layers]
    above = covered = 0
    for index in range(len(layers) - 1, -1, -1):
        layer = layers[index]
        heights = np.full(layer.gids.size, layer_heights[index])
        if raised.size:
            found = np.searchsorted(raised, layer.gids) if np.all(raised[:-1] <= raised[1:]) else None
            if found is None:
                order = np.argsort(raised)
                raised, raise_by = raised[order], raise_by[order]
                found = np.searchsorted(raised, layer.gids)
            found = np.minimum(found, raised.size - 1)
            hit = raised[found] == layer.gids
            heights[hit] += raise_by[found[hit]]
        high = heights > WALKER_Z
        # Cells as one number each (columns and rows of chunked maps may be negative).
        keys = (layer.rows.astype(np.int64) << 32) + layer.cols.astype(np.int64)
        keep = ~high & ~np.isin(keys, decided)
        decided = np.union1d(decided, keys[~high & np.isin(layer.gids, deciding)])
        above += int(high.sum())
        covered += int((~high & ~keep).sum())
        keeps[index] = keep
    out = [layer if keep.all() else _kept(layer, keep) for layer, keep in zip(layers, keeps, strict=True)]
    parts = []
    if above:
        parts.append(f"{counted(above, 'tile')} above the walker's height (z) never block")
    if covered:
        parts.append(f"{counted(covered, 'tile')} under a higher tile that says whether it collides (a bridge) do not")
    return out, "; ".join(parts)


def _kept(layer: TileLayer, keep: np.ndarray) -> TileLayer:
    return dataclasses.replace(
        layer,
        cols=layer.cols[keep],
        rows=layer.rows[keep],
        gids=layer.gids[keep],
        flips=None if layer.flips is None else layer.flips[keep],
    )
