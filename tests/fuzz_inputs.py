"""Hypothesis strategies of hostile ``rodstab`` inputs, shared by tests/test_fuzz.py and the
long on-demand run benchmarks/fuzz.py.

A case is an argv (with ``{design}`` standing for a design file and ``{tmp}`` for a scratch
directory) and the bytes of that design file. Design files are the real examples in
``examples/`` mutated at random key paths: values replaced by wrong types or extreme numbers,
keys deleted, unknown or known keys added, whole subtrees replaced by random trees; sometimes
the text itself is cut or gets stray bytes. Numeric CLI options get extreme or malformed text.
Every case is bounded: small ``--elements``, ``--max-dof 20000``, ``--max-steps 50``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib
from pathlib import Path
from typing import Any

from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = {p.name: tomllib.loads(p.read_text()) for p in sorted(ROOT.glob("examples/*.toml"))}
#: Options that bound the size of every run of a case.
BOUNDS = ["--max-dof", "20000", "--max-steps", "50"]

#: Keys the design format knows (so that mutations often hit a real key with a wrong value).
KNOWN_KEYS = ["section", "segment", "weld", "support", "analysis", "shape", "aspect", "nu",
              "torsion", "b1", "b2", "B3", "name", "length", "curvature", "natural_curvature",
              "natural_twist", "start", "angle_deg", "cusp", "ends", "end", "type", "rotation",
              "elements", "reference_load", "load_factor_segment"]
EXTREME_FLOATS = [0.0, -0.0, 1.0, -1.0, 0.5, 1e308, -1e308, 1.7976931348623157e308, 1e-320,
                  5e-324, -1e-320, 1e-300, 1e300, 1e9, 1e-9, 1e10, 1e-10, 3.0, 1e6,
                  math.inf, -math.inf, math.nan, 2 * math.pi, 0.1]
EXTREME_INTS = [0, -1, 1, 2, 3, 100, 10**9, 2**31, 2**63 - 1, -(2**63), 10**30, 10**400]
STRINGS = ["", "abc", "nan", "inf", "1e308", "1.0", "upper", "lower", "a.end", "upper.start",
           "lower.end", "nope", "s1.start", "rod.end", "arc.start", "circle", "rectangle",
           "tube", "ellipse", "hexagon", "exact", "paper", "clamped", "fork", "free",
           "sliding-clamp", "pinned", "nope.start", "a.b.end", ".", "\u00e9", "\t", "x" * 200]

scalars = st.one_of(
    st.sampled_from(EXTREME_FLOATS),
    st.sampled_from(EXTREME_INTS),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**20), max_value=10**20),
    st.booleans(),
    st.sampled_from(STRINGS),
    st.text(max_size=8),
)
keys = st.one_of(st.sampled_from(KNOWN_KEYS), st.text(min_size=1, max_size=6))
values = st.recursive(
    scalars,
    lambda children: st.one_of(st.lists(children, max_size=4),
                               st.dictionaries(keys, children, max_size=4)),
    max_leaves=10,
)


plausible_numbers = st.one_of(
    st.sampled_from(EXTREME_FLOATS),
    st.floats(-10.0, 10.0),
    st.integers(-5, 40),
    st.floats(allow_nan=False, allow_infinity=False),
)


def _at(tree: Any, path: tuple) -> Any:
    for k in path:
        tree = tree[k]
    return tree


def _paths(tree: Any, prefix: tuple = ()) -> list[tuple]:
    """Every path (tuple of keys and indices) into ``tree``, the root included."""
    out = [prefix]
    if isinstance(tree, dict):
        for k, v in tree.items():
            out += _paths(v, prefix + (k,))
    elif isinstance(tree, list):
        for i, v in enumerate(tree):
            out += _paths(v, prefix + (i,))
    return out


@st.composite
def mutated_design(draw: st.DrawFn) -> dict:
    """An example design with one to four random mutations at random key paths."""
    import copy

    data = copy.deepcopy(EXAMPLES[draw(st.sampled_from(sorted(EXAMPLES)))])
    for _ in range(draw(st.sampled_from([1, 1, 1, 2, 2, 3, 4]))):
        paths = _paths(data)
        path = draw(st.sampled_from(paths))
        parent: Any = data
        for k in path[:-1]:
            parent = parent[k]
        target = parent[path[-1]] if path else data
        action = draw(st.sampled_from(["replace", "replace", "replace", "delete", "add",
                                       "add-known", "number", "number", "number"]))
        numbers = [p for p in paths if p and isinstance(_at(data, p), (int, float))
                   and not isinstance(_at(data, p), bool)]
        if action == "number" and numbers:
            # A number where a number belongs: past the type checks, into ranges and solves.
            path = draw(st.sampled_from(numbers))
            parent = _at(data, path[:-1])
            parent[path[-1]] = draw(plausible_numbers)
        elif action == "replace" and path:
            parent[path[-1]] = draw(values)
        elif action == "delete" and path:
            del parent[path[-1]]
        elif isinstance(target, dict):
            key = draw(keys) if action == "add" else draw(st.sampled_from(KNOWN_KEYS))
            target[key] = draw(values)
        elif isinstance(target, list):
            target.append(draw(values))
    return data


def _key(k: Any) -> str:
    return json.dumps(str(k), ensure_ascii=False)


def toml_value(v: Any) -> str:
    """``v`` as a TOML value (inline tables and arrays; nan and inf as TOML writes them)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v) if v.bit_length() < 1400 else "1" + "0" * 420
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def toml_text(data: Any) -> str:
    """A TOML document of ``data``: one ``key = value`` line per top-level key."""
    if not isinstance(data, dict):
        return f"value = {toml_value(data)}\n"
    return "".join(f"{_key(k)} = {toml_value(v)}\n" for k, v in data.items())


