"""Transfer-matrix (shooting) method for the Euler-Lagrange equations of P2.

An independent second method for the clamped arc of Section 3.2: it does not use the paper's
general solution (3.5) or its factorised eigen-equations (3.7)/(3.8), only the second variation.

Derivation (checked symbolically in ``tests/test_transfer.py``). With ``x = s/L`` in ``[0, 1]``,
``u = u3/L``, ``Lbar = L/R`` and the load written as ``m = M Lbar = Lbar - L kappa_n`` (finite in
the straight limit ``Lbar -> 0``), P2 of eq (2.12) is ``B3/(2L)`` times::

    I[u, w] = int_0^1 { b1 (u'' - Lbar w)^2 + b2 (w' + Lbar u')^2
                        - m (Lbar u'^2 + Lbar w^2 + 2 u' w') } dx

whose Euler-Lagrange equations are::

    b1 (u'''' - Lbar w'') - b2 Lbar (w'' + Lbar u'') + m (Lbar u'' + w'') = 0
    b1 Lbar (u'' - Lbar w) + b2 (w'' + Lbar u'') + m (Lbar w - u'') = 0

(eq 3.4 of the paper with ``w''' -> w''`` in the first line and ``w''', u''' -> w'', u''`` in
the second: the printed third derivatives are typos, as a count of derivatives shows).
With the state ``y = (u, u', u'', u''', w, w')`` these are ``y' = S y``; the transfer matrix over
the rod is ``T = expm(S)``. Clamped ends (``u = u' = w = 0``) leave ``(u'', u''', w')(0)`` free
and require rows ``(u, u', w)`` of ``T`` times them to vanish: the 3x3 matrix
:func:`clamped_arc_matrix` is singular exactly at the critical loads.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import cast

import numpy as np

from .errors import NotConverged, RodstabInputError
from .model import FULL_SYSTEM, SUPPORT_KINDS
from .numerics import SINGULAR_TOL, Root, matrix_roots
from .results import Result


def expm(a: np.ndarray) -> np.ndarray:
    """``scipy.linalg.expm``, imported on first use (scipy.linalg costs ~0.1-0.4 s to import)."""
    from scipy.linalg import expm as _expm

    return _expm(a)


def null_space(a: np.ndarray, rcond: float | None = None) -> np.ndarray:
    """``scipy.linalg.null_space``, imported on first use."""
    from scipy.linalg import null_space as _null_space

    return _null_space(a, rcond=rcond)

#: Indices in the state vector y = (u, u', u'', u''', w, w').
_ESSENTIAL = [0, 1, 4]
_FREE = [2, 3, 5]


def arc_system_matrix(L_kappa: float, L_over_R: float, b1: float, b2: float) -> np.ndarray:
    """Return the 6x6 matrix ``S`` of ``y' = S y`` for the clamped-arc P2 (see module docstring).

    ``L_kappa = L kappa_n`` is the load, ``L_over_R = L/R`` (0 for a straight rod).
    """
    Lb = L_over_R
    m = Lb - L_kappa
    S = np.zeros((6, 6))
    S[0, 1] = S[1, 2] = S[2, 3] = 1.0
    S[4, 5] = 1.0
    # Second EL equation solved for w'' = c_u2 u'' + c_w w.
    c_u2 = -(b1 * Lb + b2 * Lb - m) / b2
    c_w = -(-b1 * Lb * Lb + m * Lb) / b2
    # First EL equation: b1 u'''' = (b1 Lbar + b2 Lbar - m) w'' + (b2 Lbar^2 - m Lbar) u''.
    k_w2 = (b1 * Lb + b2 * Lb - m) / b1
    k_u2 = (b2 * Lb * Lb - m * Lb) / b1
    S[5, 2] += c_u2
    S[5, 4] += c_w
    S[3, 2] += k_u2 + k_w2 * c_u2  # u'''' depends on u'' directly and through w''
    S[3, 4] += k_w2 * c_w
    return S


def clamped_arc_matrix(L_kappa: float, L_over_R: float, b1: float, b2: float) -> np.ndarray:
    """3x3 shooting matrix of the arc clamped at both ends; singular at the critical loads."""
    T = expm(arc_system_matrix(L_kappa, L_over_R, b1, b2))
    return T[np.ix_(_ESSENTIAL, _FREE)]


def clamped_arc_mode(
    L_kappa: float, L_over_R: float, b1: float, b2: float, n_points: int = 201
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mode ``(x, u, w)`` at a critical load: null vector of the shooting matrix, propagated.

    ``x`` runs over ``[0, 1]`` (``s = L x``); the mode is scaled so that ``max |u| = 1``.
    """
    S = arc_system_matrix(L_kappa, L_over_R, b1, b2)
    D = clamped_arc_matrix(L_kappa, L_over_R, b1, b2)
    _, _, vt = np.linalg.svd(D)
    y0 = np.zeros(6)
    y0[_FREE] = vt[-1]
    x = np.linspace(0.0, 1.0, n_points)
    step = expm(S * (x[1] - x[0]))
    ys = np.empty((n_points, 6))
    ys[0] = y0
    for i in range(1, n_points):
        ys[i] = step @ ys[i - 1]
    scale = np.max(np.abs(ys[:, 0]))
    scale = scale if scale > 0 else 1.0
    return x, ys[:, 0] / scale, ys[:, 4] / scale


#: Initial states at the arc's midpoint ``x = 1/2`` of each family: the EL equations are
#: invariant under ``x -> 1 - x`` with ``(u, w)`` unchanged, so a mode has ``u`` and ``w`` both
#: even (symmetric: ``u'``, ``u'''``, ``w'`` vanish at the midpoint, ``u``, ``u''``, ``w``
#: free) or both odd (antisymmetric: ``u``, ``u''``, ``w`` vanish, the others free).
ARC_FAMILY_FREE = {"symmetric": [0, 2, 4], "antisymmetric": [1, 3, 5]}


