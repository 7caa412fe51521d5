"""The data flows one way: each package imports only from packages upstream of it, and only the drawing
layer (render, viewer, pictures) and what is downstream of it import a drawing library.

Read from the source with :mod:`ast` (every import, inside functions and ``TYPE_CHECKING`` blocks too), so
nothing is imported to check it.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "guardsim"

#: Upstream first. A package (or top-level module) may import those before it, never those after it.
ORDER = [
    "errors",
    "files",
    "level",
    "world",
    "kernels",
    "grid",
    "importers",
    "vision",
    "scene",
    "starts",
    "trace",
    "search",
    "planners",
    "simulation",
    "motion",
    "detection",
    "bounds",
    "optimum",
    "experiment",
    "patrol",
    "sneak",
    "alert",
    "design",
    "validate",
    # The drawing layer: computing packages return the data a picture needs, these draw it.
    "render",
    "viewer",
    "pictures",
    "regress",
    "envs",
    "__init__",
    "cli",
]

#: Where the drawing layer starts: the packages before it never draw.
FIRST_DRAWING = ORDER.index("render")

#: Imports of drawing libraries (a prefix of the module imported). Reading an image (``PIL.Image``, for
#: the image importer) is not drawing.
DRAWING_LIBRARIES = ("matplotlib", "imageio", "PIL.ImageDraw", "PIL.ImageFont")

#: Crossings upstream that are known and not yet taken out; none may be added.
KNOWN = {
    # Type hints only: a compiled walk takes a view table.
    ("guardsim/kernels/walk.py", "vision"),
}


def _home(path: Path) -> str:
    """The package (or top-level module) a source file belongs to."""
    parts = path.relative_to(PACKAGE).with_suffix("").parts
    return parts[0]


def _imports(path: Path) -> list[tuple[int, str]]:
    """Every module ``path`` imports, absolute, with its line."""
    return _imports_under(path, PACKAGE)


@functools.cache
def _imports_under(path: Path, package: Path) -> list[tuple[int, str]]:
    # Parsed once per file: the checks below read every source file.
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    # The package a relative import starts from: the file's own folder (an __init__'s too).
    here = ("guardsim", *path.relative_to(package).with_suffix("").parts)[:-1]
    found: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.extend((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = list(here[: len(here) - (node.level - 1)])
                module = ".".join([*base, *([node.module] if node.module else [])])
            else:
                module = node.module or ""
            found.append((node.lineno, module))
            if not module.startswith("guardsim"):
                # ``from PIL import ImageDraw`` imports the submodule.
                found.extend((node.lineno, f"{module}.{alias.name}") for alias in node.names)
    return found


def _sources() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def _crossings() -> list[str]:
    wrong: list[str] = []
    for path in _sources():
        home = _home(path)
        if home == "__main__":
            continue
        rank = ORDER.index(home)
        name = str(path.relative_to(PACKAGE.parent))
        for line, module in _imports(path):
            parts = module.split(".")
            if parts[0] == "guardsim" and len(parts) > 1:
                other = parts[1]
                if other == home or other not in ORDER:
                    continue
                if ORDER.index(other) > rank and (name, other) not in KNOWN:
                    wrong.append(f"{name}:{line}: {home} imports {module} (downstream of it)")
            elif rank < FIRST_DRAWING and module.startswith(DRAWING_LIBRARIES):
                wrong.append(f"{name}:{line}: {home} imports {module}, a drawing library (computing code never draws)")
    # One line per import statement (``from X import Y`` reads as X and as X.Y).
    return [
        text
        for index, text in enumerate(wrong)
        if index == 0 or text.split(" imports ")[0] != wrong[index - 1].split(" imports ")[0]
    ]


def test_every_package_has_a_place_upstream_or_downstream() -> None:
    homes = {_home(path) for path in _sources()} - {"__main__"}
    assert homes <= set(ORDER), f"place these in ORDER: {sorted(homes - set(ORDER))}"


def test_each_package_imports_only_from_upstream_and_only_the_drawing_layer_draws() -> None:
    wrong = _crossings()
    assert not wrong, "\n".join(wrong)


def test_the_known_crossings_are_still_there() -> None:
    """A known crossing taken out is taken off the list, so that it cannot come back unseen."""
    seen = {
        (str(path.relative_to(PACKAGE.parent)), module.split(".")[1])
        for path in _sources()
        for _, module in _imports(path)
        if module.startswith("guardsim.") and len(module.split(".")) > 1
    }
    assert seen >= KNOWN, f"no longer crossing, take off KNOWN: {sorted(KNOWN - seen)}"


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("from guardsim.viewer import write_viewer\n", "patrol imports guardsim.viewer (downstream of it)"),
        ("from PIL import ImageDraw\n", "patrol imports PIL.ImageDraw, a drawing library"),
        ("import matplotlib.pyplot as plt\n", "patrol imports matplotlib.pyplot, a drawing library"),
        ("def f():\n    from ..render import gif\n", "patrol imports guardsim.render (downstream of it)"),
    ],
    ids=["viewer", "pil-draw", "matplotlib", "relative-render"],
)
def test_the_check_finds_a_crossing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, source: str, expected: str
) -> None:
    """The check itself can fail: a computing module that draws or imports the viewer is named."""
    package = tmp_path / "guardsim"
    (package / "patrol").mkdir(parents=True)
    (package / "patrol" / "__init__.py").write_text("")
    (package / "patrol" / "job.py").write_text(source)
    (package / "viewer").mkdir()
    (package / "viewer" / "__init__.py").write_text("from guardsim.patrol import job\n")
    monkeypatch.setitem(globals(), "PACKAGE", package)
    wrong = _crossings()
    assert len(wrong) == 1 and wrong[0].startswith("guardsim/patrol/job.py:") and expected in wrong[0], wrong


#: Import circles between modules that are known and not yet taken out; none may be added.
KNOWN_CIRCLES = [
    # The package's names come from loading.py, which reads the formats' readers from the package.
    {"guardsim.importers", "guardsim.importers.loading"},
]


def _module_graph() -> dict[str, set[str]]:
    """Each module (a package by its __init__) and the modules it imports, resolved to the longest
    module name that exists."""
    modules: dict[str, Path] = {}
    for path in _sources():
        parts = ("guardsim", *path.relative_to(PACKAGE).with_suffix("").parts)
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        found = set()
        for _, module in _imports(path):
            while module and module not in modules:
                module = module.rpartition(".")[0]
            if module and module not in (name, "guardsim"):
                found.add(module)
        graph[name] = found
    return graph


def _circles(graph: dict[str, set[str]]) -> list[set[str]]:
    """The strongly connected parts of more than one module (Tarjan's algorithm, without recursion)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[set[str]] = []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                part = set()
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    part.add(member)
                    if member == node:
                        break
                if len(part) > 1:
                    circles.append(part)
    return circles


def test_no_import_circles_but_the_known_ones() -> None:
    """Modules import each other one way only (lazy imports inside functions count too): a circle means
    two modules that are one concept, or a rule in the wrong one."""
    circles = _circles(_module_graph())
    assert sorted(map(sorted, circles)) == sorted(map(sorted, KNOWN_CIRCLES))


def test_the_circle_check_finds_a_circle() -> None:
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert _circles(graph) == [{"a", "b", "c"}]
