"""Curved-sided hexagram: six rods welded at cusps, in its four basic states (beyond the paper).

Lu, Leanza, Zhao and Hutchinson, *Multiple equilibrium states of a curved-sided hexagram*: six
identical naturally curved rods of length ``L``, rod ``i``'s end welded to rod ``i + 1``'s start
at a cusp. The closed held states of uniform moment (:mod:`rodstab.states`) include four basic
ones: ``line`` (straight rods folded, the folded 3-loop state of Section 5), ``star`` (120-degree
arcs), ``daisy`` (240 degrees) and ``eight`` (full circles, all welds at one point).

Units: ``B3 = 1``; the load factor is ``mu = kappa_n R0`` with ``R0 = 3 L / (2 pi)`` the star's
arc radius (natural curvature ``1 / R0`` per unit ``mu``), so a state of held curvature ``k``
is stress-free at ``mu = k R0``: 0 (line), 1 (star), 2 (daisy), 3 (eight), the reference load
of its stable interval. The paper's load (5.7) is ``lambda = kappa_n L / sqrt(b1 b2)``.

Two methods: the FE engine on the whole ring (:mod:`rodstab.linear`, Richardson-extrapolated
from :data:`FE_MESHES`) and the exact general solution of P2 on one arc with the cusp joint
map and a Bloch phase per harmonic (:func:`rodstab.transfer.cyclic_ring_interval`).
"""

from __future__ import annotations

import dataclasses
import functools
import math

from ..errors import RodstabInputError, require_positive
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..linear.solve import LinearStability
from ..model import Assembly
from ..numerics import find_roots
from ..results import Result
from ..sections import Section, circle, rectangle
from ..states import ring_assembly
from ..transfer import CyclicRingInterval, cyclic_ring_interval
from ._common import Method, engine

#: Rods of the hexagram.
SEGMENTS = 6
#: The four basic states and each rod's turning ``k L`` (radians).
STATE_TURNING: dict[str, float] = {"line": 0.0, "star": 2 * math.pi / 3,
                                   "daisy": 4 * math.pi / 3, "eight": 2 * math.pi}
STATES = tuple(STATE_TURNING)
#: ``L / R0`` (the star's arc is 120 degrees).
L_OVER_R0 = 2 * math.pi / 3
#: Elements per rod of the linear engine for one solve (e.g. ``rodstab hexagram``'s mode).
DEFAULT_ELEMENTS = 64
#: Meshes (elements per rod) of the FE method: its limits converge as h^4 (Hermite w, quadratic
#: omega; measured: the error falls 15-16x per halving from 16 to 96 elements), so the pair is
#: Richardson-extrapolated with order 4. Measured against the Bloch method at h/t = 4: 3.6e-4
#: at 32 and 2.1e-5 at 64 elements alone (the eight's limits), 6e-8 after extrapolation from
#: 48/96; past ~100 elements per rod round-off grows (the engine flags residuals above 1e-6).
FE_MESHES = (32, 64)
#: Order of the FE error in the mesh size (above).
FE_ORDER = 4
#: Aspect range h/t of the threshold search and of the chart.
ASPECT_RANGE = (1.0, 6.0)
#: Scan intervals of the threshold's bracket over :data:`ASPECT_RANGE`.
THRESHOLD_SCAN = 10
#: The published threshold (Lu et al.): all four states mutually stable for h/t > 3.4, bound
#: by the lower limit of the eight and the upper limit of the line. Not a method: compared.
PUBLISHED_THRESHOLD = 3.4
PUBLISHED_BINDING = ("eight.lower", "line.upper")


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Hexagram: ``section``, ``state`` (one of :data:`STATES`), rod ``length`` L."""

    section: Section = dataclasses.field(default_factory=circle)
    state: str = "star"
    length: float = 1.0

    def __post_init__(self) -> None:
        """Validate: a known state, a positive length."""
        if self.state not in STATE_TURNING:
            raise RodstabInputError(f"state must be one of {STATES}, got {self.state!r}")
        require_positive("length", self.length)

    @property
    def R0(self) -> float:
        """The star's arc radius ``3 L / (2 pi)``."""
        return self.length / L_OVER_R0

    @property
    def reference_load(self) -> float:
        """The state's stress-free ``mu = k R0``."""
        return STATE_TURNING[self.state] / L_OVER_R0