def clamped_half_arc_matrix(L_kappa: float, L_over_R: float, b1: float, b2: float,
                            family: str) -> np.ndarray:
    """3x3 shooting matrix of one family from the midpoint to a clamped end; singular at its loads.

    The rows ``(u, u', w)`` of ``expm(S/2)`` (half the arc, :func:`arc_system_matrix`) times the
    family's free midpoint values (:data:`ARC_FAMILY_FREE`), as an orthonormal basis of their
    span (see the code). The two families' loads are the
    loads of :func:`clamped_arc_matrix`, each family searched alone: a symmetric and an
    antisymmetric load closer than a scan spacing (4.5e-4 apart at ``b1 = 0.19``,
    ``b2 = 0.24``, ``L/R = 16.6``) are two roots of two functions, not a close pair of one;
    and half the length halves the exponential growth where the exponents are real.
    """
    if family not in ARC_FAMILY_FREE:
        raise RodstabInputError(f"family must be 'symmetric' or 'antisymmetric', got {family!r}")
    S = arc_system_matrix(L_kappa, L_over_R, b1, b2)
    # Where exponents are real every column of expm(S/2) is dominated by the growing solution:
    # the columns are nearly parallel, sigma_min/sigma_max ~ e^-(growth) and the row-scaled
    # determinant is round-off (b1 = 46.9, b2 = 0.061, L/R = 6.0: a false root at -8.48, the
    # true one at -276.3). So the family's solutions are propagated in steps that grow by at
    # most e^2 and re-orthonormalised after each (QR with a positive diagonal: continuous in
    # the load); the span, and so the singular loads, are those of expm(S/2) on the family.
    growth = 0.5 * float(np.max(np.abs(np.linalg.eigvals(S).real)))
    steps = max(1, math.ceil(growth / 2.0))
    step = expm(S * (0.5 / steps))
    Y = np.eye(6)[:, ARC_FAMILY_FREE[family]]
    for _ in range(steps):
        Y, R = np.linalg.qr(step @ Y)
        Y = Y * np.sign(np.diag(R))
    return cast(np.ndarray, Y[_ESSENTIAL])


def arc_root_window(L_over_R: float, b1: float, b2: float) -> tuple[float, float]:
    """Return loads ``L kappa_n`` beyond which the clamped arc is proven unstable (test fields).

    The module docstring's ``I[u, w] = Q0 - m Q1`` (``m = Lbar - L kappa_n``) is negative --
    the arc unstable -- at every load beyond ``Lbar - Q0/Q1`` for any admissible field with
    ``Q1 != 0``, so both ends of the stable interval lie between the best such bounds:

    * the twist ``u = 0``, ``w = sin(pi x)``: ``Q0 = (b2 pi^2 + b1 Lbar^2)/2``,
      ``Q1 = Lbar/2`` (the root near ``Lbar (1 - b1)`` of a stiff ``b1``: -295.9 at
      ``b1 = 50``, ``b2 = 1.3``, ``Lbar = 6``, outside any window of a few ``2 pi sqrt(b1 b2)``);
    * ``u = 1 - cos(2 pi n x)``, ``w = g u`` (the straight rod's mode (3.10) for ``n = 1``,
      ``g = 2 pi sqrt(b1/b2)``, exact there), ``n = 1 .. 8``, ``g`` over both signs.

    Returned with a margin of 5 % of the window plus 1: every end lies strictly inside.
    """
    Lb = float(L_over_R)
    bounds: list[float] = []
    if Lb > 0:
        bounds.append(Lb - (b2 * math.pi ** 2 + b1 * Lb * Lb) / Lb)
    n = np.arange(1, 9)[:, None]
    mags = np.geomspace(1e-3, 1e3, 241) * math.sqrt(b1 / b2)
    g = np.concatenate([-mags, mags])[None, :]
    k2 = (2 * math.pi * n) ** 2
    uu, upup, uppupp, uppu = 1.5, 0.5 * k2, 0.5 * k2 * k2, -0.5 * k2  # integrals over [0, 1]
    a = Lb * g
    q0 = b1 * (uppupp - 2 * a * uppu + a * a * uu) + b2 * (g + Lb) ** 2 * upup
    q1 = Lb * upup + Lb * g * g * uu + 2 * g * upup
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.where(q1 != 0, Lb - q0 / q1, np.nan)
    bounds += p[np.isfinite(p)].tolist()
    hi = min([b for b in bounds if b > Lb], default=math.inf)
    lo = max([b for b in bounds if b < Lb], default=-math.inf)
    margin = 0.05 * (hi - lo) + 1.0
    return lo - margin, hi + margin


def arc_phase(L_kappa: np.ndarray, L_over_R: float, b1: float, b2: float) -> np.ndarray:
    """Half-turns of the arc's oscillating solutions: ``sum |Im(eig S)| / (2 pi)``.

    The loads of one family are at least about one half-turn apart, so a scan with a fixed
    number of points per unit of this phase resolves them wherever they crowd.
    """
    Ss = np.array([arc_system_matrix(float(p), L_over_R, b1, b2) for p in L_kappa])
    return cast(np.ndarray, np.abs(np.linalg.eigvals(Ss).imag).sum(axis=1) / (2 * np.pi))


def phase_grid(phase: Callable[[np.ndarray], np.ndarray], lo: float, hi: float,
               per_turn: int, base: int = 64, max_points: int = 200_000,
               extra: tuple[float, ...] = ()) -> np.ndarray:
    """Scan points on ``[lo, hi]`` with at most ``1/per_turn`` of ``phase`` per interval.

    ``base`` uniform intervals plus the ``extra`` points inside, each interval bisected while
    the phase changes by more than ``1/per_turn`` across it (down to 1e-12 of the window).
    Raises :class:`~rodstab.errors.NotConverged` beyond ``max_points``.
    """
    xs = np.linspace(lo, hi, base + 1)
    xs = np.unique(np.concatenate([xs, [x for x in extra if lo < x < hi]]))
    ph = phase(xs)
    while True:
        wide = (np.abs(np.diff(ph)) * per_turn > 1.0) & (np.diff(xs) > 1e-12 * (hi - lo))
        if not wide.any():
            return xs
        if xs.size + wide.sum() > max_points:
            raise NotConverged(f"more than {max_points} scan points needed to resolve the "
                               "phase")
        mid = 0.5 * (xs[:-1] + xs[1:])[wide]
        order = np.argsort(np.concatenate([xs, mid]))
        xs = np.concatenate([xs, mid])[order]
        ph = np.concatenate([ph, phase(mid)])[order]


