"""Stacked states free of interpenetration, with a stated layer order (issue 21, part 2).

The stacked states (N-loop rings, Sec. 3.1; bi-rod, Sec. 4; folded ring, Sec. 5; the
hexagram's line) are held with coincident centrelines. Here each is *constructed* as a state of
the same :class:`~rodstab.nonlinear.discrete.DiscreteRod` with its rods (capsules of radius
``h / 2``, :mod:`rodstab.nonlinear.contact`) ``h + g0`` apart, and checked with the contact
model. Nothing is relaxed yet.

N-loop ring, wound (:func:`torus_curve`, :func:`stack_loops`). Layers that never swap cannot
close: the last loop would come back from the top layer to the bottom one through the others.
Here the layers wind round one another once (the ring wound round itself; its ribbon links
``-(N - 1)`` times: the one-loop ring folds instead into flat layers that swap,
:mod:`.folding`), on the ``(N, 1)`` torus curve ``r(phi) = ((R + a cos psi) cos phi, (R +
a cos psi) sin phi, a sin psi)``, ``psi = phi / N``, ``0 <= phi < 2 pi N``: at one azimuth the
strands sit on a regular ``N``-gon of circumradius ``a`` across the ring, ``2 a sin(pi m / N)``
apart (``m`` strands round). Points at ``phi`` and ``phi + 2 pi m + delta`` are apart by
(``rho = R + a cos psi``, ``psi' = psi + (2 pi m + delta) / N``)
``D^2 = 4 a^2 sin^2(pi m / N + delta / 2N) + 4 rho(psi) rho(psi') sin^2(delta / 2)``, whose
slope at ``delta = 0``, ``(2 a^2 / N) sin(2 pi m / N)``, is not zero for ``N >= 3``: the strands
are inclined and come nearer off the meridian plane, by ``D_mer^2 - D_min^2 = a^4 sin^2(2 pi m
/ N) / (N^2 (R^2 - 2 R a cos(pi m / N))) (1 + O(a / R))`` (none for ``m = N / 2``).
:func:`strand_distance` minimises ``D`` exactly (Newton in ``delta``, golden section in ``psi``,
every ``m``) and ``a`` is scaled until that minimum is ``h + g0``: ``a = (h + g0) / (2 sin(pi /
N)) (1 + O(a^2 / N^2 R^2))``. The length, from ``|r'|^2 = rho^2 + a^2 / N^2``, is ``N
int_0^2pi sqrt((R + a cos psi)^2 + a^2 / N^2) dpsi = 2 pi N R + pi a^2 / (N sqrt(R^2 - a^2)) +
O(a^4)``: ``R`` is lowered until it is exactly ``L``. With ``eps = a / R`` (series derived
symbolically), ``int kappa^2 ds = (2 pi N / R)(1 + eps^2 / 2 - 2 eps^2 / N^2 + eps^2 / N^4)``
(radial modulation, inclination, out-of-plane wave), so at length ``L`` (``R = R0 (1 - eps^2 /
2N^2)``, ``R0 = L / 2 pi N``) an isotropic rod's bending energy exceeds the coincident loops'
``B L / 2 R0^2`` by the fraction ``c (a / R0)^2``, ``c = (N^2 - 1)(N^2 - 2) / 2 N^4``
(:func:`bending_excess_coefficient`): ``O((h / L)^2)``. Torsion is ``O(a / N R^2)``.

Other folds (:func:`stack_layers`): each rod is offset from its planar centreline by a layer
``k`` (``k (h + g0) e3``) or an offset ``(u, k)`` (``u`` along its in-plane normal). Where a weld
joins different offsets, both rods run to the weld's mean offset along C2 ramps (quintic
smoothstep: level at both ends, so the weld's tangents and frames stay planar) of length
:data:`RAMP_FRACTION` of the contact exclusion distance (past it, the rods of a cusp are a full
spacing apart). An order that interpenetrates raises :class:`StackingError` naming the rods,
where, and the welds whose ramps cross other layers.

Folded ring of Sec. 5 (``2n`` straight rods on ``[0, L]``; cusps ``i, i + 1`` at ``x = L`` for
odd ``i``, at ``x = 0`` for even ``i`` and ``2n, 1``). Offsets along ``e3`` alone, plan kept,
cannot hold it in any order: every cusp lies where all ``2n`` rods are, so its two rods must be
adjacent layers, and the ``2n`` cusps form a cycle, which a path of ``2n`` layers (``2n - 1``
adjacent pairs) cannot hold. The traversal order (:func:`~.states.ring_of` runs 1, 2n, ..., 2:
rod 1's natural curvature is negative) fails at cusp ``1.end - 2.end`` (``x = L``, layers 0 and
``2n - 1``). What holds is the torus curve's cross-section: rod ``i`` (traversal order) at
vertex ``i`` of a regular ``2n``-gon of circumradius ``(h + g0) / (2 sin(pi / 2n))``
(:func:`~.layer_orders.polygon_offsets`), every cusp joining neighbouring vertices. Likewise
the hexagram's line; its star needs only layers 0, 1 alternating
(:func:`~.layer_orders.traversal_layers`). Not built: the eight, whose welds meet where its
lobes touch, need a braid (:func:`.cone.check_lobes`): each of its rods is a full circle, so
no rigid offset per rod keeps its two ends apart. :mod:`.braid` builds one.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any

import numpy as np

from ..errors import NotConverged, RodstabInputError, require_positive, require_positive_int
from ..nonlinear.contact import (
    ContactModel,
    Interpenetration,
    candidate_pairs,
    contact_energy,
    mesh_of_rod,
    segment_distance,
)
from ..nonlinear.discrete import DiscreteRod
from ..numerics import golden_min
from ..results import Result, jsonable
from .states import ring_of

#: Relative tolerance of the fixed points setting the torus curve's ``a`` and ``R``.
TORUS_RTOL = 1e-13
TORUS_MAX_ITER = 60
#: Quadrature points per loop (trapezoid rule on a periodic analytic integrand: spectral).
QUAD_POINTS = 512
#: Points per loop of the table that inverts the torus curve's arclength.
ARCLENGTH_POINTS = 8192
#: Planar nodes of an N-loop ring must lie on one circle to this fraction of its radius.
ON_CIRCLE_RTOL = 1e-8
#: Ramp length at a weld joining different offsets / the exclusion distance ``exclusion_factor
#: (h + dhat)``: at half of it the rods of a cusp are a spacing apart where they first interact.
RAMP_FRACTION = 0.5
#: Chord allowance of :func:`stack_loops` as a multiple of the chord error bound.
CHORD_MARGIN = 1.05
#: ``dhat / h`` of the checks' contact model (the rule of ``ContactModel``).
DHAT_FRACTION = 0.1


class StackingError(RodstabInputError):
    """A stacked state interpenetrates: the stated layer order is impossible as constructed."""


# ---------------------------------------------------------------- the (N, 1) torus curve
def torus_point(phi: np.ndarray, loops: int, R: float, a: float) -> np.ndarray:
    """Points ``(k, 3)`` of the ``(N, 1)`` torus curve at parameters ``phi`` (k,), length units."""
    phi = np.asarray(phi, float)
    rho = R + a * np.cos(phi / loops)
    return np.stack([rho * np.cos(phi), rho * np.sin(phi), a * np.sin(phi / loops)], axis=-1)


def _derivatives(phi: np.ndarray, N: int, R: float, a: float
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """First three derivatives ``(k, 3)`` of :func:`torus_point` in ``phi``."""
    psi = phi / N
    c, s, cp, sp_ = np.cos(phi), np.sin(phi), np.cos(psi), np.sin(psi)
    rho, r1, r2, r3 = R + a * cp, -a * sp_ / N, -a * cp / N**2, a * sp_ / N**3
    # (rho e_r)' = rho' e_r + rho e_phi, e_r' = e_phi, e_phi' = -e_r
    d1 = np.stack([r1 * c - rho * s, r1 * s + rho * c, a * cp / N], axis=-1)
    d2 = np.stack([(r2 - rho) * c - 2 * r1 * s, (r2 - rho) * s + 2 * r1 * c,
                   -a * sp_ / N**2], axis=-1)
    d3 = np.stack([(r3 - 3 * r1) * c - (3 * r2 - rho) * s, (r3 - 3 * r1) * s
                   + (3 * r2 - rho) * c, -a * cp / N**3], axis=-1)
    return d1, d2, d3


def curvature_torsion(phi: np.ndarray, loops: int, R: float, a: float
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Curvature (1/length) and torsion (1/length) of the torus curve at ``phi`` (k,)."""
    d1, d2, d3 = _derivatives(np.asarray(phi, float), loops, R, a)
    cr = np.cross(d1, d2)
    sp_ = np.linalg.norm(d1, axis=1)
    ncr2 = np.einsum("ij,ij->i", cr, cr)
    return np.sqrt(ncr2) / sp_**3, np.einsum("ij,ij->i", cr, d3) / ncr2


