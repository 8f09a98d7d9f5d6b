"""Stacked states free of interpenetration, with a stated layer order (issue 21, part 2).

Every stacked state (the N-loop rings of Sec. 3.1, the bi-rod of Sec. 4, the folded ring of
Sec. 5, the hexagram's line and eight) is held with coincident centrelines. Here each is
*constructed* as a state of the same :class:`~rodstab.nonlinear.discrete.DiscreteRod` whose
rods (capsules of radius ``h / 2``, :mod:`rodstab.nonlinear.contact`) are at least ``h + g0``
apart, and checked with the contact model. Nothing is relaxed yet.

N-loop ring (:func:`torus_curve`, :func:`stack_loops`). A circle of length ``L`` held as ``N``
coincident loops cannot close in layers stacked flat: the last loop would have to come back
from the top layer to the bottom one through the others. Its layers wind round one another
once, on the ``(N, 1)`` torus curve ``r(phi) = ((R + a cos(phi/N)) cos phi, (R + a cos(phi/N))
sin phi, a sin(phi/N))``, ``0 <= phi < 2 pi N``. At one azimuth the ``N`` strands sit on a
regular ``N``-gon of circumradius ``a`` in the meridian plane, ``2 a sin(pi m / N)`` apart (m
strands round). The true distance of two strands is smaller: a point at ``phi`` and one at
``phi + 2 pi m + delta`` are apart by (derived from the parametrisation, ``rho = R + a cos psi``)

    ``D^2 = 4 a^2 sin^2(pi m / N + delta / 2N) + 4 rho(psi) rho(psi') sin^2(delta / 2)``,
    ``psi = phi / N``, ``psi' = psi + (2 pi m + delta) / N``,

whose slope at ``delta = 0`` is ``(2 a^2 / N) sin(2 pi m / N)``, not zero for ``N >= 3``: the
strands are inclined, and the nearest points are a little off the meridian plane, by
``D_meridian^2 - D_min^2 ~ a^4 sin^2(2 pi m / N) / (N^2 R^2)``. :func:`strand_distance`
minimises ``D`` exactly (Newton in ``delta``, golden section in ``psi``, every ``m``), and
``a`` is scaled until that minimum is ``h + g0``: ``a = (h + g0) / (2 sin(pi / N)) (1 +
O(a^2 / N^2 R^2))``. The curve is longer than ``2 pi N R``: ``|r'(phi)|^2 = rho^2 + a^2 /
N^2``, so ``length = N int_0^2pi sqrt((R + a cos psi)^2 + a^2 / N^2) dpsi = 2 pi N R + pi
a^2 / (N sqrt(R^2 - a^2)) + O(a^4)``; ``R`` is lowered until the length is exactly ``L``.
Its squared curvature integrates (series in ``eps = a / R``, derived symbolically) to
``int kappa^2 ds = (2 pi N / R)(1 + eps^2 / 2 - 2 eps^2 / N^2 + eps^2 / N^4 + O(eps^4))``
(radial modulation, inclination, out-of-plane wave), and the length to ``2 pi N R (1 + eps^2
/ 2N^2)``, so at length ``L`` (``R = R0 (1 - eps^2 / 2N^2)``, ``R0 = L / 2 pi N``) the bending
energy of an isotropic rod exceeds the coincident loops' ``B L / 2 R0^2`` by the fraction
``c (a / R0)^2``, ``c = (N^2 - 1)(N^2 - 2) / 2 N^4`` (:func:`bending_excess_coefficient`):
``O((h / L)^2)`` at fixed ``N``. Torsion is ``O(a / N R^2)``.

The other folds (:func:`stack_layers`): each rod is given an offset from its planar centreline,
in units of the spacing ``h + g0``: a layer ``k`` (the offset ``k e3``) or an offset ``(u, k)``
along the rod's in-plane normal ``e3 x t`` and ``e3``. Where a weld joins rods of different
offsets, both run to the weld's mean offset along C2 ramps (quintic smoothstep, zero slope and
curvature at both ends, so the weld's tangents and frames stay those of the planar state) of
length :data:`RAMP_FRACTION` of the contact model's exclusion distance: past it, rods of a
cusp are a full spacing apart. The result is checked with the contact model; an order that
interpenetrates raises :class:`StackingError` naming the two rods and where.

Folded ring of Sec. 5 (``2n`` straight rods on ``[0, L]``, cusps joining rods ``i, i + 1``,
at ``x = L`` for odd ``i``, ``x = 0`` for even ``i``, and ``2n -> 1`` at ``x = 0``): stacked
in layers along ``e3`` alone it is impossible with any order, since every cusp lies where all
``2n`` rods are, so the two rods it joins must be adjacent layers (a rod between them would be
cut by the ramp), and the ``2n`` cusps form a cycle, which a path of ``2n`` layers cannot hold
(it has ``2n - 1`` adjacent pairs). The traversal order ``1..2n`` fails at the cusp ``2n ->
1`` (layers ``2n - 1`` and 0). The construction that holds is the analogue of the torus curve:
rod ``i`` at vertex ``i`` of a regular ``2n``-gon of circumradius ``(h + g0) / (2 sin(pi /
2n))`` across the bundle (:func:`polygon_offsets`), every cusp joining neighbouring vertices.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_positive, require_positive_int
from ..nonlinear.contact import (
    ContactModel,
    Interpenetration,
    candidate_pairs,
    contact_energy,
    mesh_of_rod,
    segment_distance,
)
from ..nonlinear.discrete import DiscreteRod
from ..results import Result
from .states import ring_of

#: Relative tolerance of the fixed points that set ``a`` (nearest strand distance) and ``R``
#: (curve length) of the torus curve.
TORUS_RTOL = 1e-13
TORUS_MAX_ITER = 60
#: Quadrature points per loop (trapezoid rule on a periodic analytic integrand: spectral).
QUAD_POINTS = 512
#: Points per loop of the table that inverts the torus curve's arclength.
ARCLENGTH_POINTS = 8192
#: Planar nodes of an N-loop ring must lie on one circle to this fraction of its radius.
ON_CIRCLE_RTOL = 1e-8
#: Ramp length at a weld joining different offsets, as a fraction of the contact model's
#: exclusion distance ``exclusion_factor (h + dhat)``: at half of it the two rods of a cusp are
#: a full spacing apart where they first see one another.
RAMP_FRACTION = 0.5
#: Chord allowance of :func:`stack_loops` as a multiple of the chord error bound.
CHORD_MARGIN = 1.05
#: Activation distance of the default contact model of the checks, as a fraction of ``h``
#: (the rule of :class:`~rodstab.nonlinear.contact.ContactModel`).
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


def strand_distance(loops: int, R: float, a: float, m: int | None = None) -> float:
    """True smallest 3D distance between two strands of the torus curve (length).

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
        lo, hi = grid[k] - 2 * math.pi / 720, grid[k] + 2 * math.pi / 720
        # golden section on a smooth minimum bracketed by the grid
        gr = (math.sqrt(5) - 1) / 2
        c, d = hi - gr * (hi - lo), lo + gr * (hi - lo)

        def f(p: float, mm: int = mm) -> float:
            return float(_nearest_over_delta(np.array([p]), mm, N, R, a)[0])

        fc, fd = f(c), f(d)
        while hi - lo > 1e-10:
            if fc <= fd:
                hi, d, fd = d, c, fc
                c = hi - gr * (hi - lo)
                fc = f(c)
            else:
                lo, c, fc = c, d, fd
                d = lo + gr * (hi - lo)
                fd = f(d)
        best = min(best, math.sqrt(max(min(fc, fd, float(g[k])), 0.0)))
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
    if N == 1:
        a = 0.0
        return TorusCurve(1, L, d, R0, 0.0, R0, math.inf, math.inf, torus_length(1, R0, 0.0),
                          0.0, 1 / R0, 0.0, 0.0)
    a = d / (2 * math.sin(math.pi / N))
    if a >= 0.25 * R0:
        raise RodstabInputError(f"thickness + gap = {d:g} too large for {N} loops of radius "
                                f"{R0:g}: strand circumradius {a:g} >= R0 / 4")
    R = R0
    for _ in range(TORUS_MAX_ITER):
        Dmin = strand_distance(N, R, a)
        a_new = a * d / Dmin  # D scales with a to leading order: a fast fixed point
        R_new = R + (L - torus_length(N, R, a_new)) / (2 * math.pi * N)  # dlength/dR ~ 2 pi N
        done = abs(a_new - a) <= TORUS_RTOL * a and abs(R_new - R) <= TORUS_RTOL * R
        a, R = a_new, R_new
        if done:
            break
    phi = _loop_grid(N, QUAD_POINTS)
    k, tau = curvature_torsion(phi, N, R, a)
    return TorusCurve(
        loops=N, length=L, spacing=d, R=R, a=a, R0=R0,
        meridian_distance=2 * a * math.sin(math.pi / N),
        strand_distance=strand_distance(N, R, a), length_check=torus_length(N, R, a),
        length_excess_at_R0=torus_length(N, R0, a) - L, curvature_max=float(k.max()),
        torsion_max=float(np.abs(tau).max()),
        bending_excess=bending_integral(N, R, a) / (L / R0**2) - 1.0)