def ring_system_matrix(M: float, b1: float, b2: float) -> np.ndarray:
    """4x4 matrix of ``y' = S y``, ``y = (omega, omega', beta, beta')``, for the ring (3.1).

    Euler-Lagrange equations of P2 (2.12) in ``theta = s/R`` (checked symbolically in the
    tests; they agree with the paper's (3.1))::

        b2 omega'' + (M - b1) omega + (b1 + b2 - M) beta' = 0
        b1 beta''  + (M - b2) beta  - (b1 + b2 - M) omega' = 0
    """
    c = b1 + b2 - M
    S = np.zeros((4, 4))
    S[0, 1] = 1.0
    S[2, 3] = 1.0
    S[1, 0] = -(M - b1) / b2
    S[1, 3] = -c / b2
    S[3, 2] = -(M - b2) / b1
    S[3, 1] = c / b1
    return S


#: Periodic solutions that exist for every M: the two rigid rotations about in-plane axes.
RING_RIGID_NULLITY = 2


def ring_periodicity_measure(M: float, loops: int, b1: float, b2: float) -> np.ndarray:
    """Singular values of ``T - I``, ``T = expm(2 pi N S)`` (monodromy over the N-loop ring).

    A periodic solution of (3.1) is a null vector of ``T - I``. The two rigid rotations are
    always there, so an eigenvalue ``M`` shows as a third (and, by the cos/sin pairing of the
    modes, fourth) zero singular value. Singular values are returned in decreasing order.
    """
    T = expm(2.0 * np.pi * loops * ring_system_matrix(M, b1, b2))
    return np.linalg.svd(T - np.eye(4), compute_uv=False)


def ring_periodic_null_vectors(M: float, loops: int, b1: float, b2: float,
                               n_null: int = 4) -> np.ndarray:
    """Right singular vectors of ``T - I`` for its ``n_null`` smallest singular values."""
    T = expm(2.0 * np.pi * loops * ring_system_matrix(M, b1, b2))
    _, _, vt = np.linalg.svd(T - np.eye(4))
    return vt[-n_null:]


def _mean_beta_row(M: float, loops: int, b1: float, b2: float) -> np.ndarray:
    """Row ``c`` with ``c . y0 = int_0^{2 pi N} beta dtheta`` for ``y = expm(S theta) y0``."""
    S = ring_system_matrix(M, b1, b2)
    big = np.zeros((8, 8))
    big[:4, :4] = S
    big[:4, 4:] = np.eye(4)
    integral = expm(2.0 * np.pi * loops * big)[:4, 4:]  # int_0^P expm(S theta) dtheta
    return integral[2]


#: The rigid rotations about in-plane axes in the state ``y = (omega, omega', beta, beta')`` at
#: ``theta = 0``: ``omega = cos(theta + phi)``, ``beta = sin(theta + phi)`` solve (3.1) for every
#: ``M`` (the ``k = 1`` pencil of (3.2) is ``(b1 + b2 - M) [[1, -1], [-1, 1]]``), an invariant
#: subspace of ``S`` with exponents ``+-i``. Orthonormal columns.
RING_RIGID_BASIS = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, -1.0], [1.0, 0.0]]) / math.sqrt(2.0)
#: Its orthogonal complement: the initial states that are not a rigid rotation.
RING_DEFORMATION_BASIS = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 1.0], [-1.0, 0.0]]) \
    / math.sqrt(2.0)


def ring_matching_matrix(M: float, loops: int, b1: float, b2: float) -> np.ndarray:
    """``2 sinh(P S / 2) C`` (4x2), ``P = 2 pi N``, scaled: rank-deficient where ``T - I`` is.

    Shoot (3.1) from ``theta = 0`` forwards and backwards by half the ring and match at the
    antipode: ``y(P/2) = expm(P S/2) y0`` and ``y(-P/2) = expm(-P S/2) y0`` are the same state
    of a periodic solution, so periodic solutions are the null vectors of
    ``H = expm(P S/2) - expm(-P S/2) = expm(-P S/2) (T - I)``, ``T`` the monodromy
    (:func:`ring_periodicity_measure`). Unlike ``T - I``, ``H`` has no exponential trend
    hiding roots: where ``S`` has real exponents ``+-a`` (``(b1 - M)(b2 - M) < 0``) both
    grow as ``sinh(a P/2)`` (``T - I`` is dominated by ``e^{aP}`` in ONE direction, and its
    relative smallest singular values fall below any root threshold). ``H`` is divided by
    ``e^{alpha P/2} ||S||_2`` (``alpha`` the largest ``|Re|`` of an eigenvalue of ``S``; both
    exponentials are taken of the shifted ``+-P S/2 - alpha P/2``, so nothing overflows): of
    order one, or of order ``P`` at most, for every ``M``.

    The rigid rotations (:data:`RING_RIGID_BASIS`, exponents ``+-i``, ``sinh(i pi N) = 0``)
    are null vectors at every ``M``; they are removed exactly by restricting ``H`` to their
    complement ``C`` (:data:`RING_DEFORMATION_BASIS`; ``y0 = R a + C b`` is periodic iff
    ``H C b = 0``), not by counting small singular values, whose round-off floor near
    ``M = 0`` (exponents ``+-i`` twice: nearly parallel eigenvectors) reaches 1e-12.
    """
    S = ring_system_matrix(M, b1, b2)
    half = np.pi * loops
    shift = half * float(np.max(np.abs(np.linalg.eigvals(S).real)))
    eye = np.eye(4)
    H = expm(half * S - shift * eye) - expm(-half * S - shift * eye)
    return cast(np.ndarray, H @ RING_DEFORMATION_BASIS / np.linalg.norm(S, 2))


def ring_root_window(b1: float, b2: float) -> tuple[float, float]:
    """Return loads ``M`` that bracket both ends of the ring's stable interval (two test modes).

    The stress-free state ``M = 0`` is stable (P2 positive definite beyond the rigid motions).
    Upper end: the uniform twist (mode ``j = 0`` of (3.2)) makes P2 proportional to
    ``b1 - M``, negative beyond ``M = b1``, so ``M_hi <= b1``. Lower end: the mode
    ``k = (N + 1)/N <= 2`` of (3.2) has the pencil ``A_k - M C_k`` with ``C_k`` indefinite
    (``det C_k = 1 - k^2 < 0``), singular first at ``M^-(k) = (b1 + b2)/2 - sqrt((b1 - b2)^2/4
    + b1 b2 k^2) >= min(b1, b2) - k sqrt(b1 b2) > -2 sqrt(b1 b2)``, and indefinite below it, so
    ``M_lo > -2 sqrt(b1 b2)``. Returned with a margin of 5 %: every root that can end the
    interval lies inside, none at an end of the scan.
    """
    return -2.1 * math.sqrt(b1 * b2), 1.05 * b1


