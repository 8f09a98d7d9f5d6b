"""The hexagram's eight with rods of thickness: a braid at its weld point (issue 21, part 2).

A figure-eight (:func:`~.cone.figure_eight`: ``2m`` rods, each a full circle from one point
``P``, alternate rods on two lobes, every weld a cusp at ``P``) cannot be stacked as the other
folds are (:mod:`.stacking`):

* each rod is a closed circle, so under one rigid offset per rod (flat layers, translations)
  its own start and end lie at one point and its first and last elements overlap;
* with heights only, the strands' order cannot change cyclically round ``P``.

**The braid.** Each lobe's ``m`` strands lie on a tube of radius ``a`` round the lobe's circle
(radius ``R'``, centre moved ``a + d / 2`` away from ``P``, so that the two tubes' centres at
``P`` are ``2a + d`` apart; ``d = h + g0``). Strand ``k`` (traversal order, ``k = 0 .. 2m -
1``) is at tube angle

    theta_k(sigma) = theta_0 + (180 / m) k + Delta sigma + beta_k sin(2 pi sigma),

``sigma`` in ``[0, 1]`` along the rod, ``Delta = 180 / m + 360 J`` degrees (``J`` whole turns
round the tube), the angle measured from the in-plane direction ``u`` that points from ``P``
towards the first lobe's centre (the inward normal on that lobe, the outward one on the other)
towards ``+e3``: ``x = C' + (R' -+ a cos theta) r_hat + a sin theta e3``. On a lobe the ``m``
strands stay ``360 / m`` degrees apart (to the ``beta``s' differences); at ``P`` the ``4m``
ends lie ``180 / m`` degrees apart on the two tubes' circles, and every weld joins one tube
angle on both lobes, so its connector is the translation ``(2a + d) u``. With ``a = d`` the
neighbouring ends are exactly ``d`` apart. ``theta_0 = 45 / m`` degrees keeps connectors at
tube angles ``theta`` and ``180 - theta`` (collinear, overlapping) apart: the closest two are
``a sin(45 / m)`` apart.

**Lengths.** The tube's in-plane offset changes a strand's length by about ``-+a <cos theta> /
R`` and the winding adds ``(a theta')^2 / 2``; with ``J = 0`` the strands of a lobe cover
different ranges of ``theta`` (spread about ``1.6 a / R`` for ``m = 3``: 21 % at ``h / L =
0.02``, benchmarks/eight_braid.py). With ``J >= 1`` every strand winds through every angle;
``R'`` is set so that the strands' mean length at ``beta = 0`` is the rods' length ``L``, then
each ``beta_k`` so that strand ``k``'s length is exactly ``L`` (root of the length in the
window ``|beta| <= Delta / 4 pi``, where the winding stays monotone, by
:func:`~rodstab.numerics.roots.find_roots`; the root nearest zero). The lengths are the
integral of ``|x'| = sqrt((2 pi (R' -+ a cos theta))^2 + (a theta')^2)``, by Simpson's rule on
:data:`LENGTH_POINTS` points.

The discrete state: :func:`~.discover.common_rod` (the model every state of the ring shares)
with every rod end at its braided place
(``end_offsets``: spanning welds, each joint's node at its connector's middle), the other nodes
at equal arclength along the strands, edge frames turned onto the chords
(:meth:`~rodstab.nonlinear.discrete.DiscreteRod.align_frames`); joint frames stay planar (the
offsets are defined in them). Checked with the contact model
(:func:`~.stacking.check_stacked`) before it is returned. Not an equilibrium: relax it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_positive, require_positive_int
from ..model import Assembly
from ..nonlinear.contact import ContactModel
from ..nonlinear.discrete import DiscreteRod
from ..numerics import find_roots
from .cone import figure_eight
from .discover import common_rod
from .stacked import SCAN_STEPS, WINDOW_WIDTHS, StackedLimits
from .stacking import (
    StackedState,
    StackingError,
    _segment_nodes,
    _strain,
    check_stacked,
    default_model,
)

#: Points of Simpson's rule for a strand's length (odd).
LENGTH_POINTS = 4097
#: Points of the table a strand's arclength is inverted on (node placement).
PLACE_POINTS = 8193
#: The strands' extra spacing over the elements' chord error (its estimate's margin).
CHORD_MARGIN = 1.25
#: ``dhat / h`` at which :func:`braid_limits` relaxes the built braid first (then halved).
START_DHAT = 0.1


class _Lobes:
    """The figure-eight's geometry: ``P``, the direction ``u``, lobe centres and radius."""

    def __init__(self, a: Assembly) -> None:
        m = figure_eight(a)
        if not m:
            raise RodstabInputError("braid_eight needs a figure-eight: 2m >= 4 segments, each a "
                                    "full circle from one point, cusps there, alternate "
                                    "segments on two circles (the hexagram's eight)")
        self.m = m
        segs = a.segments
        if max(sg.length for sg in segs) > (1.0 + 1e-9) * min(sg.length for sg in segs):
            raise RodstabInputError("braid_eight needs two equal lobes (every rod of one "
                                    "length), got lengths "
                                    f"{sorted({round(sg.length, 12) for sg in segs})}")
        self.P = np.asarray(segs[0].start, float)
        far = [np.asarray(sg.position(np.array([0.5 * sg.length]))[0], float) for sg in segs[:2]]
        self.centre = [0.5 * (self.P + f) for f in far]  # lobe of even, odd segments
        self.R = float(np.linalg.norm(far[0] - self.P)) * 0.5
        u = self.centre[0] - self.P
        self.u = u / np.linalg.norm(u)
        self.L = float(segs[0].length)