def build(params: Params) -> Assembly:
    """Return the ring of six rods in ``params.state`` (natural curvature ``1/R0`` per unit mu).

    Built by :func:`rodstab.states.ring_assembly`, which the model validates (ends meet at the
    cusps, moments balance); the reference load is the state's stress-free ``mu``.
    """
    s = params.section
    return ring_assembly(SEGMENTS, STATE_TURNING[params.state], weld="cusp",
                         length=params.length, natural_curvature=1.0 / params.R0, B1=s.b1,
                         B2=s.b2, B3=1.0, reference_load=params.reference_load)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``kappa_R0 = mu`` and ``lambda = kappa_n L / sqrt(b1 b2)`` (5.7)."""
    return {"kappa_R0": mu, "lambda": mu * L_OVER_R0 / params.section.sqrt_b1b2}


def engine_stability(params: Params, elements: int = DEFAULT_ELEMENTS,
                     limits: Limits = DEFAULT_LIMITS) -> LinearStability:
    """Stable interval of ``mu = kappa_n R0`` of ``params.state`` by the linear FE engine."""
    return engine(build(params), elements, limits)


def fe_interval(params: Params, limits: Limits = DEFAULT_LIMITS) -> tuple[float, float]:
    """FE stable interval of ``kappa_n R0``, extrapolated from :data:`FE_MESHES` (order 4)."""
    coarse, fine = (engine_stability(params, n, limits).load_factor_interval
                    for n in FE_MESHES)
    r = (FE_MESHES[1] / FE_MESHES[0]) ** FE_ORDER
    return tuple(float(f + (f - c) / (r - 1.0)) if math.isfinite(f) else float(f)
                 for c, f in zip(coarse, fine, strict=True))  # type: ignore[return-value]


def transfer_stability(params: Params) -> CyclicRingInterval:
    """Stable interval of ``kappa_n R0`` by the exact Bloch-reduced arc (second method)."""
    s = params.section
    return cyclic_ring_interval(STATE_TURNING[params.state], L_OVER_R0, s.b1, s.b2, SEGMENTS,
                                "cusp", params.reference_load)


@functools.lru_cache(maxsize=4096)
def transfer_interval(params: Params) -> tuple[float, float]:
    """``(lo, hi)`` of :func:`transfer_stability`.

    Memoized (a pure function of frozen parameters, an immutable result): the threshold's scan,
    the stable-band chart and the report's atlases ask for the same sections (13 of the
    report's 52 atlases were repeats).
    """
    r = transfer_stability(params)
    return r.lo, r.hi


@dataclasses.dataclass(frozen=True)
class Atlas(Result):
    """Stable interval of ``kappa_n R0`` of each basic state and of all four together.

    ``all_four`` is ``None`` when the intervals have no common point.
    """

    states: dict[str, tuple[float, float]]
    all_four: tuple[float, float] | None
    method: str


def atlas(section: Section, method: str = "transfer", limits: Limits = DEFAULT_LIMITS) -> Atlas:
    """Stable intervals of the four states for ``section`` by ``method`` ("transfer" or "fe")."""
    if method not in ("transfer", "fe"):
        raise RodstabInputError(f"method must be 'transfer' or 'fe', got {method!r}")
    out = {}
    for state in STATES:
        p = Params(section=section, state=state)
        out[state] = transfer_interval(p) if method == "transfer" else fe_interval(p, limits)
    lo = max(v[0] for v in out.values())
    hi = min(v[1] for v in out.values())
    return Atlas(states=out, all_four=(lo, hi) if lo < hi else None, method=method)


def overlap_width(atlas_: Atlas) -> float:
    """``min(upper limits) - max(lower limits)``: positive iff all four are mutually stable."""
    return (min(v[1] for v in atlas_.states.values())
            - max(v[0] for v in atlas_.states.values()))


def binding_limits(atlas_: Atlas) -> tuple[str, str]:
    """``("<state>.lower", "<state>.upper")``: the largest lower and the smallest upper limit."""
    lo = max(atlas_.states, key=lambda s: atlas_.states[s][0])
    hi = min(atlas_.states, key=lambda s: atlas_.states[s][1])
    return f"{lo}.lower", f"{hi}.upper"


@dataclasses.dataclass(frozen=True)
class Threshold(Result):
    """Smallest rectangle aspect h/t above which the four states are mutually stable.

    ``kappa_R0``: the one load at which they are at the threshold; ``binding``: the two
    limits that meet there; ``bracket``: the scan interval of h/t in which the root was found.
    """

    aspect_threshold: float
    kappa_R0: float
    binding: tuple[str, str]
    bracket: tuple[float, float]
    nu: float
    torsion: str
    method: str


def threshold(*, nu: float = 1 / 3, torsion: str = "exact", method: str = "transfer",
              aspect_range: tuple[float, float] = ASPECT_RANGE) -> Threshold:
    """Root of :func:`overlap_width` in h/t for rectangles: the package root finder.

    ``find_roots`` scans ``aspect_range`` (:data:`THRESHOLD_SCAN` intervals), brackets each sign
    change and refines it by Brent's method; the threshold is the largest root at which the
    width turns positive (above it the scan finds no other root: all four stay stable together
    up to the range's end). Raises :class:`RodstabInputError` naming the range if the width
    does not turn positive in it.
    """
    def width(aspect: float) -> float:
        sec = rectangle(aspect=aspect, nu=nu, torsion=torsion)
        return overlap_width(atlas(sec, method))

    a, b = aspect_range
    found = find_roots(width, a, b, n_scan=THRESHOLD_SCAN, rel_xtol=1e-12,
                       method_name="scan + Brent on the overlap width")
    if width(b) <= 0 or not found.roots:
        raise RodstabInputError(f"aspect range {aspect_range}: the four states are not all "
                                f"stable together at h/t = {b:g}, or no threshold inside it")
    root = found.roots[-1]
    at = atlas(rectangle(aspect=root.x, nu=nu, torsion=torsion), method)
    return Threshold(aspect_threshold=root.x, kappa_R0=max(v[0] for v in at.states.values()),
                     binding=binding_limits(at), bracket=root.bracket, nu=nu, torsion=torsion,
                     method=f"{method}: {found.method}")


def _limits(interval: tuple[float, float], state: str) -> dict[str, float]:
    return {f"{state}.kappa_R0_lower": interval[0], f"{state}.kappa_R0_upper": interval[1]}


def _fe(params: Params) -> dict[str, float]:
    out: dict[str, float] = {}
    for state in STATES:
        out |= _limits(fe_interval(dataclasses.replace(params, state=state)), state)
    return out


def _transfer(params: Params) -> dict[str, float]:
    out: dict[str, float] = {}
    for state in STATES:
        out |= _limits(transfer_interval(dataclasses.replace(params, state=state)), state)
    return out


#: Methods that solve the hexagram, each returning the stable interval of ``kappa_n R0`` of
#: all four states (``<state>.kappa_R0_lower`` / ``_upper``) for ``params.section``.
METHODS: dict[str, Method] = {"transfer": _transfer, "fe": _fe}
#: How closely each pair must agree (relative above 1, absolute below), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # FE extrapolated from 32/64 elements per rod (order 4): measured <= 2e-7 (circle, h/t 4).
    ("transfer", "fe"): 1e-6,
}


#: Points of the stable-band chart over :data:`ASPECT_RANGE`.
CHART_POINTS = 26


def chart_data(*, nu: float = 1 / 3, torsion: str = "exact", method: str = "transfer",
               n_points: int = CHART_POINTS) -> dict[str, list[float] | dict[str, list[float]]]:
    """Stable bands of ``kappa_n R0`` of the four states against h/t (rectangles).

    Returns ``{"aspect": [...], "<state>.lower": [...], "<state>.upper": [...]}`` for
    ``n_points`` aspects evenly spaced over :data:`ASPECT_RANGE`, by ``method`` (:func:`atlas`).
    """
    aspects = [float(a) for a in
               (ASPECT_RANGE[0] + (ASPECT_RANGE[1] - ASPECT_RANGE[0]) * i / (n_points - 1)
                for i in range(n_points))]
    data: dict[str, list[float]] = {"aspect": aspects}
    for a in aspects:
        at = atlas(rectangle(aspect=a, nu=nu, torsion=torsion), method)
        for state, (lo, hi) in at.states.items():
            data.setdefault(f"{state}.lower", []).append(lo)
            data.setdefault(f"{state}.upper", []).append(hi)
    return data  # type: ignore[return-value]
