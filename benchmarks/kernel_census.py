"""Count guardsim's compiled code, for issue 22's "one compiled core" figures.

Prints the compiled functions (``@jit``) and the files holding them, and the compiled calls that cross
files, split by whether they call into ``guardsim/kernels`` (the one kernel library) or elsewhere (the
rule is: never elsewhere). A call is counted when a compiled function's body names a compiled function
that its module imported from another module.

    python benchmarks/kernel_census.py
"""

from __future__ import annotations

import ast
from collections import Counter
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "guardsim"


def _is_jit(decorator: ast.expr) -> bool:
    target = decorator.func if isinstance(decorator, ast.Call) else decorator
    return isinstance(target, ast.Name) and target.id == "jit"


def _module(path: Path) -> str:
    return ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)


def main() -> None:
    compiled: dict[str, set[str]] = {}  # module -> compiled function names
    bodies: dict[str, list[ast.FunctionDef]] = {}
    imports: dict[str, dict[str, str]] = {}  # module -> imported name -> source module
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        module = _module(path)
        functions = [
            node for node in tree.body if isinstance(node, ast.FunctionDef) and any(map(_is_jit, node.decorator_list))
        ]
        if functions:
            compiled[module] = {node.name for node in functions}
            bodies[module] = functions
        imports[module] = {
            alias.asname or alias.name: node.module
            for node in tree.body
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("guardsim")
            for alias in node.names
        }
    crossing: Counter[str] = Counter()
    for module, functions in bodies.items():
        for function in functions:
            named = {node.id for node in ast.walk(function) if isinstance(node, ast.Name)}
            for name in named:
                source = imports[module].get(name)
                if source and name in compiled.get(source, set()):
                    crossing["into guardsim.kernels" if source.startswith("guardsim.kernels") else f"into {source}"] += 1
    total = sum(len(names) for names in compiled.values())
    print(f"compiled functions: {total} in {len(compiled)} files")
    for where, count in sorted(crossing.items()):
        print(f"compiled calls across files {where}: {count}")


if __name__ == "__main__":
    main()
