"""The folded six-sided ring in its straight three-loop state, by the paper's method (Section 5).

Eqs (5.4)-(5.14). Non-dimensional as in (5.7): ``x = s/L``, ``u = u3/L``,
``a = alpha / (B3 kappa_n L / B2)``, load ``lam = B3 kappa_n L / sqrt(B1 B2)`` (the lambda of
Sections 4-5; not the engine's load factor ``mu``, see docs/notation.md). With
``Delta kappa_0 = sigma kappa_n`` (``sigma = -1`` in segments 1, 3, 5, ``+1`` in 2, 4, 6) the
equations (5.4) become ``u'''' = -lam^2 u''`` and ``a'' = sigma u''``, so the transfer matrices
``T_A`` (sigma = -1) and ``T_B`` (sigma = +1) of (5.8) depend on ``lam`` only.

Joint conditions (5.5)/(5.6) in these variables: ``u, u', a`` continuous; ``u''`` and ``a'``
change sign; ``u'''_(i+1) = -u'''_i - 2 sigma_i lam^2 a'_i``. So ``D_A``, ``D_B`` of (5.9) are
``diag(1, 1, 1, -1, -1, -1)`` plus the one off-diagonal ``D_56 = -2 sigma_i lam^2`` (in these
variables it depends on ``lam``; the paper's statement that it depends on ``B2/B1`` refers to
its own, unprinted, scaling -- either way the result depends on ``lam`` alone).

State order (as printed): ``[u] = (u, u', a, u'', u''', a')``. Around the ring (5.10):
``A = (D_B T_B^-1 D_A T_A)^3`` and ``(A - I) [u1(0)] = 0``. The paper requires
``det A^(1) = 0`` (5.12) for the upper 3x3 block and then checks the lower block. The full
condition is that the 6x3 block ``[A^(1); A^(2)]`` has a null vector; both are provided.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import require_positive_int
from ..numerics import find_roots, matrix_roots
from ..results import Result


def transfer_matrix(lam: float, sigma: float) -> np.ndarray:
    """``T_A`` (``sigma = -1``) or ``T_B`` (``sigma = +1``) of (5.8): ``[u](1) = T [u](0)``."""
    lam2 = lam * lam
    S = np.zeros((6, 6))
    S[0, 1] = 1.0  # u'
    S[1, 3] = 1.0  # u''
    S[2, 5] = 1.0  # a'
    S[3, 4] = 1.0  # u'''
    S[4, 3] = -lam2  # u'''' = -lam^2 u''
    S[5, 3] = sigma  # a'' = sigma u''
    from scipy.linalg import expm  # on first use: scipy.linalg is slow to import

    return expm(S)


def joint_matrix(lam: float, sigma_i: float) -> np.ndarray:
    """``D_A`` / ``D_B`` of (5.9): ``[u_(i+1)] = D [u_i]`` at a joint (conditions 5.5/5.6)."""
    D = np.diag([1.0, 1.0, 1.0, -1.0, -1.0, -1.0])
    D[4, 5] = -2.0 * sigma_i * lam**2
    return D


def monodromy(lam: float, pairs: int = 3) -> np.ndarray:
    """Return ``A = (D_B T_B^-1 D_A T_A)^pairs`` of (5.10) (the paper's ring: 3 A-B pairs)."""
    TA, TB = transfer_matrix(lam, -1.0), transfer_matrix(lam, +1.0)
    DA, DB = joint_matrix(lam, -1.0), joint_matrix(lam, +1.0)
    P = DB @ np.linalg.solve(TB, DA @ TA)
    return np.linalg.matrix_power(P, pairs)


def blocks(lam: float, pairs: int = 3) -> tuple[np.ndarray, np.ndarray, float]:
    """``(A^(1), A^(2), max |first three columns of A - I|)`` of (5.11)."""
    AmI = monodromy(lam, pairs) - np.eye(6)
    return AmI[:3, 3:], AmI[3:, 3:], float(np.max(np.abs(AmI[:, :3])))


@dataclasses.dataclass(frozen=True)
class FoldedRingPaperMethod(Result):
    """Roots of the paper's criterion (5.12) and of the full criterion on ``[A1; A2]``."""

    det_A1_roots: tuple[float, ...]
    full_roots: tuple[float, ...]
    full_multiplicities: tuple[int, ...]
    lam_critical: float
    multiplicity: int
    first_columns_residual: float
    method: str


def folded_ring_paper_method(lo: float = 0.05, hi: float = 8.0, n_scan: int = 800, *,
                             pairs: int = 3) -> FoldedRingPaperMethod:
    """Critical ``lam`` of the folded ring by (5.8)-(5.12) as the paper states them.

    The paper's six-sided ring is ``pairs = 3`` (``2 pairs`` segments in general).

    ``det_A1_roots``: sign changes of ``det A^(1)`` and its touching zeros (what (5.12) asks);
    ``full_roots``: loads where ``[A^(1); A^(2)]`` loses rank (smallest singular value scan),
    with the null-space dimension as multiplicity. The critical value is the lowest full root.
    """
    pairs = require_positive_int("pairs", pairs)
    det_roots = find_roots(lambda t: float(np.linalg.det(blocks(t, pairs)[0])), lo, hi,
                           n_scan=n_scan).values
    full = matrix_roots(lambda t: np.vstack(blocks(t, pairs)[:2]), lo, hi, n_scan=n_scan,
                        method_name="sigma_min of [A1; A2]")
    resid = max(blocks(t, pairs)[2] for t in (lo, 1.0, hi))
    first = full.roots[0] if full.roots else None
    return FoldedRingPaperMethod(
        det_A1_roots=tuple(det_roots), full_roots=tuple(full.values),
        full_multiplicities=tuple(r.multiplicity for r in full.roots),
        lam_critical=first.x if first else math.nan,
        multiplicity=first.multiplicity if first else 0, first_columns_residual=resid,
        method="transfer matrices (5.8), joints (5.9), monodromy (5.10)-(5.12)")


#: The two-column stacking of the folded ring (segments in traversal order ``1..6``): odd
#: segments in one column, even in the other, loop ``k`` (segments ``2k - 1, 2k``) on layer
#: ``k - 1``; offsets ``(u, k)`` for :func:`~rodstab.multistable.layer_orders.layer_offsets`.
TWO_COLUMNS = tuple(((-0.5 if i % 2 == 0 else 0.5), i // 2) for i in range(6))


def two_column_contact_limit() -> float:
    """Critical ``lam`` of the folded six-ring stacked in two columns, with contact: ``pi / 2``.

    Zero gap, heights only (perturbations normal to the plane of the folded state and the twist
    they couple to; contact forbids a layer to move into the one beneath it). Derived
    independently of the FE cone (helper-14, session 17, from (5.3)-(5.7)); the FE's cone limit
    (:func:`~rodstab.multistable.cone_limit.cone_limits`) agrees (report row
    C-folded-columns). Loops ``A = (1, 2)``, ``B = (3, 4)``, ``C = (5, 6)`` on three layers,
    odd segments in one column and even in the other (:data:`TWO_COLUMNS`); the cusps at ``x =
    1`` stay in their layer, those at ``x = 0`` join ``A-B``, ``B-C``, ``C-A``. The steps:

    * Eliminating the twist (``a_i' = -lam sigma_i w_i + d_i``, ``w = u'``, with the closure
      around the ring) gives ``2 P2 = A - lam^2 B``, ``A = sum int u_i''^2``, ``B = sum int
      u_i'^2 - (sum_i [u_i(1) - u_i(0)])^2 / 6 >= 0``; without contact the critical ``w`` is
      one period round the ring's six segments, ``lam = pi / 3`` (double).
    * The welds at ``x = 0`` tie the gaps there: ``g13 + g35 + g46 = 0`` and ``g24 = g35 -
      g46``, and the same for their slopes, so with every gap ``>= 0`` all gaps and slopes
      vanish at ``x = 0``: the six rods' heights and slopes are equal there.
    * Then ``w_i(0) = 0`` (rigid motion removed) and Poincare's inequality ``int w'^2 >= (pi /
      2)^2 int w^2`` gives ``A >= (pi / 2)^2 B``; equality for ``u_(2k-1) = u_(2k) = c_k (1 -
      cos(pi x / 2))`` with ``sum c_k = 0`` and ``c_A >= c_B >= c_C`` (admissible: each loop
      peels off like a cantilever clamped at ``x = 0``), so ``lam_c = pi / 2``.

    In ``lam`` the problem has no section parameter, so the ratio to the no-contact limit is
    ``3 / 2`` for every section (``L kappa_n = lam sqrt(b1 b2)``). Holds for this stacking
    only: on the hexagon (the default, :func:`~rodstab.multistable.cone.default_layers`) the
    FE gives 1.3766 times, and with the loops winding in opposite senses the helper's FE did not
    converge (0.468 pi at 64 el., falling).
    """
    return math.pi / 2


def two_column_held_limit() -> float:
    """Critical ``lam`` of the folded six-ring in two columns held closed (every pair): ``pi``.

    The stacking of :func:`two_column_contact_limit`; each touching pair's gap held at zero
    both ways (a stack whose layers press: the subspace ``D v = 0`` of
    :func:`~rodstab.multistable.cone_limit.rod_cone_limits` with ``held_closed``). In-plane
    motions carry no prestress term and the in-plane pairs (1, 2), (3, 4), (5, 6) constrain
    only them, so the heights decide. Derived independently of the rod engine (helper-16,
    session 19: the full 3D second variation from (5.1), three discretisations to 1e-10) and
    checked here by hand:

    * The columns hold ``u1 = u3 = u5 = U_A`` and ``u2 = u4 = u6 = U_B`` (heights); the cusps
      tie ``U_A = U_B`` and their slopes at ``x = 0`` and ``x = 1``. With the twist eliminated
      as in :func:`two_column_contact_limit`, ``2 P2 = A - lam^2 B``.
    * Write ``U_A = S + D``, ``U_B = S - D``: ``A = 6 int (S''^2 + D''^2)``, ``B = 6 [int S'^2 -
      (int S')^2 + int D'^2]`` with ``D = D' = 0`` at both ends.
    * ``S' - mean`` has zero mean: Wirtinger's inequality gives ``int S''^2 >= pi^2 (int S'^2 -
      (int S')^2)``, equality for ``S = sin(pi x)``: the whole bundle bows in one half-wave,
      the two columns twisting in opposite senses, no end force, moment or torque, so no
      contact force either. ``D' `` vanishes at both ends with zero mean: ``int D''^2 >= (2
      pi)^2 int D'^2``.

    So ``lam_c = pi`` (simple; next ``2 pi``, double), three times the no-contact ``pi / 3``
    and twice the zero-force cone's ``pi / 2``, for every section (``L kappa_n = lam sqrt(b1
    b2)``). Holds for this stacking; the rod engine's held-closed bound converges to it at order
    2 (tests/test_cone_limit.py).
    """
    return math.pi


def hexagon_contact_limit() -> float:
    """Critical ``lam`` of the folded six-ring stacked on a hexagon, with contact: 1.4421095.

    Rods at the vertices of a regular hexagon of side ``h`` in traversal order, rod 1 on top
    (:func:`~rodstab.multistable.layer_orders.polygon_offsets`, the default of
    :func:`~rodstab.multistable.cone.default_layers`); zero gap, heights only (a pair's gap
    changes by ``n3 (u_(i+1) - u_i)``, ``n3`` its contact normal's out-of-plane part).
    Derived independently of the FE cone (helper-15, session 17, from (5.3)-(5.7)): the gaps
    order the heights in two chains, ``u1 >= u2 >= u3 >= u4`` and ``u1 >= u6 >= u5 >= u4``;
    at the limit all six heights are equal at one end (the three welds there at one height,
    pairs (2, 3), (4, 5), (6, 1) closed); there the eigenvalue is double, in the rotation
    sector ``u_(i+2) = omega u_i`` (``omega = exp(2 pi i / 3)``), where the twist's non-local
    term vanishes, and the conditions at the other end reduce to ``(5 cos lam - 2) sin lam =
    lam (4 cos^2 lam - 1)``; its smallest positive root (found here by :func:`find_roots`,
    bracketed) is the limit. Certified globally by the helper on a relaxed cone (25 faces,
    meshes of 8, 16 and 32 elements). A 60-degree arc of the double mode is admissible, so the
    critical mode is not unique. In ``lam`` no section parameter is left: ``L kappa_n = lam
    sqrt(b1 b2)`` for every section, 1.37711 times the no-contact ``pi / 3``.
    """
    def f(lam: float) -> float:
        return (5.0 * math.cos(lam) - 2.0) * math.sin(lam) - lam * (4.0 * math.cos(lam) ** 2
                                                                    - 1.0)

    # f ~ lam^3 > 0 near 0 (the trivial root); the first sign change lies below pi / 2
    return float(find_roots(f, 0.05, math.pi / 2, n_scan=200).values[0])
