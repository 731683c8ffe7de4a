"""The house rules of docs/architecture.md hold for the whole tree, read with the stdlib ``ast``:

* the planning layers (scenario, models, gait, planners, trajectory) never import MuJoCo, the
  simulation, the controller, the CLI, typer or matplotlib, not even lazily inside a function;
* every ``gaitshift`` import goes to the same layer or a lower one (the layer table below);
* no import cycle between ``gaitshift`` modules (lazy imports included);
* no module over 420 lines and no function over 80 lines (short, explicit allow-lists);
* no ``_private`` name crosses a module (``from x import _y``, ``module._y``, ``obj._y`` of a name
  the module does not define);
* every test module has a docstring that says what it proves.

Each checker is also fed a small bad source, so that none of these rules can pass vacuously.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterable, Mapping
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
TESTS = ROOT / "tests"

#: packages of the planning path and what they must never import (prefixes of module names)
PLANNING = ("scenario", "models", "gait", "planners", "trajectory")
FORBIDDEN = ("mujoco", "gaitshift.sim", "gaitshift.control", "gaitshift.cli", "typer", "matplotlib")

#: layer of each top-level part of the package: a module imports gaitshift modules of its own layer or
#: a lower one only (docs/architecture.md draws the same table)
LAYERS: dict[str, int] = {
    "errors": 0,
    "common": 0,
    "models": 1,
    "trajectory": 1,
    "scenario": 2,
    "gait": 3,
    "planners": 4,
    "analysis": 4,
    "robots": 5,
    "api": 6,
    "": 10,  # the package itself, the public API: gathers the entry points of every layer below the CLI
    "wholebody": 7,
    "control": 8,
    "sim": 9,
    "dds": 9,  # a world like sim: the MuJoCo world behind Unitree's low-level protocol
    "plots": 10,
    "bench": 10,
    "export": 10,
    "campaign": 10,
    "tuning": 10,  # a campaign of a robot's gait candidates
    "cli": 11,
}

MAX_MODULE_LINES = 420
#: module -> why it may be longer for now
LONG_MODULES: dict[str, str] = {
    # being split by another change
}

#: import cycles known today, each as its sorted modules (the lead removes them when fixed)
KNOWN_CYCLES: list[list[str]] = []

MAX_FUNCTION_LINES = 80
#: "module.function" -> why it may be longer for now
LONG_FUNCTIONS: dict[str, str] = {
    "gaitshift.robots.config._load_text": "robot YAML loading, owned by the robots change",
}


# --- reading the tree --------------------------------------------------------------------------------


def module_name(path: Path, base: Path = SRC) -> str:
    """``src/gaitshift/a/b.py`` -> ``gaitshift.a.b``; a package's ``__init__.py`` is the package."""
    parts = list(path.relative_to(base).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


@functools.cache
def sources() -> dict[str, str]:
    """Every module of the package: name -> source text."""
    return {module_name(p): p.read_text() for p in sorted((SRC / "gaitshift").rglob("*.py"))}


def _is_package(module: str, known: Iterable[str]) -> bool:
    return any(k.startswith(module + ".") for k in known)


def imports(source: str, module: str = "", known: Iterable[str] = ()) -> set[str]:
    """Every module ``source`` imports, wherever the import stands (module level, functions,
    ``TYPE_CHECKING`` blocks). ``from a import b`` counts as ``a.b`` when that is a known module,
    else as ``a``; relative imports are resolved against ``module``."""
    known = set(known)
    package = module if _is_package(module, known) else module.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            for alias in node.names:
                full = f"{base}.{alias.name}"
                found.add(full if full in known else base)
    return found


def forbidden_imports(source: str, module: str = "", forbidden: Iterable[str] = FORBIDDEN) -> list[str]:
    """The imports of ``source`` that start with one of the ``forbidden`` module names."""
    bad = tuple(forbidden)
    return sorted(m for m in imports(source, module) if any(m == f or m.startswith(f + ".") for f in bad))


def layer_of(module: str) -> int:
    """Layer of a gaitshift module (``gaitshift.planners.x`` -> LAYERS["planners"])."""
    parts = module.split(".")
    return LAYERS[parts[1] if len(parts) > 1 else ""]


def upward_imports(module: str, source: str, known: Iterable[str]) -> list[str]:
    """The gaitshift modules ``module`` imports from a higher layer than its own."""
    own = layer_of(module)
    mine = imports(source, module, known)
    return sorted(m for m in mine if m.split(".")[0] == "gaitshift" and layer_of(m) > own)


def import_graph(srcs: Mapping[str, str]) -> dict[str, set[str]]:
    """module -> the modules of ``srcs`` it imports (lazy imports included)."""
    return {m: imports(text, m, srcs) & set(srcs) for m, text in srcs.items()}


def cycles(graph: Mapping[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module, or a module importing itself
    (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
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
                    work.append((child, iter(sorted(graph.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1 or node in graph.get(node, ()):
                    found.append(sorted(component))
    return found


def long_modules(srcs: Mapping[str, str], limit: int = MAX_MODULE_LINES) -> dict[str, int]:
    """module -> line count, for modules over ``limit`` lines."""
    counts = {m: len(text.splitlines()) for m, text in srcs.items()}
    return {m: n for m, n in counts.items() if n > limit}


def long_functions(source: str, module: str = "", limit: int = MAX_FUNCTION_LINES) -> dict[str, int]:
    """``module.function`` (methods as ``module.Class.method``) -> lines from ``def`` to its last
    line, docstring included, for functions over ``limit`` lines."""
    out: dict[str, int] = {}

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                name = f"{prefix}.{child.name}" if prefix else child.name
                if not isinstance(child, ast.ClassDef):
                    lines = (child.end_lineno or child.lineno) - child.lineno + 1
                    if lines > limit:
                        out[name] = lines
                visit(child, name)
            else:
                visit(child, prefix)

    visit(ast.parse(source), module)
    return out


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def private_uses(source: str, module: str = "", known: Iterable[str] = ()) -> list[str]:
    """``_private`` names that ``source`` takes from another module: ``from x import _y``,
    ``x._y`` where ``x`` is an imported gaitshift module, and ``obj._y`` (``obj`` not self/cls)
    where ``_y`` is not defined in this module."""
    tree = ast.parse(source)
    own: set[str] = set()  # names this module defines: functions, classes, assignments, attributes
    module_aliases: set[str] = set()
    bad: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            own.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            own.add(node.id)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            own.add(node.attr)
        elif isinstance(node, ast.arg):
            own.add(node.arg)
        elif isinstance(node, ast.Import):
            module_aliases.update(
                (a.asname or a.name.split(".")[0]) for a in node.names if a.name.split(".")[0] == "gaitshift"
            )
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("gaitshift") and not node.level:
            for a in node.names:
                if _private(a.name):
                    bad.append(f"from {node.module} import {a.name}")
                elif f"{node.module}.{a.name}" in known or node.module == "gaitshift":
                    module_aliases.add(a.asname or a.name)
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load) and _private(node.attr)):
            continue
        root = node.value
        while isinstance(root, ast.Attribute):
            root = root.value
        from_module = isinstance(root, ast.Name) and root.id in module_aliases
        on_self = isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")
        if from_module or (not on_self and node.attr not in own):
            bad.append(ast.unparse(node))
    return bad


def says_what_it_proves(source: str) -> bool:
    """A module docstring of at least one real sentence."""
    doc = ast.get_docstring(ast.parse(source)) or ""
    return len(doc.split()) >= 5


# --- the rules on the tree ---------------------------------------------------------------------------


@pytest.mark.parametrize("package", PLANNING)
def test_planning_layers_never_import_mujoco_sim_control_cli_typer_or_matplotlib(package):
    bad = {
        m: forbidden_imports(text, m)
        for m, text in sources().items()
        if m == f"gaitshift.{package}" or m.startswith(f"gaitshift.{package}.")
    }
    assert bad, f"no module found under gaitshift.{package}"
    assert not {m: b for m, b in bad.items() if b}


def test_every_gaitshift_import_goes_to_the_same_or_a_lower_layer():
    srcs = sources()
    assert {m.split(".")[1] if "." in m else "" for m in srcs} <= set(LAYERS), "a package without a layer"
    bad = {m: upward_imports(m, text, srcs) for m, text in srcs.items()}
    assert not {m: b for m, b in bad.items() if b}


def test_no_import_cycle_between_gaitshift_modules():
    graph = import_graph(sources())
    assert sum(len(e) for e in graph.values()) > 200  # the graph really was read
    assert cycles(graph) == KNOWN_CYCLES


def test_no_module_over_420_lines_except_the_listed_ones():
    srcs = sources()
    assert set(LONG_MODULES) <= set(srcs), "an allow-listed module no longer exists: drop it from the list"
    assert set(long_modules(srcs)) <= set(LONG_MODULES)


def test_no_function_over_80_lines_except_the_listed_ones():
    found: dict[str, int] = {}
    for m, text in sources().items():
        found |= long_functions(text, m)
    assert set(found) <= set(LONG_FUNCTIONS)


def test_no_private_name_crosses_a_module():
    srcs = sources()
    bad = {m: private_uses(text, m, srcs) for m, text in srcs.items()}
    tests = {str(p.relative_to(ROOT)): private_uses(p.read_text(), "", srcs) for p in TESTS.rglob("*.py")}
    assert not {m: b for m, b in (bad | tests).items() if b}


def test_every_test_module_says_what_it_proves():
    paths = sorted(TESTS.rglob("*.py"))
    assert len(paths) > 50
    assert [str(p.relative_to(ROOT)) for p in paths if not says_what_it_proves(p.read_text())] == []


# --- each checker fails on a bad source --------------------------------------------------------------


def test_a_lazy_mujoco_import_inside_a_planner_function_is_caught():
    lazy = "def f():\n    if True:\n        import mujoco.viewer\n    from gaitshift.sim import loop\n"
    assert forbidden_imports(lazy) == ["gaitshift.sim", "mujoco.viewer"]
    assert forbidden_imports("from matplotlib import pyplot as plt\n") == ["matplotlib"]
    assert forbidden_imports("import numpy\nfrom gaitshift.models import tvlip\n") == []


def test_an_upward_import_is_caught():
    known = {"gaitshift.models.tvlip", "gaitshift.planners.registry", "gaitshift.errors"}
    src = "from gaitshift.errors import InputError\n\ndef f():\n    from gaitshift.planners import registry\n"
    assert upward_imports("gaitshift.models.x", src, known) == ["gaitshift.planners.registry"]
    assert upward_imports("gaitshift.cli.x", src, known) == []


def test_an_import_cycle_through_a_lazy_import_is_caught():
    srcs = {
        "gaitshift.a": "import gaitshift.b\n",
        "gaitshift.b": "def f():\n    from gaitshift import c\n",
        "gaitshift.c": "from gaitshift.a import x\n",
        "gaitshift.d": "import gaitshift.a\n",
    }
    assert cycles(import_graph(srcs)) == [["gaitshift.a", "gaitshift.b", "gaitshift.c"]]
    assert cycles({"m": {"m"}}) == [["m"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_a_long_module_and_a_long_method_are_caught():
    assert long_modules({"gaitshift.big": "x = 1\n" * 421, "gaitshift.ok": "x = 1\n" * 420}) == {"gaitshift.big": 421}
    body = "\n".join(["class C:", "    def m(self):", *["        x = 1"] * 80])
    assert long_functions(body, "mod") == {"mod.C.m": 81}
    assert long_functions("def f():\n    return 1\n", "mod") == {}


def test_private_names_taken_from_another_module_are_caught():
    known = {"gaitshift.planners.vhip.generator"}
    src = (
        "from gaitshift.planners.vhip.generator import _helper\n"
        "from gaitshift.planners.vhip import generator\n"
        "import gaitshift.models.tvlip\n"
        "def f(gen):\n"
        "    self = None\n"
        "    return generator._step, gaitshift.models.tvlip._T, gen._run_w, self._ok\n"
    )
    assert private_uses(src, "gaitshift.x", known) == [
        "from gaitshift.planners.vhip.generator import _helper",
        "generator._step",
        "gaitshift.models.tvlip._T",
        "gen._run_w",
    ]
    own = "class A:\n    def __init__(self):\n        self._k = 1\n\n    def same(self, o):\n        return o._k\n"
    assert private_uses(own, "gaitshift.y") == []


def test_a_test_module_without_a_docstring_is_caught():
    assert not says_what_it_proves("import pytest\n")
    assert not says_what_it_proves('"""Tests."""\n')
    assert says_what_it_proves('"""The stiffness T_r returns the CoM to its touchdown height."""\n')
