"""Design files (TOML) -> :class:`rodstab.model.Assembly`, with strict validation.

Format (every key optional unless marked; unknown keys are errors)::

    [section]                 # default section of every segment (as the CLI options)
    shape = "rectangle"       # circle | ellipse | rectangle | tube   (or b1 = .., b2 = ..)
    aspect = 2.0
    nu = 0.3333
    torsion = "exact"
    B3 = 1.0                  # in-plane bending stiffness (sets the units of B1, B2)

    [[segment]]               # required, one table per segment, in order
    name = "a"                # required, unique
    length = 1.0              # required, > 0
    curvature = 0.0           # held state 1/R (signed, + turning left); 0 = straight
    natural_curvature = 1.0   # at load factor 1 (signed, same convention)
    natural_twist = 0.0       # at load factor 1 (nonlinear model only)
    start = [0.0, 0.0]        # default: end of the previous segment (origin for the first)
    angle_deg = 0.0           # start tangent; default: previous end tangent
    cusp = false              # with default angle: reverse the previous end tangent
    section = { shape = "circle" }   # per-segment override (same keys as [section])

    [[weld]]
    ends = ["a.end", "b.start"]

    [[support]]
    end = "a.start"
    type = "clamped"          # clamped | sliding-clamp | fork | pinned | free
    rotation = [0.0, 0.0, 0.0] # imposed end rotation (rad) about the end's normal, tangent,
                              # binormal (clamps only; nonlinear model only)

    [analysis]
    elements = 32             # per segment
    reference_load = 0.0      # a load factor at which the held state is stable
    load_factor_segment = "a" # report lam = B3 kappa_n L / sqrt(B1 B2) of this segment

Plain data only: parsed with :mod:`tomllib`; nothing is evaluated.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path
from typing import Any

from .errors import RodstabInputError, require_finite, require_positive, require_positive_int
from .model import ROTATION_AXES, SUPPORT_KINDS, SUPPORTS, Assembly, Segment
from .sections import make_section

_TOP = {"section", "segment", "weld", "support", "analysis"}
_SECTION = {"shape", "aspect", "nu", "torsion", "b1", "b2", "B3"}
_SEGMENT = {"name", "length", "curvature", "natural_curvature", "natural_twist", "start",
            "angle_deg", "cusp", "section"}
_WELD = {"ends"}
_SUPPORT = {"end", "type", "rotation"}
#: Support type of a ``[[support]]`` table that gives none (a key of ``SUPPORT_KINDS``).
DEFAULT_SUPPORT = "clamped"
_ANALYSIS = {"elements", "reference_load", "load_factor_segment"}


@dataclasses.dataclass(frozen=True)
class Design:
    """A parsed design: the assembly and the analysis settings."""

    assembly: Assembly
    elements: int
    load_factor_segment: str
    source: str
    raw: dict

    def paper_load_factor(self, mu: float) -> float:
        """``lam = B3 kappa_n L / sqrt(B1 B2)`` of ``load_factor_segment`` at load ``mu``."""
        s = self.assembly.segment(self.load_factor_segment)
        return mu * s.B3 * abs(s.natural_curvature) * s.length / math.sqrt(s.B1 * s.B2)


def _check_keys(table: dict, allowed: set[str], where: str) -> None:
    if not isinstance(table, dict):
        raise RodstabInputError(f"{where} must be a table, got {table!r}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise RodstabInputError(f"unknown key(s) {unknown} in {where}; allowed: {sorted(allowed)}")


def _stiffness(spec: dict, where: str) -> tuple[float, float, float]:
    _check_keys(spec, _SECTION, where)
    B3 = require_positive(f"{where}.B3", spec.get("B3", 1.0))
    sec = make_section(spec.get("shape", "circle") if "b1" not in spec else None,
                       aspect=spec.get("aspect"), nu=spec.get("nu", 1 / 3),
                       torsion=spec.get("torsion", "exact"), b1=spec.get("b1"),
                       b2=spec.get("b2"))
    return sec.b1 * B3, sec.b2 * B3, B3


def _end(ref: Any, where: str) -> tuple[str, str]:
    if not isinstance(ref, str) or ref.count(".") != 1:
        raise RodstabInputError(f"{where}: an end is written 'segment.start' or 'segment.end', "
                                f"got {ref!r}")
    name, end = ref.split(".")
    return name, end


def parse_design(data: dict, source: str = "<dict>") -> Design:
    """Build a :class:`Design` from parsed TOML data (see the module docstring)."""
    _check_keys(data, _TOP, "the design file")
    default = data.get("section", {})
    segs_raw = data.get("segment")
    if not segs_raw:
        raise RodstabInputError("the design file needs at least one [[segment]]")
    segments: list[Segment] = []
    for i, raw in enumerate(segs_raw):
        where = f"segment[{i}]"
        _check_keys(raw, _SEGMENT, where)
        if "name" not in raw or "length" not in raw:
            raise RodstabInputError(f"{where} needs 'name' and 'length'")
        spec = dict(default)
        if "section" in raw:
            _check_keys(raw["section"], _SECTION, f"{where}.section")
            spec = dict(raw["section"]) if ("shape" in raw["section"] or "b1" in raw["section"]) \
                else spec | raw["section"]
        B1, B2, B3 = _stiffness(spec, f"{where}.section")
        prev = segments[-1] if segments else None
        if "start" in raw:
            start = raw["start"]
            if not (isinstance(start, list) and len(start) == 2):
                raise RodstabInputError(f"{where}.start must be [x, y], got {start!r}")
            start = (require_finite(f"{where}.start", start[0]),
                     require_finite(f"{where}.start", start[1]))
        else:
            start = tuple(float(v) for v in prev.end_point("end")) if prev else (0.0, 0.0)
        if "angle_deg" in raw:
            if raw.get("cusp"):
                raise RodstabInputError(f"{where}: give either angle_deg or cusp, not both")
            angle = math.radians(require_finite(f"{where}.angle_deg", raw["angle_deg"]))
        elif prev is not None:
            t = prev.tangent(prev.length)
            angle = math.atan2(t[1], t[0]) + (math.pi if raw.get("cusp") else 0.0)
        else:
            angle = 0.0
        k, kn, tw = (require_finite(f"{where}.{key}", raw.get(key, 0.0))
                     for key in ("curvature", "natural_curvature", "natural_twist"))
        segments.append(Segment(name=str(raw["name"]), length=raw["length"], curvature=k,
                                natural_curvature=kn, B1=B1, B2=B2, B3=B3, start=start, angle=angle,
                                natural_twist=tw))
    welds = []
    for i, w in enumerate(data.get("weld", [])):
        _check_keys(w, _WELD, f"weld[{i}]")
        welds.append(tuple(_end(e, f"weld[{i}]") for e in w.get("ends", [])))
    supports, rotations = [], []
    for i, s in enumerate(data.get("support", [])):
        _check_keys(s, _SUPPORT, f"support[{i}]")
        name, end = _end(s.get("end"), f"support[{i}]")
        kind = s.get("type", DEFAULT_SUPPORT)
        if not isinstance(kind, str) or kind not in SUPPORT_KINDS:
            raise RodstabInputError(f"support[{i}].type must be one of {SUPPORTS}, got {kind!r}")
        supports.append((name, end, kind))
        if "rotation" in s:
            rot = s["rotation"]
            if not (isinstance(rot, list) and len(rot) == 3
                    and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                            for v in rot)):
                raise RodstabInputError(f"support[{i}].rotation must be three numbers "
                                        f"[normal, tangent, binormal] in radians, got {rot!r}")
            rotations.append((name, end, (float(rot[0]), float(rot[1]), float(rot[2]))))
    analysis = data.get("analysis", {})
    _check_keys(analysis, _ANALYSIS, "[analysis]")
    elements = require_positive_int("analysis.elements", analysis.get("elements", 32))
    ref = analysis.get("reference_load")
    assembly = Assembly(segments=tuple(segments), welds=tuple(welds), supports=tuple(supports),
                        reference_load=(None if ref is None
                                        else require_finite("analysis.reference_load", ref)),
                        end_rotations=tuple(rotations))
    lf = analysis.get("load_factor_segment", segments[0].name)
    assembly.segment(lf)
    return Design(assembly, elements, lf, source, data)


def load_design(path: str | Path) -> Design:
    """Read and validate a TOML design file."""
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise RodstabInputError(f"cannot read design file {str(p)!r}: {exc.strerror}") from exc
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RodstabInputError(f"design file {str(p)!r} is not valid TOML: {exc}") from exc
    return parse_design(data, str(p))


def set_design_value(data: dict, key: str, value: float) -> dict:
    """Return a copy of ``data`` with the value at the dotted ``key`` replaced.

    Keys: ``section.<k>``, ``analysis.<k>``, ``segment.<name>.<k>`` (a segment by name),
    ``segment.<name>.section.<k>`` or ``support.<i>.rotation.<axis>`` (``i``: the support's
    position in the file from 0; axis: normal, tangent or binormal). The key must name an
    existing value or a known key of that table; anything else raises naming the key.
    """
    import copy

    out = copy.deepcopy(data)
    parts = key.split(".")
    if parts[0] in ("section", "analysis") and len(parts) == 2:
        allowed = _SECTION if parts[0] == "section" else _ANALYSIS
        if parts[1] not in allowed:
            raise RodstabInputError(f"--vary key {key!r}: {parts[1]!r} is not a key of "
                                    f"[{parts[0]}] (allowed: {sorted(allowed)})")
        out.setdefault(parts[0], {})[parts[1]] = value
        return out
    if parts[0] == "segment" and len(parts) in (3, 4):
        segs = [sg for sg in out.get("segment", []) if str(sg.get("name")) == parts[1]]
        if not segs:
            raise RodstabInputError(f"--vary key {key!r}: no segment named {parts[1]!r}")
        if len(parts) == 3:
            if parts[2] not in _SEGMENT - {"name", "start", "cusp", "section"}:
                raise RodstabInputError(f"--vary key {key!r}: {parts[2]!r} cannot be varied")
            segs[0][parts[2]] = value
        else:
            if parts[2] != "section" or parts[3] not in _SECTION:
                raise RodstabInputError(f"--vary key {key!r} is not segment.<name>.section.<k>")
            segs[0].setdefault("section", dict(out.get("section", {})))[parts[3]] = value
        return out
    if parts[0] == "support" and len(parts) == 4 and parts[2] == "rotation":
        sups = out.get("support", [])
        if not parts[1].isdigit() or int(parts[1]) >= len(sups):
            raise RodstabInputError(f"--vary key {key!r}: support index {parts[1]!r} is not one "
                                    f"of 0..{len(sups) - 1} (the [[support]] tables in order)")
        if parts[3] not in ROTATION_AXES:
            raise RodstabInputError(f"--vary key {key!r}: rotation axis {parts[3]!r} is not one "
                                    f"of {ROTATION_AXES}")
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise RodstabInputError(f"--vary key {key!r}: a rotation must be a number of "
                                    f"radians, got {value!r}")
        rot = list(sups[int(parts[1])].get("rotation", [0.0, 0.0, 0.0]))
        rot[ROTATION_AXES.index(parts[3])] = value
        sups[int(parts[1])]["rotation"] = rot
        return out
    raise RodstabInputError(f"--vary key {key!r} must be section.<k>, analysis.<k>, "
                            "segment.<name>.<k>, segment.<name>.section.<k> or "
                            f"support.<i>.rotation.<{'|'.join(ROTATION_AXES)}>")


@dataclasses.dataclass(frozen=True)
class VarySpec:
    """A parsed ``--vary KEY=START:STOP[:N]``.

    ``n`` values of ``key`` from ``start`` to ``stop`` (a sweep), or ``n`` steps from ``start`` to
    ``stop`` (a continuation).
    """

    key: str
    start: float
    stop: float
    n: int


#: The grammar of ``--vary``, as its error messages quote it.
VARY_GRAMMAR = "KEY=START:STOP[:N]"


def _vary_number(spec: str, part: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise RodstabInputError(f"--vary {part} {text.strip()!r} is not a number "
                                f"(in {spec!r}; expected {VARY_GRAMMAR})") from None
    if not math.isfinite(value):
        raise RodstabInputError(f"--vary {part} {text.strip()!r} is not a finite number "
                                f"(in {spec!r})")
    return value


def parse_vary(spec: str, *, default_n: int) -> VarySpec:
    """Parse ``KEY=START:STOP[:N]`` (the ``--vary`` option of ``sweep`` and ``continue``).

    ``KEY`` is non-empty (whether it names a design value is checked where it is used:
    :func:`set_design_value`, :func:`rodstab.nonlinear.parameters.parameter`); ``START`` and
    ``STOP`` are finite numbers; ``N``, a positive integer, defaults to ``default_n``.
    Raises :class:`RodstabInputError` naming the part that is wrong and its text.
    """
    n_default = require_positive_int("default_n", default_n)
    if not isinstance(spec, str) or "=" not in spec:
        raise RodstabInputError(f"--vary must be {VARY_GRAMMAR}, got {spec!r}")
    key, _, rng = spec.partition("=")
    key = key.strip()
    if not key:
        raise RodstabInputError(f"--vary KEY '' is empty: expected {VARY_GRAMMAR}, "
                                f"got {spec!r}")
    parts = rng.split(":")
    if len(parts) not in (2, 3):
        raise RodstabInputError(f"--vary must be {VARY_GRAMMAR}, got {spec!r} "
                                f"({len(parts)} part(s) after '=')")
    start = _vary_number(spec, "START", parts[0])
    stop = _vary_number(spec, "STOP", parts[1])
    if len(parts) == 2:
        return VarySpec(key, start, stop, n_default)
    text = parts[2].strip()
    if not (text.isascii() and text.isdigit()) or int(text) < 1:
        raise RodstabInputError(f"--vary N {text!r} must be a positive integer (in {spec!r})")
    return VarySpec(key, start, stop, int(text))


#: Fewest elements per segment of the nonlinear rod (``rodstab equilibrium``): a design's
#: ``[analysis] elements`` is chosen for the linear engine (Hermite FE, fourth order), the
#: discrete rod converges at second order and needs at least this many.
NONLINEAR_MIN_ELEMENTS = 16
#: Default elements per segment of a continuation (``rodstab continue``).
CONTINUATION_ELEMENTS = 16


def nonlinear_elements(design: Design) -> int:
    """Elements per segment of the nonlinear rod for ``design``: its own, at least 16.

    ``max(design.elements, NONLINEAR_MIN_ELEMENTS)``.
    """
    return max(design.elements, NONLINEAR_MIN_ELEMENTS)
