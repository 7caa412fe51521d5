"""The words and property values that mark a part of a Tiled map as wall, floor, spawn or player.

Names are split into whole words (``Walls 1``, ``base_wall``, ``CollisionShape`` -> collision shape);
a property marks a wall when its name says so and its value is true (a bool, a non-zero number, or
``true``/``yes``/``1``), and opts out when false; ``--wall-property NAME[=VALUE]`` replaces the guess.
:mod:`guardsim.importers.tiled_roles` applies them to a whole map.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from collections.abc import Set as AbstractSet
from typing import Any

from guardsim.errors import ArgumentError
from guardsim.files.reading import quoted
from guardsim.importers.tiled_data import Properties

__all__ = [
    "ABOVE_WORDS",
    "BODY_WORDS",
    "FALSE_TEXTS",
    "FLOOR_WORDS",
    "GRAVITY_WORDS",
    "MOVING_BODIES",
    "NEGATION_WORDS",
    "PLAYER_WORDS",
    "SIDE_VIEW_WORDS",
    "SPAWN_WORDS",
    "TRUE_TEXTS",
    "VOID_MIN_REST",
    "WALL_FLAGS",
    "WALL_WORDS",
    "body_mark",
    "flag",
    "parse_wall_property",
    "pulls",
    "says",
    "truth",
    "wall_mark",
    "words",
]

#: Whole words in a layer, class or property name that say "wall".
WALL_WORDS = frozenset(
    [
        "wall",
        "walls",
        "collision",
        "collisions",
        "collide",
        "collides",
        "collider",
        "colliders",
        "collidable",
        "solid",
        "solids",
        "obstacle",
        "obstacles",
        "blocked",
        "blocking",
        "blocker",
        "blockers",
        "impassable",
        "barrier",
        "barriers",
    ]
)
#: Whole words in a layer name that say floor.
FLOOR_WORDS = frozenset(["floor", "floors", "ground", "grounds"])
#: Whole words in a layer name that say it is drawn above the player (roofs, tree tops), so not floor.
ABOVE_WORDS = frozenset(["above", "over", "overhead", "overlay", "roof", "roofs", "fringe", "canopy"])
#: Whole words in a layer, class or name that say guard spawn.
SPAWN_WORDS = frozenset(
    ["spawn", "spawns", "spawner", "spawners", "guard", "guards", "start", "starts", "patrol", "patrols"]
)
#: Whole words in an object's name or class (or its tile's class) that say it is the player's start.
PLAYER_WORDS = frozenset(["player", "players", "hero", "heroes"])
#: Whole words that turn a collision property's name around (``no_collision``, ``NotSolid``).
NEGATION_WORDS = frozenset(["no", "not", "non", "never", "without"])
#: Property texts that read true or false (any case, spaces stripped); other texts say neither.
TRUE_TEXTS = frozenset(["true", "yes", "1", "on", "y"])
FALSE_TEXTS = frozenset(["false", "no", "0", "off", "n", ""])
#: A painted void leaves at least this share of its layer's cells as floor.
VOID_MIN_REST = 0.05
#: Boolean properties that mark walls.
WALL_FLAGS = ("collision", "collides", "collide", "collidable", "solid", "blocked", "obstacle", "wall")
#: Whole words in a layer's name or class that say the map is a side view (a platformer), not drawn from above.
SIDE_VIEW_WORDS = frozenset(["platform", "platforms", "platformer", "ladder", "ladders"])
#: Whole words in a map property's name that say the map has gravity (a side view) when its value is true or a
#: non-zero number: ``gravity``, ``GravityY``, ``jump_height``.
GRAVITY_WORDS = frozenset(["gravity", "jump", "jumps"])
#: Whole words in an object's or tile's class that say it is a physics body (``Fixture``, ``StaticBody2D``).
BODY_WORDS = frozenset(["body", "bodies", "fixture", "fixtures", "rigidbody", "physics"])
#: Body types (a ``bodyType`` property's value, or a word of the class) that move: never walls.
MOVING_BODIES = frozenset(["dynamic", "kinematic", "rigid", "rigidbody"])


def words(name: str) -> set[str]:
    """The lower-case words of a name: split at non-letters and camelCase humps.

    >>> sorted(words("base_wall")), sorted(words("WallsLayer2")), sorted(words("Wallpaper"))
    (['base', 'wall'], ['2', 'layer', 'walls'], ['wallpaper'])
    """
    spaced = re.sub(r"([a-z])([A-Z])|([A-Za-z])([0-9])", r"\1\3 \2\4", name)
    # An upper-case run before a capitalised word is a word of its own: "NPCWall" is "NPC Wall".
    spaced = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1 \2", spaced)
    return {part.lower() for part in re.split(r"[^A-Za-z0-9]+", spaced) if part}


def says(name: str, vocabulary: AbstractSet[str]) -> bool:
    return bool(words(name) & vocabulary)


def flag(properties: Properties, *keys: str) -> bool | None:
    """The first of ``keys`` present as a boolean-like property: ``True``/``False``, or ``None``."""
    for key in keys:
        if key in properties:
            value: Any = properties[key]
            if isinstance(value, str):
                return value.strip().lower() in ("true", "1", "yes")
            return bool(value)
    return None


def truth(value: Any) -> bool | None:
    """Whether a property's value reads true, false, or neither (``None``), whatever its type.

    >>> truth(True), truth(1), truth(0.0), truth(" Yes "), truth("false"), truth(""), truth("stone")
    (True, True, False, True, False, False, None)
    """
    if isinstance(value, bool):
        return value
    if isinstance(value, (int, float)):
        return None if value != value else value != 0
    if isinstance(value, str):
        text = value.strip().lower()
        return True if text in TRUE_TEXTS else False if text in FALSE_TEXTS else None
    return None


def parse_wall_property(text: str) -> tuple[str, str | None]:
    """``NAME`` or ``NAME=VALUE`` (the ``--wall-property`` option) as ``(name, value or None)``.

    Raises ``ValueError`` with a phrase saying what is wrong.

    >>> parse_wall_property("blocks"), parse_wall_property("terrain = rock")
    (('blocks', None), ('terrain', 'rock'))
    """
    name, equals, value = text.partition("=")
    name, value = name.strip(), value.strip()
    if not name:
        raise ArgumentError(f"{quoted(text)} has no property name: expected NAME or NAME=VALUE")
    if equals and not value:
        raise ArgumentError(f"{quoted(text)} has no value after '=': expected NAME or NAME=VALUE")
    return name, value if equals else None


def _equals(value: Any, wanted: str) -> bool:
    """Whether a property's value is ``wanted`` as typed on the command line (numbers and booleans by value,
    text without regard to case)."""
    if isinstance(value, bool) or isinstance(wanted, bool):
        return truth(wanted) is value
    if isinstance(value, (int, float)):
        try:
            return float(wanted) == value
        except ValueError:
            return False
    return str(value).strip().lower() == wanted.strip().lower()


def wall_mark(properties: Properties, wall_properties: Sequence[tuple[str, str | None]] = ()) -> bool | None:
    """Whether a tile's or object's properties mark it a wall (``True``), opt it out (``False``), or say
    nothing (``None``).

    With ``wall_properties`` (``--wall-property``), only those are read: a property ``NAME`` that reads
    true (or false), or a property ``NAME`` equal to ``VALUE``. Otherwise every property whose name says
    wall (:data:`WALL_WORDS`) is read, of any type: a true one marks a wall, a false one opts out, and one
    whose name says ``no`` or ``not`` opts out when true. A mark wins over an opt-out.

    >>> wall_mark({"CollisionShape": 1}), wall_mark({"IsBlocking": "false"}), wall_mark({"no_collision": True})
    (True, False, False)
    >>> wall_mark({"terrain": "Rock"}, [("terrain", "rock")]), wall_mark({"solid": True}, [("terrain", "rock")])
    (True, None)
    """
    result: bool | None = None
    if wall_properties:
        for name, wanted in wall_properties:
            if name not in properties:
                continue
            value = properties[name]
            if wanted is not None:
                if _equals(value, wanted):
                    return True
            elif (said := truth(value)) is not None:
                if said:
                    return True
                result = False
        return result
    for key, value in properties.items():
        named = words(key)
        if not named & WALL_WORDS:
            continue
        said = truth(value)
        if named & NEGATION_WORDS:
            said = False if said else None
        if said:
            return True
        if said is False:
            result = False
    return result


def body_mark(kind: str, properties: Properties) -> bool | None:
    """Whether a tile or object is a static physics body (``True``: a wall), a moving one (``False``), or not
    a body as far as it says (``None``).

    A property whose name says body (``bodyType``, ``body_type``) tells the type: ``static`` is a wall,
    ``dynamic`` or ``kinematic`` is not. Otherwise a class that names a body (:data:`BODY_WORDS`:
    ``Fixture``, ``StaticBody2D``, ``RigidBody``) is static when its class says so or its property
    ``static`` (``isStatic``) reads true, and moving when its class or that property says so.

    >>> body_mark("Fixture", {"static": True}), body_mark("", {"bodyType": "dynamic"}), body_mark("StaticBody2D", {})
    (True, False, True)
    >>> body_mark("Fixture", {}), body_mark("Sign", {"static": True}), body_mark("RigidBody2D", {})
    (None, None, False)
    """
    for key, value in properties.items():
        if "body" in words(key) and isinstance(value, str):
            said = value.strip().lower()
            if said == "static":
                return True
            if said in MOVING_BODIES:
                return False
    named = words(kind)
    if not named & BODY_WORDS:
        return None
    if "static" in named:
        return True
    if named & MOVING_BODIES:
        return False
    for key, value in properties.items():
        if words(key) - {"is"} == {"static"}:
            return truth(value)
    return None


def pulls(value: Any) -> bool:
    """Whether a gravity-like property's value pulls: true, or a non-zero number (as a number or as text).

    >>> pulls(9.8), pulls("600"), pulls(True), pulls(0), pulls("0.0"), pulls("none")
    (True, True, True, False, False, False)
    """
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            return truth(value) is True
    return bool(truth(value))