#: Scan points per unit of the ring's phase ``N Re(kappa)`` (adjacent roots of (3.1) differ
#: by 1 in it): every root is then at least this many scan intervals from the next.
RING_SCAN_PER_TURN = 8


def _ring_phase(M: np.ndarray, loops: int, b1: float, b2: float) -> np.ndarray:
    """``N Re(kappa)``: ``+-i kappa`` the exponents of (3.1) besides the rigid ``+-i``.

    From the eigenvalues of ``S`` (``sum |Im| = 2 + 2 Re(kappa)``), vectorised over ``M``.
    Roots are where it is a whole number (not every whole number is a root: the rigid
    rotations, ``kappa = 1``, give one at ``M = b1 + b2`` only).
    """
    Ss = np.array([ring_system_matrix(float(m), b1, b2) for m in M])
    im = np.abs(np.linalg.eigvals(Ss).imag).sum(axis=1)
    return cast(np.ndarray, loops * np.maximum(0.5 * im - 1.0, 0.0))


def ring_scan_grid(b1: float, b2: float, loops: int, lo: float, hi: float,
                   max_points: int = 200_000) -> np.ndarray:
    """Scan points on ``[lo, hi]`` with at most ``1/RING_SCAN_PER_TURN`` of phase per interval.

    Adjacent roots differ by one in the phase :func:`_ring_phase`, which turns fast near
    ``M = b1, b2`` (``kappa ~ sqrt|M - b|``) and for large ``|M|``: a uniform grid of any
    fixed size steps over roots there (``N = 9``, ``b1 = 0.05``: ``M = b1`` and the next root
    are 6e-4 apart on a window of width 3). Starting from 64 uniform intervals plus the points
    ``b1``, ``b2`` (the ``kappa = 0`` roots, with at least three scan intervals between them
    when they differ), every interval with more phase is bisected.
    """
    extra = [b1, b2]
    gap = abs(b1 - b2)
    if gap > 0:
        extra += [b + d * gap / 8 for b in (b1, b2) for d in (-3, -2, -1, 1, 2, 3)]
    try:
        return phase_grid(lambda M: _ring_phase(M, loops, b1, b2), lo, hi, RING_SCAN_PER_TURN,
                          base=64, max_points=max_points, extra=tuple(extra))
    except NotConverged as exc:
        raise NotConverged(f"ring transfer (N = {loops}, b1 = {b1:g}, b2 = {b2:g}): "
                           f"{exc}") from None


def ring_interval_transfer(b1: float, b2: float, loops: int) -> tuple[float, float, list[float]]:
    """Stable interval of ``M`` for the N-loop ring by the monodromy method (second method).

    Finds the periodic solutions of (3.1) beyond the two rigid rotations as the singular
    points of :func:`ring_matching_matrix` (:func:`rodstab.numerics.matrix_roots`),
    outwards from ``M = 0`` in doubling windows up to the bounds :func:`ring_root_window`,
    each scanned on :func:`ring_scan_grid`; drops those that violate closure
    ``int beta dtheta = 0`` (at ``M = b2``, ``beta = const`` -- the paper's "spurious" root),
    and returns ``(M_lo, M_hi, admissible_roots)`` with the admissible roots nearest to
    ``M = 0`` on either side (``admissible_roots``: those of the windows searched). No
    Fourier ansatz, no (3.3): only the window is from test modes. Every minimum of
    the measure is a root or bounded well away from zero (the matching matrix has no
    ill-conditioned non-roots: ``|sin|`` of the phase times a matrix of full rank, or
    ``sinh`` where the exponents are real), so a minimum is a root at ``SINGULAR_TOL``: the
    round-off floor of the half-ring exponentials near ``M = 0`` (1e-11) is above the
    default touching threshold. At a root ``j >= 1`` every periodic deformation closes up
    (``T = I``): the whole matching matrix vanishes, so its ``sigma_min`` is scanned against
    the scan's typical size (``absolute``), not against its own ``sigma_max``.

    Raises :class:`~rodstab.errors.NotConverged` if a side has no admissible root in the
    window (which the window's derivation excludes): never an infinite end.
    """
    lo_w, hi_w = ring_root_window(b1, b2)

    def closes(root: Root) -> bool:
        # The root's periodic deformations: the right singular vectors of H C for its
        # multiplicity's smallest singular values.
        _, _, vt = np.linalg.svd(ring_matching_matrix(root.x, loops, b1, b2))
        null = RING_DEFORMATION_BASIS @ vt[vt.shape[0] - max(root.multiplicity, 1):].T
        c = _mean_beta_row(root.x, loops, b1, b2)
        # Closure removes one null direction unless every periodic solution already closes.
        lost = 1 if np.linalg.norm(c @ null) > 1e-8 * (np.linalg.norm(c) + 1.0) else 0
        return null.shape[1] - lost > 0

    admissible: list[float] = []
    ends = []
    for side, limit in ((-1.0, lo_w), (1.0, hi_w)):
        # Outwards from M = 0 in windows that double (overlapping by a tenth): the first
        # window with an admissible root holds the nearest one, and the roots beyond it are
        # not refined.
        reach, width, nearest = 0.0, abs(limit) / 16, None
        while nearest is None and reach < abs(limit):
            a, b = sorted((side * max(reach - 0.1 * width, 0.0),
                           side * min(reach + width, abs(limit))))
            found = matrix_roots(
                lambda M: ring_matching_matrix(M, loops, b1, b2), a, b,
                grid=ring_scan_grid(b1, b2, loops, a, b), touch_tol=SINGULAR_TOL,
                absolute=True, method_name="half-ring shooting matched at the antipode, "
                                           "phase-resolved sigma_min scan + golden section")
            for root in found.roots:
                if root.x * side > 0 and root.x not in admissible and closes(root):
                    admissible.append(root.x)
                    if nearest is None or abs(root.x) < abs(nearest):
                        nearest = root.x
            reach += width
            width *= 2.0
        if nearest is None:
            raise NotConverged(
                f"ring transfer (b1 = {b1:g}, b2 = {b2:g}, N = {loops}): no admissible root "
                f"{'below' if side < 0 else 'above'} M = 0 up to {limit:g}, where the test "
                "modes of ring_root_window prove one")
        ends.append(nearest)
    return ends[0], ends[1], sorted(admissible)


# --------------------------------------------------------------------------------------------
# Assemblies of straight segments (Sections 4 and 5): general solution per segment, joined by
# the geometric AND the natural joint conditions into one square system.