def bending_excess(loops: int, length: float, thickness: float, gap: float) -> float:
    """Relative bending energy of the torus curve above the coincident loops (isotropic rod).

    ``int kappa^2 ds / (L / R0^2) - 1`` (dimensionless), ``~ c a^2 / R0^2`` (module doc).
    """
    return torus_curve(loops, length, thickness, gap).bending_excess


def bending_excess_coefficient(loops: int) -> float:
    """``c = (N^2 - 1)(N^2 - 2) / 2 N^4``: bending excess ``~ c (a / R0)^2`` (module doc)."""
    N = require_positive_int("loops", loops)
    return (N * N - 1) * (N * N - 2) / (2.0 * N**4)


# ---------------------------------------------------------------- checks with the contact model
def default_model(thickness: float) -> ContactModel:
    """Contact model of the checks: capsules of radius ``h / 2``, ``dhat = 0.1 h``.

    The stiffness does not enter a check (only gaps and the model's refusal do).
    """
    h = require_positive("thickness", thickness)
    return ContactModel.from_thickness(h, dhat=DHAT_FRACTION * h, stiffness=1.0)


def _where(rod: DiscreteRod, e: int) -> str:
    """``segment 'name' at s = ...`` for edge ``e`` (its midpoint's arclength)."""
    seg_of = rod.edge_segment
    k = int(seg_of[e])
    first = int(np.flatnonzero(seg_of == k)[0])
    n = int(np.count_nonzero(seg_of == k))
    seg = rod.assembly.segments[k]
    return f"segment {seg.name!r} at s = {(e - first + 0.5) * seg.length / n:.4g}"


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

    Parameters
    ----------
    rod : DiscreteRod
        The state (node positions ``rod.x``, lab frame).
    model : ContactModel
        Capsule radii, exclusions and barrier (:func:`default_model`).
    gap : float
        ``g0``: the gap the construction aimed at (length).
    tolerance : float
        Its stated error (chord error, length).

    Returns
    -------
    ContactCheck
        Raises :class:`StackingError` naming the two segments and where, if two non-excluded
        capsules overlap or the contact model refuses the state.
    """
    mesh = mesh_of_rod(rod, model)
    P = candidate_pairs(mesh, rod.x)
    P = P[~mesh.excluded_elements(P[:, 0], P[:, 1])]
    E, x = mesh.edges, rod.x
    g = segment_distance(x[E[P[:, 0], 0]], x[E[P[:, 0], 1]], x[E[P[:, 1], 0]],
                         x[E[P[:, 1], 1]]) - mesh.radius[P[:, 0]] - mesh.radius[P[:, 1]]
    if len(g):
        k = int(np.argmin(g))
        where = f"{_where(rod, int(P[k, 0]))} and {_where(rod, int(P[k, 1]))}"
        g_min = float(g[k])
    else:
        where, g_min = "no pair within reach", math.inf
    if g_min <= 0.0:
        raise StackingError(f"the stacked state interpenetrates: {where} overlap by "
                            f"{-g_min:.4g} (gap {g_min:.4g} <= 0, capsule radius "
                            f"{float(mesh.radius.max()):g})")
    try:
        energy = contact_energy(mesh, x)[0]
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
        Each segment's offset ``(name, u, k)`` in units of ``h + g0``: ``u`` along the held
        frame's ``d1 = t x e3``, ``k`` along ``e3`` (the layer). For the torus curve, the
        strand's position round the ``N``-gon at the segment's start, ``(name, u, k)`` with
        ``u = cos psi``, ``k = sin psi`` in units of ``a``.
    changes : tuple of str
        Where the curve changes layer (welds joining different offsets, with both offsets).
    chord_error : float
        Bound on how much nearer the elements (chords) stand than the curve they sample:
        ``l_max^2 kappa_max / 4`` (two sagittas, length).
    max_strain : float
        Largest ``|chord / rest length - 1|`` of an element (the stretch Newton will remove).
    max_offset : float
        Largest node displacement from the coincident state (length).
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
        out = super().to_dict() if False else {
            f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "rod"}
        from ..results import jsonable
        res = jsonable(out)
        assert isinstance(res, dict)
        return res


def _strain(rod: DiscreteRod) -> float:
    chord = np.linalg.norm(rod.x[rod.edge_nodes[:, 1]] - rod.x[rod.edge_nodes[:, 0]], axis=1)
    return float(np.max(np.abs(chord / rod.rest_length - 1.0)))


# ---------------------------------------------------------------- N-loop rings on the torus curve
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
    order = _traversal(rod)
    X = rod.x[order]
    if np.max(np.abs(X[:, 2])) > 0.0:
        raise RodstabInputError("stack_loops needs the planar coincident ring (z = 0), got a "
                                f"node at z = {float(np.max(np.abs(X[:, 2]))):g}")
    c = X.mean(axis=0)
    rad = np.linalg.norm(X[:, :2] - c[:2], axis=1)
    R0m = float(rad.mean())
    if np.max(np.abs(rad - R0m)) > ON_CIRCLE_RTOL * R0m:
        raise RodstabInputError(f"stack_loops needs coincident circular loops: node radii "
                                f"from {rad.min():.9g} to {rad.max():.9g}")
    chords = np.linalg.norm(np.roll(X, -1, axis=0) - X, axis=1)
    arcs = 2 * R0m * np.arcsin(np.minimum(chords / (2 * R0m), 1.0))
    L = float(arcs.sum())
    N = round(L / (2 * math.pi * R0m))
    if N < 1 or abs(N * 2 * math.pi * R0m - L) > 1e-6 * L:
        raise RodstabInputError(f"stack_loops: the ring's length {L:.9g} is not a whole number "
                                f"of turns of its circle (radius {R0m:.9g})")
    t = np.concatenate([[0.0], np.cumsum(arcs)[:-1]])
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
    rel = X[0, :2] - c[:2]
    sense = 1.0 if np.cross(rel, X[1, :2] - X[0, :2]) > 0 else -1.0
    az = math.atan2(rel[1], rel[0]) + sense * phi
    rho = tc.R + tc.a * np.cos(phi / N)
    new = rod.copy()
    new.x[order] = np.stack([c[0] + rho * np.cos(az), c[1] + rho * np.sin(az),
                             tc.a * np.sin(phi / N)], axis=1)
    new.align_frames()
    # joint frames: d2 onto the curve's tangent at the joint (the planar tangent's sense kept)
    pos = np.empty(len(rod.x))
    pos[order] = phi
    d1 = _derivatives(pos, N, tc.R, tc.a)[0]
    # the canonical curve turned to the ring's start azimuth and sense (z kept)
    a0 = math.atan2(rel[1], rel[0])
    ca, sa = math.cos(a0), math.sin(a0)
    tan = np.stack([ca * d1[:, 0] - sa * sense * d1[:, 1], sa * d1[:, 0] + ca * sense * d1[:, 1],
                    d1[:, 2]], axis=1)
    tan /= np.linalg.norm(tan, axis=1)[:, None]
    for e, j, _, end in rod.end_links:
        node = rod.edge_nodes[e, 0 if end == "start" else 1]
        new.R_joint[j] = _turn_onto(rod.R_joint[j], tan[node])
    model = default_model(h) if model is None else model
    check = check_stacked(new, model, g0, 0.0 if chord_allowance else chord_error)
    names = [s.name for s in rod.assembly.segments]
    psi0 = {}
    for name, d in ring_of(rod.assembly).order:
        k = names.index(name)
        first = _segment_nodes(rod, k)[0 if d > 0 else -1]
        psi0[name] = float(pos[first] / N)
    layers = tuple((nm, math.cos(psi0[nm]), math.sin(psi0[nm])) for nm in names)
    return StackedState(
        rod=new, method=f"({N}, 1) torus curve, R = {tc.R:.9g}, a = {tc.a:.9g}",
        thickness=h, gap=g0, layers=layers,
        changes=(f"the strands turn round one another once, by 2 pi / {N} per loop",),
        chord_error=chord_error, max_strain=_strain(new),
        max_offset=float(np.max(np.linalg.norm(new.x - rod.x, axis=1))), check=check, torus=tc)


def _turn_onto(F: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Frame ``F`` (3, 3) turned by the smallest rotation taking ``+-d2`` onto ``t``."""
    d2 = F[:, 1]
    t = t if float(d2 @ t) >= 0.0 else -t
    k = np.cross(d2, t)
    c = float(d2 @ t)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return (np.eye(3) + K + K @ K / (1.0 + c)) @ F
