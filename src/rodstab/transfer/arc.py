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

import math
from collections.abc import Callable
from typing import cast

import numpy as np

from ..errors import NotConverged, RodstabInputError


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