def straight_segment_system(m: float, B1: float, B2: float) -> np.ndarray:
    """6x6 ``S`` of ``y' = S y``, ``y = (w, w', w'', w''', omega, omega')``, straight held state.

    P2 density ``1/2 {B1 w''^2 + B2 omega'^2 - 2 m w' omega'}`` with held moment
    ``m = B3 (k - kappa_n) = -B3 kappa_n``; Euler-Lagrange (= (4.5), (5.4) with
    ``m = B3 Delta kappa_0``): ``B1 w'''' + m omega'' = 0``, ``B2 omega'' = m w''``.
    """
    S = np.zeros((6, 6))
    S[0, 1] = S[1, 2] = S[2, 3] = S[4, 5] = 1.0
    S[5, 2] = m / B2
    S[3, 2] = -m * m / (B1 * B2)
    return S


def _end_quantities(y: np.ndarray, m: float, B1: float, B2: float) -> dict[str, np.ndarray]:
    """Rows (as linear maps of ``y``) of the end quantities of a straight segment.

    ``V = -(B1 w''' + m omega')`` (shear), ``Mb = B1 w'' + m omega / 2`` (bending moment about
    ``n``), ``Tq = B2 omega' - m w' / 2`` (torque): the coefficients of ``dw``, ``dw'``,
    ``d omega`` in the boundary terms of the first variation of the exact second variation,
    P2's integrand plus its end term ``1/2 m [w' omega]`` (which gives the ``m omega / 2`` and
    ``m w' / 2``; derived at :func:`rodstab.linear.assembly.end_term_matrices`). Without the
    end term the natural joint conditions hold only at smooth welds and cusps.
    """
    w, dw, d2w, d3w, om, dom = (y[i] for i in range(6))
    return {"w": w, "dw": dw, "om": om, "V": -(B1 * d3w + m * dom),
            "Mb": B1 * d2w + 0.5 * m * om, "Tq": B2 * dom - 0.5 * m * dw}


#: Rigid motions of a free planar assembly (translation, two rotations): always in the null
#: space of the assembled system.
ASSEMBLY_RIGID_NULLITY = 3


def straight_assembly_matrix(assembly, mu: float) -> np.ndarray:
    """Square system ``A(mu) c = 0`` of an assembly of straight segments (second method).

    Unknowns: the six initial values ``y_i(0)`` of every segment; ``y_i(L) = expm(S_i L) y_i(0)``
    exactly (no discretisation). At each joint (ends ``e`` with held tangent ``t_e``, normal
    ``n_e = t_e x e3``, sign ``+1`` at an end ``s = L``, ``-1`` at a start): geometric continuity
    of ``w`` and of the rotation vector ``theta_e = w'_e n_e + omega_e t_e``; then either the
    support conditions (clamped: ``w = 0``, ``theta = 0``) or the natural conditions
    ``sum_e sign_e V_e = 0`` and ``sum_e sign_e (Mb_e n_e + Tq_e t_e) = 0``. A free assembly has
    ``ASSEMBLY_RIGID_NULLITY`` null vectors for every ``mu``. Supports are read from
    :data:`~rodstab.model.SUPPORT_KINDS`: a kind holding ``w`` and every rotation gives the
    clamp conditions, kinds without :data:`~rodstab.model.FULL_SYSTEM` in their methods (fork,
    pinned) raise :class:`RodstabInputError`, the rest (free) hold nothing.
    """
    segs = assembly.segments
    for s in segs:
        if s.curvature != 0.0:
            raise RodstabInputError(f"straight_assembly_matrix needs straight segments; "
                                    f"{s.name!r} has curvature {s.curvature!r}")
    n = len(segs)
    index = {s.name: i for i, s in enumerate(segs)}
    rows: list[np.ndarray] = []

    def end_rows(name: str, end: str) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray,
                                                 float]:
        s = segs[index[name]]
        m = -mu * s.B3 * s.natural_curvature
        S = straight_segment_system(m, s.B1, s.B2)
        Y = np.zeros((6, 6 * n))
        Y[:, 6 * index[name]: 6 * index[name] + 6] = (
            np.eye(6) if end == "start" else expm(S * s.length))
        t = s.tangent(0.0 if end == "start" else s.length)
        nrm = np.array([t[1], -t[0]])
        return _end_quantities(Y, m, s.B1, s.B2), t, nrm, (1.0 if end == "end" else -1.0)

    for joint in assembly.joints():
        ends = [end_rows(name, end) for name, end in joint]
        q0, t0, n0, _ = ends[0]
        theta0 = [q0["dw"] * n0[c] + q0["om"] * t0[c] for c in range(2)]
        for q, t, nrm, _ in ends[1:]:
            rows.append(q["w"] - q0["w"])
            for c in range(2):
                rows.append(q["dw"] * nrm[c] + q["om"] * t[c] - theta0[c])
        kinds = [k for name, end, k in assembly.supports if (name, end) in joint]
        held = [SUPPORT_KINDS[k] for k in kinds]
        if any(h.holds_deflection and h.holds_all_rotations for h in held):
            rows += [q0["w"], theta0[0], theta0[1]]
        elif any(FULL_SYSTEM not in h.methods for h in held):
            raise RodstabInputError(f"straight_assembly_matrix supports only clamped or free "
                                    f"joints, got {kinds}")
        else:
            # sum() of arrays (at least one end): an array, never the start value 0.
            rows.append(cast(np.ndarray, sum(sg * q["V"] for q, _, _, sg in ends)))
            for c in range(2):
                rows.append(sum(sg * (q["Mb"] * nrm[c] + q["Tq"] * t[c])
                                for q, t, nrm, sg in ends))
    return np.array(rows)


