"""Rings of n identical arcs welded end to start (smooth or at cusps): the Bloch method.

Reduced by their n-fold cyclic symmetry to one arc and a Bloch phase per harmonic
(:func:`cyclic_ring_matrix`), the stable interval by :func:`cyclic_ring_interval` (the
curved-sided hexagram, the rings of :mod:`rodstab.multistable.atlas`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import cast

import numpy as np

from ..errors import RodstabInputError
from ..numerics import SINGULAR_TOL, matrix_roots
from ..results import Result
from .arc import arc_phase, arc_root_window, arc_system_matrix, expm, phase_grid

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
    """``rho G - right`` for ``rho = exp(2 pi i m / n)``: real for ``rho = +-1``, else complex.

    Its determinant times ``rho^-3`` is real (the one-arc map is similar to a symplectic one,
    so its characteristic polynomial is palindromic; checked by the root finder, which takes
    the determinant's sign along its fixed phase: :func:`rodstab.numerics.matrix_roots`).
    """
    if (2 * harmonic) % segments == 0:
        rho = 1.0 if harmonic % segments == 0 else -1.0
        return cast(np.ndarray, rho * G - right)
    phase = 2 * math.pi * harmonic / segments
    return cast(np.ndarray, complex(math.cos(phase), math.sin(phase)) * G - right)


def _pair(harmonic: int, segments: int) -> int:
    """Real modes per complex null vector of harmonic ``m``: 2 (the pair ``m, n - m``) or 1."""
    return 1 if (2 * harmonic) % segments == 0 else 2


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
    A = _bloch(G, right, harmonic, segments)
    if not np.iscomplexobj(A):
        return A
    n = A.shape[0]
    out = np.empty((2 * n, 2 * n))  # [[re, -im], [im, re]], filled directly (np.block: 5x slower)
    out[:n, :n] = out[n:, n:] = A.real
    out[:n, n:] = -A.imag
    out[n:, :n] = A.imag
    return out


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
        nullity.append(k)  # complex null vectors of the harmonic's matrix
        if k:
            borders[h] = (U[:, -k:], Vt[-k:].conj().T)

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
            scale = float(np.linalg.norm(A)) or 1.0  # Frobenius: the size, without an SVD
            out = np.zeros((A.shape[0] + k, A.shape[1] + k), dtype=A.dtype)
            out[:A.shape[0], :A.shape[1]] = A
            out[:A.shape[0], A.shape[1]:] = scale * W
            out[A.shape[0]:, :A.shape[1]] = scale * N.conj().T
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
                        best = (r.x, h, r.multiplicity * _pair(h, n), r.residual)
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
        multiplicity_hi=hi[2],
        rigid_nullity=tuple(k * _pair(h, n) for h, k in zip(harmonics, nullity, strict=True)),
        residual=max(lo[3], hi[3]),
        method=f"exact second variation on one arc, {weld_label} joint map, Bloch phase per "
               f"harmonic 0..{n // 2}, sigma_min scan on a phase-resolved grid up to a "
               "test-field bound",
        converged=not reasons, reason="; ".join(reasons))
