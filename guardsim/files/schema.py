"""The JSON Schemas (draft 2020-12) of every JSON document guardsim reads, shipped in the package.

=============  ======================  ==============================================================
name           file                    read by
=============  ======================  ==============================================================
``level``      ``level.schema.json``   every command taking a level (:func:`guardsim.load_level`)
``patrol``     ``patrol.schema.json``  ``patrol --evaluate``, ``sneak``, ``check`` and ``alert --patrol``
``checks``     ``checks.schema.json``  ``check --checks`` (JSON, or TOML with the same structure)
``manifest``   ``manifest.schema.json`` ``regress`` (a level's ``manifest.json``)
``trace``      ``trace.schema.json``   ``regress`` (stored references) and ``view``
=============  ======================  ==============================================================

Each schema covers what an editor can check as a file is typed: types, required and unknown keys and
ranges. Readers validate with :func:`check` first, so that the first fault in a document is one line
``FILE: PLACE: what is wrong`` (PLACE a JSON path such as ``guards[1].loop[3]``), and then check only
what a schema cannot say: that cells lie on the level's grid, that a loop's steps are 4-neighbours,
that lengths match a shape. The level's own loader (:func:`guardsim.level.check_level_data`) is still
hand-written; ``tests/test_schema.py`` checks that it and the level schema agree.

Two readings are stricter than plain JSON Schema, and the same in every reader: an ``integer`` is a
number written without a fraction (``1``, not ``1.0``), and a ``number`` is finite (a TOML checks file
can hold ``nan`` and ``inf``, which JSON cannot).

A schema node may carry ``x-message``, guardsim's wording of its faults (editors ignore it): a string
words any fault inside the node's value; an object words the faults of the named keywords of the node
itself. Placeholders: ``{value}`` (the value as JSON, elided), ``{repr}`` (as Python writes it),
``{type}``, ``{count}`` (items in the value), ``{key}`` and ``{known}`` (an unknown or missing key, and
the known ones).
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Iterable
from importlib import resources
from typing import Any

from guardsim.errors import ArgumentError, GuardsimError
from guardsim.files.reading import excerpt, json_type, quoted

__all__ = [
    "SCHEMAS",
    "SCHEMA_FILE",
    "check",
    "level_schema",
    "level_schema_text",
    "problem",
    "schema",
    "schema_file",
    "schema_text",
]

#: The schemas shipped, by name.
SCHEMAS = ("level", "patrol", "checks", "manifest", "trace")
#: The level schema's file name inside the ``guardsim`` package.
SCHEMA_FILE = "level.schema.json"
#: Longest excerpt of a value quoted in a message.
_SHOWN = 40


def schema_file(name: str = "level") -> str:
    """The file name of schema ``name`` inside the ``guardsim`` package.

    >>> schema_file("patrol")
    'patrol.schema.json'
    """
    if name not in SCHEMAS:
        raise ArgumentError(f"unknown schema {name!r}; known: {', '.join(SCHEMAS)}")
    return f"{name}.schema.json"


def schema_text(name: str = "level") -> str:
    """Schema ``name`` as shipped, as text."""
    return resources.files("guardsim").joinpath(schema_file(name)).read_text(encoding="utf-8")


@functools.cache
def _schema(name: str) -> dict[str, Any]:
    return json.loads(schema_text(name))


def schema(name: str = "level") -> dict[str, Any]:
    """Schema ``name`` as a dictionary (a fresh copy).

    >>> schema("trace")["$schema"]
    'https://json-schema.org/draft/2020-12/schema'
    """
    return json.loads(json.dumps(_schema(name)))


def level_schema_text() -> str:
    """The level schema as shipped, as text."""
    return schema_text("level")


def level_schema() -> dict[str, Any]:
    """The level schema as a dictionary.

    Examples
    --------
    >>> level_schema_text() == schema_text("level")
    True
    >>> schema = level_schema()
    >>> schema["$schema"], schema["required"]
    ('https://json-schema.org/draft/2020-12/schema', ['outer'])
    """
    return schema("level")


def _is_integer(_checker: Any, value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(_checker: Any, value: Any) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    return isinstance(value, int) and not isinstance(value, bool)


@functools.cache
def _validator(name: str) -> Any:
    """A draft 2020-12 validator of schema ``name``, with guardsim's integers and numbers, and a fast
    ``items``: a list whose items all pass a plain predicate compiled from a simple item schema (types,
    bounds, item counts: cells, headings, grid rows) is accepted at once; any other list, and every list
    holding a fault, goes through jsonschema's own ``items``, which words the fault. A stored trace of
    32,000 ticks checks in a tenth of the time."""
    from jsonschema import Draft202012Validator, validators  # type: ignore[import-untyped]

    root = _schema(name)
    checker = Draft202012Validator.TYPE_CHECKER.redefine_many({"integer": _is_integer, "number": _is_number})
    plain_items = Draft202012Validator.VALIDATORS["items"]

    def items(validator: Any, item_schema: Any, instance: Any, node: Any) -> Any:
        if isinstance(instance, list):
            passes = _predicate(root, item_schema)
            if passes is not None and all(map(passes, instance)):
                return
        yield from plain_items(validator, item_schema, instance, node)

    strict = validators.extend(Draft202012Validator, {"items": items}, type_checker=checker)
    return strict(root)


#: The keywords a schema node compiled by :func:`_predicate` may hold (the others are annotations).
_PLAIN_KEYWORDS = {
    "type",
    "minimum",
    "maximum",
    "exclusiveMinimum",
    "exclusiveMaximum",
    "items",
    "minItems",
    "maxItems",
}
_ANNOTATIONS = {"description", "default", "x-message", "$ref"}
_TYPE_TESTS: dict[str, Any] = {
    "integer": lambda value: _is_integer(None, value),
    "number": lambda value: _is_number(None, value),
    "null": lambda value: value is None,
    "array": lambda value: isinstance(value, list),
    "string": lambda value: isinstance(value, str),
    "boolean": lambda value: isinstance(value, bool),
    "object": lambda value: isinstance(value, dict),
}
_PREDICATES: dict[int, Any] = {}


def _predicate(root: dict[str, Any], node: Any) -> Any:
    """A function telling whether a value is valid against ``node``, or ``None`` when ``node`` holds
    more than types, bounds and item counts (then only jsonschema judges)."""
    key = id(node)
    if key not in _PREDICATES:
        _PREDICATES[key] = (node, _compile(root, node))  # the node is kept, so that its id stays its own
    return _PREDICATES[key][1]


def _compile(root: dict[str, Any], node: Any) -> Any:
    if not isinstance(node, dict) or not set(node) <= _PLAIN_KEYWORDS | _ANNOTATIONS:
        return None
    if "$ref" in node:
        if set(node) & _PLAIN_KEYWORDS:
            return None
        return _predicate(root, _resolve(root, node["$ref"]))
    names = node.get("type", list(_TYPE_TESTS))
    tests = [_TYPE_TESTS[name] for name in ([names] if isinstance(names, str) else names)]
    low, high = node.get("minimum", -math.inf), node.get("maximum", math.inf)
    above, below = node.get("exclusiveMinimum", -math.inf), node.get("exclusiveMaximum", math.inf)
    fewest, most = node.get("minItems", 0), node.get("maxItems", math.inf)
    each = _predicate(root, node["items"]) if "items" in node else None
    if "items" in node and each is None:
        return None

    def passes(value: Any) -> bool:
        if not any(test(value) for test in tests):
            return False
        if _is_number(None, value):
            return low <= value <= high and above < value < below
        if isinstance(value, list):
            return fewest <= len(value) <= most and (each is None or all(map(each, value)))
        return True

    return passes


def problem(data: Any, name: str) -> str | None:
    """The first fault of ``data`` against schema ``name`` as ``"PLACE: what is wrong"`` (or just what
    is wrong, at the top level), or ``None`` when it is valid.

    Examples
    --------
    >>> problem({"shape": [3, 11], "guards": [{"loop": [[5, 1], [5, "1"]], "headings": [0, 0]}]}, "patrol")
    'guards[0].loop[1]: expected [col, row], two whole numbers, got [5,"1"]'
    >>> problem({"max_idle": 600}, "checks")
    "unknown rule 'max_idle' (known: guards, max_cover_steps, max_idleness, max_slack, min_slack, no_unreachable, patrol, planner, safe, sneak, undetected, unheard)"
    >>> problem({"shape": [3, 11], "guards": [{"loop": [[5, 1]], "headings": [0]}]}, "patrol") is None
    True
    """
    from jsonschema.exceptions import best_match  # type: ignore[import-untyped]

    first = next(iter(_validator(name).iter_errors(data)), None)
    if first is None:
        return None
    error = best_match([first])
    place, message = _describe(error, _schema(name), data)
    return f"{place}: {message}" if place else message


def check(data: Any, name: str, *, source: str, error: type[GuardsimError] = GuardsimError, prefix: str = "") -> None:
    """Raise ``error("SOURCE: PREFIX PLACE: what is wrong")`` at the first fault of ``data`` against
    schema ``name``; return when it is valid.

    >>> check({"format": 1, "episodes": []}, "manifest", source="manifest.json")
    Traceback (most recent call last):
    ...
    guardsim.errors.GuardsimError: manifest.json: episodes: must be a non-empty list
    """
    found = problem(data, name)
    if found is not None:
        raise error(f"{source}: {prefix}{found}")


# ---------------------------------------------------------------- wording a fault


def _describe(error: Any, root: dict[str, Any], data: Any) -> tuple[str, str]:
    """``(place, message)`` of one validation error: the node's own ``x-message`` for the keyword, else
    the deepest string ``x-message`` around the fault (said of that node's value), else a plain one."""
    keyword = error.validator
    trail = _trail(root, list(error.absolute_schema_path)[:-1])
    path = list(error.absolute_path)
    own_node, own_depth = trail[-1]
    for node, depth in reversed(trail):
        if depth != own_depth:
            break
        worded = node.get("x-message")
        if isinstance(worded, dict) and keyword in worded:
            return _place(path[:depth]), _fill(worded[keyword], error.instance, own_node, error)
    chosen = None
    for node, depth in trail:
        if isinstance(node.get("x-message"), str) and (chosen is None or depth > chosen[1]):
            chosen = (node, depth)
    if chosen is not None:
        node, depth = chosen
        value = _at(data, path[:depth])
        return _place(path[:depth]), _fill(node["x-message"], value, node, error)
    return _place(path[: len(path)]), _plain(error, own_node)


def _trail(root: dict[str, Any], schema_path: list[Any]) -> list[tuple[dict[str, Any], int]]:
    """The schema nodes the error's schema path goes through, each with the depth of the instance it
    applies to; ``$ref`` hops (left out of jsonschema's paths) are followed, both ends kept."""
    node, depth = root, 0
    trail = [(node, depth)]
    position = 0
    while position < len(schema_path):
        key = schema_path[position]
        while key not in node and "$ref" in node:
            node = _resolve(root, node["$ref"])
            trail.append((node, depth))
        if key in ("properties", "patternProperties", "prefixItems", "allOf", "anyOf", "oneOf", "dependentSchemas"):
            node = node[key][schema_path[position + 1]]
            depth += key in ("properties", "patternProperties", "prefixItems")
            position += 2
        else:
            node = node[key]
            depth += key in ("items", "additionalProperties", "unevaluatedItems", "unevaluatedProperties", "contains")
            position += 1
        trail.append((node, depth))
    while "$ref" in node:
        node = _resolve(root, node["$ref"])
        trail.append((node, depth))
    return trail


def _resolve(root: dict[str, Any], reference: str) -> dict[str, Any]:
    """A local ``#/$defs/name`` reference (the only kind the shipped schemas hold)."""
    node: Any = root
    for part in reference.removeprefix("#/").split("/"):
        node = node[part]
    return node


def _at(data: Any, path: Iterable[Any]) -> Any:
    for step in path:
        data = data[step]
    return data


def _place(path: list[Any]) -> str:
    """A JSON path as guardsim writes it: ``guards[1].loop[3]``."""
    text = ""
    for step in path:
        if isinstance(step, int):
            text += f"[{step}]"
        elif str(step).isidentifier():
            text += f".{step}" if text else str(step)
        else:
            text += f"[{excerpt(step, _SHOWN)}]"
    return text


def _fill(template: str, value: Any, node: dict[str, Any], error: Any) -> str:
    """``template`` with its placeholders filled in (plain replacement: templates hold JSON braces)."""
    key, known = _key_of(error, node)
    shown = {
        "{value}": excerpt(value, _SHOWN),
        "{repr}": _repr(value),
        "{type}": json_type(value),
        "{count}": str(len(value)) if isinstance(value, (list, dict, str)) else "?",
        "{key}": key,
        "{known}": known,
    }
    for placeholder, text in shown.items():
        template = template.replace(placeholder, text)
    return template


def _repr(value: Any) -> str:
    shown = repr(value)
    if not shown.isprintable():
        shown = shown.encode("unicode_escape", "backslashreplace").decode("ascii")
    return shown if len(shown) <= _SHOWN else shown[: _SHOWN - 3] + "..."


def _key_of(error: Any, node: dict[str, Any]) -> tuple[str, str]:
    """The key a ``required`` or unknown-key fault is about (quoted), and the node's known keys."""
    known = sorted(node.get("properties", {}))
    instance = error.instance if isinstance(error.instance, dict) else {}
    if error.validator == "required":
        missing = [name for name in error.validator_value if name not in instance]
        return (f'"{missing[0]}"' if missing else "?"), ", ".join(known)
    extra = [name for name in instance if name not in known]
    return (quoted(str(extra[0])) if extra else "?"), ", ".join(known)


_TYPE_NAMES = {
    "integer": "a whole number",
    "number": "a number",
    "string": "a string",
    "array": "a list",
    "object": "an object",
    "boolean": "true or false",
    "null": "null",
}


def _plain(error: Any, node: dict[str, Any]) -> str:
    """The message of a fault whose node has no wording of its own."""
    keyword, limit, value = error.validator, error.validator_value, error.instance
    key, known = _key_of(error, node)
    if keyword == "type":
        names = [limit] if isinstance(limit, str) else limit
        return f"expected {' or '.join(_TYPE_NAMES.get(name, name) for name in names)}, got {json_type(value)}"
    if keyword == "required":
        return f"missing {key}"
    if keyword in ("additionalProperties", "unevaluatedProperties"):
        return f"unknown key {key} (known: {known})"
    if keyword == "enum":
        return f"{excerpt(value, _SHOWN)} is not one of {', '.join(excerpt(item, _SHOWN) for item in limit)}"
    if keyword == "const":
        return f"expected {excerpt(limit, _SHOWN)}, got {excerpt(value, _SHOWN)}"
    bounds = {
        "minimum": "at least",
        "exclusiveMinimum": "over",
        "maximum": "at most",
        "exclusiveMaximum": "under",
    }
    if keyword in bounds:
        return f"must be {bounds[keyword]} {limit:g}, not {excerpt(value, _SHOWN)}"
    if keyword in ("minItems", "maxItems"):
        most = "at least" if keyword == "minItems" else "at most"
        return f"expected {most} {limit} items, got {len(value)}"
    return excerpt(error.message, 120)
