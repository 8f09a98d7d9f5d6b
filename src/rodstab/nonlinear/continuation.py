"""Beyond the onset: post-buckled branches from a bifurcation, and imperfection sensitivity.

Branch from the bifurcation (amplitude control): at the critical load ``mu_c`` of the held
state, the critical mode's largest out-of-plane nodal displacement ``z_k`` is prescribed,
``z_k = a``, and the load ``mu`` is solved for with the equilibrium equations by a bordered
Newton method::

    [ H(q, mu)   dg/dmu ] [dq ]     [ g(q, mu)  ]
    [ e_k^T      0      ] [dmu] = - [ z_k - a   ]

(``g`` is affine in ``mu``, so ``dg/dmu = g(q, mu + 1) - g(q, mu)`` exactly). Amplitude control
passes through the bifurcation and through limit points of ``mu`` alike. The initial
post-buckling is read from ``mu(a) = mu_c + c1 a + c2 a^2``: ``c1 != 0`` asymmetric,
``c2 > 0`` stable symmetric (supercritical), ``c2 < 0`` unstable symmetric (subcritical).

Continuation in any parameter, folds, branch switching and imperfection sensitivity:
:mod:`.paths`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..model import Assembly
from ..results import Result
from .discrete import PENALTY, DiscreteRod, discretise
from .parameters import LoadFactor, Parameter
from .solve import critical_load_factor, lowest_modes

#: The default continuation parameter.
LOAD = LoadFactor()


@dataclasses.dataclass(frozen=True)
class Branch(Result):
    """A traced post-buckled branch: amplitude, load, energy, lowest eigenvalue at fixed load."""

    load_factor_critical: float
    amplitude: tuple[float, ...]
    load_factor: tuple[float, ...]
    energy: tuple[float, ...]
    lowest_eigenvalue: tuple[float, ...]
    c1: float
    c2: float
    verdict: str
    converged: bool
    method: str
    shapes: tuple = ()  # node positions (n, 3) along the positive-amplitude side


def post_buckling_verdict(amps: np.ndarray, values: np.ndarray, p_c: float,
                          stable_side: float) -> tuple[str, float, float]:
    """Initial post-buckling from ``p - p_c = c1 a + c2 a^2`` fitted over a branch's first
    points (both signs of the amplitude ``a``); ``stable_side``: the sign of ``p - p_c`` where
    the primary path is stable. Returns (verdict, c1, c2)."""
    if len(amps) < 3:
        return "undetermined (branch too short)", math.nan, math.nan
    c2, c1, _ = (float(v) for v in np.polyfit(amps, np.asarray(values) - p_c, 2))
    amax = float(np.max(np.abs(amps)))
    if abs(c1) * amax > 0.2 * abs(c2) * amax**2 and abs(c1) > 0:
        return "asymmetric (transcritical): unstable on one side", c1, c2
    if c2 * stable_side > 0:
        return ("unstable symmetric (subcritical): the branch lies where the primary is "
                "stable", c1, c2)
    return ("stable symmetric (supercritical): the branch lies where the primary is unstable",
            c1, c2)


def _mode_node(rod: DiscreteRod, vec: np.ndarray) -> tuple[int, float]:
    """The free z-unknown where the mode's out-of-plane displacement is largest."""
    free = rod.free_dofs()
    z_free = [i for i, dof in enumerate(free) if dof < 3 * len(rod.x) and dof % 3 == 2]
    k = max(z_free, key=lambda i: abs(vec[i]))
    return k, float(vec[k])


def _solve_bordered(M: sp.spmatrix, rhs: np.ndarray) -> np.ndarray | None:
    """Solve a bordered system; at a double eigenvalue (singular ``M``: a second critical
    mode, as in the symmetric folded ring or a ring's rotation copy) take the minimum-norm
    solution, which keeps that mode's amplitude. None if that fails too."""
    import warnings

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = spla.spsolve(M.tocsc(), rhs)
    if np.all(np.isfinite(sol)):
        return sol
    if M.shape[0] > 4000:
        return None
    sol = np.linalg.lstsq(M.toarray(), rhs, rcond=1e-12)[0]
    return sol if np.all(np.isfinite(sol)) else None


