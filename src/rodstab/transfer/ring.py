"""Transfer matrices of the N-loop ring (Section 3.1): periodicity of P2's Euler-Lagrange system.

The ring's state ``y = (omega, omega', beta, beta')`` obeys ``y' = S y`` (eq. 3.1); a
critical load is where a periodic solution other than the two rigid rotations exists (the
monodromy ``T - I``, or the better-scaled :func:`ring_matching_matrix`, loses rank);
:func:`ring_interval_transfer` gives the stable interval of ``M``.
"""

from __future__ import annotations

import math
from typing import cast

import numpy as np

from ..errors import NotConverged
from ..numerics import SINGULAR_TOL, Root, matrix_roots
from .arc import expm, phase_grid


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