def straight_assembly_modes(assembly, mu: float, n_points: int = 101,
                            known_nullity: int = ASSEMBLY_RIGID_NULLITY) -> list[dict]:
    """Null vectors of :func:`straight_assembly_matrix` at ``mu``, rigid motions removed.

    Returns one entry per deformation mode: ``{segment name: (x, w, omega)}`` with ``x = s/L``
    in ``[0, 1]``, propagated exactly by ``expm``; every mode is gauged so that ``w``, ``w'``
    and ``omega`` vanish at the start of the first segment (as the paper does for Fig. 9) and
    scaled to ``max |w| = 1``.
    """
    from scipy.linalg import null_space

    A = straight_assembly_matrix(assembly, mu)
    s = np.linalg.svd(A, compute_uv=False)
    null = null_space(A, rcond=max(1e-9, 1e3 * s[-1] / s[0]))
    if known_nullity:
        # Rigid motions: the null space at a load with no eigenvalue nearby (here mu = 0).
        rigid = null_space(straight_assembly_matrix(assembly, 0.0), rcond=1e-9)
        null = null - rigid @ np.linalg.lstsq(rigid, null, rcond=None)[0]
        u, sv, _ = np.linalg.svd(null, full_matrices=False)
        null = u[:, sv > 1e-6 * sv.max()] if sv.size else null
    modes = []
    segs = assembly.segments
    for k in range(null.shape[1]):
        c = null[:, k].copy()
        if known_nullity:
            # Gauge: subtract the rigid motion matching w, w', omega at segment 1's start.
            rig = null_space(straight_assembly_matrix(assembly, 0.0), rcond=1e-9)
            G = rig[[0, 1, 4], :]
            c = c - rig @ np.linalg.lstsq(G, c[[0, 1, 4]], rcond=None)[0]
        mode = {}
        for i, seg in enumerate(segs):
            m = -mu * seg.B3 * seg.natural_curvature
            S = straight_segment_system(m, seg.B1, seg.B2)
            xs = np.linspace(0.0, 1.0, n_points)
            ys = np.array([expm(S * seg.length * x) @ c[6 * i: 6 * i + 6] for x in xs])
            mode[seg.name] = (xs, ys[:, 0], ys[:, 4])
        scale = max(np.max(np.abs(v[1])) for v in mode.values()) or 1.0
        modes.append({k2: (x, w / scale, om / scale) for k2, (x, w, om) in mode.items()})
    return modes


@dataclasses.dataclass(frozen=True)
class FullSystemCritical(Result):
    """Lowest singular load of the full system, in ``lam = B3 kappa L / sqrt(B1 B2)``."""

    lambda_c: float
    multiplicity: int
    next_roots: tuple[float, ...]
    residual: float
    method: str


def full_system_critical(assembly, mu_per_lambda: float, known_nullity: int,
                         lambda_max: float) -> FullSystemCritical:
    """Lowest singular load of :func:`straight_assembly_matrix` for ``0.02 < lam < lambda_max``.

    ``mu_per_lambda`` converts the paper's ``lam`` to the assembly's load factor ``mu``
    (``sqrt(b1 b2)`` for unit lengths and unit natural curvature); ``known_nullity`` counts
    the rigid motions (``ASSEMBLY_RIGID_NULLITY`` for a free assembly, 0 if clamped). One root
    finder on the smallest singular value, with the multiplicity.
    """
    g = mu_per_lambda
    found = matrix_roots(lambda mu: straight_assembly_matrix(assembly, mu), 0.02 * g,
                         lambda_max * g, n_scan=300, known_nullity=known_nullity,
                         method_name="full system of general solutions, sigma_min scan")
    if not found.roots:
        return FullSystemCritical(math.nan, 0, (), math.nan, found.method)
    first = found.roots[0]
    return FullSystemCritical(first.x / g, first.multiplicity,
                              tuple(r.x / g for r in found.roots[1:4]), first.residual,
                              found.method)


# --------------------------------------------------------------------------------------------
# Rings of n identical arcs welded end to start (smooth or at cusps), reduced by their n-fold
# cyclic symmetry to one arc and a Bloch phase per harmonic (the curved-sided hexagram).

