"""Curved-sided hexagram: six rods welded at cusps, in its four basic states (beyond the paper).

Lu, Leanza, Zhao and Hutchinson, *Multiple equilibrium states of a curved-sided hexagram*: six
identical naturally curved rods of length ``L``, rod ``i``'s end welded to rod ``i + 1``'s start
at a cusp. The closed held states of uniform moment (:mod:`rodstab.multistable.states`) include four
basic ones: ``line`` (straight rods folded, the folded 3-loop state of Section 5), ``star``
(120-degree arcs), ``daisy`` (240 degrees) and ``eight`` (full circles, all welds at one point).

Units: ``B3 = 1``; the load factor is ``mu = kappa_n R0`` with ``R0 = 3 L / (2 pi)`` the star's
arc radius (natural curvature ``1 / R0`` per unit ``mu``), so a state of held curvature ``k``
is stress-free at ``mu = k R0``: 0 (line), 1 (star), 2 (daisy), 3 (eight), the reference load
of its stable interval. The paper's load (5.7) is ``lambda = kappa_n L / sqrt(b1 b2)``.

Two methods: the FE engine on the whole ring (:mod:`rodstab.linear`, its mesh refined from
:data:`FE_MESHES` to the FE's target error, :func:`rodstab.multistable.atlas.fe_interval`)
and the exact general solution of P2 on one arc with the cusp joint map and a Bloch phase per
harmonic (:func:`rodstab.transfer.cyclic_ring_interval`).
"""

from __future__ import annotations

import dataclasses
import functools
import math

from ..errors import NotConverged, RodstabInputError, require_positive, require_positive_int
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..linear.solve import LinearStability
from ..model import Assembly
from ..multistable import atlas as ring_atlas
from ..multistable.states import HeldState, Ring, uniform_ring
from ..results import Result
from ..sections import Section, circle, rectangle
from ..transfer import CyclicRingInterval
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
#: Starting meshes (elements per rod) of the FE method
#: (:data:`rodstab.multistable.atlas.FE_MESHES`): its limits converge as h^4 (measured: the
#: error falls 15-16x per halving from 16 to 96 elements; against the Bloch method at
#: h/t = 4: 3.6e-4 at 32 and 2.1e-5 at 64 elements, the eight's limits), so the mesh is refined
#: from this pair until the Richardson estimate of each end's error is
#: :data:`rodstab.linear.solve.FE_TARGET_RTOL`.
FE_MESHES = ring_atlas.FE_MESHES
#: Order of the FE error in the mesh size (above).
FE_ORDER = ring_atlas.FE_ORDER
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


def ring(section: Section, length: float = 1.0) -> Ring:
    """Return the six cusp-welded rods of ``section`` (``B3 = 1``, kappa_n = ``mu / R0``)."""
    return uniform_ring(SEGMENTS, weld="cusp", length=length,
                        natural_curvature=L_OVER_R0 / length, B1=section.b1, B2=section.b2,
                        B3=1.0)


def _held_state(rg: Ring, state: str) -> HeldState:
    """Return the ring's held state called ``state`` (:func:`..multistable.atlas.select_states`)."""
    return ring_atlas.select_states(rg, (state,))[0]


