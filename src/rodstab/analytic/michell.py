"""Michell's problem: a pre-twisted straight rod closed into an N-loop ring (Section 3.3).

Eqs (3.16)-(3.26). Isotropic bending (``B1 = B3``, so ``b1 = 1``), ``b2 = B2/B3``, load
``b2 omega0'`` (the pre-twist ``d omega/ds = omega0'/R``, non-dimensional by ``R``).

Derivation used here (independent of the paper's polar route). With ``phi_r = u3'/R`` and
``phi_3 = -(u_r' - u_theta)/R`` (eq 3.18), ``beta^2 gamma' = phi_3 phi_r' - phi_r phi_3'`` and
``beta'^2 + beta^2 gamma'^2 = phi_r'^2 + phi_3'^2``, so (3.21) is the quadratic form
``P2 = 1/2 int { -b2 w0 (phi_3 phi_r' - phi_r phi_3') + phi_r'^2 + phi_3'^2 - phi_r^2 } dtheta``.
The modes (3.22) with ``theta -> theta/N`` (``k = j/N``) give ``phi_r = b k cos(k theta)``,
``phi_3 = c sin(k theta)``, ``c = a (k^2 - 1)``; over ``0..2 pi N`` the form is
``pi N [x^T K x]`` with ``x = (b k, c)`` and ``K = [[k^2 - 1, b2 w0 k], [b2 w0 k, k^2]]``
(this reproduces (3.26), ``r = c / (b k)``). ``K`` is positive definite iff ``k > 1`` and
``(b2 w0)^2 < k^2 - 1``: the critical twist is ``b2 w0 = sqrt(k^2 - 1)`` minimised over
``k = j/N > 1``, i.e. ``j = N + 1``; for one loop ``j = 2`` and ``b2 w0 = sqrt(3)`` (Michell 1889).
For N > 1 the modes ``0 < j < N`` have ``k^2 - 1 < 0``: the ring is unstable at every twist.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import RodstabInputError, require_positive, require_positive_int
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, require_steps
from ..numerics import sigma_min_2x2
from ..results import Result


def michell_mode_pencil(k: float) -> tuple[np.ndarray, np.ndarray]:
    """Pencil ``(A, C)`` in the load ``t = b2 omega0'`` for mode ``k = j/N`` (``k > 1``).

    ``K(t) = A - t C`` with ``A = diag(k^2 - 1, k^2)``, ``C = [[0, -k], [-k, 0]]``, acting on
    ``(b k, c)``. ``A`` is positive definite only for ``k > 1``.
    """
    return np.diag([k * k - 1.0, k * k]), np.array([[0.0, -k], [-k, 0.0]])


def michell_p2_closed_form(t: float, j: int, r: float, loops: int = 1) -> float:
    """Eq (3.26) per unit ``pi/2 (b j)^2``: ``N [2 t k r + k^2 (1 + r^2) - 1]``, ``k = j/N``."""
    k = j / loops
    return loops * (2 * t * k * r + k * k * (1 + r * r) - 1)


@dataclasses.dataclass(frozen=True)
class MichellStability(Result):
    """Critical pre-twist of an N-loop ring of isotropic bending stiffness (Section 3.3).

    ``b2_omega0_critical`` is ``None``-valued (NaN) when the untwisted ring is already
    unstable (``unstable_modes`` lists the modes ``j`` unstable at zero twist). ``r_critical``
    is the in-plane/out-of-plane amplitude ratio ``a (j^2 - 1)/(b j)`` of the critical mode for
    a positive twist (``b = ∓ sqrt(3) a`` for one loop).
    """

    loops: int
    b2: float
    b2_omega0_critical: float
    omega0_critical: float
    mode_j: int
    r_critical: float
    stable_at_zero_twist: bool
    unstable_modes: tuple[int, ...]
    residual: float
    method: str


def michell_stability(b2: float, loops: int = 1, *, b1: float = 1.0,
                      j_max: int | None = None,
                      limits: Limits = DEFAULT_LIMITS) -> MichellStability:
    """Critical twist ``b2 omega0'`` of Michell's ring with N loops (eqs 3.21-3.26).

    Parameters
    ----------
    b2 : float
        ``B2 / B3`` (> 0).
    loops : int
        Number of loops N.
    b1 : float
        Must be 1: the analysis (and the paper's) assumes isotropic bending ``B1 = B3``.
    j_max : int, optional
        Highest mode number checked (default ``3 N + 4``).
    limits : Limits, optional
        Refuse (``RodstabInputError``) more than ``limits.max_steps`` modes to check.
    """
    b2 = require_positive("b2", b2)
    N = require_positive_int("loops", loops)
    if abs(require_positive("b1", b1) - 1.0) > 1e-12:
        raise RodstabInputError(f"b1 must be 1 for Michell's problem (isotropic bending), "
                                f"got {b1!r}")
    j_max = 3 * N + 4 if j_max is None else j_max
    require_steps(j_max, f"loops {N}", "Fourier modes to check (one eigenproblem each)", limits)
    unstable = tuple(j for j in range(1, N))  # k < 1: k^2 - 1 < 0 at zero twist
    # Modes k = j/N > 1, vectorised: K(t) = A - t C (michell_mode_pencil) is singular at
    # t = +-sqrt(k^2 - 1) (det = k^2 (k^2 - 1 - t^2)); the positive root bounds the twist.
    ks = np.arange(N + 1, j_max + 1) / N
    t = np.sqrt(ks * ks - 1.0)
    i = int(np.argmin(t))
    t_c, j_c = float(t[i]), N + 1 + i
    # Each mode checked on its pencil: sigma_min(A - t C) / ||A||_2, as
    # numerics.pencil_interval reports its residual.
    residual = float(np.max(sigma_min_2x2(ks * ks - 1.0, ks * ks, t * ks) / (ks * ks))) \
        if ks.size else 0.0
    k = j_c / N
    t_c_report = math.nan if unstable else t_c
    return MichellStability(
        loops=N, b2=b2, b2_omega0_critical=t_c_report,
        omega0_critical=t_c_report / b2 if not unstable else math.nan,
        mode_j=unstable[0] if unstable else j_c,
        r_critical=-t_c / k if not unstable else math.nan,
        stable_at_zero_twist=not unstable, unstable_modes=unstable, residual=residual,
        method="quadratic form of (3.21) in (phi_r, phi_3), modes (3.22), closed-form roots "
               "vectorised over the modes, each checked on its pencil",
    )


def michell_p2_paper_route(t: float, j: int, r: float, *, n_quad: int = 512) -> float:
    """P2 of (3.21) per unit ``pi/2 (b j)^2`` by quadrature, following the paper's polar route.

    The trial fields (3.22) give ``beta cos(gamma) = b j cos(j theta)`` and
    ``beta sin(gamma) = -a (j^2 - 1) sin(j theta)`` (3.23); ``beta``, ``gamma`` and their
    derivatives are formed from these exactly as in (3.24) (with ``(beta gamma')^2`` computed
    from ``beta^2 gamma'`` and ``beta^2``, not from the printed ``j^4``) and (3.21) is integrated
    by the trapezoid rule (spectrally accurate for the periodic integrand). A second method for
    :func:`michell_stability`: it shares no algebra with the quadratic form used there.
    """
    th = np.linspace(0.0, 2 * np.pi, n_quad, endpoint=False)
    bj = 1.0
    c = r * bj  # a (j^2 - 1)
    x, dx = bj * np.cos(j * th), -bj * j * np.sin(j * th)  # beta cos(gamma) and derivative
    y, dy = -c * np.sin(j * th), -c * j * np.cos(j * th)  # beta sin(gamma) and derivative
    beta2 = x * x + y * y
    beta2_gp = x * dy - y * dx  # beta^2 gamma'
    dbeta2 = (x * dx + y * dy) ** 2 / beta2  # beta'^2
    bgp2 = beta2_gp**2 / beta2  # (beta gamma')^2
    integrand = -t * beta2_gp + dbeta2 + bgp2 - x * x
    integral = float(np.mean(integrand) * 2 * np.pi)
    return 0.5 * integral / (0.5 * np.pi * bj * bj)


def michell_critical_paper_route(j: int = 2) -> float:
    """Smallest twist ``t = b2 omega0'`` at which ``min_r P2(t, j, r) = 0`` (quadrature route).

    ``min_r`` by golden-section search on ``r`` in ``[-5, 0]`` (the minimiser has ``r t < 0``)
    and the root in ``t`` by the package root finder on ``[0.1, 5]``.
    """
    from ..numerics import find_roots, golden_min

    def min_p2(t: float) -> float:
        return golden_min(lambda r: michell_p2_paper_route(t, j, r), -5.0, -1e-6, 1e-10)[1]

    found = find_roots(min_p2, 0.1, 5.0, n_scan=60)
    return found.roots[0].x if found.roots else math.nan
