"""How a value flows from the command line into rodstab: which functions receive it (issue 20).

Runs one ``rodstab`` command line in this process (``rodstab.cli.main``) under
:func:`sys.settrace` and, at every call of a function defined in the imported ``rodstab``
package, looks at the arguments the call received. A call *receives the traced value* when an
argument (``self`` and ``cls`` left out: a method reading its own object is no hop)

* ``value``: is a number equal to it (``float``, ``int``, numpy scalars; exact equality, so
  pick an unusual value such as 3.217 that no computation produces by chance);
* ``text``: is a string holding its text (``"3.217"`` in ``"section.aspect=3.217:4:6"``): the
  value before it is parsed;
* ``container``: holds it in a list, tuple, set, dict (values) or numpy array of at most
  :data:`SMALL` entries, up to :data:`DEPTH` levels down (the grid of an atlas, a design's raw
  TOML table);
* ``object``: is an object of an input class (one defined in :data:`INPUT_MODULES`: a
  ``Design``, ``Section``, ``Assembly``, ``Segment``, a ``--vary`` spec, ``Limits``) carrying
  it in an attribute, up to :data:`DEPTH` levels down (``Design.section.aspect``, a ``--vary``
  spec's ``start``). The solvers' own state (a ``DiscreteRod`` holding the load factor, a
  ``Ring``) is not looked into: every step of a solve would count. Properties are not
  evaluated; a closure's captured variables are not looked into.

Counted per command: the distinct rodstab functions (``module:qualname``) and modules that
received the value, and their calls (each row says how it came: the first kind above that
matched), per floor of the package (:data:`FLOORS`: the command line, the input modules, the
applications, the engines, the output); the calls of the functions named ``require*``,
``check*`` or ``validate*`` (:data:`VALIDATION`) among them (validations of the value); and,
whatever their arguments, the calls of ``rodstab.io.design.parse_design``,
``rodstab.io.design.load_design`` and ``rodstab.multistable.states.ring_of``. "To the solver"
is every floor but the output (where a value seen is an answer on its way back). Functions
are matched by where their code is, so run it with the checkout to measure first on
``PYTHONPATH``.

What it cannot see: a value the code transforms (the built-in structures' kappa_n R0 becomes
the model's load factor through a formula: only the hops before it count), a value captured
by a closure rather than passed, and calls in worker processes.

Run (from the repository; the command's own output is discarded)::

    PYTHONPATH=src python benchmarks/trace_value_flow.py 3.217 -- atlas examples/hexagram.toml \\
        --vary section.aspect=3.217:4:6 --out /tmp/atlas --workers 0 --no-progress
    PYTHONPATH=src python benchmarks/trace_value_flow.py 1.4567 -- barrier \\
        examples/hexagram.toml --from star --to daisy --load-factor 1.4567

``--workers 0``: an atlas's points solved in this process (a worker process is not traced).
``--json`` (before ``--``) prints the counts as one JSON object; ``--table SAVED.json`` prints
the table of one.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import json
import re
import sys
import time
from collections import Counter
from pathlib import Path
from types import CodeType, FrameType
from typing import Any

import numpy as np

#: Containers and arrays longer than this are not looked into (a rod's node positions).
SMALL = 64
#: How many levels of containers and attributes are looked into below an argument.
DEPTH = 3
#: Counted whatever their arguments: (module, function).
COUNTED = (("rodstab.io.design", "parse_design"), ("rodstab.io.design", "load_design"),
           ("rodstab.multistable.states", "ring_of"))
#: A function whose name matches is a validation (``require_finite``, ``check``, ``_check_x``).
VALIDATION = re.compile(r"^_?(require|check|validate)(_|$)")
#: The floors a function is counted in, by the longest prefix of its module (as
#: tests/test_layout.py's, with the output apart: printing, JSON, files, figures).
FLOORS = {
    "cli": ("rodstab.cli",),
    "input": ("rodstab", "rodstab.errors", "rodstab.limits", "rodstab.model", "rodstab.sections",
              "rodstab.units", "rodstab.io", "rodstab.executor"),
    "application": ("rodstab.multistable", "rodstab.problems", "rodstab.sweep",
                    "rodstab.checks"),
    "engine": ("rodstab.kinematics", "rodstab.analytic", "rodstab.transfer", "rodstab.linear",
               "rodstab.nonlinear", "rodstab.numerics"),
    "output": ("rodstab.cli.output", "rodstab.results", "rodstab.plot", "rodstab.report",
               "rodstab.io.outputs"),
}
#: Output functions of a module on another floor, by ``module:qualname``: the printing helpers
#: of the single-module CLI before issue 20 (now :mod:`rodstab.cli.output`).
OUTPUT_FUNCTIONS = ("rodstab.cli:_fmt", "rodstab.cli:_emit", "rodstab.cli:_section_line",
                    "rodstab.cli:_units_line")
#: Classes whose objects are looked into (``object`` above): the design and its parts, the
#: options' values.
INPUT_MODULES = ("rodstab.io", "rodstab.sections", "rodstab.model", "rodstab.cli",
                 "rodstab.units", "rodstab.limits")


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(x, bool)


def carries(x: Any, value: float, text: str, depth: int = DEPTH) -> str | None:
    """Return how ``x`` carries ``value`` (value, text, container, object) or None."""
    if _is_number(x):
        return "value" if x == value else None
    if isinstance(x, str):
        return "text" if text in x else None
    if depth == 0:
        return None
    if isinstance(x, np.ndarray):
        if x.size <= SMALL and x.dtype.kind in "fiu" and bool(np.any(x == value)):
            return "container"
        return None
    if isinstance(x, dict):
        items: Any = list(x.values())
    elif isinstance(x, (list, tuple, set, frozenset)):
        items = list(x)
    else:
        items = None
    if items is not None:
        if len(items) > SMALL:
            return None
        return "container" if any(carries(i, value, text, depth - 1) for i in items) else None
    module = type(x).__module__
    if not any(module == m or module.startswith(m + ".") for m in INPUT_MODULES):
        return None
    if dataclasses.is_dataclass(x):
        fields = [getattr(x, f.name, None) for f in dataclasses.fields(x)]
    else:
        fields = list(getattr(x, "__dict__", {}).values())
    return "object" if any(carries(f, value, text, depth - 1) for f in fields) else None


@dataclasses.dataclass
class Trace:
    """What :func:`trace` saw: calls per function that received the value, and the counted."""

    calls: Counter = dataclasses.field(default_factory=Counter)
    how: dict[str, str] = dataclasses.field(default_factory=dict)
    counted: Counter = dataclasses.field(default_factory=Counter)
    seconds: float = 0.0
    exit_status: Any = None


def trace(argv: list[str], value: float, text: str) -> Trace:
    """Run ``rodstab ARGV`` in this process and record the calls that receive ``value``."""
    import rodstab
    from rodstab.cli import main

    root = Path(rodstab.__file__).resolve().parent
    names: dict[CodeType, str | None] = {}  # code -> "module:qualname", None if not rodstab's

    def name_of(code: CodeType) -> str | None:
        if code not in names:
            path = Path(code.co_filename).resolve()
            if root not in path.parents:
                names[code] = None
            else:
                rel = path.relative_to(root.parent).with_suffix("")
                parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
                names[code] = ".".join(parts) + ":" + getattr(code, "co_qualname",
                                                              code.co_name)
        return names[code]

    out = Trace()
    counted = {f"{m}:{f}" for m, f in COUNTED}

    def on_call(frame: FrameType, event: str, arg: Any) -> None:
        if event != "call":
            return None
        code = frame.f_code
        name = name_of(code)
        if name is None:
            return None
        if name in counted:
            out.counted[name] += 1
        n = (code.co_argcount + code.co_kwonlyargcount + bool(code.co_flags & 0x04)
             + bool(code.co_flags & 0x08))
        local = frame.f_locals
        for a in code.co_varnames[:n]:
            if a in ("self", "cls") or a not in local:
                continue
            how = carries(local[a], value, text)
            if how is not None:
                out.calls[name] += 1
                out.how.setdefault(name, how)
                break
        return None

    t0 = time.perf_counter()
    sink = io.StringIO()
    sys.settrace(on_call)
    try:
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            main(argv)
    except SystemExit as exc:
        out.exit_status = exc.code
    finally:
        sys.settrace(None)
    out.seconds = time.perf_counter() - t0
    return out


def floor(name: str) -> str:
    """The key of :data:`FLOORS` holding the function ``module:qualname``."""
    if name in OUTPUT_FUNCTIONS:
        return "output"
    module = name.split(":")[0]
    return max(((f, p) for f, prefixes in FLOORS.items() for p in prefixes
                if module == p or (p != "rodstab" and module.startswith(p + "."))),
               key=lambda fp: len(fp[1]))[0]


def _counts(calls: dict[str, int]) -> dict[str, Any]:
    modules = sorted({n.split(":")[0] for n in calls})
    validations = {n: c for n, c in calls.items()
                   if VALIDATION.match(n.split(":")[1].split(".")[-1])}
    return {"functions": len(calls), "modules": len(modules), "calls": sum(calls.values()),
            "validation_calls": sum(validations.values()),
            "validation_functions": len(validations)}


def summary(t: Trace) -> dict[str, Any]:
    """The counts of a :class:`Trace` (JSON-ready): per floor, and to the solver (all floors
    but the output), each: functions, modules, calls, validations."""
    out: dict[str, Any] = {"to_solver": _counts({n: c for n, c in t.calls.items()
                                                 if floor(n) != "output"})}
    for f in FLOORS:
        out[f] = _counts({n: c for n, c in t.calls.items() if floor(n) == f})
    out |= {"counted": {f"{m}:{f}": t.counted.get(f"{m}:{f}", 0) for m, f in COUNTED},
            "rows": [{"function": n, "calls": c, "how": t.how[n], "floor": floor(n)}
                     for n, c in sorted(t.calls.items())],
            "exit_status": t.exit_status, "seconds": round(t.seconds, 1)}
    return out


def report(s: dict[str, Any], argv: list[str], raw: str) -> str:
    """The table of a :func:`summary`."""
    lines = [f"rodstab {' '.join(argv)}",
             f"value {raw}; exit status {s['exit_status']}, {s['seconds']} s traced",
             f"{'floor':<12} {'functions':>9} {'modules':>7} {'calls':>7} {'validations':>11}"]
    for f in ("to_solver", *FLOORS):
        c = s[f]
        lines.append(f"{f:<12} {c['functions']:>9} {c['modules']:>7} {c['calls']:>7} "
                     f"{c['validation_calls']:>11}")
    lines += [f"  {r['floor']:<11}  {r['calls']:>7}  {r['how']:<9}  {r['function']}"
              for r in s["rows"]]
    lines += [f"calls of {name}: {n}" for name, n in s["counted"].items()]
    return "\n".join(lines)


def from_json(saved: dict[str, Any]) -> Trace:
    """The :class:`Trace` of a saved ``--json`` output (to count it again)."""
    return Trace(calls=Counter({r["function"]: r["calls"] for r in saved["rows"]}),
                 how={r["function"]: r["how"] for r in saved["rows"]},
                 counted=Counter(saved["counted"]), seconds=saved["seconds"],
                 exit_status=saved["exit_status"])


def main() -> None:
    """``trace_value_flow.py [--json] VALUE -- ARGV...``: print the table or JSON;
    ``trace_value_flow.py --table SAVED.json``: the table of a saved ``--json`` output."""
    args = sys.argv[1:]
    if args[:1] == ["--table"] and len(args) == 2:
        saved = json.loads(Path(args[1]).read_text())
        print(report(summary(from_json(saved)), saved.get("argv", ["?"]),
                     saved.get("value", "?")))
        return
    if "--" not in args:
        sys.exit(__doc__)
    cut = args.index("--")
    head, argv = args[:cut], args[cut + 1:]
    as_json = "--json" in head
    (raw,) = [a for a in head if a != "--json"]
    s = summary(trace(argv, float(raw), raw)) | {"argv": argv, "value": raw}
    print(json.dumps(s, indent=1) if as_json else report(s, argv, raw))

if __name__ == "__main__":
    main()