def _theta(k: int, m: int, turns: int, phase: float, beta: float, sig: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """Tube angle of strand ``k`` and its derivative in ``sigma`` (module doc; radians)."""
    delta = math.radians(180.0 / m + 360.0 * turns)
    th = (math.radians(phase + 180.0 / m * k) + delta * sig
          + beta * np.sin(2 * math.pi * sig))
    return th, delta + 2 * math.pi * beta * np.cos(2 * math.pi * sig)


def _speed(k: int, lobes: _Lobes, a: float, R: float, turns: int, phase: float, beta: float,
           sig: np.ndarray) -> np.ndarray:
    """``|x'(sigma)|`` of strand ``k`` (module doc)."""
    th, dth = _theta(k, lobes.m, turns, phase, beta, sig)
    sgn = -1.0 if k % 2 == 0 else 1.0
    return np.sqrt((2 * math.pi * (R + sgn * a * np.cos(th))) ** 2 + (a * dth) ** 2)


def _length(k: int, lobes: _Lobes, a: float, R: float, turns: int, phase: float,
            beta: float) -> float:
    sig = np.linspace(0.0, 1.0, LENGTH_POINTS)
    f = _speed(k, lobes, a, R, turns, phase, beta, sig)
    h = 1.0 / (LENGTH_POINTS - 1)
    return float(h / 3.0 * (f[0] + f[-1] + 4.0 * f[1:-1:2].sum() + 2.0 * f[2:-1:2].sum()))


def _strand(k: int, seg: Any, lobes: _Lobes, a: float, d: float, R: float, turns: int,
            phase: float, beta: float, sig: np.ndarray) -> np.ndarray:
    """Points (len(sig), 3) of strand ``k`` (segment ``seg``) at ``sigma = sig`` (module doc).

    ``x = C' + (R -+ a cos theta) r_hat + a sin theta e3``: ``r_hat`` the planar segment's
    radial direction from its lobe's centre (so the strand runs as the segment does), ``C'``
    that centre moved ``a + d / 2`` away from ``P``.
    """
    lobe = k % 2
    sgn = -1.0 if lobe == 0 else 1.0
    centre = lobes.centre[lobe] + (a + 0.5 * d) * (lobes.u if lobe == 0 else -lobes.u)
    planar = np.asarray(seg.position(sig * seg.length), float).reshape(-1, 2)
    rhat = (planar - lobes.centre[lobe]) / lobes.R
    th = _theta(k, lobes.m, turns, phase, beta, sig)[0]
    xy = centre + (R + sgn * a * np.cos(th))[:, None] * rhat
    return np.column_stack([xy, a * np.sin(th)])


def braid_eight(a: Assembly, elements_per_segment: int, load_factor: float, thickness: float,
                gap: float, *, tube: float = 1.0, turns: int = 1, phase: float | None = None,
                model: ContactModel | None = None) -> StackedState:
    """Build a figure-eight's braided stacked state and check it (module doc).

    Parameters
    ----------
    a : Assembly
        A figure-eight (:func:`~.cone.figure_eight`), e.g. the hexagram's eight held.
    elements_per_segment : int
        Elements per rod.
    load_factor : float
        The state's load factor (natural curvature over the held one).
    thickness, gap : float
        ``h`` (capsule diameter) and ``g0 > 0`` (length); ``d = h + g0``.
    tube : float
        ``a / d``: the tube's radius (``>= 1``: neighbouring ends at ``P`` are ``a`` apart).
    turns : int
        ``J >= 1``: whole turns of every strand round its tube besides the ``180 / m``
        degrees (with ``J = 0`` the lengths cannot be made equal).
    phase : float, optional
        ``theta_0`` in degrees (default ``45 / m``).
    model : ContactModel, optional
        The check's contact model (default :func:`~.stacking.default_model`).

    Returns
    -------
    StackedState
        ``layers``: per rod ``(name, cos theta_k(0), sin theta_k(0))`` (units of ``a``);
        ``changes``: the winding, the ``beta``s and ``R' / R``. Raises :class:`StackingError`
        if no winding gives every strand the rods' length, or the contact check fails.
    """
    h = require_positive("thickness", thickness)
    g0 = require_positive("gap", gap)
    n = require_positive_int("elements_per_segment", elements_per_segment)
    if not (math.isfinite(tube) and tube >= 1.0):
        raise RodstabInputError(f"tube must be at least 1 (a >= d), got {tube!r}")
    if int(turns) != turns or turns < 1:
        raise RodstabInputError(f"turns must be a whole number >= 1, got {turns!r}")
    lobes = _Lobes(a)
    m = lobes.m
    ph = 45.0 / m if phase is None else float(phase)
    # The elements are chords and stand up to l^2 kappa / 4 nearer one another than the
    # strands (two sagittas; kappa: the lobe's plus the winding's): the strands are put that
    # much further apart, so that the elements keep the gap g0 (as stack_loops does).
    wind = math.radians(180.0 / m + 360.0 * turns) * 1.5  # |theta'| <= 1.5 Delta in the window
    d = h + g0
    for _ in range(3):
        kappa = 1.0 / lobes.R + tube * d * (wind / lobes.L) ** 2
        d = h + g0 + CHORD_MARGIN * (lobes.L / n) ** 2 * kappa / 4.0
    tube_a = tube * d
    segs = a.segments
    def mean(R: float) -> float:
        return float(np.mean([_length(k, lobes, tube_a, R, turns, ph, 0.0)
                              for k in range(2 * m)])) - lobes.L

    search = find_roots(mean, 0.5 * lobes.R, 1.5 * lobes.R)
    found = search.roots
    if not found or not search.converged:
        raise StackingError(f"no lobe radius gives the braid's strands the rods' mean length "
                            f"(a = {tube_a:g}, {turns} turn(s))")
    R = min((r.x for r in found), key=lambda x: abs(x - lobes.R))
    window = math.radians(180.0 / m + 360.0 * turns) / (4 * math.pi)
    betas = []
    for k in range(2 * m):
        def excess(b: float, k: int = k) -> float:
            return _length(k, lobes, tube_a, R, turns, ph, b) - lobes.L

        search = find_roots(excess, -window, window)
        roots = search.roots
        if not roots or not search.converged:
            raise StackingError(f"strand {segs[k].name!r}: no beta in (+-{window:.4g}) gives it "
                                f"the rods' length {lobes.L:g} (a = {tube_a:g}, {turns} "
                                f"turn(s)); turns = 1 closed the hexagram's eight at h/L "
                                "0.002 to 0.02, turns = 2 did not")
        betas.append(min((r.x for r in roots), key=abs))
    # strand points on a fine table, and the planar segment's own direction
    sig = np.linspace(0.0, 1.0, PLACE_POINTS)
    strands, ends = [], {}
    for k, sg in enumerate(segs):
        pts = _strand(k, sg, lobes, tube_a, d, R, turns, ph, betas[k], sig)
        strands.append(pts)
        for end, p, s_end in (("start", pts[0], 0.0), ("end", pts[-1], sg.length)):
            q = np.asarray(sg.position(np.array([s_end])), float).reshape(2)
            ends[(sg.name, end)] = p - np.array([q[0], q[1], 0.0])
    rod = common_rod(a, n, load_factor, end_offsets=ends)
    new = rod.copy()
    for k in range(len(segs)):
        pts = strands[k]
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        nodes = _segment_nodes(new, k)
        at = np.linspace(0.0, arc[-1], len(nodes))
        new.x[nodes[1:-1]] = np.column_stack([np.interp(at[1:-1], arc, pts[:, c])
                                              for c in range(3)])
    new.align_frames()
    model = default_model(h) if model is None else model
    kappa = 1.0 / R + tube_a * (math.radians(180.0 / m + 360.0 * turns) + 2 * math.pi
                                * max(abs(b) for b in betas)) ** 2 / lobes.L ** 2
    lmax = float(np.max(np.linalg.norm(new.x[new.edge_nodes[:, 1]]
                                       - new.x[new.edge_nodes[:, 0]], axis=1)))
    chord_error = lmax**2 * kappa / 4.0
    check = check_stacked(new, model, g0)
    layers = tuple((sg.name, math.cos(_theta(k, m, turns, ph, betas[k], np.zeros(1))[0][0]),
                    math.sin(_theta(k, m, turns, ph, betas[k], np.zeros(1))[0][0]))
                   for k, sg in enumerate(segs))
    return StackedState(
        rod=new, method=f"figure-eight braid: {m} strands a lobe on tubes of radius "
        f"{tube_a:.6g}, {180 / m + 360 * turns:g} deg round the tube a rod",
        thickness=h, gap=g0, layers=layers,
        changes=(f"lobe radius R' = {R:.9g} ({R / lobes.R:.6g} R)",
                 "beta (deg): " + ", ".join(f"{sg.name} {math.degrees(b):.4f}"
                                            for sg, b in zip(segs, betas, strict=True)),
                 f"welds: connectors (2a + d) = {2 * tube_a + d:.6g} across the tangent at P"),
        chord_error=chord_error, max_strain=_strain(new),
        max_offset=float(np.max(np.linalg.norm(new.x - rod.x, axis=1))), check=check)



def hold_braid(a: Assembly, elements_per_segment: int, load_factor: float,
               thickness_ratio: float, dhat_fraction: float = START_DHAT, *, turns: int = 1,
               contact: bool = True) -> tuple[StackedState, DiscreteRod, bool, int, float]:
    """Build the braided figure-eight and relax it at ``load_factor`` with contact.

    Rods of thickness ``h = thickness_ratio L`` (capsules; ``dhat = dhat_fraction h``, the
    stiffness of :func:`~rodstab.nonlinear.equilibrium.rod_contact_model`), every pair
    started ``dhat / 2`` apart (:func:`braid_eight`), relaxed with contact
    (:func:`~rodstab.nonlinear.newton.relax`: Newton, then down any unstable mode). The built
    braid is far from equilibrium (its strands tighten into a bundle); relaxed at once with a
    small ``dhat`` Newton ends elsewhere or nowhere (measured: h/L = 0.01, 16 el.: not
    converged at dhat = 0.05 h, another state 0.021 higher at 0.025 h). So it is relaxed at
    :data:`START_DHAT` first, and ``dhat`` is then halved to the one asked, relaxed each time
    (6 Newton iterations a halving there). ``contact`` False: the same braided model (welds,
    offsets) relaxed without contact, its rods free to pass one another.

    Returns
    -------
    tuple
        The built state (:class:`~.stacking.StackedState`), the relaxed rod (with its contact
        model attached), and Newton's ``(converged, iterations, residual)`` at the last step.
    """
    from ..nonlinear.contact import attach_contact
    from ..nonlinear.equilibrium import rod_contact_model
    from ..nonlinear.newton import relax as relax_down

    h = require_positive("thickness_ratio", thickness_ratio) * a.segments[0].length
    q = require_positive("dhat_fraction", dhat_fraction)
    ladder = [max(q, START_DHAT)]
    while ladder[-1] > q:
        ladder.append(max(q, 0.5 * ladder[-1]))
    model = rod_contact_model(a, h, ladder[0])
    st = braid_eight(a, elements_per_segment, load_factor, h, 0.5 * model.dhat, turns=turns,
                     model=model)
    rod = st.rod.copy()
    rod.load_factor = float(load_factor)
    ok, its, res = False, 0, math.nan
    for step_q in ladder if contact else ladder[:1]:
        if contact:
            rod.contact = None
            attach_contact(rod, rod_contact_model(a, h, step_q))
        ok, its, res = relax_down(rod)
        if not ok:
            break
    return st, rod, ok, its, res


def braid_limits(a: Assembly, no_contact: tuple[float, float], *, thickness_ratio: float = 0.01,
                 elements_per_segment: int = 16, dhat_fraction: float = START_DHAT,
                 start_load_factor: float | None = None, turns: int = 1,
                 scan_steps: int = SCAN_STEPS, window: float = WINDOW_WIDTHS,
                 contact: bool = True) -> StackedLimits:
    """Return the stable interval in ``mu`` of the braided figure-eight held with contact.

    :func:`hold_braid` at ``start_load_factor`` (default: the middle of ``no_contact``), then
    followed both ways in the load factor as the stacked N-loop ring is
    (:func:`~.stacked.stacked_limits`: steps of the no-contact interval's width over
    ``scan_steps``, ``window`` widths past each end; the first sign change of the verdict
    eigenvalue bracketed and refined; a jump of the eigenvalue, a Newton failure or a state
    that leaves the branch, as Newton past a fold finds one, reported as the branch ending,
    never as a limit). ``contact`` False: the same braided model without contact.
    ``benchmarks/eight_braid_fold.py`` locates the branch's ends by arclength continuation too.
    """
    from .stacked import _side, describe

    lo, hi = (float(v) for v in no_contact)
    if not lo < hi:
        raise RodstabInputError(f"no_contact must be an interval (lo < hi), got {no_contact!r}")
    mu0 = 0.5 * (lo + hi) if start_load_factor is None else float(start_load_factor)
    if not lo < mu0 < hi:
        raise RodstabInputError(f"start_load_factor must lie inside the no-contact interval "
                                f"({lo:.6g}, {hi:.6g}), got {start_load_factor!r}")
    steps = require_positive_int("scan_steps", scan_steps)
    w = require_positive("window", window)
    st, rod, ok, its, res = hold_braid(a, elements_per_segment, mu0, thickness_ratio,
                                       dhat_fraction, turns=turns, contact=contact)
    first = describe(rod, st.rod, ok, its, res)
    if not first.stable:
        raise RodstabInputError(f"start_load_factor {mu0!r}: the relaxed braid is not stable "
                                f"(converged {ok}, eigenvalue {first.lowest_eigenvalue:.3g}); "
                                "start elsewhere")
    step = (hi - lo) / steps
    width = hi - lo
    lower = _side(rod, st.rod, mu0, -step, lo - w * width)
    upper = _side(rod, st.rod, mu0, step, hi + w * width)
    return StackedLimits(len(a.segments), float(thickness_ratio), int(elements_per_segment),
                         float(dhat_fraction), bool(contact), (lo, hi), step, first, lower,
                         upper)