def _loop_grid(N: int, per_loop: int) -> np.ndarray:
    return np.arange(N * per_loop) * (2 * math.pi / per_loop)


def torus_length(loops: int, R: float, a: float) -> float:
    """Length of the torus curve: ``N int_0^2pi sqrt((R + a cos psi)^2 + a^2/N^2) dpsi``."""
    psi = np.arange(QUAD_POINTS) * (2 * math.pi / QUAD_POINTS)
    speed = np.sqrt((R + a * np.cos(psi)) ** 2 + (a / loops) ** 2)
    return float(loops * speed.mean() * 2 * math.pi)  # trapezoid = mean on a period


def bending_integral(loops: int, R: float, a: float) -> float:
    """``int kappa^2 ds`` over the whole torus curve (1/length)."""
    phi = _loop_grid(loops, QUAD_POINTS)
    k, _ = curvature_torsion(phi, loops, R, a)
    speed = np.linalg.norm(_derivatives(phi, loops, R, a)[0], axis=1)
    return float(np.mean(k**2 * speed) * 2 * math.pi * loops)


def _strand_d2(psi: np.ndarray, delta: np.ndarray, m: int, N: int, R: float, a: float
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``D^2`` of the module doc and its first two derivatives in ``delta``."""
    u = math.pi * m / N + delta / (2 * N)
    q = psi + (2 * math.pi * m + delta) / N
    rho0, rho1 = R + a * np.cos(psi), R + a * np.cos(q)
    r1, r2 = -a * np.sin(q) / N, -a * np.cos(q) / N**2
    cd, sd = np.cos(delta), np.sin(delta)
    f = 2 * a * a * (1 - np.cos(2 * u)) + 2 * rho0 * rho1 * (1 - cd)
    f1 = 2 * a * a * np.sin(2 * u) / N + 2 * rho0 * (r1 * (1 - cd) + rho1 * sd)
    f2 = 2 * a * a * np.cos(2 * u) / N**2 + 2 * rho0 * (r2 * (1 - cd) + 2 * r1 * sd + rho1 * cd)
    return f, f1, f2


def _nearest_over_delta(psi: np.ndarray, m: int, N: int, R: float, a: float) -> np.ndarray:
    """``min_delta D^2`` at each ``psi`` (Newton from the meridian plane, ``delta = 0``)."""
    delta = np.zeros_like(psi)
    for _ in range(30):
        _, f1, f2 = _strand_d2(psi, delta, m, N, R, a)
        step = f1 / f2  # f2 ~ 2 R^2 > 0 near delta = 0: a convex minimum
        delta = delta - step
        if np.max(np.abs(step)) < 1e-15:
            break
    return _strand_d2(psi, delta, m, N, R, a)[0]


def _nearest_at(psi: float, m: int, N: int, R: float, a: float) -> float:
    return float(_nearest_over_delta(np.array([psi]), m, N, R, a)[0])


def strand_distance(loops: int, R: float, a: float, m: int | None = None) -> float:
    """Return the true smallest 3D distance between two strands of the torus curve (length).

    Minimises ``D`` of the module doc over ``delta`` (Newton) and ``psi`` (grid, then a
    golden-section refinement), for the strands ``m`` apart round the ``N``-gon (every
    ``m = 1 .. N - 1`` when ``m`` is None). ``inf`` for one loop.
    """
    N = require_positive_int("loops", loops)
    ms = range(1, N) if m is None else [m]
    best = math.inf
    grid = np.arange(720) * (2 * math.pi / 720)
    for mm in ms:
        g = _nearest_over_delta(grid, mm, N, R, a)
        k = int(np.argmin(g))
        f = functools.partial(_nearest_at, m=mm, N=N, R=R, a=a)
        _, fmin = golden_min(f, grid[k] - 2 * math.pi / 720, grid[k] + 2 * math.pi / 720, 1e-10)
        best = min(best, math.sqrt(max(min(fmin, float(g[k])), 0.0)))
    return best


@dataclasses.dataclass(frozen=True)
class TorusCurve(Result):
    """The ``(N, 1)`` torus curve of an N-loop ring of length ``L`` stacked at spacing ``d``.

    Attributes
    ----------
    loops, length, spacing : int, float, float
        ``N``, ``L`` and ``d = h + g0`` (length).
    R, a : float
        Major radius (set so that the length is ``L``) and the strands' circumradius (set so
        that the nearest strands are ``d`` apart in 3D), length.
    R0 : float
        Radius of the coincident loops, ``L / 2 pi N``.
    meridian_distance : float
        ``2 a sin(pi / N)``: the neighbours' distance at one azimuth (>= ``d``).
    strand_distance : float
        True smallest distance between strands (``d`` to :data:`TORUS_RTOL`).
    length_check : float
        Length of the curve recomputed at ``R, a`` (``L``).
    length_excess_at_R0 : float
        What the curve at ``R0`` would add to ``L``: ``pi a^2 / (N sqrt(R0^2 - a^2))`` to
        leading order.
    curvature_max, torsion_max : float
        Largest curvature and |torsion| (1/length).
    bending_excess : float
        ``int kappa^2 ds / (L / R0^2) - 1``: the relative bending energy above the
        coincident state for an isotropic rod.
    """

    loops: int
    length: float
    spacing: float
    R: float
    a: float
    R0: float
    meridian_distance: float
    strand_distance: float
    length_check: float
    length_excess_at_R0: float
    curvature_max: float
    torsion_max: float
    bending_excess: float


def fit_spacing(distance: Any, length: Any, target: float, L: float, a: float, R: float,
                rtol: float, max_iter: int, who: str) -> tuple[float, float]:
    """Scale a stacked curve's spacing ``a`` and radius ``R`` so ``distance(a, R) = target``.

    ... and ``length(a, R) = L``: fixed point ``a <- a target / distance``, ``R <- R L /
    length`` (each scales so to leading order), to ``rtol``; else NotConverged naming ``who``.
    """
    for _ in range(max_iter):
        a_new = a * target / distance(a, R)
        R_new = R * L / length(a_new, R)
        done = abs(a_new - a) <= rtol * a and abs(R_new - R) <= rtol * R
        a, R = a_new, R_new
        if done:
            return a, R
    raise NotConverged(f"{who}: spacing and radius not fixed to {rtol:g} in {max_iter} "
                       "iterations")


def torus_curve(loops: int, length: float, thickness: float, gap: float) -> TorusCurve:
    """Return the torus curve of an N-loop ring: ``R``, ``a`` and the checks (module doc).

    Parameters
    ----------
    loops : int
        ``N >= 1`` (one loop: ``a = 0``, the planar circle).
    length : float
        Total length ``L`` of the ring (length).
    thickness : float
        ``h``: capsule diameter (length), the out-of-plane height of the section.
    gap : float
        ``g0 > 0``: gap left between neighbouring capsules (length).

    Returns
    -------
    TorusCurve
        Raises :class:`~rodstab.errors.RodstabInputError` when ``a`` is not small against
        ``R`` (the strands would not fit: ``a >= R0 / 4``).
    """
    N = require_positive_int("loops", loops)
    L = require_positive("length", length)
    h = require_positive("thickness", thickness)
    g0 = require_positive("gap", gap)
    d = h + g0
    R0 = L / (2 * math.pi * N)
    if N == 1:  # nothing to stack
        return TorusCurve(1, L, d, R0, 0.0, R0, math.inf, math.inf, L, 0.0, 1 / R0, 0.0, 0.0)
    a = d / (2 * math.sin(math.pi / N))
    if a >= 0.25 * R0:
        raise RodstabInputError(f"thickness + gap = {d:g} too large for {N} loops of radius "
                                f"{R0:g}: strand circumradius {a:g} >= R0 / 4")
    a, R = fit_spacing(lambda a, R: strand_distance(N, R, a),
                       lambda a, R: torus_length(N, R, a), d, L, a, R0, TORUS_RTOL,
                       TORUS_MAX_ITER, f"torus_curve (N = {N}, a / R0 = {a / R0:.3g})")
    phi = _loop_grid(N, QUAD_POINTS)
    k, tau = curvature_torsion(phi, N, R, a)
    return TorusCurve(
        loops=N, length=L, spacing=d, R=R, a=a, R0=R0,
        meridian_distance=2 * a * math.sin(math.pi / N),
        strand_distance=strand_distance(N, R, a), length_check=torus_length(N, R, a),
        length_excess_at_R0=torus_length(N, R0, a) - L, curvature_max=float(k.max()),
        torsion_max=float(np.abs(tau).max()),
        bending_excess=bending_integral(N, R, a) / (L / R0**2) - 1.0)


def bending_excess_coefficient(loops: int) -> float:
    """``c = (N^2 - 1)(N^2 - 2) / 2 N^4``: bending excess ``~ c (a / R0)^2`` (module doc)."""
    N = require_positive_int("loops", loops)
    return (N * N - 1) * (N * N - 2) / (2.0 * N**4)


def default_model(thickness: float) -> ContactModel:
    """Contact model of the checks: capsules of radius ``h / 2``, ``dhat = 0.1 h``.

    The stiffness does not enter a check (only gaps and the model's refusal do).
    """
    h = require_positive("thickness", thickness)
    return ContactModel.from_thickness(h, dhat=DHAT_FRACTION * h, stiffness=1.0)


def _where(rod: DiscreteRod, e: int) -> str:
    """``segment 'name' at s = ...`` for edge ``e`` (its midpoint's arclength)."""
    mine = np.flatnonzero(rod.edge_segment == rod.edge_segment[e])
    seg = rod.assembly.segments[int(rod.edge_segment[e])]
    return f"segment {seg.name!r} at s = {(e - mine[0] + 0.5) * seg.length / len(mine):.4g}"


def _pair_gaps(rod: DiscreteRod, model: ContactModel) -> tuple[np.ndarray, np.ndarray]:
    """Non-excluded element pairs within the broad phase's reach (k, 2) and their gaps (k,)."""
    mesh = mesh_of_rod(rod, model)
    P = candidate_pairs(mesh, rod.x)
    P = P[~mesh.excluded_elements(P[:, 0], P[:, 1])]
    E, x = mesh.edges, rod.x
    return P, segment_distance(x[E[P[:, 0], 0]], x[E[P[:, 0], 1]], x[E[P[:, 1], 0]],
                               x[E[P[:, 1], 1]]) - mesh.radius[P[:, 0]] - mesh.radius[P[:, 1]]


@dataclasses.dataclass(frozen=True)
class ContactCheck(Result):
    """Gaps of a stacked state under the contact model (non-excluded element pairs).

    Attributes
    ----------
    min_gap : float
        Smallest capsule gap ``d - r_a - r_b`` (length; ``inf`` if no pair is within reach).
    where : str
        The two elements where it is reached (segment and arclength of each).
    required : float
        ``g0 - tolerance`` (length): the gap the construction promises, less its chord error.
    holds : bool
        ``min_gap >= required``.
    pairs : int
        Non-excluded element pairs within the broad phase's reach.
    energy : float
        :func:`~rodstab.nonlinear.contact.contact_energy` at the state (it did not raise).
    """

    min_gap: float
    where: str
    required: float
    holds: bool
    pairs: int
    energy: float


def check_stacked(rod: DiscreteRod, model: ContactModel, gap: float,
                  tolerance: float = 0.0) -> ContactCheck:
    """Check a stacked state with the contact model; raise :class:`StackingError` if it fails.

    ``rod``: the state (``rod.x``, lab frame); ``model``: capsule radii, exclusions, barrier
    (:func:`default_model`); ``gap``: the ``g0`` aimed at and ``tolerance`` its stated error
    (chord error), both lengths. Raises :class:`StackingError` naming the two segments and
    where, if two non-excluded capsules overlap or the contact model refuses the state.
    """
    P, g = _pair_gaps(rod, model)
    k = int(np.argmin(g)) if len(g) else -1
    where = f"{_where(rod, int(P[k, 0]))} and {_where(rod, int(P[k, 1]))}" if len(g) else \
        "no pair within reach"
    g_min = float(g[k]) if len(g) else math.inf
    if g_min <= 0.0:
        raise StackingError(f"the stacked state interpenetrates: {where} overlap by "
                            f"{-g_min:.4g} (gap {g_min:.4g} <= 0)")
    try:
        energy = contact_energy(mesh_of_rod(rod, model), rod.x)[0]
    except Interpenetration as exc:
        raise StackingError(f"the contact model refuses the stacked state ({exc}); nearest "
                            f"pair: {where}, gap {g_min:.4g}") from exc
    return ContactCheck(min_gap=g_min, where=where, required=gap - tolerance,
                        holds=g_min >= gap - tolerance, pairs=len(P), energy=float(energy))


@dataclasses.dataclass(frozen=True)
class StackedState(Result):
    """A stacked state of a discrete rod and how it was built (``to_dict`` leaves out ``rod``).

    Attributes
    ----------
    rod : DiscreteRod
        The state (same model as the coincident rod it was built from).
    method : str
        The construction.
    thickness, gap : float
        ``h`` and ``g0`` (length).
    layers : tuple of (str, float, float)
        ``(name, u, k)`` per segment: its offset in units of ``h + g0`` (``u`` in-plane,
        ``k`` the layer); on the torus curve the strand's place round the ``N``-gon at the
        segment's start (``cos psi, sin psi``, units of ``a``).
    changes : tuple of str
        Where the curve changes layer (welds joining different offsets, with both offsets).
    chord_error : float
        How much nearer the elements (chords) may stand than the curve they sample, at most:
        ``l_max^2 kappa_max / 4`` (two sagittas, length).
    max_strain, max_offset : float
        Largest ``|chord / rest length - 1|`` (the stretch Newton will remove) and largest
        node displacement from the coincident state (length).
    check : ContactCheck
    torus : TorusCurve or None
    """

    rod: DiscreteRod
    method: str
    thickness: float
    gap: float
    layers: tuple[tuple[str, float, float], ...]
    changes: tuple[str, ...]
    chord_error: float
    max_strain: float
    max_offset: float
    check: ContactCheck
    torus: TorusCurve | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON form of every field but ``rod``."""
        return {f.name: jsonable(getattr(self, f.name)) for f in dataclasses.fields(self)
                if f.name != "rod"}


def _strain(rod: DiscreteRod) -> float:
    chord = np.linalg.norm(rod.x[rod.edge_nodes[:, 1]] - rod.x[rod.edge_nodes[:, 0]], axis=1)
    return float(np.max(np.abs(chord / rod.rest_length - 1.0)))


def _segment_nodes(rod: DiscreteRod, k: int) -> np.ndarray:
    """Nodes of segment ``k`` from its start to its end (``discretise`` lays edges in order)."""
    E = np.flatnonzero(rod.edge_segment == k)
    return np.append(rod.edge_nodes[E, 0], rod.edge_nodes[E[-1], 1])


def _traversal(rod: DiscreteRod) -> np.ndarray:
    """Every node once, in the order the ring is traversed (:func:`~.states.ring_of`)."""
    ring = ring_of(rod.assembly)
    index = {s.name: i for i, s in enumerate(rod.assembly.segments)}
    parts = []
    for name, d in ring.order:
        nodes = _segment_nodes(rod, index[name])
        parts.append((nodes if d > 0 else nodes[::-1])[:-1])
    order = np.concatenate(parts)
    if len(order) != len(rod.x) or len(np.unique(order)) != len(order):
        raise RodstabInputError("stack_loops needs a ring whose nodes the traversal visits "
                                f"once each, got {len(order)} visits of {len(rod.x)} nodes")
    return order


@dataclasses.dataclass(frozen=True)
class CoincidentLoops:
    """The coincident planar N-loop ring a stacking starts from (:func:`coincident_loops`).

    ``order``: the nodes along the traversal, ``X`` their positions, ``t`` their arclengths;
    ``centre``, ``R0``, ``length``, ``loops``; ``azimuth`` of the first node, ``sense`` +1 if
    the traversal runs counter-clockwise about ``e3``.
    """

    order: np.ndarray
    X: np.ndarray
    centre: np.ndarray
    R0: float
    length: float
    loops: int
    t: np.ndarray
    azimuth: float
    sense: float

    def place(self, rod: DiscreteRod, xyz: np.ndarray, tangent: np.ndarray) -> DiscreteRod:
        """Return ``rod`` moved onto a curve given in the canonical frame, frames following.

        ``xyz``, ``tangent`` (nodes in traversal order, 3): positions and unit tangents of a
        curve centred at the origin that starts on ``+e1`` and runs counter-clockwise; they
        are turned to the ring's start azimuth and sense. Each edge frame is turned by the
        smallest rotation that puts ``d2`` on its new chord (the strip stays as flat as it
        can), each joint frame by the smallest one that puts its ``d2`` on the tangent.
        """
        ca, sa = math.cos(self.azimuth), math.sin(self.azimuth)

        def turned(v: np.ndarray, shift: np.ndarray) -> np.ndarray:
            return np.stack([shift[0] + ca * v[:, 0] - sa * self.sense * v[:, 1],
                             shift[1] + sa * v[:, 0] + ca * self.sense * v[:, 1],
                             shift[2] + v[:, 2]], axis=1)

        new = rod.copy()
        new.x[self.order] = turned(xyz, np.array([self.centre[0], self.centre[1], 0.0]))
        new.align_frames()
        tan = np.empty_like(rod.x)
        tan[self.order] = turned(tangent, np.zeros(3))
        tan /= np.linalg.norm(tan, axis=1)[:, None]
        for e, j, _, end in rod.end_links:
            node = rod.edge_nodes[e, 0 if end == "start" else 1]
            new.R_joint[j] = _turn_onto(rod.R_joint[j], tan[node])
        return new


def coincident_loops(rod: DiscreteRod, who: str) -> CoincidentLoops:
    """Read the coincident planar N-loop ring; exit 2 (naming ``who``) if ``rod`` is not one."""
    order = _traversal(rod)
    X = rod.x[order]
    if np.max(np.abs(X[:, 2])) > 0.0:
        raise RodstabInputError(f"{who} needs the planar coincident ring (z = 0), got a "
                                f"node at z = {float(np.max(np.abs(X[:, 2]))):g}")
    c = X.mean(axis=0)
    rad = np.linalg.norm(X[:, :2] - c[:2], axis=1)
    R0m = float(rad.mean())
    if np.max(np.abs(rad - R0m)) > ON_CIRCLE_RTOL * R0m:
        raise RodstabInputError(f"{who} needs coincident circular loops: node radii "
                                f"from {rad.min():.9g} to {rad.max():.9g}")
    chords = np.linalg.norm(np.roll(X, -1, axis=0) - X, axis=1)
    arcs = 2 * R0m * np.arcsin(np.minimum(chords / (2 * R0m), 1.0))
    L = float(arcs.sum())
    N = round(L / (2 * math.pi * R0m))
    if N < 1 or abs(N * 2 * math.pi * R0m - L) > 1e-6 * L:
        raise RodstabInputError(f"{who}: the ring's length {L:.9g} is not a whole number "
                                f"of turns of its circle (radius {R0m:.9g})")
    rel = X[0, :2] - c[:2]
    step = X[1, :2] - X[0, :2]
    return CoincidentLoops(
        order=order, X=X, centre=c, R0=R0m, length=L, loops=N,
        t=np.concatenate([[0.0], np.cumsum(arcs)[:-1]]), azimuth=math.atan2(rel[1], rel[0]),
        sense=1.0 if rel[0] * step[1] - rel[1] * step[0] > 0 else -1.0)


def stack_loops(rod: DiscreteRod, thickness: float, gap: float,
                model: ContactModel | None = None, *, chord_allowance: bool = True
                ) -> StackedState:
    """Build the N-loop ring's stacked state on the ``(N, 1)`` torus curve and check it.

    Parameters
    ----------
    rod : DiscreteRod
        The coincident N-loop ring (``discretise`` or ``common_rod`` of
        ``rodstab.problems.ring.build``): every node on one planar circle, the loops
        traversed one after the other.
    thickness : float
        ``h``: capsule diameter (length).
    gap : float
        ``g0 > 0`` between neighbouring capsules (length).
    model : ContactModel, optional
        The check's contact model (default :func:`default_model`).
    chord_allowance : bool
        The elements are chords of the curve and stand up to ``e = l^2 kappa_max / 4``
        nearer one another than the strands (``l`` the largest element arc). True: the
        strands are put ``h + g0 + 1.05 e`` apart, so the elements keep gaps ``>= g0``
        (checked). False: ``h + g0`` apart, the check asks for gaps ``>= g0 - e`` and refuses
        only an overlap (a coarse mesh with ``e > g0`` may then be refused).

    Returns
    -------
    StackedState
        Node ``i`` at planar arclength ``t_i`` (along the traversal from its first node) goes
        to the torus curve's point at arclength ``t_i`` (the lengths are equal), the curve
        centred on the circle and starting (``phi = 0``, outermost strand) at the first node,
        running the same way round; each edge frame turned by the smallest rotation that puts
        ``d2`` on the new chord (the strip stays as flat as it can, ``d3`` near ``e3``), each
        joint frame by the smallest one that puts its ``d2`` on the curve's tangent there.
        Raises :class:`StackingError` if the contact check fails.
    """
    h = require_positive("thickness", thickness)
    g0 = require_positive("gap", gap)
    ring = coincident_loops(rod, "stack_loops")
    L, N, t = ring.length, ring.loops, ring.t
    arcs = np.diff(np.append(t, L))
    tc = torus_curve(N, L, h, g0)
    # two sagittas of chords of arc <= l on a curve of curvature <= kappa_max
    chord_error = float(arcs.max()) ** 2 * tc.curvature_max / 4.0
    if chord_allowance and N > 1:
        # the margin covers kappa_max growing with a (by O(a / R) of itself)
        tc = torus_curve(N, L, h, g0 + CHORD_MARGIN * chord_error)
        chord_error = float(arcs.max()) ** 2 * tc.curvature_max / 4.0
    # arclength of the torus curve on a fine table, inverted by interpolation
    phis = np.linspace(0.0, 2 * math.pi * N, N * ARCLENGTH_POINTS + 1)
    speed = np.sqrt((tc.R + tc.a * np.cos(phis / N)) ** 2 + (tc.a / N) ** 2)
    s_tab = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(phis))])
    phi = np.interp(t * (s_tab[-1] / L), s_tab, phis)
    rho = tc.R + tc.a * np.cos(phi / N)
    xyz = np.stack([rho * np.cos(phi), rho * np.sin(phi), tc.a * np.sin(phi / N)], axis=1)
    new = ring.place(rod, xyz, _derivatives(phi, N, tc.R, tc.a)[0])
    model = default_model(h) if model is None else model
    check = check_stacked(new, model, g0, 0.0 if chord_allowance else chord_error)
    pos = np.empty(len(rod.x))
    pos[ring.order] = phi
    psi0 = [float(pos[_segment_nodes(rod, k)[0]]) / N for k in range(len(rod.assembly.segments))]
    layers = tuple((sg.name, math.cos(p), math.sin(p))
                   for sg, p in zip(rod.assembly.segments, psi0, strict=True))
    return StackedState(
        rod=new, method=f"({N}, 1) torus curve, R = {tc.R:.9g}, a = {tc.a:.9g}",
        thickness=h, gap=g0, layers=layers,
        changes=(f"the strands turn round one another once, by 2 pi / {N} per loop",),
        chord_error=chord_error, max_strain=_strain(new),
        max_offset=float(np.max(np.linalg.norm(new.x - rod.x, axis=1))), check=check, torus=tc)


def _turn_onto(F: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Frame ``F`` (3, 3) turned by the smallest rotation taking ``+-d2`` onto ``t``."""
    t = t * np.sign(float(F[:, 1] @ t) or 1.0)
    k = np.cross(F[:, 1], t)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return (np.eye(3) + K + K @ K / (1.0 + float(F[:, 1] @ t))) @ F  # Rodrigues, cos + sin


# ---------------------------------------------------------------- other folds: layers and ramps
def smoothstep(t: np.ndarray) -> np.ndarray:
    """Quintic smoothstep ``S(t) = 6t^5 - 15t^4 + 10t^3`` on [0, 1] (clamped): C2 ramps.

    ``S' = S'' = 0`` at both ends; ``max S' = 15 / 8``, ``max |S''| = 10 / sqrt(3)``.
    """
    t = np.clip(np.asarray(t, float), 0.0, 1.0)
    return t**3 * (10.0 - 15.0 * t + 6.0 * t * t)


#: ``max |S''|`` of :func:`smoothstep` (at ``t = (3 -+ sqrt 3) / 6``).
SMOOTHSTEP_MAX_CURVATURE = 10.0 / math.sqrt(3.0)


def _segment_arclength(rod: DiscreteRod, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes of segment ``k`` (start to end) and their arclengths (``discretise``'s linspace)."""
    nodes = _segment_nodes(rod, k)
    return nodes, np.linspace(0.0, rod.assembly.segments[k].length, len(nodes))


def layer_offsets(names: list[str], layers: dict[str, Any]) -> dict[str, tuple[float, float]]:
    """Every segment's offset ``(u, k)``: a layer ``k`` or a pair; exit 2 naming a bad one."""
    unknown, missing = sorted(set(layers) - set(names)), [n for n in names if n not in layers]
    if unknown or missing:
        raise RodstabInputError(f"layers must give every segment of {names} once; unknown "
                                f"{unknown}, missing {missing}")
    off = {}
    for name in names:
        value = layers[name]
        if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
            off[name] = (0.0, float(value))
        elif isinstance(value, (tuple, list)) and len(value) == 2:
            off[name] = (float(value[0]), float(value[1]))
        elif isinstance(value, (tuple, list)) and len(value) == 3:
            raise RodstabInputError(f"layers[{name!r}] = {value!r}: a shift along the rod (the "
                                    "third number) is a setting of the stacked model whose "
                                    "welds span the layers (transitions, barrier), not of "
                                    "this method")
        else:
            raise RodstabInputError(f"layers[{name!r}] must be a layer number or an offset (u, "
                                    f"k), got {value!r}")
        if not all(math.isfinite(v) for v in off[name]):
            raise RodstabInputError(f"layers[{name!r}] must be finite, got {value!r}")
    return off


def _senses(rod: DiscreteRod, thickness: float) -> np.ndarray:
    """``+-1`` per segment: -1 where it runs against the first segment it lies on.

    The in-plane offsets of :func:`stack_layers` are along ``d1 = t x e3`` turned by this sign,
    so that rods lying on one another but run in opposite senses (the hexagram's line, its
    rods joined by cusps) share one in-plane direction. A segment is compared at its middle
    element with the nearest element (midpoints within ``h``) of a segment before it.
    """
    x, E, seg = rod.x, rod.edge_nodes, rod.edge_segment
    mid = 0.5 * (x[E[:, 0]] + x[E[:, 1]])
    tan = x[E[:, 1]] - x[E[:, 0]]
    tan /= np.linalg.norm(tan, axis=1)[:, None]
    sense = np.ones(len(rod.assembly.segments))
    for k in range(1, len(sense)):
        mine = np.flatnonzero(seg == k)
        e = mine[len(mine) // 2]
        before = np.flatnonzero(seg < k)
        dist = np.linalg.norm(mid[before] - mid[e], axis=1)
        j = int(np.argmin(dist))
        if dist[j] <= thickness:
            sense[k] = sense[seg[before[j]]] * (1.0 if tan[e] @ tan[before[j]] >= 0 else -1.0)
    return sense


def _lab_offset(seg: Any, s: np.ndarray, uk: tuple[float, float], sense: float, d: float
                ) -> np.ndarray:
    """Lab offset vectors (m, 3) of ``seg`` at arclengths ``s``: ``d (u n + k e3)``.

    ``n = t x e3`` of the held tangent, turned round where ``sense`` is -1 (:func:`_senses`).
    """
    u, z = uk
    t = sense * seg.tangent(s).reshape(-1, 2)
    n = np.stack([t[:, 1], -t[:, 0], np.zeros(len(t))], axis=1)
    return d * (u * n + z * np.array([0.0, 0.0, 1.0]))


def _fmt(o: tuple[float, float]) -> str:
    return f"layer {o[1]:g}" if o[0] == 0.0 else f"offset ({o[0]:.4g}, {o[1]:.4g})"


def stack_layers(rod: DiscreteRod, layers: dict[str, Any], thickness: float, gap: float, *,
                 model: ContactModel | None = None, ramp: float | None = None) -> StackedState:
    """Offset each rod of a planar state by its layer, ramp at welds, check with contact.

    Parameters
    ----------
    rod : DiscreteRod
        Planar state (``discretise`` or ``common_rod``), e.g. with coincident rods.
    layers : dict
        For every segment name: a layer ``k`` or an offset ``(u, k)`` in units of ``h + g0``
        (:func:`layer_offsets`), ``u`` along the held ``d1 = t x e3``, turned round on a rod
        running against the first rod it lies on (:func:`_senses`).
    thickness : float
        ``h``: capsule diameter (length).
    gap : float
        ``g0 > 0`` (length).
    model : ContactModel, optional
        The check's contact model (default :func:`default_model`).
    ramp : float, optional
        Ramp length at a weld joining different offsets (length; default
        :data:`RAMP_FRACTION` of the model's exclusion distance ``exclusion_factor (h +
        dhat)``); at most half of each ramped segment.

    Returns
    -------
    StackedState
        ``changes`` lists every weld joining different offsets. Raises :class:`StackingError`
        naming the two segments and where, if the order interpenetrates.
    """
    h = require_positive("thickness", thickness)
    g0 = require_positive("gap", gap)
    d = h + g0
    model = default_model(h) if model is None else model
    a = rod.assembly
    names = [s.name for s in a.segments]
    off = layer_offsets(names, layers)
    ell = RAMP_FRACTION * model.exclusion_factor * (h + model.dhat) if ramp is None else \
        require_positive("ramp", ramp)

    sense = _senses(rod, h)

    def offset(k: int, s: np.ndarray) -> np.ndarray:
        return _lab_offset(a.segments[k], s, off[names[k]], sense[k], d)

    # the offset of every weld: the mean of its ends' offsets
    index = {nm: i for i, nm in enumerate(names)}
    weld_off, changes, jumps = {}, [], []
    for joint in a.joints():
        ends = [offset(index[nm], np.array([0.0 if e == "start" else a.segment(nm).length]))[0]
                for nm, e in joint]
        w = np.mean(ends, axis=0)
        for end in joint:
            weld_off[end] = w
        if len(joint) > 1 and max(float(np.linalg.norm(v - w)) for v in ends) > 1e-12 * d:
            nm, e = joint[0]
            p = a.segment(nm).end_point(e)
            changes.append(" - ".join(f"{m}.{f} {_fmt(off[m])}" for m, f in joint)
                           + f" at ({p[0]:.4g}, {p[1]:.4g}): ramps of length {ell:.4g}")
            jumps.append(max(float(np.linalg.norm(v - w)) for v in ends) / d)
    new = rod.copy()
    kappa_max, jump_max = 0.0, 0.0
    for k, seg in enumerate(a.segments):
        nodes, s = _segment_arclength(rod, k)
        o = offset(k, s)
        for side, s_end, w_of in (("start", 0.0, 1.0 - smoothstep(s / ell)),
                                  ("end", seg.length, 1.0 - smoothstep((seg.length - s) / ell))):
            jump = weld_off[(seg.name, side)] - offset(k, np.array([s_end]))[0]
            if float(np.linalg.norm(jump)) > 1e-12 * d:
                if 2 * ell > seg.length:
                    raise RodstabInputError(f"ramp {ell:g} is longer than half of segment "
                                            f"{seg.name!r} (length {seg.length:g})")
                o = o + w_of[:, None] * jump
                jump_max = max(jump_max, float(np.linalg.norm(jump)))
        new.x[nodes] = rod.x[nodes] + o
        r_off = float(np.max(np.linalg.norm(o, axis=1)))
        kappa_max = max(kappa_max, abs(seg.curvature) * (1 + r_off * abs(seg.curvature)))
    kappa_max += jump_max * SMOOTHSTEP_MAX_CURVATURE / ell**2
    new.align_frames()  # ramps start and end level: joint frames keep the planar tangent
    lmax = float(np.max(np.linalg.norm(rod.x[rod.edge_nodes[:, 1]] - rod.x[rod.edge_nodes[:, 0]],
                                       axis=1)))
    chord_error = lmax**2 * kappa_max / 4.0
    try:
        check = check_stacked(new, model, g0, chord_error)
    except StackingError as exc:
        far = [c for c, j in zip(changes, jumps, strict=True) if j > 0.5 * (1 + 1e-9)]
        raise StackingError(f"{exc}. Layer order {dict((n, _fmt(off[n])) for n in names)}; welds "
                            f"joining offsets more than one spacing apart (their ramps pass "
                            f"through the rods between): {far or 'none'}") from exc
    return StackedState(
        rod=new, method="planar state offset by layer, C2 quintic ramps at welds",
        thickness=h, gap=g0, layers=tuple((n, *off[n]) for n in names), changes=tuple(changes),
        chord_error=chord_error, max_strain=_strain(new),
        max_offset=float(np.max(np.linalg.norm(new.x - rod.x, axis=1))), check=check)
