"""Transfer matrices of assemblies of straight segments (Sections 4 and 5).

The general solution per segment, joined by the geometric AND the natural joint conditions
into one square system (:func:`straight_assembly_matrix`), singular at the critical loads
(:func:`full_system_critical`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import cast

import numpy as np

from ..errors import RodstabInputError
from ..model import FULL_SYSTEM, SUPPORT_KINDS
from ..numerics import matrix_roots
from ..results import Result
from .arc import expm


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
