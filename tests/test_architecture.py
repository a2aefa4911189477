"""The house's shape (issue 29): no import circles, a small top level, small modules, one set of
equations, and docs/architecture.md's picture drawn from the real imports.

The import graph is read from the sources (``ast``), every ``import`` statement counted wherever it
stands -- at the top of a module or inside a function -- since a circle through a function-level
import is still a circle: the two modules cannot be understood, tested or moved one without the
other.  A string literal in code that names one of our modules (``"stand.x.y"``, ``"stand.x.y:obj"``:
registries, ``importlib``, ``_jit.closure``) is an import too (issue 40).  ``from P import name`` is an edge to ``P.name`` when that is a module, else to ``P``.
Importing a module does not count as importing its package's ``__init__`` (as in grimp).
"""
from __future__ import annotations

import ast
import functools
import re
from pathlib import Path
import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("stand", "dsp", "vision")
#: modules allowed at stand's top level besides packages
TOP_LEVEL_LIMIT = 6
LINE_LIMIT = 600
#: the right-hand sides that run: planar kernel, generic kernel, and one more (issue 29 item 4)
RHS_MODULE_LIMIT = 3


def _modules() -> dict:
    """Dotted module name -> (path, is_package) for every module of the three packages."""
    mods = {}
    for pkg in PACKAGES:
        for path in (ROOT / pkg).rglob("*.py"):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            is_pkg = parts[-1] == "__init__"
            mods[".".join(parts[:-1] if is_pkg else parts)] = (path, is_pkg)
    return mods


#: a string literal naming one of our modules, optionally with an object: ``"stand.x.y"``,
#: ``"stand.x.y:obj"`` (registries, ``importlib.import_module``, ``_jit.closure`` arguments)
MODULE_STRING = re.compile(r"((?:stand|dsp|vision)(?:\.\w+)+)(?::[\w.]+)?")


def import_targets(tree, here: str, mods) -> list:
    """Dotted names a module's source imports: ``import``/``from`` statements anywhere (also inside
    functions) and string literals in code that name a module of ours exactly (``"stand.x.y"`` or
    ``"stand.x.y:obj"``); docstrings do not count.  ``here`` is the package relative imports start from.
    One walk of the tree: the string literals are kept with their node and the docstrings
    (a module's, class's or function's first statement) dropped at the end, the order of the walk kept."""
    docs = set()
    found = []                        # (the string constant or None, target)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(None, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = here.split(".")[: len(here.split(".")) - (node.level - 1)]
                base = ".".join(up + ([node.module] if node.module else []))
            found += [(None, f"{base}.{a.name}" if f"{base}.{a.name}" in mods else base)
                      for a in node.names]
        elif isinstance(node, ast.Constant):
            if isinstance(node.value, str):
                m = MODULE_STRING.fullmatch(node.value)
                if m and m.group(1) in mods:
                    found.append((node, m.group(1)))
        elif isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) \
                and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                docs.add(id(first.value))
    return [name for node, name in found if node is None or id(node) not in docs]


@functools.lru_cache(maxsize=None)
def _tree(path: Path):
    """A source file's syntax tree, parsed once per test process (the files do not change
    during a run; the checks below walk the same trees)."""
    return ast.parse(path.read_text(), filename=str(path))


def import_graph() -> dict:
    """Module -> set of the package's modules it imports (anywhere in its source, strings too);
    a fresh copy of the graph read once per test process."""
    return {name: set(edges) for name, edges in _import_graph().items()}


@functools.lru_cache(maxsize=None)
def _import_graph() -> dict:
    mods = _modules()

    def owner(name):  # the longest prefix of ``name`` that is a module of ours
        while name and name not in mods:
            name = name.rpartition(".")[0]
        return name or None

    graph = {}
    for name, (path, is_pkg) in mods.items():
        here = name if is_pkg else name.rpartition(".")[0]
        tree = _tree(path)
        edges = {o for o in map(owner, import_targets(tree, here, mods)) if o and o != name}
        graph[name] = edges
    return graph


def circles(graph: dict) -> list:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = 0
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