#: Joint map of a cusp on ``(u, u', omega, P_u, P_u', P_w)`` (:func:`arc_end_matrix`): the next
#: arc's tangent and normal are the reversed ones, so ``u`` and the shear keep their sign and
#: the slope, the twist and the two moment components change it (continuity of ``u`` and of
#: the rotation vector ``u' n + omega t``, balance of force and moment at the weld).
CUSP_JOINT_MAP = np.diag([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
#: Singular values below this times the largest, at a load where the ring is stable, are its
#: rigid motions (counted per harmonic, then declared to the root finder as known nullity).
RIGID_SV_RTOL = 1e-9


def arc_end_matrix(L_kappa: float, L_over_R: float, b1: float, b2: float) -> np.ndarray:
    """6x6 map from the state ``y`` of :func:`arc_system_matrix` to ``(u, u', omega, P)``.

    ``P = (P_u, P_u', P_w)`` are the coefficients of ``du``, ``du'``, ``d omega`` in the boundary
    terms of the first variation of the module docstring's ``I[u, w]`` (``Lbar = L/R``,
    ``m = Lbar - L kappa_n``)::

        P_u  = -b1 (u''' - Lbar w') + Lbar b2 (w' + Lbar u') - m (Lbar u' + w')
        P_u' =  b1 (u'' - Lbar w)
        P_w  =  b2 (w' + Lbar u') - m u'

    (shear, bending moment about the normal ``n = t x e3`` and torque; at ``Lbar = 0`` the
    ``V``, ``Mb``, ``Tq`` of :func:`straight_segment_system` with ``B3 = 1``, lengths in ``L``).
    """
    Lb = L_over_R
    m = Lb - L_kappa
    G = np.zeros((6, 6))
    G[0, 0] = G[1, 1] = G[2, 4] = 1.0
    G[3, 3] = -b1
    G[3, 5] = b1 * Lb + b2 * Lb - m
    G[3, 1] = b2 * Lb * Lb - m * Lb
    G[4, 2] = b1
    G[4, 4] = -b1 * Lb
    G[5, 5] = b2
    G[5, 1] = b2 * Lb - m
    return G


def weld_joint_map(turn: float) -> np.ndarray:
    """6x6 map of a weld turning the tangent by ``turn`` (radians, about ``e3``) on ``Gt y``.

    ``Gt y = (u, u', omega, P_u, P_u' + m omega / 2, P_w + m u' / 2)`` (:func:`arc_end_matrix`
    with the end term of the exact second variation, :func:`_with_end_term`): ``u`` and the
    shear are scalars along ``e3``; the rotation vector ``u' n + omega t`` and the moment
    ``(P_u' + m omega / 2) n + (P_w + m u' / 2) t`` are continuous vectors of the plane, whose
    components in the next arc's frame ``(n, t)`` turned by ``turn`` are
    ``(cos a x + sin a y, -sin a x + cos a y)``. ``turn = pi`` is :data:`CUSP_JOINT_MAP`,
    ``turn = 0`` the identity.
    """
    c, s = math.cos(turn), math.sin(turn)
    rot = np.array([[c, s], [-s, c]])
    J = np.eye(6)
    J[1:3, 1:3] = rot
    J[4:6, 4:6] = rot
    if abs(turn - math.pi) <= 1e-12 or abs(turn + math.pi) <= 1e-12:
        return CUSP_JOINT_MAP.copy()  # exact signs (cos pi, sin pi are rounded)
    return J


def _with_end_term(G: np.ndarray, L_kappa: float, L_over_R: float) -> np.ndarray:
    """:func:`arc_end_matrix` ``G`` with the end term ``1/2 m [u' omega]`` in its moments.

    The exact second variation is P2's integral plus ``1/2 m [u' omega]`` over every arc
    (derived at :func:`rodstab.linear.assembly.end_term_matrices`; ``m = L/R - L kappa_n``):
    its first variation adds ``m omega / 2`` to ``P_u'`` and ``m u' / 2`` to ``P_w``. At a
    cusp or a smooth weld the added terms cancel between the two ends; at other angles not.
    """
    m = L_over_R - L_kappa
    Gt = G.copy()
    Gt[4] += 0.5 * m * G[2]
    Gt[5] += 0.5 * m * G[1]
    return Gt


def _cyclic_parts(L_kappa: float, L_over_R: float, b1: float, b2: float,
                  weld: str | float) -> tuple[np.ndarray, np.ndarray]:
    """``(G H^-1, J G T H^-1)``, ``H = expm(S/2)``, of :func:`cyclic_ring_matrix` (every harmonic).

    ``weld``: ``"cusp"``, ``"smooth"`` or the tangent's turn across a weld in radians. The
    unknown is the state at MID-ARC, ``z = H y(0)``: the same singular loads (``H`` is
    invertible), but each exponential spans half the arc, so where the solutions grow as
    ``e^(a s)`` the matrix is conditioned as ``e^(a L/2)``, not ``e^(a L)``. Over whole arcs
    the Bloch matrix of a one-loop ring (one full circle, b1 = 20.5, b2 = 0.39) lost enough
    digits to pass for singular at (L/2 pi) kappa_n = -6.0, where (3.3) has no root (its
    lower end is 1 - b1 = -19.51): differential test, rings seed 0 index 132 (also 159).
    """
    if isinstance(weld, str):
        if weld not in ("cusp", "smooth"):
            raise RodstabInputError(f"weld must be 'cusp', 'smooth' or a turn in radians, "
                                    f"got {weld!r}")
        turn = math.pi if weld == "cusp" else 0.0
    else:
        turn = float(weld)
        if not math.isfinite(turn):
            raise RodstabInputError(f"weld turn must be finite, got {weld!r}")
    S = arc_system_matrix(L_kappa, L_over_R, b1, b2)
    G = _with_end_term(arc_end_matrix(L_kappa, L_over_R, b1, b2), L_kappa, L_over_R)
    half, back = expm(0.5 * S), expm(-0.5 * S)
    return G @ back, weld_joint_map(turn) @ G @ half


def _bloch(G: np.ndarray, right: np.ndarray, harmonic: int, segments: int) -> np.ndarray:
    """``rho G - right`` for ``rho = exp(2 pi i m / n)``, real (6x6 or the 12x12 real form)."""
    if (2 * harmonic) % segments == 0:
        rho = 1.0 if harmonic % segments == 0 else -1.0
        return cast(np.ndarray, rho * G - right)
    phase = 2 * math.pi * harmonic / segments
    re = math.cos(phase) * G - right
    im = math.sin(phase) * G
    n = G.shape[0]
    out = np.empty((2 * n, 2 * n))  # [[re, -im], [im, re]], filled directly (np.block: 5x slower)
    out[:n, :n] = out[n:, n:] = re
    out[:n, n:] = -im
    out[n:, :n] = im
    return out


def cyclic_ring_matrix(L_kappa: float, L_over_R: float, b1: float, b2: float, harmonic: int,
                       segments: int, weld: str | float) -> np.ndarray:
    """Bloch matrix of harmonic ``m`` of a ring of ``segments`` equal arcs; singular at its loads.

    Arc ``i + 1`` is arc ``i`` turned about ``e3`` (by ``L/R + pi`` across a cusp, ``L/R``
    across a smooth weld, ``L/R + a`` across a weld turning the tangent by ``a``), so the P2
    of every arc is the same in its own frame and the modes of harmonic ``m`` have
    ``y_{i+1}(0) = rho y_i(0)``, ``rho = exp(2 pi i m / n)``. With ``T = expm(S)`` over one
    arc (:func:`arc_system_matrix`), ``G`` = :func:`arc_end_matrix` with the end term
    (:func:`_with_end_term`) and ``J`` = :func:`weld_joint_map`, the
    weld conditions of arc ``i``'s end and arc ``i + 1``'s start read
    ``(rho G - J G T) y_i(0) = 0``, solved for the mid-arc state ``z = expm(S/2) y_i(0)``
    (:func:`_cyclic_parts`: the same roots, half the exponential growth). For ``rho = +-1``
    this 6x6 matrix is real; otherwise its
    real 12x12 form ``[[Re, -Im], [Im, Re]]`` is returned, singular on the pair ``m, n - m``
    together (a mode of multiplicity 2).
    """
    G, right = _cyclic_parts(L_kappa, L_over_R, b1, b2, weld)
    return _bloch(G, right, harmonic, segments)


@dataclasses.dataclass(frozen=True)
class CyclicRingInterval(Result):
    """Stable interval of the load factor of a cyclic ring of arcs, one end from each side.

    ``lo``/``hi`` are the singular loads nearest below/above ``reference`` over the harmonics
    ``0 .. n/2``; ``harmonic_*`` the harmonic ``m`` (the pair ``m, n - m``) and
    ``multiplicity_*`` the null-space dimension there; ``rigid_nullity`` the rigid motions per
    harmonic. ``converged`` is False, with the ``reason``, when a side has no singular load up
    to the load where test fields prove one (that end is then ``-inf``/``+inf``, not a result).
    """

    lo: float
    hi: float
    harmonic_lo: int
    harmonic_hi: int
    multiplicity_lo: int
    multiplicity_hi: int
    rigid_nullity: tuple[int, ...]
    residual: float
    method: str
    converged: bool
    reason: str


#: Scan intervals of :func:`cyclic_ring_interval` per unit of :func:`arc_phase` (one arc).
CYCLIC_PER_TURN = 8


def cyclic_ring_interval(L_over_R: float, L_kappa_per_mu: float, b1: float, b2: float,
                         segments: int, weld: str | float, reference: float, *,
                         chunk: float = 1.0) -> CyclicRingInterval:
    """Stable interval of ``mu`` (``L kappa_n = mu L_kappa_per_mu``) around a stable ``reference``.

    For every harmonic ``m = 0 .. n/2`` of :func:`cyclic_ring_matrix`, the rigid motions are
    counted at ``reference`` (singular values below :data:`RIGID_SV_RTOL`); then the package's
    root finder (:func:`rodstab.numerics.matrix_roots`, the rigid motions as known nullity)
    scans outwards from ``reference`` in windows that start at ``chunk`` and double
    (overlapping by a tenth), each on a grid resolving the phase of one arc's solutions
    (:func:`phase_grid`, :func:`arc_phase`), until a singular load is found. An eigenvalue of
    the pencil crosses zero exactly at a singular load, so the first one on each side bounds
    the stable interval.

    Where to stop is derived, not a fixed span: a test field on ONE arc that vanishes with its
    slope and twist at both ends is admissible for the whole ring (zero at every weld), so the
    clamped arc's bounds :func:`arc_root_window` (``L/R`` of one arc) prove the ring unstable
    beyond them. A side with no singular load up to there is returned as ``-inf``/``+inf``
    with ``converged=False`` and the reason (5 cusp rods, ``b1 = 90``, ``b2 = 1.4``,
    ``theta = 36`` deg: the lower end -56.8 lies beyond the former fixed span of 50).
    """
    n = int(segments)
    harmonics = range(n // 2 + 1)
    if L_kappa_per_mu == 0 or not math.isfinite(L_kappa_per_mu):
        raise RodstabInputError(f"L_kappa_per_mu must be finite and nonzero, got "
                                f"{L_kappa_per_mu!r}")

    parts: dict[float, tuple[np.ndarray, np.ndarray]] = {}  # the harmonics share T(mu)

    def matrix(h: int) -> Callable[[float], np.ndarray]:
        def at(mu: float) -> np.ndarray:
            if mu not in parts:
                parts[mu] = _cyclic_parts(mu * L_kappa_per_mu, L_over_R, b1, b2, weld)
            return _bloch(*parts[mu], h, n)
        return at

    def phase(mus: np.ndarray) -> np.ndarray:
        return arc_phase(mus * L_kappa_per_mu, L_over_R, b1, b2)

    bound = sorted(p / L_kappa_per_mu for p in arc_root_window(L_over_R, b1, b2))
    nullity = []
    borders: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for h in harmonics:
        U, s, Vt = np.linalg.svd(matrix(h)(reference))
        k = int(np.sum(s <= RIGID_SV_RTOL * s[0]))
        nullity.append(k)
        if k:
            borders[h] = (U[:, -k:], Vt[-k:].T)

    def searched(h: int) -> Callable[[float], np.ndarray]:
        """Return the harmonic's matrix, bordered by its rigid motions' null vectors if any.

        ``[[A, W], [N^T, 0]]`` (``N``, ``W``: right and left null vectors at ``reference``;
        the rigid motions are null at every load) is nonsingular where ``A`` has only the
        rigid null space, and has a determinant sign: scanning ``A``'s ``(k+1)``-th smallest
        singular value instead lost a root where it crossed the next one (3 rods welded at
        -13.85 deg: 5.7629 for 5.674256). Roots are checked on ``A`` itself.
        """
        if h not in borders:
            return matrix(h)
        W, N = borders[h]
        k = N.shape[1]

        def at(mu: float) -> np.ndarray:
            A = matrix(h)(mu)
            scale = float(np.linalg.norm(A, 2)) or 1.0
            out = np.zeros((A.shape[0] + k, A.shape[1] + k))
            out[:A.shape[0], :A.shape[1]] = A
            out[:A.shape[0], A.shape[1]:] = scale * W
            out[A.shape[0]:, :A.shape[1]] = scale * N.T
            return out
        return at

    def is_root_of_a(h: int, x: float) -> bool:
        s = np.linalg.svd(matrix(h)(x), compute_uv=False)
        return bool(s[-1 - nullity[h]] <= math.sqrt(SINGULAR_TOL) * s[0])
    found: dict[int, tuple[float, int, int, float]] = {}
    reasons = []
    for side, limit in ((-1, bound[0]), (1, bound[1])):
        best: tuple[float, int, int, float] | None = None
        reach, width = 0.0, float(chunk)
        distance = (limit - reference) * side
        while best is None and reach < distance:
            # Windows overlap by a tenth of a window: a root within one scan spacing of a
            # window's end (where sigma_min has no interior minimum on the grid) is found by
            # the next window as an interior point.
            a, b = sorted((reference + side * max(reach - 0.1 * width, 0.0),
                           reference + side * min(reach + width, distance)))
            grid = phase_grid(phase, a, b, CYCLIC_PER_TURN, base=32)
            for h in harmonics:
                search = matrix_roots(searched(h), a, b, grid=grid,
                                      method_name="Bloch harmonic")
                roots = [r for r in search.roots if (r.x - reference) * side > 0
                         and (h not in borders or is_root_of_a(h, r.x))]
                if roots:
                    r = roots[0] if side > 0 else roots[-1]
                    if best is None or abs(r.x - reference) < abs(best[0] - reference):
                        best = (r.x, h, r.multiplicity, r.residual)
            reach += width
            width *= 2.0
            parts.clear()
        if best is None:
            reasons.append(f"no singular load {'below' if side < 0 else 'above'} the "
                           f"stress-free load {reference:.6g} up to {limit:.6g}, where a "
                           "test field on one arc proves one")
        found[side] = best if best is not None else (side * math.inf, -1, 0, 0.0)
    lo, hi = found[-1], found[1]
    weld_label = weld if isinstance(weld, str) else f"{math.degrees(weld):.6g}deg"
    return CyclicRingInterval(
        lo=lo[0], hi=hi[0], harmonic_lo=lo[1], harmonic_hi=hi[1], multiplicity_lo=lo[2],
        multiplicity_hi=hi[2], rigid_nullity=tuple(nullity), residual=max(lo[3], hi[3]),
        method=f"exact second variation on one arc, {weld_label} joint map, Bloch phase per "
               f"harmonic 0..{n // 2}, sigma_min scan on a phase-resolved grid up to a "
               "test-field bound",
        converged=not reasons, reason="; ".join(reasons))
