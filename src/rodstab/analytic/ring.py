"""Stability of untwisted circular rings with N loops (paper Section 3.1, eqs 3.1-3.3).

Non-dimensional: ``b1 = B1/B3``, ``b2 = B2/B3``, load ``M = 1 - R kappa_n`` (Audoly & Seffen's
parameter), ``R = L / (2 pi N)``. Modes ``omega = A cos(j theta / N)``, ``beta = B sin(j theta/N)``
(eq 3.2) give, for each ``k = j/N``, a 2x2 symmetric pencil ``A_k - M C_k`` whose determinant is
``(1 - k^2) (M^2 - (b1 + b2) M + b1 b2 (1 - k^2))``.

Finding (typo in eq 3.3): the roots of that quadratic are
``M± = (b1 + b2)/2 ± sqrt((b1 - b2)^2/4 + b1 b2 k^2)``; the paper prints ``b2 k^2`` under the root,
which coincides only when ``b1 = 1`` (circular sections, the only case the paper evaluates).
:func:`ring_mode_eigenvalues` implements the corrected form; ``printed=True`` gives the printed one.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import require_positive, require_positive_int
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, require_steps
from ..numerics import sigma_min_2x2
from ..results import Result


def ring_mode_pencil(k: float, b1: float, b2: float) -> tuple[np.ndarray, np.ndarray]:
    """Pencil ``(A, C)`` of P2 (2.12) restricted to the mode (3.2) with ``k = j/N``.

    P2 over the ring is ``(pi N B3 / (2 R)) * x^T (A - M C) x`` with ``x = (A, B)`` the
    amplitudes of ``omega`` and ``beta`` -- the algebraic system printed just before (3.3). For
    ``k = 0`` (uniform axisymmetric twist, ``beta = 0``) the pencil is 1x1, ``A = [b1]``,
    ``C = [1]``, and the prefactor is twice that. Prefactors do not change the eigenvalues.
    """
    if k == 0:
        return np.array([[b1]]), np.array([[1.0]])
    A = np.array([[b1 + b2 * k * k, -(b1 + b2) * k], [-(b1 + b2) * k, b1 * k * k + b2]])
    C = np.array([[1.0, -k], [-k, 1.0]])
    return A, C


def ring_mode_eigenvalues(
    j: int, loops: int, b1: float, b2: float, *, printed: bool = False
) -> tuple[float, float]:
    """Closed-form roots ``(M-, M+)`` of mode ``j`` of an N-loop ring, eq (3.3).

    With ``printed=True`` returns eq (3.3) exactly as printed in the paper (``b2 k^2`` under the
    root); the default is the corrected form ``b1 b2 k^2`` (see the module docstring). For
    ``j = 0`` (no ``beta``), the one physical root is ``M = b1`` and is returned as both values'
    relevant bound by :func:`ring_stability`.
    """
    k = j / loops
    c = b2 * k * k if printed else b1 * b2 * k * k
    root = math.sqrt(0.25 * (b1 - b2) ** 2 + c)
    mid = 0.5 * (b1 + b2)
    return mid - root, mid + root


@dataclasses.dataclass(frozen=True)
class ModeBound(Result):
    """Bounds on ``M`` set by one mode ``j``: stable for ``lower < M < upper``."""

    j: int
    lower: float
    upper: float


def ring_mode_bound(j: int, loops: int, b1: float, b2: float) -> ModeBound:
    """Bounds on ``M`` from mode ``j`` (``k = j/N``): the interval about ``M = 0`` (eq 3.3).

    ``det(A_k - M C_k) = (1 - k^2) (M^2 - (b1 + b2) M + b1 b2 (1 - k^2))`` with roots
    ``M- <= M+`` (:func:`ring_mode_eigenvalues`). ``C_k`` is positive definite for ``k < 1``, so
    both roots lie above 0 and the mode bounds ``M < M-`` only; for ``k > 1`` it is indefinite
    and ``M- < 0 < M+`` bound both sides; ``k = 0`` (twist alone) gives ``M < b1``. The same
    interval as :func:`rodstab.numerics.pencil_interval` on :func:`ring_mode_pencil`
    (tests/test_ring.py), at a fraction of its cost.
    """
    if j == 0:
        return ModeBound(0, -math.inf, b1)
    M_minus, M_plus = ring_mode_eigenvalues(j, loops, b1, b2)
    if j < loops:
        return ModeBound(j, -math.inf, M_minus)
    return ModeBound(j, M_minus, M_plus)


def _pencil_residuals(k: np.ndarray, bounds: np.ndarray, b1: float, b2: float) -> float:
    """Largest ``sigma_min(A_k - M C_k) / ||A_k||_2`` over the modes at their finite bounds.

    Vectorised over the modes (``k``, ``bounds`` of equal shape), singular values in closed
    form (:func:`rodstab.numerics.sigma_min_2x2`). ``k = 0`` is the 1x1 pencil ``b1 - M``
    embedded as ``diag(b1 - M, b2)`` (:func:`ring_mode_pencil`).
    """
    ok = np.isfinite(bounds)
    k, M = k[ok], bounds[ok]
    a11 = b1 + b2 * k * k - M
    a22 = np.where(k == 0, b2, b1 * k * k + b2 - M)
    a12 = np.where(k == 0, 0.0, -(b1 + b2) * k + M * k)
    # ||A_k||_2: the larger eigenvalue of the symmetric positive A_k
    p11, p22 = b1 + b2 * k * k, b1 * k * k + b2
    p12 = np.where(k == 0, 0.0, -(b1 + b2) * k)
    norm = 0.5 * (p11 + p22) + np.sqrt(0.25 * (p11 - p22) ** 2 + p12 * p12)
    return float(np.max(sigma_min_2x2(a11, a22, a12) / norm)) if k.size else 0.0


@dataclasses.dataclass(frozen=True)
class RingStability(Result):
    """Stable interval of an N-loop untwisted ring (Section 3.1).

    ``M_interval = (M_C^-, M_C^+)``; ``kappa_L_over_2pi_interval`` is the same interval in
    ``(L / 2 pi) kappa_n = N (1 - M)`` (so its ends are swapped). ``bounding_modes`` gives the
    mode numbers ``j`` that set the lower and upper ends of ``M_interval``.
    """

    loops: int
    b1: float
    b2: float
    M_interval: tuple[float, float]
    kappa_L_over_2pi_interval: tuple[float, float]
    bounding_modes: tuple[int, int]
    modes: tuple[ModeBound, ...]
    residual: float
    converged: bool
    method: str


def ring_stability(b1: float, b2: float, loops: int, *, j_max: int | None = None,
                   limits: Limits = DEFAULT_LIMITS) -> RingStability:
    """Stable interval of ``M = 1 - R kappa_n`` for an untwisted N-loop ring (Section 3.1).

    Every mode ``j = 0 .. j_max`` except the rigid ``j = N`` is bounded by the closed-form roots
    of its pencil (:func:`ring_mode_bound`), each checked by the pencil's smallest singular value
    there (``residual``).
    ``j_max`` defaults to ``2 N + 4``: ``M-(k)`` falls and ``M+(k)`` rises monotonically in
    ``k = j/N``, so the binding modes are ``j = 0``, ``N - 1`` and ``N + 1``; the extra modes
    are a check of that argument, not needed for the answer.

    Parameters
    ----------
    b1, b2 : float
        Stiffness ratios ``B1/B3`` and ``B2/B3`` (> 0).
    loops : int
        Number of loops N >= 1.
    j_max : int, optional
        Highest mode number checked (default ``2 N + 4``).
    limits : Limits, optional
        Refuse (``RodstabInputError``) more than ``limits.max_steps`` modes to check.
    """
    b1 = require_positive("b1", b1)
    b2 = require_positive("b2", b2)
    N = require_positive_int("loops", loops)
    j_max = 2 * N + 4 if j_max is None else j_max
    require_steps(j_max, f"loops {N}", "Fourier modes to check (one eigenproblem each)", limits)
    # j = N: rigid-body rotations about in-plane axes, P2 = 0 for every M (left out).
    j = np.arange(j_max + 1)
    j = j[j != N]
    k = j / N
    # (3.3), corrected, vectorised over the modes (ring_mode_bound mode by mode)
    root = np.sqrt(0.25 * (b1 - b2) ** 2 + b1 * b2 * k * k)
    m_minus, m_plus = 0.5 * (b1 + b2) - root, 0.5 * (b1 + b2) + root
    upper = np.where(j == 0, b1, np.where(j < N, m_minus, m_plus))
    lower = np.where(j > N, m_minus, -np.inf)
    residual = _pencil_residuals(np.concatenate([k, k]), np.concatenate([upper, lower]), b1, b2)
    i_lo, i_hi = int(np.argmax(lower)), int(np.argmin(upper))
    lo, hi = float(lower[i_lo]), float(upper[i_hi])
    modes = tuple(ModeBound(jj, lw, up)
                  for jj, lw, up in zip(j.tolist(), lower.tolist(), upper.tolist(), strict=True))
    return RingStability(
        loops=N,
        b1=b1,
        b2=b2,
        M_interval=(lo, hi),
        kappa_L_over_2pi_interval=(N * (1.0 - hi), N * (1.0 - lo)),
        bounding_modes=(int(j[i_lo]), int(j[i_hi])),
        modes=modes,
        residual=residual,
        converged=residual < 1e-10,
        method="Fourier modes (3.2), closed-form roots (3.3) vectorised over the modes, each "
               "checked on its pencil",
    )


@dataclasses.dataclass(frozen=True)
class RingOverlap(Result):
    """Overlap of the stable ``(L/2pi) kappa_n`` intervals of two ring loop counts."""

    loops: tuple[int, int]
    intervals: tuple[tuple[float, float], tuple[float, float]]
    overlap: tuple[float, float] | None


def ring_overlap(b1: float, b2: float, loops_a: int = 1, loops_b: int = 3) -> RingOverlap:
    """Compare the stable natural-curvature ranges of an ``loops_a`` and a ``loops_b`` ring.

    Both rings are made of the same rod (same ``L``, ``kappa_n``), so the ranges are compared in
    ``(L / 2 pi) kappa_n`` (Section 3.1, after eq 3.3).
    """
    ra = ring_stability(b1, b2, loops_a)
    rb = ring_stability(b1, b2, loops_b)
    ia, ib = ra.kappa_L_over_2pi_interval, rb.kappa_L_over_2pi_interval
    lo, hi = max(ia[0], ib[0]), min(ia[1], ib[1])
    return RingOverlap((ra.loops, rb.loops), (ia, ib), (lo, hi) if lo < hi else None)


@dataclasses.dataclass(frozen=True)
class HeldRing(Result):
    """Stable interval of the 3-loop ring with every touching pair held closed (zero gap).

    ``M_interval`` and ``kappa_L_over_2pi_interval`` as :class:`RingStability`'s;
    ``binding``: what bounds each end (``"common j"``: the one-loop mode ``j`` of the strands
    moving together; ``"turning n"``: the strands' triangle turning with ``f_n``).
    """

    b1: float
    b2: float
    M_interval: tuple[float, float]
    kappa_L_over_2pi_interval: tuple[float, float]
    binding: tuple[str, str]
    method: str


#: Fourier components ``f_n`` of the triangle's turning checked by :func:`held_ring_interval`.
HELD_TURNING_MODES = 12


def _turning_energy(k: float, M: float, b1: float, b2: float) -> float:
    """P2 of the out-of-plane mode ``k`` with its twist amplitude eliminated, plus in-plane.

    Per unit amplitude of ``u3`` and of ``u_r`` (equal in the turning): the Schur complement
    of the pencil (3.2) ``A - M C`` (:func:`ring_mode_pencil`) on ``omega``'s amplitude, times
    ``k^2`` (``u3 = -beta / k``), plus the inextensible in-plane bending ``(1 - k^2)^2`` in the
    same prefactor.
    """
    A, C = ring_mode_pencil(k, b1, b2)
    Q = A - M * C
    return k * k * (Q[0, 0] * Q[1, 1] - Q[0, 1] ** 2) / Q[0, 0] + (1.0 - k * k) ** 2


def held_ring_interval(b1: float, b2: float, *, modes: int = HELD_TURNING_MODES) -> HeldRing:
    """Stable interval of the 3-loop ring on the torus with every touching pair held closed.

    Zero-thickness linear theory (docs/theory/contact.md; derived independently of the rod
    engine's :func:`rodstab.multistable.cone_limit.rod_cone_limits` ``held_closed``, which it
    checks): holding the strands' pairwise gaps closed leaves their common motion, the
    one-loop ring three times as stiff (:func:`ring_stability` at ``N = 1``), and one relative
    motion, the triangle of strands turning about its centre, ``u = f(theta) t(theta)``. A
    component ``f_n`` of ``f`` moves the wavenumbers ``k = n -+ 1/3`` together, each with equal
    ``u3`` and ``u_r``: energy ``S_n(M) = q(n - 1/3) + q(n + 1/3)`` (``S_0 = q(1/3)``,
    :func:`_turning_energy`). The interval in ``M`` is the one-loop interval where every
    ``S_n > 0`` (``n <= modes``), found by :func:`rodstab.numerics.find_roots` on ``min_n
    S_n``, the part containing the free 3-loop ring's interval.
    """
    from ..numerics import find_roots

    b1 = require_positive("b1", b1)
    b2 = require_positive("b2", b2)
    one = ring_stability(b1, b2, 1)
    lo, hi = one.M_interval
    inside = float(np.mean(ring_stability(b1, b2, 3).M_interval))

    def turning(M: float) -> tuple[float, int]:
        vals = [_turning_energy(1 / 3, M, b1, b2)] + [
            _turning_energy(n - 1 / 3, M, b1, b2) + _turning_energy(n + 1 / 3, M, b1, b2)
            for n in range(1, modes + 1)]
        i = int(np.argmin(vals))
        return float(vals[i]), i

    roots = find_roots(lambda M: turning(M)[0], lo, hi).values
    below = [r for r in roots if r < inside]
    above = [r for r in roots if r > inside]
    m_lo, m_hi = (max(below) if below else lo), (min(above) if above else hi)
    binding = (f"turning n={turning(m_hi - 1e-9 * (hi - lo))[1]}" if above else
               f"common j={one.bounding_modes[1]}",
               f"turning n={turning(m_lo + 1e-9 * (hi - lo))[1]}" if below else
               f"common j={one.bounding_modes[0]}")
    return HeldRing(b1, b2, (m_lo, m_hi), (3 * (1 - m_hi), 3 * (1 - m_lo)), binding,
                    f"common motion (eq. 3.3 at N = 1) and the triangle's turning f_n, n <= "
                    f"{modes} (Schur complement of the (3.2) pencil plus in-plane bending), "
                    "roots of min_n S_n by scan and Brent")