def _bordered_newton(rod: DiscreteRod, k: int, a: float, *, param: Parameter = LOAD,
                     max_iter: int = 40) -> bool:
    """Solve g = 0 with the free unknown ``k`` held at ``a`` and the parameter free (in place)."""
    free = rod.free_dofs()
    scale = float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))
    n = len(free)
    for _ in range(max_iter):
        _, g, H = rod.energy_terms()
        gf = g[free]
        dof = free[k]
        val = rod.x.reshape(-1)[dof]
        if np.max(np.abs(gf)) <= 1e-9 * scale and abs(val - a) <= 1e-12 * max(1.0, abs(a)):
            return True
        gm = param.dgrad(rod)[free]
        ek = sp.csr_matrix(([1.0], ([0], [k])), shape=(1, n))
        M = sp.bmat([[H[free][:, free], sp.csr_matrix(gm[:, None])], [ek, None]], format="csc")
        sol = _solve_bordered(M, -np.concatenate([gf, [val - a]]))
        if sol is None:
            return False
        dq = np.zeros(rod.n_dof)
        dq[free] = sol[:n]
        rod.apply(dq)
        param.set(rod, param.get(rod) + float(sol[n]))
    return False


def _advance(rod: DiscreteRod, k: int, target: float, direction: np.ndarray,
             depth: int = 0) -> bool:
    """Move the branch to amplitude ``target`` (predictor along ``direction``, bordered Newton
    corrector); on failure restore the state and take two half steps (at most 5 halvings)."""
    free = rod.free_dofs()
    saved = rod.copy()
    cur = rod.x.reshape(-1)[free[k]]
    dq = np.zeros(rod.n_dof)
    dq[free] = direction * (target - cur)
    rod.apply(dq)
    if _bordered_newton(rod, k, target):
        return True
    rod.assign(saved)
    if depth >= 5:
        return False
    mid = 0.5 * (cur + target)
    return (_advance(rod, k, mid, direction, depth + 1)
            and _advance(rod, k, target, direction, depth + 1))


def post_buckling_branch(a: Assembly, lo: float, hi: float, *, elements_per_segment: int = 24,
                         amplitudes: np.ndarray | None = None) -> Branch:
    """Trace the post-buckled branch from the first bifurcation of the held state in (lo, hi].

    ``amplitudes`` are the prescribed largest out-of-plane displacements (in the length unit;
    default: 12 values up to 2 % of the assembly's total length, both signs are not needed for
    the verdict but ``-a`` is traced too to detect asymmetry).
    """
    crit = critical_load_factor(a, lo, hi, elements_per_segment=elements_per_segment)
    mu_c = crit.load_factor_critical
    rod0 = discretise(a, elements_per_segment, mu_c)
    _, vecs = lowest_modes(rod0, 1)
    k, amp = _mode_node(rod0, vecs[:, 0])
    if amplitudes is None:
        amplitudes = np.linspace(0.0, 0.02 * a.total_length, 13)[1:]
    rows = []
    shapes = [rod0.x.copy()]
    ok_all = True
    for sign in (1.0, -1.0):
        rod = rod0.copy()
        free = rod.free_dofs()
        base = rod.x.reshape(-1)[free[k]]
        for s_amp in amplitudes:
            target = base + sign * s_amp
            ok = _advance(rod, k, target, vecs[:, 0] / amp)
            ok_all &= ok
            if not ok:
                break
            mu_fixed = rod.load_factor
            if sign > 0:
                shapes.append(rod.x.copy())
            ev = float(lowest_modes(rod, 1)[0][0])
            rows.append((sign * s_amp, mu_fixed, rod.energy(), ev))
    rows.sort()
    A = np.array([r[0] for r in rows])
    M = np.array([r[1] for r in rows])
    small = np.abs(A) <= 0.5 * np.max(np.abs(A))
    # The side of mu_c where the held state is stable (below it unless the bracket says so).
    stable_side = -1.0 if lowest_modes(discretise(a, elements_per_segment, lo), 1)[0][0] > 0 \
        else 1.0
    verdict, c1, c2 = post_buckling_verdict(A[small], M[small], mu_c, stable_side)
    return Branch(mu_c, tuple(A), tuple(M), tuple(r[2] for r in rows), tuple(r[3] for r in rows),
                  c1, c2, verdict, bool(ok_all),
                  "amplitude-controlled bordered Newton from the critical mode", tuple(shapes))
