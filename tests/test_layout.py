"""The package's layout (issue 20): module sizes, the layers, and no import circles.

Read from the source with :mod:`ast` (nothing is imported): every ``import rodstab...`` and
``from ... import ...`` of the package, at the top of a module or inside a function (the CLI's
lazy imports too), is an edge from the importing module to the module it names (``from PKG
import name`` names ``PKG.name`` when that is a module, else ``PKG``).
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parent.parent / "src"
PACKAGE = SRC / "rodstab"

#: Longest module, in lines.
MAX_LINES = 800
#: Modules allowed longer than MAX_LINES, each with the reason: none since issue 20.
TOO_LONG: dict[str, str] = {}

#: The engines: independent methods, one floor.
ENGINES = ("rodstab.kinematics", "rodstab.analytic", "rodstab.transfer", "rodstab.linear",
           "rodstab.nonlinear")
#: The floors of the package, lowest first: a module imports only from its own floor or a
#: lower one. A module belongs to the floor of the longest prefix naming it.
LAYERS: list[tuple[str, ...]] = [
    ("rodstab", "rodstab.errors", "rodstab.results", "rodstab.limits"),
    ("rodstab.numerics",),
    # The model and what reads it in and writes it out. executor (where points run: processes
    # or dask) needs only the ground floor; it serves multistable.atlas and sweep.
    ("rodstab.model", "rodstab.sections", "rodstab.units", "rodstab.io", "rodstab.executor"),
    ENGINES,
    ("rodstab.multistable",),
    # sweep: linear stability over a grid of designs, an application like the problems.
    ("rodstab.problems", "rodstab.sweep"),
    ("rodstab.checks",),
    # plot below report: the report draws its figures with plot (report.figures uses
    # plot.plots.plot_stable_bands), and plot needs nothing above the engines.
    ("rodstab.plot",),
    ("rodstab.report",),
    ("rodstab.cli",),
]
#: Imports between two different engines (kinematics, analytic, transfer, linear, nonlinear),
#: each with its reason. None today: each engine is an independent method, compared with the
#: others only by the problems and checks above them.
ENGINE_CROSSINGS: dict[tuple[str, str], str] = {}
#: Import circles allowed, each (a set of modules) with the reason. None.
CIRCLES: dict[frozenset[str], str] = {}


def _module(path: Path) -> tuple[str, bool]:
    rel = path.relative_to(SRC).with_suffix("")
    if rel.name == "__init__":
        return ".".join(rel.parts[:-1]), True
    return ".".join(rel.parts), False


FILES = {_module(p)[0]: p for p in sorted(PACKAGE.rglob("*.py"))}


@functools.cache
def _edges() -> dict[str, set[str]]:
    """Module -> the package modules it imports (parsed once, when a test first asks: every
    xdist worker collects this file, one runs it)."""
    out: dict[str, set[str]] = {}
    for mod, path in FILES.items():
        package = mod if _module(path)[1] else mod.rpartition(".")[0]
        targets = out.setdefault(mod, set())
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names if a.name.split(".")[0] == "rodstab")
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    name = ".".join(base + ([node.module] if node.module else []))
                else:
                    name = node.module or ""
                if name.split(".")[0] != "rodstab":
                    continue
                for a in node.names:
                    targets.add(f"{name}.{a.name}" if f"{name}.{a.name}" in FILES else name)
    return out



def _floor(mod: str) -> tuple[int, str]:
    """(floor index, the prefix that put it there)."""
    best = max((p for floor in LAYERS for p in floor
                if mod == p or (p != "rodstab" and mod.startswith(p + "."))), key=len)
    return next(i for i, floor in enumerate(LAYERS) if best in floor), best


def test_every_module_is_on_a_floor_and_every_import_names_a_module():
    for mod, targets in _edges().items():
        _floor(mod)
        for t in targets:
            assert t in FILES, f"{mod} imports {t}, which is no module of the package"


def test_no_module_is_longer_than_800_lines_but_the_listed_ones():
    long = {mod: len(path.read_text().splitlines()) for mod, path in FILES.items()}
    long = {mod: n for mod, n in long.items() if n > MAX_LINES}
    assert set(long) <= set(TOO_LONG), {m: n for m, n in long.items() if m not in TOO_LONG}
    # the list holds only what is still long: a module split since leaves it
    assert set(TOO_LONG) <= set(long), set(TOO_LONG) - set(long)


#: Longest module of the command line (issue 20: a command module parses and prints only).
MAX_CLI_LINES = 400


def test_the_cli_modules_are_short():
    long = {mod: n for mod, path in FILES.items() if mod.startswith("rodstab.cli")
            and (n := len(path.read_text().splitlines())) > MAX_CLI_LINES}
    assert not long, long


def test_no_module_imports_from_a_higher_floor():
    up = [(mod, t) for mod, targets in _edges().items() for t in targets
          if _floor(t)[0] > _floor(mod)[0]]
    assert not up, "\n".join(f"{m} (floor {_floor(m)[1]}) imports {t} (floor {_floor(t)[1]})"
                             for m, t in up)


def test_the_engines_do_not_import_each_other():
    crossings = {(_floor(mod)[1], _floor(t)[1]) for mod, targets in _edges().items()
                 for t in targets if _floor(mod)[1] in ENGINES and _floor(t)[1] in ENGINES
                 and _floor(mod)[1] != _floor(t)[1]}
    assert crossings <= set(ENGINE_CROSSINGS), crossings - set(ENGINE_CROSSINGS)


def test_multistable_needs_neither_problems_nor_the_cli():
    for mod, targets in _edges().items():
        if mod.startswith("rodstab.multistable"):
            assert not {t for t in targets if t.startswith(("rodstab.problems", "rodstab.cli",
                                                            "rodstab.checks"))}, mod


def _circles() -> list[frozenset[str]]:
    """Strongly connected components of more than one module (Tarjan), and self-imports."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[frozenset[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in _edges().get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = set()
            while True:
                w = stack.pop()
                on.discard(w)
                comp.add(w)
                if w == v:
                    break
            if len(comp) > 1 or v in _edges().get(v, ()):
                found.append(frozenset(comp))

    for v in sorted(_edges()):
        if v not in index:
            visit(v)
    return found


def test_there_is_no_import_circle():
    circles = [c for c in _circles() if c not in CIRCLES]
    assert not circles, [sorted(c) for c in circles]


@pytest.mark.parametrize("old, new", [("rodstab.nonlinear.newton", "rodstab.nonlinear.constraint")])
def test_the_circle_solve_discover_is_gone(old, new):
    """nonlinear.solve took retract_step from discover, which imports solve: now constraint.

    Newton's step (``lm_step``, which retracts) left nonlinear.solve for nonlinear.newton when
    solve was split (issue 20); solve only re-exports, and neither imports discover.
    """
    assert new in _edges()[old] and "rodstab.multistable.discover" not in _edges()[old]
    assert "rodstab.multistable.discover" not in _edges()["rodstab.nonlinear.solve"]
    assert old not in _edges()[new]
