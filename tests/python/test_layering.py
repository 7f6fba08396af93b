"""The package's parts import downwards only: compute below, present above (issue 32).

Every ``import`` of every module under ``python/drillpy`` counts, module-level and function-level
alike (an import inside a function is a dependency all the same); ``if TYPE_CHECKING:`` imports count
too. A *part* is a subpackage (``drillpy.records``) or a top-level module (``drillpy.jsonio``). The
layers, lowest first; a part may import its own modules and the parts of lower layers, never a part of
its own layer or above:

0. foundation -- the engine and the helpers every part uses: ``_core``, ``units``, ``validate``,
   ``outputs``, ``jsonio``, ``progress``, ``provenance``, ``text`` and the package's ``__init__``
   (imports among these are allowed; they form no circle, which the last test checks);
1. ``model`` -- configuration, one simulation, thresholds;
2. ``uncertainty`` -- stochastic and structural models, Monte Carlo, robust speeds;
3. ``records``, ``study``, ``control`` -- measured records and their analysis; studies past one
   machine (they run the uncertainty's studies); controllers under uncertainty;
4. ``loop`` -- the modelling loop on a record (it reads, cleans and simulates records); ``calibration``
   -- the Bayesian calibration of the rig model (priors, summaries, ABC-SMC, posterior);
5. ``figures`` -- draws the result objects of the parts below;
6. ``reports`` -- composes compute -> figures -> files;
7. ``cli`` -- parses, calls one library function, prints;
8. ``__main__`` -- ``python -m drillpy``.

Run ``python3 tests/python/test_layering.py`` from the repository root to print the part-level graph.
"""
from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "python" / "drillpy"

FOUNDATION = ("_core", "units", "validate", "outputs", "jsonio", "progress", "provenance", "text", "__init__")
LAYERS = (FOUNDATION, ("model",), ("uncertainty",), ("records", "study", "control"), ("loop", "calibration"), ("figures",),
          ("reports",), ("cli",), ("__main__",))
LEVEL = {part: i for i, layer in enumerate(LAYERS) for part in layer}


def _part(module: str) -> str | None:
    """The part of a dotted module name inside drillpy (``drillpy`` itself is ``__init__``)."""
    names = module.split(".")
    if names[0] != "drillpy":
        return None
    return names[1] if len(names) > 1 else "__init__"


def _module_of(path: Path) -> tuple[str, str]:
    """(dotted name, dotted package) of a source file."""
    names = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if names[-1] == "__init__":
        names.pop()
        return ".".join(names), ".".join(names)
    return ".".join(names), ".".join(names[:-1])


def _targets(node, package: str) -> list[str]:
    """The drillpy modules an Import/ImportFrom node names (relative imports resolved)."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    base = node.module or ""
    if node.level:
        pkg = package.split(".")
        pkg = pkg[:len(pkg) - (node.level - 1)]
        base = ".".join(pkg + ([node.module] if node.module else []))
    if base == "drillpy":  # from drillpy import x: x is a part (or a name of the package's __init__)
        return [f"drillpy.{a.name}" if (PACKAGE / a.name).is_dir() or (PACKAGE / f"{a.name}.py").exists()
                else "drillpy" for a in node.names]
    return [base]


def imports() -> dict:
    """(importing part, imported part) -> ["file:line module", ...], every import statement counted."""
    edges = defaultdict(list)
    for path in sorted(PACKAGE.rglob("*.py")):
        module, package = _module_of(path)
        src = _part(module)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            for target in _targets(node, package):
                dst = _part(target)
                if dst is not None and dst != src:
                    edges[(src, dst)].append(f"{path.relative_to(PACKAGE.parent)}:{node.lineno} {target}")
    return edges


def _cycles(edges) -> list:
    """The strongly connected parts with more than one member (Tarjan)."""
    graph = defaultdict(set)
    for a, b in edges:
        graph[a].add(b)
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            scc = []
            while True:
                w = stack.pop()
                on.discard(w)
                scc.append(w)
                if w == v:
                    break
            if len(scc) > 1:
                out.append(sorted(scc))

    for v in sorted(set(graph) | {b for _, b in edges}):
        if v not in index:
            visit(v)
    return out


def test_every_part_has_a_layer():
    parts = {p.stem if p.is_file() else p.name for p in PACKAGE.iterdir()
             if (p.suffix in (".py", ".so", ".pyi") or (p / "__init__.py").exists())}
    parts = {p.split(".")[0] for p in parts} - {"py"}
    assert parts <= set(LEVEL), sorted(parts - set(LEVEL))


def test_no_part_imports_its_own_layer_or_above():
    upward = [f"{a} -> {b}: {where}" for (a, b), wheres in sorted(imports().items())
              for where in wheres
              if not (LEVEL[a] == LEVEL[b] == 0) and LEVEL[b] >= LEVEL[a]]
    assert not upward, "imports against the layer order:\n" + "\n".join(upward)


def test_no_import_circle_between_parts():
    assert _cycles(imports()) == []


#: No module holds more lines of code than this (issue 32): blank lines, comments and docstrings aside.
MAX_CODE_LINES = 500


def code_lines(path: Path) -> int:
    """Lines of code of a module: not blank, not a comment, not inside a docstring."""
    src = path.read_text()
    doc = set()
    for node in ast.walk(ast.parse(src)):
        body = getattr(node, "body", None)
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and body \
                and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                and isinstance(body[0].value.value, str):
            doc.update(range(body[0].lineno, body[0].end_lineno + 1))
    return sum(1 for i, line in enumerate(src.splitlines(), 1)
               if line.strip() and not line.strip().startswith("#") and i not in doc)


def test_code_lines_are_counted_without_docstrings_and_comments(tmp_path):
    f = tmp_path / "m.py"
    f.write_text('"""doc\nmore"""\n# note\n\ndef f():\n    """one"""\n    return 1  # inline\n')
    assert code_lines(f) == 2


def test_no_module_over_the_line_limit():
    long = {str(p.relative_to(PACKAGE)): n for p in sorted(PACKAGE.rglob("*.py"))
            if (n := code_lines(p)) > MAX_CODE_LINES}
    assert long == {}


if __name__ == "__main__":
    graph = imports()
    for (a, b), wheres in sorted(graph.items(), key=lambda kv: (LEVEL[kv[0][0]], kv[0])):
        mark = "" if LEVEL[b] < LEVEL[a] or LEVEL[a] == LEVEL[b] == 0 else "   <-- against the order"
        print(f"{a} -> {b} ({len(wheres)}){mark}")
    print("circles:", _cycles(graph))
