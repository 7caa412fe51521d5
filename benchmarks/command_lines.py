"""Lines in the body of each command function (the ``@click.command`` functions of ``guardsim/cli``),
docstring included, longest first: the command line only parses, calls the library and prints.

Usage::

    python benchmarks/command_lines.py            # this checkout's guardsim/cli
    python benchmarks/command_lines.py OTHER/cli  # another checkout's
"""

from __future__ import annotations

import argparse
import ast
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def command_lines(folder: Path) -> list[tuple[int, str]]:
    """``(body lines, "module.function")`` of each command function in ``folder``, longest first."""
    found = []
    for path in sorted(folder.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef) and any("command" in ast.unparse(d) for d in node.decorator_list):
                found.append(((node.end_lineno or node.lineno) - node.body[0].lineno + 1, f"{path.stem}.{node.name}"))
    return sorted(found, key=lambda item: (-item[0], item[1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", nargs="?", type=Path, default=REPO / "guardsim" / "cli")
    args = parser.parse_args()
    for lines, name in command_lines(args.folder):
        print(f"{lines:4d}  {name}")


if __name__ == "__main__":
    main()
