"""By how much contact moves a stacked state's limit: the minimum of the form on the cone.

:mod:`.cone` decides whether contact at zero gap keeps a no-contact limit ``mu_c`` or moves it
outward. This module finds where it moves it to: the first load factor past ``mu_c`` at which
P2 (2.12, FE) is no longer positive on the cone ``C = {v : g_i(v) >= 0}`` of perturbations that
close no gap between touching layers (the gaps of :func:`.cone.touching_pairs`, first order,
``n_z (w_a - w_b)``). At each load the question "is ``v^T K(mu) v > 0`` on ``C``" is decided
with a certificate by :func:`rodstab.numerics.copositive.positive_on_cone` (an eigen-split of
``K`` and exact least-distance programmes: positive, or a witness perturbation, or undecided).

Search (scan, then refine; the window from the no-contact interval): loads ``mu_c +- i dmu``,
``dmu`` = :data:`SCAN_STEPS`-th of the no-contact interval's width, out to
:data:`WINDOW_WIDTHS` widths; the first load with a witness and the last certified one bracket
the limit with contact, which bisection shrinks to :data:`XTOL` (relative). The bracket is
certified at both ends: positive on the cone at its inner end (or ``mu_c`` itself, where ``K``
is positive semi-definite), a witness at its outer end. An undecided load (more than two non-
positive directions, or the arcs not certified in the allowed solves) is bisected against the
last certified load for a witness before it; failing one, the scan goes on past it, and ends
with what is certified so far, said so, if no witness follows. A load where the form is
positive again after a witness, between two scan points, is not looked for.

What it is exact for: the FE's perturbations are P2's, out of plane (``w`` and the twist); a
gap whose normal has an in-plane part (the torus curve's, the hexagon's) is only tested in its
height component. An in-plane part of a perturbation costs energy but can open such a gap, so
the limit with contact against every perturbation lies between ``mu_c`` and the one given here
(equal where the touching layers' normals are vertical: flat layers).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..errors import NotConverged, RodstabInputError, require_positive, require_positive_int
from ..linear.solve import linear_pencil, linear_stability
from ..model import Assembly
from ..numerics.copositive import NOT_POSITIVE, POSITIVE, positive_on_cone
from ..results import Result
from .cone import MAX_DENSE_DOF, gap_changes, torus_normal, touching_pairs

#: Scan step: this fraction of the no-contact interval's width (or of ``max(|mu_c|, 1)`` when
#: the interval is one-sided).
SCAN_STEPS = 40
#: How far past ``mu_c`` the scan goes, in widths.
WINDOW_WIDTHS = 1.0
#: The search window of :func:`rod_cone_limits` with ``held_closed``, in widths: pairs held
#: closed stiffen the stack far more than the cone (the 3-loop circular ring's upper limit
#: moves 1.4 widths past the no-contact one).
HELD_WINDOW_WIDTHS = 3.0
#: The bracket is refined to this, relative to ``max(|mu|, 1)``.
XTOL = 1e-5


@dataclasses.dataclass(frozen=True)
class ConeLimit(Result):
    """The limit with contact at zero gap on one side of the no-contact interval.

    Attributes
    ----------
    side : str
        ``"lower"`` or ``"upper"``.
    no_contact : float
        ``mu_c``, the no-contact limit (FE of P2).
    status : str
        ``"bracketed"`` (the limit with contact lies in ``bracket``), ``"beyond window"``
        (positive on the cone up to ``bracket[0]``, the window's end) or ``"undecided"``
        (certified up to ``bracket[0]``; ``message`` says what stopped it).
    bracket : tuple of float
        ``(certified positive on the cone, witness of instability)`` in load factor, the first
        nearer ``mu_c``; the second is ``nan`` unless bracketed.
    load_factor : float
        The bracket's midpoint (``nan`` unless bracketed).
    shift : float
        ``load_factor - mu_c`` (outward positive on both sides; ``nan`` unless bracketed).
    decisions : int
        Loads decided.
    message : str
    """

    side: str
    no_contact: float
    status: str
    bracket: tuple[float, float]
    load_factor: float
    shift: float
    decisions: int
    message: str


@dataclasses.dataclass(frozen=True)
class ConeLimits(Result):
    """Both sides' limits with contact at zero gap (:func:`cone_limits` and the others).

    ``interval``: the no-contact limits the searches start from; ``elements_per_segment``: the
    mesh (0 for :func:`ring_cone_limits`, which has none).
    """

    interval: tuple[float, float]
    lower: ConeLimit | None
    upper: ConeLimit | None
    elements_per_segment: int
    method: str


def _bisect(decide: Any, inner: float, outer: float, far: float, xtol: float
            ) -> tuple[float, float, int, str]:
    """Shrink towards the limit from ``inner`` (certified positive on the cone).

    ``outer``: a load with a witness (``nan``: none yet); ``far``: an undecided load beyond
    (``nan``: none). Bisects against ``outer`` if known, else ``far``, to ``xtol`` (relative);
    an undecided midpoint moves ``far`` while no witness is known, and stops the refinement
    once one is. Returns ``(inner, outer, decisions, why it stopped early or "")``.
    """
    count, why = 0, ""
    while True:
        target = outer if math.isfinite(outer) else far
        if abs(target - inner) <= xtol * max(abs(inner), 1.0):
            return inner, outer, count, why
        mid = 0.5 * (inner + target)
        d = decide(mid)
        count += 1
        if d.status == NOT_POSITIVE:
            outer = mid
        elif d.status == POSITIVE:
            inner = mid
        elif math.isfinite(outer):
            return inner, outer, count, f"; refinement stopped at {mid:.6g}: {d.message}"
        else:
            far, why = mid, d.message


def _search(decide: Any, mu_c: float, sign: float, width: float, side: str,
            xtol: float = XTOL, window: float = WINDOW_WIDTHS) -> ConeLimit:
    """Scan outward from ``mu_c``, then bisect the first certified bracket (module doc).

    An undecided scan load (next to the limit, where the form's minimum on the cone is within
    the decision's floor of zero; or where the next modes cross and ``K`` has more
    non-positive directions than the decision handles) is bisected towards, for a witness
    before it; failing that, the scan goes on past it, and a witness found there closes a
    bracket whose inner end is the last load certified before the undecided one.
    """
    step = width / SCAN_STEPS
    inner, count, undecided = mu_c, 0, ""
    for i in range(1, int(math.ceil(SCAN_STEPS * window)) + 1):
        mu = mu_c + sign * i * step
        d = decide(mu)
        count += 1
        if d.status == POSITIVE:
            if not undecided:
                inner = mu
            continue
        witness = d.status == NOT_POSITIVE
        if not witness and undecided:
            continue
        inner, outer, more, why = _bisect(decide, inner, mu if witness else math.nan,
                                          math.nan if witness else mu, xtol)
        count += more
        if not math.isfinite(outer):
            undecided = f"{why or d.message} (certified to {inner:.6g})"
            continue
        mid = 0.5 * (inner + outer)
        stopped = why if why.startswith(";") else ""
        if undecided and not stopped:
            stopped = f"; undecided between: {undecided}"
        return ConeLimit(side, mu_c, "bracketed", (inner, outer), mid, sign * (mid - mu_c),
                         count, "certified: positive on the cone at the inner end (or the "
                         "no-contact limit), a witness at the outer" + stopped)
    if undecided:
        return ConeLimit(side, mu_c, "undecided", (inner, math.nan), math.nan, math.nan, count,
                         undecided)
    return ConeLimit(side, mu_c, "beyond window", (inner, math.nan), math.nan, math.nan, count,
                     f"positive on the cone out to {inner:.6g} ({window:g} widths of "
                     "the no-contact interval)")


#: Both ends of the interval: what the searches look for by default.
SIDES = ("lower", "upper")


def _check_sides(sides: tuple[str, ...]) -> tuple[str, ...]:
    if not sides or any(x not in SIDES for x in sides):
        raise RodstabInputError(f"sides must be some of {SIDES}, got {sides!r}")
    return tuple(sides)


def _both_sides(decide: Any, lo: float, hi: float, xtol: float, start: Any = None,
                sides: tuple[str, ...] = SIDES, window: float = WINDOW_WIDTHS
                ) -> tuple[ConeLimit | None, ConeLimit | None]:
    """Search each finite end of the no-contact interval ``(lo, hi)`` outward (:func:`_search`).

    ``start(mu_c, sign, width)``: the load the search starts from (default ``mu_c``); only the
    ``sides`` asked for are searched (the others are None).
    """
    both = math.isfinite(lo) and math.isfinite(hi)
    out: list[ConeLimit | None] = []
    for mu_c, sign, side in ((lo, -1.0, "lower"), (hi, 1.0, "upper")):
        if not math.isfinite(mu_c) or side not in sides:
            out.append(None)
            continue
        width = (hi - lo) if both else max(abs(mu_c), 1.0)
        mu0 = float(mu_c) if start is None else start(float(mu_c), sign, width)
        out.append(_search(decide, mu0, sign, width, side, xtol, window))
    return out[0], out[1]


#: A cone row this small against the largest is a gap nothing changes (a normal with no height,
#: up to round-off): dropped, since scaled to unit length its round-off sign would constrain.
ZERO_ROW_RTOL = 1e-9


def _unit_rows(D: np.ndarray) -> np.ndarray:
    """Return the cone's rows scaled to unit length, those below :data:`ZERO_ROW_RTOL` dropped."""
    norms = np.linalg.norm(D, axis=1)
    keep = norms > ZERO_ROW_RTOL * (float(np.max(norms)) if norms.size else 0.0)
    return D[keep] / norms[keep, None]


def cone_limits(a: Assembly, layers: dict[str, Any] | str, elements_per_segment: int = 24,
                *, xtol: float = XTOL, sides: tuple[str, ...] = SIDES,
                pairs: Any = None, held_closed: bool = False) -> ConeLimits:
    """Limits with contact at zero gap: where P2 stops being positive on the cone (module doc).

    Parameters
    ----------
    a : Assembly
        The planar held state with stacked rods (as for :func:`.cone.contact_cone`).
    layers : dict or "torus"
        The layer order (:func:`.cone.touching_pairs`); not re-checked here for realisability
        (:func:`.cone.contact_cone` does that).
    elements_per_segment : int
        FE mesh of P2.
    xtol : float
        The bracket's width to refine to, relative to ``max(|mu|, 1)``.
    sides : tuple of str
        The ends to search (``"lower"``, ``"upper"``).
    pairs : list, optional
        The touching pairs in :func:`.cone.touching_pairs`' form, given instead of the ones
        ``layers`` makes (a stacking it cannot name: benchmarks/folded_three_loops.py).
    held_closed : bool
        Every touching pair's gap held at zero both ways (as :func:`rod_cone_limits`): the
        bound of a stack whose every pair presses.

    Returns
    -------
    ConeLimits
        Per finite side of the no-contact interval asked for, the certified bracket of the
        limit with contact (load factors); None for a side not asked for or not finite.
    """
    from scipy.linalg import null_space

    sides = _check_sides(sides)
    n = require_positive_int("elements_per_segment", elements_per_segment)
    lin = linear_stability(a, n)
    pencil = linear_pencil(a, n)
    if pencil.K0.shape[0] > MAX_DENSE_DOF:
        raise RodstabInputError(f"elements_per_segment = {n}: {pencil.K0.shape[0]} FE unknowns, "
                                f"more than the dense solve's {MAX_DENSE_DOF}")
    pairs = touching_pairs(a, layers, n) if pairs is None else pairs
    N = null_space(pencil.G.toarray())
    K0 = N.T @ pencil.K0.toarray() @ N
    K1 = N.T @ pencil.K1.toarray() @ N
    D = _unit_rows(gap_changes(pencil, pairs, N)[0])  # side by side (n_z = 0): no row
    if held_closed and len(D):  # definiteness on the subspace D v = 0
        Z = null_space(D)
        K0, K1, D = Z.T @ K0 @ Z, Z.T @ K1 @ Z, np.zeros((0, Z.shape[1]))

    def decide(mu: float) -> Any:
        return positive_on_cone(K0 + mu * K1, D)

    lo, hi = lin.load_factor_interval
    lower, upper = _both_sides(decide, lo, hi, xtol, sides=sides,
                               window=HELD_WINDOW_WIDTHS if held_closed else WINDOW_WIDTHS)
    where = ("the subspace holding every touching pair's gap closed" if held_closed
             else "the cone of gap-keeping perturbations at zero gap")
    return ConeLimits((float(lo), float(hi)), lower, upper, n,
                      f"minimum of P2 (2.12, FE) on {where} (out of plane): certified decisions "
                      "(eigen-split + least-distance programmes), scanned and bisected in the "
                      "load factor")


#: Fourier modes ``j = 0 .. RING_MODES`` of eq. (3.2) in :func:`ring_cone_limits` (``j = N``,
#: the rigid tilt, left out), and samples per loop of the torus's gaps.
RING_MODES = 48
RING_SAMPLES = 192


def ring_cone_limits(b1: float, b2: float, loops: int, modes: int = RING_MODES,
                     samples: int = RING_SAMPLES, *, xtol: float = XTOL) -> ConeLimits:
    """Compute the N-loop ring's limits with contact on the torus from eq. (3.2)'s modes.

    An independent discretisation of :func:`cone_limits`' question for the ring: P2 is block
    diagonal in the modes ``omega = A cos(k theta)``, ``beta = B sin(k theta)`` and their
    quarter-period shifts, ``k = j / N`` (:func:`rodstab.analytic.ring.ring_mode_pencil`; one
    prefactor for every ``j >= 1``), and ``w = int beta ds = -(R B / k) cos(k theta)``. The gaps
    are the torus's (:func:`.cone.ring_mode_margin`'s geometry): loop ``m`` at azimuth ``phi``
    sits at ``psi_m = (phi + 2 pi m) / N``, neighbours touch with ``n_z`` the height of their
    unit normal, and the gap changes by ``n_z (w_a - w_b)`` at ``samples`` azimuths per pair.
    Load factor ``mu = R kappa_n = 1 - M`` (the FE's for :func:`rodstab.problems.ring.build`).
    """
    from ..analytic.ring import ring_mode_pencil, ring_stability

    require_positive("b1", b1)
    require_positive("b2", b2)
    N = require_positive_int("loops", loops)
    js = [j for j in range(1, require_positive_int("modes", modes) + 1) if j != N]
    nb = 2 * len(js)  # (A, B) per phase
    K0 = np.zeros((2 * nb, 2 * nb))
    K1 = np.zeros_like(K0)
    phi = np.linspace(0.0, 2 * math.pi, require_positive_int("samples", samples),
                      endpoint=False)
    pairs = sorted({(min(m, (m + 1) % N), max(m, (m + 1) % N)) for m in range(N)
                    if m != (m + 1) % N})
    rows = []
    for ka, kb in pairs:
        _, nz = torus_normal(phi, ka, kb, N)
        D = np.zeros((len(phi), 2 * nb))
        for i, j in enumerate(js):
            k = j / N
            A, C = ring_mode_pencil(k, b1, b2)
            for ph in range(2):  # phase 0: cos/sin; phase 1: shifted a quarter period
                sl = slice(ph * nb + 2 * i, ph * nb + 2 * i + 2)
                K0[sl, sl] = A - C  # A - M C with M = 1 - mu: (A - C) + mu C
                K1[sl, sl] = C
                ta, tb = phi + 2 * math.pi * ka, phi + 2 * math.pi * kb
                wa = -np.cos(k * ta) / k if ph == 0 else -np.sin(k * ta) / k
                wb = -np.cos(k * tb) / k if ph == 0 else -np.sin(k * tb) / k
                D[:, ph * nb + 2 * i + 1] = nz * (wa - wb)
        rows.append(D)
    Dm = _unit_rows(np.vstack(rows))
    an = ring_stability(b1, b2, N)
    lo, hi = 1.0 - an.M_interval[1], 1.0 - an.M_interval[0]

    def decide(mu: float) -> Any:
        return positive_on_cone(K0 + mu * K1, Dm)

    lower, upper = _both_sides(decide, lo, hi, xtol)
    return ConeLimits((lo, hi), lower, upper, 0,
                      f"minimum of P2 on the torus's cone in eq. (3.2)'s Fourier modes j <= "
                      f"{modes} (closed-form 2x2 pencils), {samples} azimuths per pair")


#: Held node positions closer than this fraction of the mean element length coincide.
NODE_COINCIDE = 1e-6


def rod_cone_limits(a: Assembly, layers: dict[str, Any] | str, elements_per_segment: int = 24,
                    *, normals: str = "full", thickness_ratio: float = 1e-3,
                    xtol: float = XTOL, sides: tuple[str, ...] = SIDES,
                    held_closed: bool = False) -> ConeLimits:
    """Find the limits with contact at zero gap on the nonlinear engine's rod, in-plane included.

    The same question as :func:`cone_limits` on another discretisation, which also has the
    in-plane motions: the discrete rod (:func:`rodstab.nonlinear.discrete.discretise`) at its
    planar held state, its Hessian in Kirchhoff coordinates
    (:meth:`~rodstab.nonlinear.discrete.DiscreteRod.kirchhoff_hessian`) restricted to the
    inextensible, unshearable motions (every edge's strain unknowns ``eta = 0``) and to the
    closure constraints, affine in the load factor. The touching pairs are pairs of
    coincident nodes (not joints) whose layers touch, as in :func:`.cone.touching_pairs`; a
    pair's gap changes by ``n . (dx_a - dx_b)`` with ``n`` the unit normal between the layers
    (:func:`_rod_gap_rows`). ``normals="height"`` keeps only ``n``'s height component (the
    FE's model: it must then agree with :func:`cone_limits` to the meshes' error); ``"full"``
    lets an in-plane motion open a gap too.

    The no-contact limits ``mu_c`` the search starts from are the rod's own (the lowest
    eigenvalue's sign change next to the FE's, :func:`_own_limit`), so a shift is contact's,
    not the two discretisations' difference. ``sides``: the ends searched (as
    :func:`cone_limits`).

    ``held_closed``: every touching pair's gap held at zero both ways (the subspace ``D v =
    0`` in place of the cone ``D v >= 0``): layers pressed together with a force, which a
    perturbation can neither open (first order, it would do work against the force) nor
    close. Its limits lie outside the cone's (a subspace of the cone); those of a stack whose
    pairs carry force, as the nonlinear method's at finite thickness, lie between the two as
    the force vanishes (docs/theory/contact.md).
    """
    from scipy.linalg import null_space

    from ..nonlinear.contact_chords import position_map
    from ..nonlinear.discrete import discretise

    sides = _check_sides(sides)
    n = require_positive_int("elements_per_segment", elements_per_segment)
    require_positive("thickness_ratio", thickness_ratio)
    if normals not in ("full", "height"):
        raise RodstabInputError(f"normals must be 'full' or 'height', got {normals!r}")
    rods = [discretise(a, n, mu) for mu in (0.0, 1.0)]
    khs = [r.kirchhoff_hessian() for r in rods]
    kh, rod = khs[0], rods[0]
    ne = len(rod.R_edge)
    eta = kh.border + np.arange(3 * ne)
    keep = np.setdiff1d(np.arange(kh.A.shape[0]), eta)
    Q = null_space(kh.G.toarray()[:, keep])
    A0 = kh.A.toarray()[np.ix_(keep, keep)]
    A1 = khs[1].A.toarray()[np.ix_(keep, keep)] - A0
    K0, K1 = Q.T @ A0 @ Q, Q.T @ A1 @ Q
    T = position_map(rod, kh.zmap, kh.chord, kh.border).toarray()[:, keep] @ Q
    D = _rod_gap_rows(a, rod, T, layers, normals, thickness_ratio)
    if not len(D):  # never the whole space in silence: the limits would be the no-contact ones
        raise RodstabInputError(
            f"layers = {layers!r}: no two nodes of touching layers coincide on the rod's mesh "
            f"of {n} elements per segment (rods of unequal lengths do not share nodes); the "
            "rod engine's cone needs them")
    rows, Kf = len(D), (K0, K1)  # the no-contact limits are the whole space's
    if held_closed:  # definiteness on the subspace: the cone module's plain case (no rows)
        Z = null_space(D)
        K0, K1, D = Z.T @ K0 @ Z, Z.T @ K1 @ Z, np.zeros((0, Z.shape[1]))

    def decide(mu: float) -> Any:
        return positive_on_cone(K0 + mu * K1, D)

    lo, hi = linear_stability(a, n).load_factor_interval
    lower, upper = _both_sides(decide, lo, hi, xtol,
                               lambda mu_c, sign, width: _own_limit(*Kf, mu_c, sign, width),
                               sides, HELD_WINDOW_WIDTHS if held_closed else WINDOW_WIDTHS)
    own = tuple(float(side.no_contact) if side is not None else float(mu)
                for side, mu in ((lower, lo), (upper, hi)))
    where = ("on the subspace of perturbations holding every touching pair's gap closed"
             if held_closed else "on the cone of gap-keeping perturbations at zero gap")
    return ConeLimits((own[0], own[1]), lower, upper, n,
                      f"minimum of the discrete rod's inextensible Hessian (Kirchhoff "
                      f"coordinates) {where}, {rows} touching node pairs, normals "
                      f"{normals!r}: certified decisions, scanned and bisected in the load "
                      "factor")


def limits_with_contact(a: Assembly, layers: dict[str, Any] | str, elements_per_segment: int = 24,
                        *, xtol: float = XTOL, sides: tuple[str, ...] = SIDES) -> ConeLimits:
    """Return the limits with contact at zero gap under every perturbation, in-plane included.

    Where every touching pair's normal is a height (flat layers: the bi-rod, the eight's
    lobes), in-plane motions change no gap and the planar state's second variation does not
    couple them to the out-of-plane ones, so the FE's out-of-plane question
    (:func:`cone_limits`, whose gap samples are denser) is the whole question. Otherwise (a
    polygon, the torus) the rod engine with the full normals (:func:`rod_cone_limits`).
    ``method`` of the result names the engine.
    """
    pairs = touching_pairs(a, layers, require_positive_int("elements_per_segment",
                                                           elements_per_segment))
    if pairs and all(np.all(np.abs(np.abs(nz) - 1.0) <= 1e-12) for *_, nz in pairs):
        return cone_limits(a, layers, elements_per_segment, xtol=xtol, sides=sides)
    return rod_cone_limits(a, layers, elements_per_segment, xtol=xtol, sides=sides)


def _node_places(rod: Any) -> tuple[np.ndarray, np.ndarray]:
    """Per node: its segment (-1 for a node of two or more: a joint) and arc length on it."""
    nx = len(rod.x)
    seg_of = np.full(nx, -2)
    s_of = np.zeros(nx)
    for k in range(len(rod.assembly.segments)):
        es = np.flatnonzero(rod.edge_segment == k)
        nodes = np.r_[rod.edge_nodes[es, 0], rod.edge_nodes[es[-1], 1]]
        s = np.r_[0.0, np.cumsum(rod.rest_length[es])]
        for i, si in zip(nodes, s, strict=True):
            seg_of[i] = k if seg_of[i] in (-2, k) else -1
            s_of[i] = si
    return seg_of, s_of


def _rod_gap_rows(a: Assembly, rod: Any, T: np.ndarray, layers: dict[str, Any] | str,
                  normals: str, thickness_ratio: float) -> np.ndarray:
    """Return the rows ``n . (T_a - T_b)`` (unit norm) of the touching coincident node pairs.

    The normal from ``b`` to ``a`` is the layers': for offsets ``(u, k)`` (units of the
    spacing) ``((u_a - u_b) d1, k_a - k_b)``, ``d1 = t x e3`` turned by the segment's sense as
    :func:`~.stacking.stack_layers` does; on the torus, loop ``m`` at azimuth ``theta`` at
    ``psi = (theta + 2 pi m) / N`` (as :func:`.cone._torus_pairs`), ``(cos psi_a - cos psi_b)
    e_r + (sin psi_a - sin psi_b) e3``, ``e_r`` outward from the ring's centre.
    """
    from .cone import _loops
    from .stacking import _senses, layer_offsets

    x = rod.x
    le = float(np.mean(rod.rest_length))
    seg_of, s_of = _node_places(rod)
    names = [sg.name for sg in a.segments]
    torus = isinstance(layers, str)
    if isinstance(layers, str):
        from .folding import folded_layers

        N = _loops(a)
        single = len(a.segments) == 1
        loop = a.segments[0].length / N if single else a.segments[0].length
        centre = np.mean(x, axis=0)
    else:
        off = layer_offsets(names, layers)
        sense = _senses(rod, thickness_ratio * a.total_length / len(names))
    rows = []
    for i in range(len(x)):
        if seg_of[i] < 0:
            continue
        close = np.flatnonzero(np.linalg.norm(x[i + 1:] - x[i], axis=1) <= NODE_COINCIDE * le)
        for j in close + i + 1:
            if seg_of[j] < 0:
                continue
            ia, ib = int(seg_of[i]), int(seg_of[j])
            if torus:
                ka = int(s_of[i] // loop) if single else ia
                kb = int(s_of[j] // loop) if single else ib
                theta = 2 * math.pi * (s_of[i] % loop) / loop
                if layers == "folded":  # flat layers: touching where one layer apart
                    d = folded_layers(N, np.array([theta]))[[ka, kb], 0]
                    if ka == kb or not math.isclose(abs(d[0] - d[1]), 1.0):
                        continue
                    nr, nz = 0.0, float(np.sign(d[0] - d[1]))
                elif (ka - kb) % N not in (1, N - 1) or ka == kb:
                    continue
                else:
                    nr, nz = torus_normal(theta, ka, kb, N)
                er = (x[i] - centre) * np.array([1.0, 1.0, 0.0])
                nrm = nr * er / np.linalg.norm(er) + nz * np.array([0.0, 0.0, 1.0])
            else:
                (ua, ka_), (ub, kb_) = off[names[ia]], off[names[ib]]
                if abs(math.hypot(ua - ub, ka_ - kb_) - 1.0) > 1e-9:
                    continue
                e = np.flatnonzero((rod.edge_segment == ia)
                                   & np.any(rod.edge_nodes == i, axis=1))[0]
                t = x[rod.edge_nodes[e, 1]] - x[rod.edge_nodes[e, 0]]
                d1 = sense[ia] * np.cross(t / np.linalg.norm(t), [0.0, 0.0, 1.0])
                nrm = (ua - ub) * d1 + (ka_ - kb_) * np.array([0.0, 0.0, 1.0])
            nrm = nrm / np.linalg.norm(nrm)
            if normals == "height":
                nrm = np.array([0.0, 0.0, nrm[2]])
            rows.append(nrm @ (T[3 * i: 3 * i + 3] - T[3 * j: 3 * j + 3]))
            if torus:
                # The loops' junctions are smooth: no cusp whose strands' order ties them
                # there. Samples toward them, whose normal turns along the edge, over-
                # constrained (held closed: the 3-loop rectangle h/t = 2 stayed at N x one
                # loop, 8.4254 at 48 el., against an independent derivation's 7.966; without
                # them 7.8771, 7.9449 at 24, 48 el.).
                continue
            rows.extend(nrm @ r for r in _edge_rows(rod, T, i, int(j), seg_of,
                                                   NODE_COINCIDE * le))
    return _unit_rows(np.array(rows).reshape(-1, T.shape[1]))


def _edge_rows(rod: Any, T: np.ndarray, i: int, j: int, seg_of: np.ndarray, tol: float
               ) -> list[np.ndarray]:
    """Displacement differences near two joints at one place next to a touching pair ``(i, j)``.

    Where the edges from ``i`` and from ``j`` end at two different joints at one place (the
    welds of a cusp point, whose strands' order can tie their motions together there), the
    points ``xi = 1 - 2^-G`` of the way along both edges (``G`` = :data:`~.cone.WELD_GRADING`)
    are paired as the nodes are, as the FE's samples are graded toward a weld
    (:func:`.cone._touching_pairs`). The rod's centreline is straight between nodes, so the
    differences are linear in ``xi`` and this one point's row implies every ``xi`` before it.
    Each item: the ``(3, c)`` difference ``T_a - T_b`` there.
    """
    from .cone import WELD_GRADING

    E, x = rod.edge_nodes, rod.x
    xi = 1.0 - 0.5 ** WELD_GRADING
    out = []
    for ea in np.flatnonzero(np.any(E == i, axis=1)):
        ip = int(E[ea, 1] if E[ea, 0] == i else E[ea, 0])
        if seg_of[ip] != -1:
            continue
        for eb in np.flatnonzero(np.any(E == j, axis=1)):
            jp = int(E[eb, 1] if E[eb, 0] == j else E[eb, 0])
            if jp != ip and seg_of[jp] == -1 and np.linalg.norm(x[jp] - x[ip]) <= tol:
                out.append((1.0 - xi) * (T[3 * i: 3 * i + 3] - T[3 * j: 3 * j + 3])
                           + xi * (T[3 * ip: 3 * ip + 3] - T[3 * jp: 3 * jp + 3]))
    return out


#: The rod's own no-contact limit is looked for within this many widths of the FE's.
OWN_WINDOW = 0.05


def _own_limit(K0: np.ndarray, K1: np.ndarray, mu_c: float, sign: float, width: float) -> float:
    """Return the rod's no-contact limit next to the FE's ``mu_c`` (lowest eigenvalue's zero).

    Bracketed by steps doubling from ``1e-4`` widths, inward (stable, positive) and outward
    (negative), within :data:`OWN_WINDOW` widths; refined by Brent
    (:func:`rodstab.numerics.refine_root`).
    """
    from scipy.linalg import eigh

    from ..numerics import refine_root

    def low(mu: float) -> float:
        return float(eigh(K0 + mu * K1, eigvals_only=True, subset_by_index=[0, 0])[0])

    ends = []
    for direction, want in ((-sign, 1.0), (sign, -1.0)):
        step, found = 1e-4 * width, None
        while step <= OWN_WINDOW * width:
            if want * low(mu_c + direction * step) > 0:
                found = mu_c + direction * step
                break
            step *= 2
        if found is None:
            raise NotConverged(f"the rod's own no-contact limit is not within {OWN_WINDOW:g} "
                               f"widths of the FE's {mu_c:.6g} (the two discretisations differ "
                               "more than that on this mesh: give more elements per segment)")
        ends.append(found)
    return float(refine_root(low, min(ends), max(ends)))