def build(params: Params) -> Assembly:
    """Return the ring of six rods in ``params.state`` (natural curvature ``1/R0`` per unit mu).

    :meth:`rodstab.multistable.states.Ring.held` of :func:`ring`, which the model validates (ends
    meet at the cusps, moments balance); the reference load is the state's stress-free ``mu``.
    """
    return ring(params.section, params.length).held(STATE_TURNING[params.state],
                                                    reference_load=params.reference_load)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``kappa_R0 = mu`` and ``lambda = kappa_n L / sqrt(b1 b2)`` (5.7)."""
    return {"kappa_R0": mu, "lambda": mu * L_OVER_R0 / params.section.sqrt_b1b2}


def engine_stability(params: Params, elements: int = DEFAULT_ELEMENTS,
                     limits: Limits = DEFAULT_LIMITS) -> LinearStability:
    """Stable interval of ``mu = kappa_n R0`` of ``params.state`` by the linear FE engine."""
    return engine(build(params), elements, limits)


def fe_interval(params: Params, limits: Limits = DEFAULT_LIMITS) -> tuple[float, float]:
    """FE stable interval of ``kappa_n R0`` (:func:`..multistable.atlas.fe_interval`, order 4)."""
    rg = ring(params.section, params.length)
    return ring_atlas.fe_interval(rg, _held_state(rg, params.state), limits).interval


def transfer_stability(params: Params) -> CyclicRingInterval:
    """Stable interval of ``kappa_n R0`` by the exact Bloch-reduced arc (second method)."""
    return ring_atlas.bloch_interval(ring(params.section, params.length),
                                     STATE_TURNING[params.state])


@functools.lru_cache(maxsize=4096)
def transfer_interval(params: Params) -> tuple[float, float]:
    """``(lo, hi)`` of :func:`transfer_stability`.

    Memoized (a pure function of frozen parameters, an immutable result): the threshold's scan,
    the stable-band chart and the report's atlases ask for the same sections (13 of the
    report's 52 atlases were repeats).
    """
    r = transfer_stability(params)
    if not r.converged:
        raise NotConverged(f"hexagram {params.state}: {r.reason}")
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
    if method not in ring_atlas.METHODS:
        raise RodstabInputError(f"method must be 'transfer' or 'fe', got {method!r}")
    rg = ring(section)
    out = {s.label: ring_atlas.state_interval(rg, s, method, limits).interval
           for s in ring_atlas.select_states(rg, STATES)}
    both = ring_atlas.best_overlap(out, len(out))
    return Atlas(states=out, all_four=both.load_interval if both.width > 0 else None,
                 method=method)


def overlap_width(atlas_: Atlas) -> float:
    """``min(upper limits) - max(lower limits)``: positive iff all four are mutually stable."""
    return ring_atlas.best_overlap(atlas_.states, len(atlas_.states)).width


def binding_limits(atlas_: Atlas) -> tuple[str, str]:
    """``("<state>.lower", "<state>.upper")``: the largest lower and the smallest upper limit."""
    return ring_atlas.best_overlap(atlas_.states, len(atlas_.states)).binding


def rectangle_atlas(values: list[float], *, nu: float = 1 / 3, torsion: str = "exact",
                    method: str = "transfer", ks: tuple[int, ...] | None = None
                    ) -> ring_atlas.RingAtlas:
    """:func:`..multistable.atlas.ring_atlas` of the four states over rectangles' h/t ``values``.

    ``ks``: the numbers of mutually stable states whose h/t ranges are solved for (default
    all; each range end costs a root search).
    """
    return ring_atlas.ring_atlas(lambda a: ring(rectangle(aspect=a, nu=nu, torsion=torsion)),
                                 values, STATES, key="h/t", method=method, ks=ks)


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


def _grid(lo: float, hi: float, n_points: int) -> list[float]:
    return [float(lo + (hi - lo) * i / (n_points - 1)) for i in range(n_points)]


def threshold(*, nu: float = 1 / 3, torsion: str = "exact", method: str = "transfer",
              aspect_range: tuple[float, float] = ASPECT_RANGE) -> Threshold:
    """Root of :func:`overlap_width` in h/t for rectangles: the start of the atlas's range.

    :func:`rectangle_atlas` on :data:`THRESHOLD_SCAN` intervals of ``aspect_range``; its
    range of four mutually stable states (each end in the grid refined by Brent, the package
    root finder) must reach the range's end: the threshold is where it begins. Raises
    :class:`RodstabInputError` naming the range if the four are not all stable together at
    its end or are so everywhere in it.
    """
    a, b = aspect_range
    at = rectangle_atlas(_grid(a, b, THRESHOLD_SCAN + 1), nu=nu, torsion=torsion,
                         method=method, ks=(len(STATES),))
    four = at.coexistence[0]
    last = four.ranges[-1] if four.ranges else None
    if last is None or last[1] != at.values[-1] or four.brackets[-1][0] is None:
        raise RodstabInputError(f"aspect range {aspect_range}: the four states are not all "
                                f"stable together at h/t = {b:g}, or no threshold inside it")
    root, bracket = last[0], four.brackets[-1][0]
    there = atlas(rectangle(aspect=root, nu=nu, torsion=torsion), method)
    both = ring_atlas.best_overlap(there.states, len(STATES))
    return Threshold(aspect_threshold=root, kappa_R0=both.load_interval[0],
                     binding=both.binding, bracket=bracket, nu=nu, torsion=torsion,
                     method=f"{method}: grid of {THRESHOLD_SCAN} intervals + Brent on the "
                            "overlap width")


def _limits(interval: tuple[float, float], state: str) -> dict[str, float]:
    return {f"{state}.kappa_R0_lower": interval[0], f"{state}.kappa_R0_upper": interval[1]}


def _by(method: str) -> Method:
    def solve(params: Params) -> dict[str, float]:
        out: dict[str, float] = {}
        for state, interval in atlas(params.section, method).states.items():
            out |= _limits(interval, state)
        return out
    return solve


#: Methods that solve the hexagram, each returning the stable interval of ``kappa_n R0`` of
#: all four states (``<state>.kappa_R0_lower`` / ``_upper``) for ``params.section``.
METHODS: dict[str, Method] = {"transfer": _by("transfer"), "fe": _by("fe")}
#: How closely each pair must agree (relative above 1, absolute below), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # FE refined to an estimated 2.5e-7 (relative); the differential test's cusp rings of
    # 3-10 rods, every section shape: <= 1.4e-7 (seed 0).
    ("transfer", "fe"): 1e-6,
}


#: Points of the stable-band chart over :data:`ASPECT_RANGE`.
CHART_POINTS = 26


def chart_data(*, nu: float = 1 / 3, torsion: str = "exact", method: str = "transfer",
               n_points: int = CHART_POINTS) -> dict[str, list[float]]:
    """Stable bands of ``kappa_n R0`` of the four states against h/t (rectangles).

    Returns ``{"aspect": [...], "<state>.lower": [...], "<state>.upper": [...]}`` for
    ``n_points`` aspects evenly spaced over :data:`ASPECT_RANGE`, by ``method``
    (:func:`rectangle_atlas`), and the h/t ranges of all four mutually stable
    (``"all_stable.start"``, ``"all_stable.end"``; each end between grid values a root, as
    :func:`threshold`'s).
    """
    bands = rectangle_atlas(_grid(*ASPECT_RANGE, n_points), nu=nu, torsion=torsion,
                            method=method, ks=(len(STATES),)).bands()
    return {"aspect": bands.pop("value"), **bands}


# ---------------------------------------------------------------- with contact (issue 21)
#: Elements per rod of the limits with contact (:func:`contact_atlas`). Measured at h/t = 4
#: against 48: the line's upper limit (rod engine) 2.2734 / 2.2730 at 24 / 32, the eight's
#: lower (FE, lobes' heights) 1.4118 / 1.4131 at 24 / 48.
CONTACT_ELEMENTS = 24


@dataclasses.dataclass(frozen=True)
class ContactAtlas(Result):
    """Stable intervals of ``kappa_n R0`` of the four states with contact at zero gap.

    ``states``: each state's interval with contact (a side that cannot bind, listed in
    ``skipped``, keeps its no-contact value); ``no_contact``: the intervals without;
    ``layers``: how each state's layers were chosen, or that nothing touches; ``all_four``: the
    common part (``None`` when empty), bound by ``binding``; ``elements``: the mesh of the
    cone limits (per rod).
    """

    states: dict[str, tuple[float, float]]
    no_contact: dict[str, tuple[float, float]]
    layers: dict[str, str]
    skipped: tuple[str, ...]
    all_four: tuple[float, float] | None
    binding: tuple[str, str]
    width: float
    elements: int
    method: str


def contact_atlas(section: Section, elements: int = CONTACT_ELEMENTS) -> ContactAtlas:
    """Return the four states' stable intervals with contact at zero gap, every perturbation.

    A state whose rods touch nowhere at zero thickness (the star, the daisy: only at their
    welds) keeps its interval (:func:`transfer_interval`). A stacked state (the line on the
    hexagon, the eight's lobes in flat layers: :func:`..multistable.cone.default_layers`)
    gets the limits with contact of :func:`..multistable.cone_limit.limits_with_contact` on
    ``elements`` per rod, for the sides that can bind: contact only widens an interval, so a
    lower limit already below an untouched state's lower limit (or an upper above an untouched
    upper) cannot bind, is not searched, and is listed in ``skipped``. Raises
    :class:`NotConverged` (exit 3) if a side that can bind is not bracketed.
    """
    from ..multistable.cone import default_layers, touching_pairs
    from ..multistable.cone_limit import limits_with_contact

    n = require_positive_int("elements", elements)
    free = {s: transfer_interval(Params(section=section, state=s)) for s in STATES}
    stacked, how = {}, {}
    for s in STATES:
        a = build(Params(section=section, state=s))
        layers, why = default_layers(a)
        if touching_pairs(a, layers, n):
            stacked[s], how[s] = (a, layers), why
        else:
            how[s] = "no rods lie on one another at zero thickness: unchanged"
    lo_free = max((free[s][0] for s in STATES if s not in stacked), default=-math.inf)
    hi_free = min((free[s][1] for s in STATES if s not in stacked), default=math.inf)
    out, skipped = dict(free), []
    for s, (a, layers) in stacked.items():
        lo, hi = free[s]
        sides = tuple(side for side, can in (("lower", lo > lo_free), ("upper", hi < hi_free))
                      if can)
        skipped += [f"{s}.{side}" for side in ("lower", "upper") if side not in sides]
        if not sides:
            continue
        lim = limits_with_contact(a, layers, n, sides=sides)
        ends = []
        for side, nc in (("lower", lo), ("upper", hi)):
            found = getattr(lim, side)
            if side not in sides:
                ends.append(nc)
            elif found is None or found.status != "bracketed":
                raise NotConverged(f"hexagram {s}, b1 = {section.b1:.6g}, b2 = {section.b2:.6g}: "
                                   f"the {side} limit with "
                                   f"contact is not bracketed ("
                                   f"{'no limit' if found is None else found.message})")
            else:
                ends.append(found.load_factor)
        out[s] = (ends[0], ends[1])
    both = ring_atlas.best_overlap(out, len(out))
    return ContactAtlas(
        states=out, no_contact=free, layers=how, skipped=tuple(skipped),
        all_four=both.load_interval if both.width > 0 else None, binding=both.binding,
        width=both.width, elements=n,
        method=f"limits with contact at zero gap, {n} el./rod (the FE where every touching "
               "normal is a height, else the rod engine); untouched states by the exact arc")


#: The threshold with contact is refined to this in h/t (each width costs a cone search; the
#: limits' own mesh error, ~1e-3 relative at :data:`CONTACT_ELEMENTS`, is larger).
CONTACT_ASPECT_XTOL = 1e-4


@functools.lru_cache(maxsize=256)
def _contact_width(aspect: float, nu: float, torsion: str, elements: int) -> float:
    """Overlap width of :func:`contact_atlas` for a rectangle (memoized: scan and Brent)."""
    return contact_atlas(rectangle(aspect=aspect, nu=nu, torsion=torsion), elements).width


def contact_threshold(*, nu: float = 1 / 3, torsion: str = "exact",
                      elements: int = CONTACT_ELEMENTS,
                      aspect_range: tuple[float, float] = ASPECT_RANGE) -> Threshold:
    """Smallest rectangle h/t above which the four states are mutually stable with contact.

    As :func:`threshold`, on the overlap width of :func:`contact_atlas` (limits with contact
    at zero gap, ``elements`` per rod): scanned on :data:`THRESHOLD_SCAN` intervals of
    ``aspect_range``, the last sign change refined by Brent (the package root finder). Raises
    :class:`RodstabInputError` naming the range if the four are not stable together at its end
    or are so everywhere in it.
    """
    from ..numerics import refine_root

    n = require_positive_int("elements", elements)
    grid = _grid(*aspect_range, THRESHOLD_SCAN + 1)
    widths = [_contact_width(a, nu, torsion, n) for a in grid]
    if widths[-1] <= 0 or all(w > 0 for w in widths):
        raise RodstabInputError(f"aspect range {aspect_range}: the four states with contact are "
                                f"not all stable together at h/t = {grid[-1]:g}, or are so "
                                "everywhere in it: no threshold inside it")
    k = max(i for i in range(len(grid) - 1) if widths[i] <= 0 < widths[i + 1])
    root = refine_root(lambda a: _contact_width(a, nu, torsion, n), grid[k], grid[k + 1],
                       rel_xtol=CONTACT_ASPECT_XTOL / (grid[k + 1] - grid[k]))
    there = contact_atlas(rectangle(aspect=root, nu=nu, torsion=torsion), n)
    lower = there.states[there.binding[0].split(".")[0]][0]  # the binding lower limit
    return Threshold(aspect_threshold=root, kappa_R0=lower, binding=there.binding,
                     bracket=(grid[k], grid[k + 1]), nu=nu, torsion=torsion,
                     method=f"with contact at zero gap ({there.method}): grid of "
                            f"{THRESHOLD_SCAN} intervals + Brent on the overlap width")