@st.composite
def design_bytes(draw: st.DrawFn) -> bytes:
    """The bytes of a design file: mostly a mutated example, sometimes a damaged text."""
    text = toml_text(draw(mutated_design())).encode()
    damage = draw(st.sampled_from(["none"] * 6 + ["cut", "bytes", "nest"]))
    if damage == "cut":
        text = text[:draw(st.integers(0, len(text)))]
    elif damage == "bytes":
        at = draw(st.integers(0, len(text)))
        text = text[:at] + draw(st.binary(min_size=1, max_size=4)) + text[at:]
    elif damage == "nest":
        depth = draw(st.sampled_from([10, 1000, 5000]))
        text += b"deep = " + b"[" * depth + b"]" * depth + b"\n"
    return text


def _num_text() -> st.SearchStrategy[str]:
    return st.one_of(
        st.sampled_from(["0", "-0.0", "1e308", "-1e308", "1e-320", "nan", "inf", "-inf", "1",
                         "2", "-1", "0.5", "1e9", "99999999999999999999", "1e400", "abc", "",
                         "0x10", "1_000", " 3", "3.0", "1e-300", "360", "720", "5e-324"]),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.integers(-(10**12), 10**12).map(str),
        st.text(max_size=6),
    )


def _vary_text() -> st.SearchStrategy[str]:
    key = st.sampled_from(["load_factor", "section.aspect", "section.nu", "section.b1",
                           "section.B3", "analysis.elements", "analysis.reference_load",
                           "segment.upper.natural_curvature", "segment.upper.length",
                           "segment.upper.section.nu", "segment.zz.length",
                           "support.0.rotation.tangent", "support.9.rotation.normal",
                           "support.x.rotation.normal", "section.shape", "", "foo",
                           "segment.upper.natural_twist", "analysis.load_factor_segment"])
    part = st.one_of(_num_text(), st.sampled_from(["0", "1", "0.5", "2"]))
    n = st.one_of(st.sampled_from(["2", "3", "0", "-1", "1.5", "x", "", "10**9",
                                   "99999999999999999999", "1" + "0" * 5000]),
                  st.integers(1, 4).map(str))
    return st.one_of(
        st.tuples(key, part, part, n).map(lambda t: f"{t[0]}={t[1]}:{t[2]}:{t[3]}"),
        st.tuples(key, part, part).map(lambda t: f"{t[0]}={t[1]}:{t[2]}"),
        st.text(max_size=12),
    )


@dataclasses.dataclass(frozen=True)
class Case:
    """One fuzz case: ``argv`` (``{design}``, ``{tmp}`` to substitute) and the design bytes."""

    argv: tuple[str, ...]
    design: bytes | None


def _section_opts() -> st.SearchStrategy[list[str]]:
    opt = st.sampled_from(["--aspect", "--nu", "--b1", "--b2"])
    pairs = st.lists(st.tuples(opt, _num_text()), max_size=3)
    shape = st.sampled_from([[], ["--shape", "rectangle"], ["--shape", "tube"],
                             ["--shape", "ellipse"]])
    return st.tuples(shape, pairs).map(lambda t: t[0] + [x for p in t[1] for x in p])


@st.composite
def cli_case(draw: st.DrawFn) -> Case:
    """A bounded run of one command with a fuzzed design file or fuzzed numeric options."""
    kind = draw(st.sampled_from(["analyze"] * 6 + ["section", "ring", "michell", "arc",
                                                   "folded-ring", "equilibrium", "continue",
                                                   "sweep", "analyze-example"]))
    if kind in ("analyze", "analyze-example"):
        design = draw(design_bytes()) if kind == "analyze" else None
        path = "{design}" if design is not None else "examples/" + draw(
            st.sampled_from(sorted(EXAMPLES)))
        elements = draw(st.one_of(st.just([]), st.sampled_from(["1", "2", "4", "8"]).map(
            lambda e: ["--elements", e]), _num_text().map(lambda e: ["--elements", e])))
        if not elements and design is None:
            elements = ["--elements", "4"]
        return Case(("analyze", path, *elements, *BOUNDS), design)
    if kind == "section":
        return Case(("section", *draw(_section_opts())), None)
    if kind in ("ring", "michell"):
        return Case((kind, "--loops", draw(_num_text()), *draw(_section_opts()), *BOUNDS),
                    None)
    if kind == "arc":
        return Case(("arc", "--L-over-R", draw(_num_text()), *draw(_section_opts())), None)
    if kind == "folded-ring":
        return Case(("folded-ring", "--segments", draw(_num_text()), "--arc-angle",
                     draw(_num_text()), *BOUNDS), None)
    example = "examples/" + draw(st.sampled_from(["birod.toml", "twisted_rod.toml",
                                                  "straight_clamped_rod.toml"]))
    if kind == "equilibrium":
        return Case(("equilibrium", example, "--load-factor", draw(_num_text()), "--elements",
                     draw(st.sampled_from(["2", "4", "8"])), *BOUNDS), None)
    vary = draw(_vary_text())
    if kind == "continue":
        return Case(("continue", example, "--vary", vary, "--elements", "4", "--branch-steps",
                     "0", "--no-progress", "--max-dof", "20000", "--max-steps", "4"), None)
    return Case(("sweep", example, "--vary", vary, "--elements", "4", "--no-progress",
                 "--out", "{tmp}/sweep", "--max-dof", "20000", "--max-steps", "3"), None)


def argv_of(case: Case, tmp: Path) -> list[str]:
    """The argv of ``case`` with its design file written into ``tmp``."""
    design = tmp / "design.toml"
    if case.design is not None:
        design.write_bytes(case.design)
    return [a.replace("{design}", str(design)).replace("{tmp}", str(tmp)) for a in case.argv]