def test_circle_finder_finds_a_planted_circle():
    """The checker itself: a circle through a function-level import is found, a chain is not."""
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert circles(g) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []
    src = "def f():\n    from stand.x import y\n"
    tree = ast.parse(src)
    assert any(isinstance(n, ast.ImportFrom) for n in ast.walk(tree))   # ast.walk sees inside defs


def test_no_import_circles():
    found = circles(import_graph())
    assert not found, "import circles (imports inside functions count):\n" + "\n".join(
        " <-> ".join(c) for c in found)


def test_stand_top_level_is_small():
    loose = sorted(p.name for p in (ROOT / "stand").glob("*.py"))
    assert len(loose) <= TOP_LEVEL_LIMIT, loose


def test_no_module_over_the_line_limit():
    big = []
    for pkg in PACKAGES:
        for path in (ROOT / pkg).rglob("*.py"):
            if "vendor" in path.parts:
                continue
            n = len(path.read_text().splitlines())
            if n > LINE_LIMIT:
                big.append(f"{path.relative_to(ROOT)} ({n} lines)")
    assert not big, big


def test_equations_of_motion_are_written_once():
    """Functions named like a right-hand side (``rhs``, ``make_rhs``, ``..._rhs``) live in at most
    three modules of stand/; the books' own forms are test oracles (tests/oracles/)."""
    owners = set()
    for path in (ROOT / "stand").rglob("*.py"):
        for node in ast.walk(_tree(path)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and re.search(
                    r"(^|_)rhs($|_)", node.name):
                owners.add(str(path.relative_to(ROOT)))
    assert len(owners) <= RHS_MODULE_LIMIT, sorted(owners)


def package_of(module: str) -> str:
    """``stand.model.rotors.flexible`` -> ``stand.model``; ``dsp.lines`` -> ``dsp``."""
    parts = module.split(".")
    return ".".join(parts[:2]) if parts[0] == "stand" else parts[0]


def package_edges() -> set:
    """(from, to) between stand's packages (and the leaves), from the module graph."""
    graph = import_graph()
    edges = set()
    for mod, targets in graph.items():
        for t in targets:
            a, b = package_of(mod), package_of(t)
            if a != b:
                edges.add((a, b))
    return edges


#: used by every layer, left out of the picture (said in docs/architecture.md)
BASE = {"stand.errors", "stand._jit", "stand.io", "stand"}


def reachable(edges: set, a: str) -> set:
    seen, todo = set(), [a]
    while todo:
        for x, y in edges:
            if x == todo[-1] and y not in seen:
                seen.add(y)
                todo.append(y)
                break
        else:
            todo.pop()
    return seen


def test_architecture_picture_shows_every_arrow():
    """docs/architecture.md's diagram (mermaid ids are the dotted names with ``_``: stand_model)
    draws only real package imports, and every real import follows its arrows (directly or
    through other packages): a new upward import fails here until the picture shows it."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    block = re.search(r"```mermaid\n(.*?)```", text, re.S)
    assert block, "docs/architecture.md has no mermaid diagram"
    drawn = set(re.findall(r"^\s*(\w+)(?:\[[^\]]*\])?\s*-->\s*(\w+)", block.group(1), re.M))
    node = lambda name: name.replace(".", "_")   # a mermaid id: stand.model -> stand_model
    real = {(node(a), node(b)) for a, b in package_edges()
            if a not in BASE and b not in BASE and a != "stand.__main__"}
    not_real = sorted(drawn - real)
    not_drawn = sorted((a, b) for a, b in real if b not in reachable(drawn, a))
    assert not not_real and not not_drawn, \
        f"drawn but not imported: {not_real}; imported but not along the arrows: {not_drawn}"


def declared_layers() -> list:
    """The stack, lowest first, as docs/architecture.md declares it: the line
    ``Layers, lowest first: `a` → `b` → ...`` (issue 40: a strict stack)."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    m = re.search(r"^Layers, lowest first: (.*)$", text, re.M)
    assert m, "docs/architecture.md declares no 'Layers, lowest first:' line"
    return re.findall(r"`([\w.]+)`", m.group(1))


def against_the_stack(graph: dict, layers: list) -> list:
    """Module edges that do not go from a higher layer to a lower one ("a -> b (A above? no)").
    Every package must have a layer; imports inside one package are free (no circles is checked
    apart)."""
    rank = {name: i for i, name in enumerate(layers)}
    bad = []
    for mod, targets in sorted(graph.items()):
        a = package_of(mod)
        for t in sorted(targets):
            b = package_of(t)
            if a == b:
                continue
            if a not in rank or b not in rank:
                bad.append(f"{mod} -> {t}: package {a if a not in rank else b} has no layer")
            elif rank[a] < rank[b]:
                bad.append(f"{mod} -> {t}: {a} imports {b}, a higher layer")
    return bad


def test_layer_checker_finds_planted_violations():
    """The checker itself: an upward import statement inside a function, and an upward registry
    string, are found; a downward import, a docstring and a string that is not a module are not."""
    mods = {"stand.model.a": None, "stand.scene.b": None, "stand.scene": None}
    src = ('"""Docstring naming stand.scene.b."""\n'
           "def f():\n    from stand.scene import b\n"
           'REG = {"x": ("stand.scene.b:Thing", "")}\n'
           'MSG = "stand.analyze"\n')
    found = import_targets(ast.parse(src), "stand.model", mods)
    assert found == ["stand.scene.b", "stand.scene.b"], found
    assert import_targets(ast.parse('"""stand.scene.b"""\n'), "stand.model", mods) == []
    layers = ["stand.model", "stand.scene"]
    graph = {"stand.model.a": {"stand.scene.b"}, "stand.scene.b": {"stand.model.a"}}
    bad = against_the_stack(graph, layers)
    assert len(bad) == 1 and bad[0].startswith("stand.model.a -> stand.scene.b"), bad
    assert against_the_stack({"stand.scene.b": {"stand.model.a"}}, layers) == []
    assert "has no layer" in against_the_stack({"stand.new.c": {"stand.model.a"}}, layers)[0]


def test_packages_form_a_strict_stack():
    """Every import between two packages -- statement or module string -- goes from a higher layer
    to a lower one of docs/architecture.md's order (no exceptions), and the order names every
    package."""
    layers = declared_layers()
    graph = import_graph()
    missing = sorted({package_of(m) for m in graph} - set(layers))
    assert not missing, f"packages without a layer in docs/architecture.md: {missing}"
    bad = against_the_stack(graph, layers)
    assert not bad, f"{len(bad)} imports against the stack:\n" + "\n".join(bad)


#: what the command line may import (issue 40): the API, itself, the errors and the io layer
CLI_MAY_IMPORT = ("stand.api", "stand.cli", "stand.errors", "stand.io")


def cli_imports_beyond_the_api(graph: dict) -> list:
    """``(cli module, imported module)`` for each import of stand/cli outside
    :data:`CLI_MAY_IMPORT` (``stand`` itself, ``stand._jit``, ``dsp``, ... included)."""
    allowed = lambda m: any(m == p or m.startswith(p + ".") for p in CLI_MAY_IMPORT)  # noqa: E731
    return sorted((mod, t) for mod, targets in graph.items()
                  if mod == "stand.cli" or mod.startswith("stand.cli.")
                  for t in targets if not allowed(t))


def test_cli_imports_only_the_api():
    """stand/cli calls the library only through stand.api (plus stand.cli, stand.errors,
    stand.io), imports inside functions counted; the checker itself finds a planted import."""
    planted = {"stand.cli.x": {"stand.api", "stand.io.numbers", "stand.apiary", "stand"},
               "stand.clinic": {"dsp"}}
    assert cli_imports_beyond_the_api(planted) == [("stand.cli.x", "stand"),
                                                   ("stand.cli.x", "stand.apiary")]
    bad = cli_imports_beyond_the_api(import_graph())
    assert not bad, "stand/cli imports beyond stand.api: " + ", ".join(f"{a} -> {b}" for a, b in bad)
