"""Does contact change a stacked state's stability limit? The linear method (issue 21, part 3).

At the idealised stacked state -- layers at zero gap, no contact force -- contact adds no
energy; it only restricts the perturbations to those that do not close a gap between layers
that touch, given their order. The second variation must then be positive on that **cone**,
not on the whole space. Write ``v`` for a perturbation and ``K(mu)`` for P2 (2.12) on the
admissible unknowns (:func:`rodstab.linear.solve.linear_pencil`); the cone is ``C = {v : g_i(v)
>= 0}``, ``g_i`` the first-order change of gap ``i``.

At a no-contact limit ``mu_c`` of multiplicity ``m``, ``K(mu_c)`` is positive semi-definite
with the critical eigenspace ``Phi`` (``m`` modes) as its null space. Two cases, decided
exactly:

* Some nonzero ``c`` has ``g_i(Phi c) >= 0`` for every ``i``: that critical mode keeps every
  gap open, it is admissible, and the limit with contact is ``mu_c`` -- **unchanged**.
* None has: on the compact set ``C`` intersected with the unit sphere the quadratic form
  ``v^T K(mu_c) v`` vanishes only on ``Phi`` (the held state stable in its plane, as the paper
  assumes: an in-plane part, which could open a gap the out-of-plane part closes, costs
  energy), which it does not meet, so its minimum there is
  positive and stays positive a little past ``mu_c``: contact **moves the limit outward** (the
  stable interval widens there; by an amount this method does not give, which needs the
  minimum of the form on the cone). Contact at zero gap can only widen the interval: it
  removes perturbations, it adds no energy.

The gaps. Layers are offsets ``(u, k)`` of the planar centrelines, in units of the spacing
``h + g0`` (:func:`rodstab.multistable.stacking.stack_layers`; ``u`` in the plane along the
in-plane normal the stacked rods share, ``k`` along ``e3``). Two segments touch where their
held centrelines coincide and their offsets are one spacing apart; the normal from ``b`` to
``a`` is ``n = (u_a - u_b, k_a - k_b)``. P2's modes are out-of-plane (``w = u3`` and the twist),
so their gap change is ``n_z (w_a - w_b)`` with ``n_z = k_a - k_b``; the in-plane part of a
general perturbation is zero on the critical modes and does not enter the test of the first
case. A pair side by side in the plane (``n_z = 0``) is never closed by them.

What it is exact for: the first-order (cone) condition at zero gap. A critical mode that moves
touching layers together (gap change zero everywhere, e.g. the bi-rod) passes the test with
equality -- tangent to the cone's boundary -- and second-order effects of finite thickness can
then go either way: the nonlinear method with contact (:mod:`.stacked`) decides those.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..errors import (
    RodstabInputError,
    require_in_range,
    require_positive,
    require_positive_int,
)
from ..linear.solve import linear_pencil, linear_stability, node_fields
from ..model import CONTACT_DHAT_FRACTION, CONTACT_THICKNESS_RATIO, Assembly
from ..results import Result

#: Held centrelines closer than this fraction of the total length coincide (stacked).
COINCIDE_TOL = 1e-9
#: Offsets this close to one spacing apart touch.
TOUCH_TOL = 1e-9
#: A gap change counts as zero below this, the modes scaled to ``max |w| = 1`` (their
#: round-off: ~3e-13 on the bi-rod, whose layers move together; the FE's error is in the
#: load, not in a sign).
GAP_ROUNDOFF = 1e-9
#: Samples per element where the gap changes are tested (the element's nodes and thirds).
SAMPLES_PER_ELEMENT = 3
#: Extra samples toward a welded end, at ``2^-k`` (``k = 1 ..``) of the first sample spacing.
#: Where welds meet at one point the layers' order round them can tie the strands' motions
#: together there (the hexagram's eight: a cycle of orders forces equal heights at its weld
#: point); uniform samples reach that only as the mesh refines (the folded six-ring's limit
#: with contact, circle, 16/32 el.: 1.2420/1.2456 uniform, 1.2484/1.2484 graded; the eight's
#: upper, h/t = 4, 16 el.: 4.995 at 3 samples per element, 5.167 at 96, 5.1777 graded 8, 5.1795
#: graded 16).
WELD_GRADING = 8
#: Modes whose own critical load (first order: ``mu_c - lambda / x^T K1 x``) lies within this
#: of ``mu_c`` (relative to ``max(|mu_c|, 1)``) make up the critical eigenspace: a ring's pair
#: of Fourier modes split by the mesh (~1e-5 at 24 elements per loop, rectangle h/t = 2, where
#: the engine's multiplicity rule counts them apart) is one eigenspace; the next modes are
#: ~0.1 away. "Unchanged" thus means: to within this fraction.
CLUSTER_RTOL = 1e-3
#: The critical eigenspace is found by dense linear algebra (a null space and a symmetric
#: eigen solve, O(n^3)): up to this many FE unknowns (3960, the 3-loop ring at 330 elements
#: per loop: 17 s for both limits on one core).
MAX_DENSE_DOF = 4000
#: Elements per full turn of a segment, at least, of the nonlinear mesh on which the layer
#: order is built and checked (:func:`contact_cone`).
CHECK_ELEMENTS = 32
#: Points of the coarse search for the matching point on the other segment.
MATCH_GRID = 2001


@dataclasses.dataclass(frozen=True)
class ConeSide(Result):
    """The verdict at one end of the no-contact interval.

    Attributes
    ----------
    load_factor : float
        The no-contact limit ``mu_c`` (FE of P2).
    multiplicity : int
        Dimension of the critical eigenspace tested (:data:`CLUSTER_RTOL`: may exceed the
        engine's count, which splits a ring's pair of modes beyond its tolerance).
    unchanged : bool
        True: a critical mode keeps every gap open (the limit with contact is ``mu_c``);
        False: every critical mode closes a gap somewhere (contact moves the limit outward).
    margin : float
        The best combination's smallest gap change over its largest (``-1 .. 1``; >= 0 when
        unchanged; 0 when the mode moves the touching layers together). At a double limit the
        best on the unit circle of the orthonormal modes (free of the eigensolver's basis); at
        a simple one the mode itself; for three or more modes the linear programme's, whose
        size (not sign) depends on the basis.
    largest_gap_change : float
        The best combination's largest ``|n_z (w_a - w_b)|`` (mode scaled to ``max |w| = 1``):
        0 means the layers move together.
    closes_at : str
        Where the best combination closes a gap (empty when unchanged).
    """

    load_factor: float
    multiplicity: int
    unchanged: bool
    margin: float
    largest_gap_change: float
    closes_at: str


@dataclasses.dataclass(frozen=True)
class ContactCone(Result):
    """Both ends of the no-contact interval of a stacked state, tested against the cone.

    ``realised``: how the layer order was shown free of interpenetration (built and checked
    with the contact model, or for a figure-eight its lobes only, :func:`check_lobes`).
    """

    interval: tuple[float, float]
    lower: ConeSide | None
    upper: ConeSide | None
    pairs: tuple[str, ...]
    elements_per_segment: int
    method: str
    realised: str = ""
    #: The built order's ribbon self-linking (:func:`~.linking.self_linking`; None where not
    #: built or not given): states of one ring with other numbers are other objects.
    linking: int | None = None


def _hermite(s_nodes: np.ndarray, w: np.ndarray, dw: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Evaluate at ``s`` the cubic Hermite interpolant of ``(w, dw)`` at the nodes."""
    from scipy.interpolate import CubicHermiteSpline

    return np.asarray(CubicHermiteSpline(s_nodes, w, dw, axis=0)(s))


def _matches(a: Assembly, ia: int, ib: int, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For held points ``s`` of segment ``ia``: the nearest arc length on ``ib``, its distance."""
    sa, sb = a.segments[ia], a.segments[ib]
    p = sa.position(s)
    grid = np.linspace(0.0, sb.length, MATCH_GRID)
    q = sb.position(grid)
    k = np.argmin(np.linalg.norm(p[:, None, :] - q[None, :, :], axis=2), axis=1)
    # Refine on the held arc: the foot of the perpendicular, by Newton on (q(t) - p) . t(t).
    t = grid[k]
    for _ in range(4):
        tan = sb.tangent(t)
        f = np.einsum("ij,ij->i", sb.position(t) - p, tan)
        t = np.clip(t - f, 0.0, sb.length)  # d/dt of f = 1 + O(k |q - p|)
    return t, np.linalg.norm(sb.position(t) - p, axis=1)


Pairs = list[tuple[int, int, np.ndarray, np.ndarray, np.ndarray]]


def _touching_pairs(a: Assembly, offsets: dict[str, tuple[float, float]], n: int) -> Pairs:
    """``(ia, ib, s_a, s_b, n_z)`` for every pair of segments that lie on one another and touch.

    Samples: :data:`SAMPLES_PER_ELEMENT` per element of ``ia``, graded toward its welded ends
    (:data:`WELD_GRADING`), where the held centrelines coincide (within :data:`COINCIDE_TOL`
    of the total length), except at a welded end of either segment (the rod engine's
    :func:`.cone_limit.rod_cone_limits` likewise pairs no joint node).
    """
    tol = COINCIDE_TOL * a.total_length
    out = []
    names = [s.name for s in a.segments]
    welded = {e for j in a.joints() if len(j) > 1 for e in j}
    for ia in range(len(names)):
        for ib in range(ia + 1, len(names)):
            (ua, ka), (ub, kb) = offsets[names[ia]], offsets[names[ib]]
            if abs(math.hypot(ua - ub, ka - kb) - 1.0) > TOUCH_TOL:
                continue
            la = a.segments[ia].length
            s = np.linspace(0.0, la, SAMPLES_PER_ELEMENT * n + 1)
            near = la / (SAMPLES_PER_ELEMENT * n) * 0.5 ** np.arange(1, WELD_GRADING + 1)
            none = np.zeros(0)
            s = np.unique(np.r_[s, near if (names[ia], "start") in welded else none,
                                la - near if (names[ia], "end") in welded else none])
            t, dist = _matches(a, ia, ib, s)
            on = dist <= tol
            # Not at a weld: there the spanning weld joins the layers and their order does not
            # hold (with the weld points the folded ring's limits with contact jump with the
            # mesh, 1.25-1.77; without, they converge: docs/theory/contact.md).
            lb = a.segments[ib].length
            on[0] &= (names[ia], "start") not in welded
            on[-1] &= (names[ia], "end") not in welded
            for k in (0, len(s) - 1):
                for end, at in (("start", 0.0), ("end", lb)):
                    if abs(t[k] - at) <= tol and (names[ib], end) in welded:
                        on[k] = False
            if np.count_nonzero(on) >= 2:
                out.append((ia, ib, s[on], t[on], np.full(np.count_nonzero(on), ka - kb)))
    return out


def _loops(a: Assembly) -> int:
    """Loops of an N-loop ring (N >= 2), else 0.

    One segment per loop (``rodstab.problems.ring.build``: full loops of one circle from one
    point), or one segment winding ``N`` times round its circle (a design's single ``ring``).
    """
    segs = a.segments
    first = segs[0]
    turns = abs(first.curvature * first.length) / (2 * math.pi)
    if len(segs) == 1:
        return round(turns) if round(turns) >= 2 and math.isclose(turns, round(turns),
                                                                  rel_tol=1e-9) else 0
    same = all(
        math.isclose(abs(s.curvature * s.length), 2 * math.pi, rel_tol=1e-9)
        and math.isclose(s.curvature, first.curvature, rel_tol=1e-12)
        and math.dist(s.start, first.start) <= COINCIDE_TOL * a.total_length
        and math.isclose(s.angle, first.angle, rel_tol=0.0, abs_tol=1e-12) for s in segs)
    return len(segs) if same else 0


#: How a figure-eight's order is checked (:func:`check_lobes`).
EIGHT_REALISED = ("lobes only: each lobe's strands one spacing apart or more; the weld point, "
                  "where every weld meets and the strands' order changes, is not built by "
                  "the cone (the nonlinear engine's equilibrium --layers braid builds one)")


def figure_eight(a: Assembly) -> int:
    """Strands per lobe ``m`` of a figure-eight, else 0.

    A figure-eight: ``2m >= 4`` segments, each a full circle from one point ``P``, segment
    ``k``'s end welded to segment ``k + 1``'s start (cyclically) with the tangent reversed (a
    cusp), the even segments on one circle and the odd on another (the hexagram's eight:
    all six welds at ``P``, three rods stacked on each lobe).
    """
    segs = a.segments
    if len(segs) < 4 or len(segs) % 2:
        return 0
    tol = COINCIDE_TOL * a.total_length
    joints = {frozenset(j) for j in a.joints()}
    p = np.asarray(segs[0].start, dtype=float)
    far = [sg.position(np.array([0.5 * sg.length]))[0] for sg in segs]
    for k, sg in enumerate(segs):
        nxt = segs[(k + 1) % len(segs)]
        if not (math.isclose(abs(sg.curvature * sg.length), 2 * math.pi, rel_tol=1e-9)
                and np.linalg.norm(np.asarray(sg.start, dtype=float) - p) <= tol
                and frozenset({(sg.name, "end"), (nxt.name, "start")}) in joints
                and np.allclose(nxt.tangent(0.0), -sg.tangent(sg.length), atol=1e-9)
                and np.linalg.norm(far[k] - far[k % 2]) <= tol):
            return 0
    return len(segs) // 2 if np.linalg.norm(far[0] - far[1]) > tol else 0


def lobe_layers(a: Assembly) -> dict[str, int]:
    """Flat layers of a figure-eight's lobes in traversal order: ``0, 1, ..`` on each lobe."""
    return {sg.name: k // 2 for k, sg in enumerate(a.segments)}


def check_lobes(a: Assembly, layers: dict[str, Any]) -> None:
    """Refuse a figure-eight's order with two strands of a lobe less than one spacing apart.

    ``StackingError`` (exit 2) naming them; unknown or missing names: ``RodstabInputError``.
    The weld point, where every weld meets and the order changes, is not built here (the
    cone's state has flat layers on the lobes; :mod:`.braid` builds a braided eight).
    """
    from .stacking import StackingError, layer_offsets

    segs = a.segments
    off = layer_offsets([sg.name for sg in segs], layers)
    for lobe in (0, 1):
        names = [sg.name for sg in segs[lobe::2]]
        for i, na in enumerate(names):
            for nb in names[i + 1:]:
                d = math.dist(off[na], off[nb])
                if d < 1.0 - TOUCH_TOL:
                    raise StackingError(
                        f"the stacked eight interpenetrates: segments {na!r} and {nb!r} lie on "
                        f"one lobe {d:.4g} spacings apart (layers {layers[na]!r} and "
                        f"{layers[nb]!r}); give each strand of a lobe its own layer")


def _torus_pairs(a: Assembly, n: int, folded: bool = False) -> Pairs:
    """Touching pairs of the N-loop ring stacked on the ``(N, 1)`` torus curve, at zero gap.

    ``folded``: of the ring folded flat instead (:func:`~.folding.folded_layers`: ``n_z = +-1``
    where two loops' layers differ by one, 0 elsewhere).

    Loop ``k`` (traversal order: segment ``k``, or the ``k``-th turn of a single segment) at
    azimuth ``theta`` is at the angle ``psi_k = (theta + 2 pi k) / N`` of the curve's
    cross-section (:func:`.stacking.torus_curve`: radial offset ``a cos psi``, height ``a sin
    psi``): loops ``k, k + 1`` (mod ``N``) are neighbouring vertices of its ``N``-gon and touch,
    with the normal from ``b`` to ``a`` ``(cos psi_a - cos psi_b, sin psi_a - sin psi_b) /
    |.|``, whose height component is ``n_z``; it turns along the ring, so no flat order holds
    the loops.
    """
    N = _loops(a)
    if not N:
        raise RodstabInputError(f"layers={'folded' if folded else 'torus'!r} needs an N-loop "
                                "ring: N >= 2 full loops of one circle, one segment each in "
                                "traversal order (rodstab.problems.ring.build) or one segment "
                                "of N turns")
    single = len(a.segments) == 1
    loop = a.segments[0].length / N if single else a.segments[0].length
    out = []
    s = np.linspace(0.0, loop, SAMPLES_PER_ELEMENT * (n // N if single else n) + 1)
    theta = 2 * math.pi * s / loop
    pairs = {(k, (k + 1) % N) for k in range(N)}
    if folded:
        from .folding import folded_layers

        layer = folded_layers(N, theta)
        pairs = {(ka, kb) for ka in range(N) for kb in range(ka + 1, N)}
    for ka, kb in sorted({(min(p), max(p)) for p in pairs if p[0] != p[1]}):
        if folded:
            d = layer[ka] - layer[kb]
            nz = np.where(np.isclose(np.abs(d), 1.0), np.sign(d), 0.0)
        else:
            _, nz = torus_normal(theta, ka, kb, N)
        if single:
            out.append((0, 0, s + ka * loop, s + kb * loop, nz))
        else:
            out.append((ka, kb, s, s.copy(), nz))
    return out


def torus_normal(theta: Any, ka: int, kb: int, loops: int) -> tuple[Any, Any]:
    """Return the unit normal from loop ``kb`` to ``ka`` on the ``(N, 1)`` torus at ``theta``.

    Loop ``m`` sits at the angle ``psi_m = (theta + 2 pi m) / N`` of the curve's cross-section
    (radial offset ``cos psi``, height ``sin psi``, :func:`.stacking.torus_curve`); returns the
    normal's radial and height components ``(n_r, n_z)`` (arrays like ``theta``).
    """
    pa, pb = (theta + 2 * math.pi * ka) / loops, (theta + 2 * math.pi * kb) / loops
    dr, dz = np.cos(pa) - np.cos(pb), np.sin(pa) - np.sin(pb)
    size = np.hypot(dr, dz)
    return dr / size, dz / size


def touching_pairs(a: Assembly, layers: dict[str, Any] | str, n: int) -> Pairs:
    """Return the touching pairs of a layer order, on ``n`` elements.

    ``layers``: ``"torus"`` (the wound N-loop ring), ``"folded"`` (the N-loop ring folded flat,
    :func:`~.folding.folded_layers`) or offsets. Each ``(ia, ib, s_a, s_b, n_z)``: the
    segments, the matched arc lengths on each and the normal's height component there
    (:func:`_touching_pairs`, :func:`_torus_pairs`).
    """
    from .stacking import layer_offsets

    if isinstance(layers, str):
        return _torus_pairs(a, n, folded=layers == "folded")
    return _touching_pairs(a, layer_offsets([s.name for s in a.segments], layers), n)


def _best_combination(A: np.ndarray) -> tuple[np.ndarray, float]:
    """``c`` with ``max |c| = 1`` maximising ``min_i (A c)_i``, and that minimum.

    Every nonzero ``c`` scales to one with some ``c_j = +-1``: one linear programme per
    ``(j, sign)`` (HiGHS), ``max t`` subject to ``A c >= t``, ``-1 <= c <= 1``.
    """
    from scipy.optimize import linprog

    rows, m = A.shape
    best_c, best_t = np.zeros(m), -math.inf
    for j in range(m):
        for sign in (1.0, -1.0):
            bounds = [(-1.0, 1.0)] * m + [(None, None)]
            bounds[j] = (sign, sign)
            res = linprog(np.r_[np.zeros(m), -1.0], A_ub=np.c_[-A, np.ones(rows)],
                          b_ub=np.zeros(rows), bounds=bounds, method="highs")
            if res.status != 0:
                raise RodstabInputError(f"the cone test's linear programme failed: {res.message}")
            if -res.fun > best_t:
                best_c, best_t = res.x[:m], -res.fun
    return best_c, best_t


def gap_matrix(a: Assembly, pencil: Any, mu_c: float, mult: int, pairs: Pairs,
               null: np.ndarray | None = None, *, scaled: bool = True
               ) -> tuple[np.ndarray, list[tuple[str, str, float, float]]]:
    """Gap changes of the critical modes: ``A[i, k] = n_z (w_a - w_b)`` at sample ``i``, mode ``k``.

    The critical eigenspace of ``K(mu_c)`` on the closure constraints (dense): the ``mult``
    eigenvectors with the eigenvalues nearest zero, and any other whose own critical load is
    within :data:`CLUSTER_RTOL` of ``mu_c``; each scaled to ``max |w| = 1``. Rows: every
    sample of every touching pair, named ``(a, b, s on a, s on b)`` in the second return value.
    ``null``: the closure constraints' null space, if already computed (the same at both ends).
    ``scaled`` False: the eigenvectors as the eigensolver gives them, orthonormal in the
    reduced unknowns, unscaled. Within a multiple eigenvalue the solver's basis is arbitrary
    (it changed with the BLAS kernels), so a size measured on the unit circle of combinations
    is basis-free only in these columns (:func:`circle_scan_margin`); the verdict (a
    combination keeping every gap, or none) does not depend on it.
    """
    A, scale = gap_changes(pencil, pairs, critical_modes(pencil, mu_c, mult, null))
    return (A / np.where(scale > 0, scale, 1.0) if scaled else A), _where(a, pairs)


def _where(a: Assembly, pairs: Pairs) -> list[tuple[str, str, float, float]]:
    """Name every row of :func:`gap_matrix`: ``(a, b, s on a, s on b)``."""
    names = [s.name for s in a.segments]
    return [(names[ia], names[ib], float(x), float(y)) for ia, ib, sa, sb, _ in pairs
            for x, y in zip(sa, sb, strict=True)]


def critical_modes(pencil: Any, mu_c: float, mult: int, null: np.ndarray | None = None
                   ) -> np.ndarray:
    """Return the critical eigenspace of :func:`gap_matrix` (orthonormal, pencil unknowns)."""
    from scipy.linalg import eigh, null_space

    if pencil.K0.shape[0] > MAX_DENSE_DOF:
        raise RodstabInputError(
            f"the cone test solves dense and the FE has {pencil.K0.shape[0]} unknowns, more "
            f"than {MAX_DENSE_DOF}: give fewer elements per segment (--elements)")
    K = (pencil.K0 + mu_c * pencil.K1).toarray()
    N = null_space(pencil.G.toarray()) if null is None else null
    lam, X = eigh(N.T @ K @ N)
    near = np.argsort(np.abs(lam))[: max(mult, 1) + 8]
    K1n = N.T @ pencil.K1.toarray() @ N
    rayleigh = np.einsum("ij,ij->j", X[:, near], K1n @ X[:, near])
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.abs(lam[near] / rayleigh)
    order = near[(shift <= CLUSTER_RTOL * max(abs(mu_c), 1.0)) | (np.arange(len(near)) < mult)]
    return N @ X[:, order]


def gap_changes(pencil: Any, pairs: Pairs, vecs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First-order gap changes ``n_z (w_a - w_b)`` of perturbations, and their sizes.

    ``vecs`` ``(n_reduced, c)``: perturbations in the pencil's unknowns on the closure
    constraints (``pencil.disc.Z @ vecs`` are full FE vectors). Returns ``(rows, c)`` gap
    changes at every sample of every touching pair (:func:`touching_pairs`' order; linear in
    ``vecs``: with the identity it is the cone's matrix) and each column's ``max |w|``.
    """
    full = np.asarray(pencil.disc.Z @ vecs).reshape(pencil.disc.Z.shape[0], -1)
    fields = [f[1:4] for f in node_fields(pencil.disc, full)]
    scale = np.max([np.max(np.abs(w), axis=0) for _, w, _ in fields], axis=0)
    rows = [nz[:, None] * (_hermite(*fields[ia], sa) - _hermite(*fields[ib], sb))
            for ia, ib, sa, sb, nz in pairs]
    return (np.vstack(rows) if rows else np.zeros((0, full.shape[1]))), scale


def _side(a: Assembly, pencil: Any, mu_c: float, mult: int, pairs: Pairs,
          null: np.ndarray | None = None) -> ConeSide:
    """Decide one no-contact limit against the cone (module doc)."""
    if not pairs:  # nothing touches at zero thickness (the star: only at its welds)
        return ConeSide(float(mu_c), mult, True, 0.0, 0.0, "")
    V = critical_modes(pencil, mu_c, mult, null)
    unscaled, scale = gap_changes(pencil, pairs, V)
    A, where = unscaled / np.where(scale > 0, scale, 1.0), _where(a, pairs)
    mult = A.shape[1]
    c, t = _best_combination(A)
    g = A @ c
    if mult == 2:
        # The verdict is the LP's (exact); the combination reported is the one best on the
        # unit circle of the orthonormal modes, which does not depend on the basis the
        # eigensolver returned (the box LP's did: largest gap change 0.433 or 0.471 on the
        # folded ring's lower limit with two BLAS kernel sets), scaled to max |w| = 1.
        u, _ = _circle_best(unscaled)
        one, w = gap_changes(pencil, pairs, (V @ u)[:, None])
        g = one[:, 0] / max(float(w[0]), 1e-300)
        t = float(np.min(g))
    big = float(np.max(np.abs(g)))
    floor = GAP_ROUNDOFF  # the modes are scaled to max |w| = 1
    unchanged = t >= -floor
    margin = 0.0 if big <= floor else max(-1.0, min(1.0, t / big)) + 0.0
    closes = ""
    if not unchanged:
        i = int(np.argmin(g))
        na, nb, sa, sb = where[i]
        closes = f"between {na!r} at s = {sa:.4g} and {nb!r} at s = {sb:.4g}"
    return ConeSide(float(mu_c), mult, bool(unchanged), float(margin),
                    big if big > floor else 0.0, closes)


def contact_cone(a: Assembly, layers: dict[str, Any] | str, elements_per_segment: int = 32, *,
                 thickness_ratio: float = CONTACT_THICKNESS_RATIO) -> ContactCone:
    """Test each no-contact limit of a stacked planar state against the cone of contact.

    Parameters
    ----------
    a : Assembly
        The planar held state, stacked rods on one another (coincident centrelines).
    layers : dict or "torus"
        Every segment's layer ``k`` or offset ``(u, k)`` in units of the spacing, as for
        :func:`rodstab.multistable.stacking.stack_layers` (e.g.
        :func:`~rodstab.multistable.layer_orders.traversal_layers`); or ``"torus"`` for an N-loop
        ring stacked on the ``(N, 1)`` torus curve (:func:`~.stacking.stack_loops`), whose
        contact normals turn along the ring (:func:`_torus_pairs`).
    elements_per_segment : int
        Mesh of P2's finite elements (:func:`rodstab.linear.solve.linear_stability`).
    thickness_ratio : float
        ``h / L`` (``L`` the mean rod length) at which the layer order is checked to be
        realisable: :func:`~rodstab.multistable.stacking.stack_layers` builds it at gap ``0.05
        h`` and refuses an order whose rods interpenetrate (``StackingError``, exit 2), e.g.
        flat layers for the folded ring. The test itself is at zero gap and thickness.

    Returns
    -------
    ContactCone
        The no-contact interval (load factors) and, at each finite end, whether contact leaves
        it unchanged or raises it (module doc), with the touching pairs tested.
    """
    from ..nonlinear.discrete import discretise as discretise_rod
    from .folding import fold_loops
    from .linking import self_linking
    from .stacking import StackingError, stack_layers, stack_loops

    n = require_positive_int("elements_per_segment", elements_per_segment)
    names = [s.name for s in a.segments]
    hL = require_in_range("thickness_ratio", require_positive("thickness_ratio", thickness_ratio),
                          0.0, 1.0, "h / L")
    h = hL * a.total_length / len(names)
    g0 = 0.5 * CONTACT_DHAT_FRACTION * h
    # The order is built on a mesh of at least CHECK_ELEMENTS per turn, whatever the FE's:
    # its question is geometric, and coarse chords would add their sagitta to the spacing.
    turns = max(1, max(round(abs(sg.curvature * sg.length) / (2 * math.pi)) for sg in a.segments))
    rod = discretise_rod(a, max(n, CHECK_ELEMENTS * turns), 1.0)
    if isinstance(layers, str) and layers not in ("torus", "folded"):
        raise RodstabInputError(f"layers must be a mapping of segment names, 'torus' or "
                                f"'folded', got {layers!r}")
    realised = (f"built at h/L = {hL:g} with gap {CONTACT_DHAT_FRACTION / 2:g} h and checked "
                "with the contact model")
    if isinstance(layers, str):
        pairs = touching_pairs(a, layers, n)  # refuses a design that is no N-loop ring
        try:
            built = (stack_loops if layers == "torus" else fold_loops)(rod, h, g0).rod
        except StackingError:
            raise
        except RodstabInputError as exc:  # too thick for the loops, or no folding (even N)
            raise RodstabInputError(f"the layer order cannot be built at thickness_ratio h/L "
                                    f"= {hL:g} (h = {h:.4g}): {exc}") from None
    elif figure_eight(a):  # every weld at one point: the lobes are checked, not the point
        check_lobes(a, layers)
        realised = EIGHT_REALISED
        pairs = touching_pairs(a, layers, n)
        built = None
    else:  # stack_layers checks the names and the order (exit 2 naming them)
        built = stack_layers(rod, layers, h, g0).rod
        pairs = touching_pairs(a, layers, n)
    lin = linear_stability(a, n)
    pencil = linear_pencil(a, n)
    lo, hi = lin.load_factor_interval
    null = None
    if pairs and pencil.K0.shape[0] <= MAX_DENSE_DOF:
        from scipy.linalg import null_space

        null = null_space(pencil.G.toarray())
    sides = []
    for mu, mult in ((lo, lin.multiplicity_lo), (hi, lin.multiplicity)):
        sides.append(_side(a, pencil, mu, max(int(mult), 1), pairs, null)
                     if math.isfinite(mu) else None)
    return ContactCone(
        (float(lo), float(hi)), sides[0], sides[1],
        tuple(f"{names[ia]}/{names[ib]}" for ia, ib, _, _, _ in pairs), n,
        "first-order cone test of the critical eigenspace of P2 (2.12, FE) at zero gap: "
        "gap changes n_z (w_a - w_b), one LP per (coordinate, sign) (HiGHS)", realised,
        None if built is None else self_linking(built).value)


def is_loop_ring(a: Assembly) -> bool:
    """Whether ``a`` is an N-loop ring (N >= 2): one segment per loop, or one of N turns."""
    return _loops(a) > 0


def default_layers(a: Assembly, thickness_ratio: float = CONTACT_THICKNESS_RATIO,
                   elements_per_segment: int = 32) -> tuple[dict[str, Any] | str, str]:
    """Choose a layer order for the stacked held state of ``a``; say how it was chosen.

    An N-loop ring: ``"torus"`` (flat layers cannot close it). Otherwise each rod, in traversal
    order, on the lowest free layer (:func:`~.layer_orders.traversal_layers`); where that order
    interpenetrates (a cycle of cusps, as the folded ring's), the rods on the vertices of a
    polygon in traversal order (:func:`~.layer_orders.polygon_offsets`). Raises ``StackingError``
    (exit 2) when neither holds, naming the first's failure: give the order.
    """
    from ..nonlinear.discrete import discretise as discretise_rod
    from .layer_orders import polygon_offsets, traversal_layers
    from .stacking import StackingError, stack_layers
    from .states import ring_of

    if is_loop_ring(a):
        return "torus", "the (N, 1) torus curve (an N-loop ring)"
    if figure_eight(a):
        return (dict(lobe_layers(a)),
                "flat layers on each lobe of the eight in traversal order (other orders move "
                "the limits differently; the weld point is not built here: equilibrium "
                "--layers braid builds one)")
    h = thickness_ratio * a.total_length / len(a.segments)
    rod = discretise_rod(a, elements_per_segment, 1.0)
    flat = traversal_layers(rod, h)
    try:
        stack_layers(rod, flat, h, 0.5 * CONTACT_DHAT_FRACTION * h)
        return flat, "flat layers in traversal order"
    except StackingError as first:
        try:
            order = [nm for nm, _ in ring_of(a).order]
        except RodstabInputError:
            raise first from None
        poly = polygon_offsets(order)
        try:
            stack_layers(rod, poly, h, 0.5 * CONTACT_DHAT_FRACTION * h)
        except StackingError:
            raise first from None
        return poly, "a polygon in traversal order (flat layers interpenetrate)"


def ring_mode_margin(j: int, loops: int, samples: int = 720) -> float:
    """Return how well eq. (3.2)'s mode ``j`` of an N-loop ring on the torus keeps the gaps.

    Loop ``m`` at azimuth ``theta`` sits at ``psi_m = (theta + 2 pi m) / N`` of the torus's
    cross-section, and the mode with ``j`` waves along the whole ring moves it out of plane by
    ``cos(k (theta + 2 pi m) + c)``, ``k = j / N`` (eq. 3.2's ``w``; rigid motions move every
    loop at one azimuth alike). Returns the best over the phase ``c`` of the smallest gap change
    ``n_z (w_a - w_b)`` over neighbouring loops and ``theta`` (``samples`` points each): ``>= 0``
    when a phase keeps every gap (up to the scan's resolution), negative otherwise. Independent
    of the FE and of the linear programmes of :func:`contact_cone`.
    """
    th = np.linspace(0.0, 2 * math.pi, samples + 1)
    k = j / loops
    pairs = [(m, (m + 1) % loops) for m in range(loops if loops > 2 else 1)]
    best = -math.inf
    for c in np.linspace(0.0, 2 * math.pi, samples, endpoint=False):
        worst = math.inf
        for b, a in pairs:
            pa, pb = (th + 2 * math.pi * a) / loops, (th + 2 * math.pi * b) / loops
            d = np.stack([np.cos(pa) - np.cos(pb), np.sin(pa) - np.sin(pb)])
            gap = d[1] / np.linalg.norm(d, axis=0) * (np.cos(k * (th + 2 * math.pi * a) + c)
                                                      - np.cos(k * (th + 2 * math.pi * b) + c))
            worst = min(worst, float(np.min(gap)))
        best = max(best, worst)
    return best


def circle_scan_margin(A: np.ndarray) -> float:
    """Best smallest gap change over the unit circle of a two-mode eigenspace, exactly.

    ``A`` (samples x 2) from :func:`gap_matrix`: ``max_u min_i A_i . u`` over unit ``u``. At a
    maximiser either one row is the smallest alone, and ``u`` points along it, or two rows are
    equal, and ``u`` is normal to their difference: every such ``u`` is tried (``O(rows^3)``
    products). A check of the linear programmes that needs none of them. Its sign holds in
    any basis; its size is the eigenspace's own (unchanged by rotating or reflecting the
    basis) for orthonormal modes (``gap_matrix(..., scaled=False)``), and so is
    :func:`relative_circle_margin`.
    """
    return _circle_best(A)[1]


def _circle_best(A: np.ndarray) -> tuple[np.ndarray, float]:
    """Return the maximiser ``u`` (unit, 2) of :func:`circle_scan_margin` and its value."""
    A = np.asarray(A, dtype=float)
    norms = np.linalg.norm(A, axis=1)
    cand = [A[norms > 0] / norms[norms > 0, None]]
    i, j = np.triu_indices(len(A), 1)
    d = A[i] - A[j]
    dn = np.linalg.norm(d, axis=1)
    perp = np.stack([-d[:, 1], d[:, 0]], axis=1)[dn > 0] / dn[dn > 0, None]
    cand += [perp, -perp]
    U = np.vstack(cand)
    if not len(U):  # every row zero: every combination leaves every gap as it is
        return np.array([1.0, 0.0]), 0.0
    best, at = -math.inf, U[0]
    for k in range(0, len(U), 4096):  # bounded memory: a block of candidates at a time
        worst = np.min(U[k:k + 4096] @ A.T, axis=1)
        top = int(np.argmax(worst))
        if worst[top] > best:
            best, at = float(worst[top]), U[k + top]
    return at, best


def relative_circle_margin(A: np.ndarray) -> float:
    """:func:`circle_scan_margin` over the largest gap change of any unit combination.

    That largest change is ``max_i |A_i|`` (row norms), so for orthonormal modes the ratio
    (``-1 .. 1``) depends on the eigenspace only, not on the basis an eigensolver returned.
    """
    big = float(np.max(np.linalg.norm(A, axis=1))) if len(A) else 0.0
    return circle_scan_margin(A) / big if big > 0 else 0.0
