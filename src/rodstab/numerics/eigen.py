"""The one eigen solver of rodstab: stable intervals of symmetric pencils, lowest eigenpairs.

* :func:`lowest_eigenpairs` -- the lowest eigenpairs of a sparse symmetric matrix (dense
  solver for small ones, shift-invert Lanczos with an inertia-certified shift beyond), each
  pair's residual checked; :func:`jacobi_scaling` is the one diagonal scaling used before it
  and before the sparse pencil solve; :class:`ConstrainedFactor`, :func:`lowest_eigenpairs_on`
  and :func:`definite_on` the same on the null space of linear constraints.
* :func:`pencil_interval` (dense), :func:`pencil_interval_sparse` -- for a pencil
  ``K(p) = A - p C`` with ``A`` symmetric positive definite, the open interval of the load
  parameter ``p`` containing 0 on which ``K(p)`` stays positive definite, with the critical
  modes, their multiplicities (:func:`.roots.multiplicity_tolerance`) and residuals.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..errors import NotConverged, RodstabInputError
from ..results import Result
from .roots import MULTIPLICITY_RTOL, multiplicity_tolerance

#: Converged when every critical eigenvector's relative residual is below this; for a
#: symmetric pencil the eigenvalue error is of the order of the residual squared.
SPARSE_RESIDUAL_TOL = 1e-6
#: Up to this many unknowns :func:`lowest_eigenpairs` uses a dense solver; beyond, shift-invert
#: Lanczos (tested against the dense solver, tests/test_paths.py). The dense solve is O(n^3)
#: and, with a multithreaded BLAS on a loaded machine, slow already at a few hundred unknowns
#: (0.85 s at 300 measured on 2 busy cores, 0.006 s sparse).
DENSE_EIG_MAX = 200
#: Largest matrix :func:`lowest_eigenpairs` solves densely when Lanczos does not converge
#: (LAPACK eigh of 4000 unknowns: ~10 s on one core).
DENSE_FALLBACK_MAX = 4000
#: :func:`lowest_eigenpairs` has converged when every pair's residual ``|A v - lam v|`` is
#: below this times ``max |A_ij|`` (ARPACK's own test is relative to the shifted-inverted
#: eigenvalue, which says little about a tiny eigenvalue of a stiff matrix).
EIG_RESIDUAL_TOL = 1e-8
#: The Lanczos shift of :func:`lowest_eigenpairs` lies at least twice this times ``max |A_ij|``
#: below the lowest eigenvalue (when that is ~0): a few units of round-off. (An absolute 1e-12
#: made the lowest eigenvalues of a Jacobi-scaled rod Hessian at 1e-14..1e-17, hundreds of
#: elements per segment, one cluster as seen from the shift: ~7000 Lanczos steps, 15-45 s.)
EIG_SHIFT_FLOOR = 1e-14


def _sla() -> Any:
    """Return ``scipy.linalg``, imported on first use (~0.1-0.4 s to import)."""
    import scipy.linalg

    return scipy.linalg


@dataclasses.dataclass(frozen=True)
class PencilInterval(Result):
    """Stable interval ``(lo, hi)`` of the load ``p`` for the pencil ``A - p C`` (``A`` SPD).

    ``lo`` / ``hi`` are ``-inf`` / ``+inf`` when no eigenvalue bounds that side. ``mode_lo`` and
    ``mode_hi`` are the critical eigenvectors (columns span the repeated eigenspace);
    ``residual`` is the largest ``||A v - p C v|| / ||A v||`` over the critical modes.
    """

    lo: float
    hi: float
    multiplicity_lo: int
    multiplicity_hi: int
    mode_lo: np.ndarray | None
    mode_hi: np.ndarray | None
    residual: float
    converged: bool
    n_dof: int
    method: str
    #: The computed eigenvalues (as loads ``p = 1/theta``) on each side, nearest to 0 first:
    #: a caller with an error estimate of its own (an FE mesh error) re-applies the
    #: multiplicity rule to them (:func:`multiplicity_of`).
    near_lo: tuple[float, ...] = ()
    near_hi: tuple[float, ...] = ()


#: Eigenvalues per side kept in :attr:`PencilInterval.near_lo` / ``near_hi``.
NEAR_VALUES = 12
#: Restarts of one sparse Lanczos run (ARPACK ``maxiter``). The extreme eigenvalues converge in
#: a few (every both-ends run of tests/test_linear.py and test_hexagram.py within 30); a
#: requested value inside an accumulation point of the spectrum (a strongly anisotropic ring
#: accumulates theta at -1/b2 as well as at 0) never does, and ARPACK's default (10 n) then ran
#: 70 s before failing. The converged part is used and certified by the inertia.
LANCZOS_MAXITER = 30
#: Lanczos runs of :func:`pencil_interval_sparse` per end before it gives up certifying it.
LANCZOS_ATTEMPTS = 4

#: Pencils up to this size are reduced in numpy (:func:`pencil_interval`), larger by LAPACK.
SMALL_PENCIL = 8


def pencil_window(theta: float, error_rtol: float | None) -> float:
    """Return the multiplicity window about the load ``p = 1/theta``, in units of ``theta``.

    :func:`multiplicity_tolerance` ``w`` of ``p`` with the relative error estimate
    ``error_rtol`` of the load; ``|1/theta' - 1/theta| <= w`` is ``|theta' - theta| <= w
    theta^2`` to first order.
    """
    p = 1.0 / theta
    err = None if error_rtol is None else error_rtol * abs(p)
    return multiplicity_tolerance(p, err) * theta * theta


def pencil_interval(A: np.ndarray, C: np.ndarray, *,
                    error_rtol: float | None = None) -> PencilInterval:
    """Stable interval of the load ``p`` for the symmetric pencil ``K(p) = A - p C``.

    ``A`` (the second variation at zero load) must be symmetric positive definite; ``C`` is
    symmetric, possibly indefinite or singular. With ``C v = theta A v`` (a definite generalized
    symmetric problem solved by LAPACK ``sygv`` through ``scipy.linalg.eigh``), ``K(p)`` is
    positive definite exactly for ``1/theta_min < p < 1/theta_max`` (``theta_min < 0 <
    theta_max``); a side with no eigenvalue of that sign is unbounded.

    Eigenvalues that are one with the critical one by the multiplicity rule
    (:func:`multiplicity_tolerance`, the caller's relative error estimate ``error_rtol`` of
    the loads: a discretisation splits a symmetric pair by about its own error) count towards
    its multiplicity.

    Raises
    ------
    RodstabInputError
        (a ValueError) If ``A`` is not positive definite (the unloaded state is then not
        stable and no interval about ``p = 0`` exists).
    """
    A = np.asarray(A, dtype=float)
    C = np.asarray(C, dtype=float)
    n = A.shape[0]
    try:
        if n <= SMALL_PENCIL:
            # LAPACK sygv's own reduction (Cholesky A = L L^T, eigh of L^-1 C L^-T), in numpy:
            # the small mode pencils of the analytic modules then import no scipy.linalg
            L = np.linalg.cholesky(A)
            Li = np.linalg.inv(L)
            theta, W = np.linalg.eigh(Li @ C @ Li.T)
            V = Li.T @ W
        else:
            _sla().cholesky(A, lower=True)
            theta, V = _sla().eigh(C, A)
    except np.linalg.LinAlgError as exc:
        raise RodstabInputError("pencil_interval: A (zero-load second variation) is not "
                                "positive definite") from exc
    cnorm = max(float(np.max(np.abs(theta))), 1e-300)
    tol = MULTIPLICITY_RTOL * cnorm

    def side(sel: np.ndarray, pick: float) -> tuple[float, int, tuple | None]:
        if not sel.any():
            return (math.inf if pick > 0 else -math.inf), 0, None
        th = theta[sel]
        t = th.max() if pick > 0 else th.min()
        if abs(t) <= tol:
            return (math.inf if pick > 0 else -math.inf), 0, None
        close = np.abs(theta - t) <= pencil_window(float(t), error_rtol)
        return 1.0 / float(t), int(close.sum()), (V[:, close], theta[close])

    hi, m_hi, vt_hi = side(theta > tol, +1.0)
    lo, m_lo, vt_lo = side(theta < -tol, -1.0)
    residual = 0.0
    for vt in (vt_hi, vt_lo):
        if vt is None:
            continue
        v, th = vt
        for k in range(v.shape[1]):  # each vector with its own eigenvalue
            Av = A @ v[:, k]
            residual = max(residual, float(np.linalg.norm(Av - (C @ v[:, k]) / th[k])
                                           / np.linalg.norm(Av)))
    v_hi = None if vt_hi is None else vt_hi[0]
    v_lo = None if vt_lo is None else vt_lo[0]
    pos, neg = np.sort(theta[theta > tol])[::-1], np.sort(theta[theta < -tol])
    return PencilInterval(lo, hi, m_lo, m_hi, v_lo, v_hi, residual,
                          bool(residual < 1e-8), n, "generalized symmetric eigh (LAPACK sygv)",
                          near_lo=tuple(1.0 / neg[:NEAR_VALUES]),
                          near_hi=tuple(1.0 / pos[:NEAR_VALUES]))


def count_below(A: Any, sigma: float) -> int | None:
    """Count the eigenvalues of the sparse symmetric ``A`` below ``sigma`` (Sylvester's inertia).

    ``A - sigma I = P L D L^T P^T`` by SuperLU in symmetric mode (diagonal pivots, the same
    symmetric ordering for rows and columns), so the negative entries of ``U``'s diagonal count
    the eigenvalues below ``sigma``. None when that factorisation is not available (singular,
    or the pivoting left the diagonal).
    """
    return _ldlt(A, sigma)[1]


def _ldlt(A: Any, sigma: float) -> tuple[Any, int | None]:
    """Symmetric factorisation of ``A - sigma I`` and its count of negative pivots.

    ``(lu, count)``: SuperLU in symmetric mode (see :func:`count_below`); ``(None, None)`` when
    it fails, ``(lu, None)`` when the pivoting left the diagonal (no inertia).
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    n = A.shape[0]
    try:
        lu = spla.splu((A - sigma * sp.identity(n)).tocsc(), permc_spec="MMD_AT_PLUS_A",
                       diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:
        return None, None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return lu, None
    d = lu.U.diagonal()
    return lu, (int(np.sum(d < 0)) if np.all(np.isfinite(d)) else None)


def jacobi_scaling(A: Any) -> np.ndarray:
    """Return ``d = 1 / sqrt(|diag A|)`` (1 where the diagonal is 0), shape ``(n,)``.

    ``D A D`` (``D = diag(d)``) has a unit diagonal and, by Sylvester's law, the inertia of
    ``A``: the same stable/unstable verdict and the same load at which it changes. It evens
    out unknowns of different units (an FE displacement ~h^-3 against a slope ~h^-1, a rod's
    stiff stretch penalty against its bending), without which a factorisation loses digits.
    """
    dg = np.abs(np.asarray(A.diagonal(), dtype=float))
    dg[dg == 0] = 1.0
    return 1.0 / np.sqrt(dg)


def lowest_eigenpairs(A: Any, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Return the ``k`` lowest eigenpairs ``(vals (k,), vecs (n, k))`` of sparse symmetric ``A``.

    Dense (LAPACK ``eigh``) up to :data:`DENSE_EIG_MAX` unknowns (``k <= n``); beyond, shift-
    invert Lanczos (ARPACK ``eigsh``, ``k < n``), which returns the eigenvalues NEAREST its
    shift: the shift is therefore moved below the lowest eigenvalue and certified there by the
    inertia (:func:`count_below` = 0), so the nearest are the lowest and none is missed (a
    negative eigenvalue farther from 0 than a small positive one would be missed by a shift
    placed from the eigenvalue nearest 0 alone). Raises :class:`~rodstab.errors.NotConverged`
    when a pair's residual exceeds :data:`EIG_RESIDUAL_TOL` ``max |A_ij|``.
    """
    import warnings

    import scipy.sparse.linalg as spla

    from ..errors import NotConverged

    n = A.shape[0]
    if n <= DENSE_EIG_MAX:
        vals, vecs = _sla().eigh(A.toarray(), subset_by_index=[0, min(k, n) - 1])
    else:
        # A fixed start vector: ARPACK's default is random, which makes the last digits -- and
        # so the sign of quantities near zero along a path -- differ from run to run.
        v0 = np.linspace(1.0, 2.0, n)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            lam0 = spla.eigsh(A, k=1, sigma=0.0, which="LM", tol=1e-10, v0=v0)[0][0]
        step = max(abs(lam0), EIG_SHIFT_FLOOR * float(abs(A).max()))
        sigma = min(lam0, 0.0) - 2.0 * step
        for _ in range(80):
            lu, below = _ldlt(A, sigma)
            if below == 0:
                break
            step *= 2.0
            sigma = min(lam0, 0.0) - 2.0 * step
        else:
            raise NotConverged("could not place a Lanczos shift below the lowest eigenvalue "
                               "(no inertia-certified shift in 80 doublings)")
        assert lu is not None  # below == 0 only with a factorisation
        # The certifying factorisation of A - sigma I is the shift-invert operator: no second
        # factorisation inside eigsh.
        op = spla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
        kk = min(k, n - 1)
        vals = vecs = None
        # ARPACK's default basis (2k + 1 vectors) can stall when the shift had to go far below
        # the lowest eigenvalues (an unstable state: the transformed ones 1/(lam - sigma)
        # crowd): a 7-rod cusp ring at 16 elements per rod, 1.03x past its lower limit, ran
        # 20001 iterations (38 s) with 2 of 4 converged, and a 60-vector basis took 20 s.
        # A near-zero cluster (rigid motions, near-neutral modes of a ring) converges slowly
        # at best: a first try with few restarts, then dense where that is cheap.
        tries = ((max(2 * kk + 1, 20), 1000),) if n <= DENSE_FALLBACK_MAX else \
            ((max(2 * kk + 1, 20), 1000), (max(4 * kk, 60), 20000))
        for ncv, iters in tries:
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    vals, vecs = spla.eigsh(A, k=kk, sigma=sigma, which="LM", tol=1e-10,
                                            maxiter=iters, v0=v0, OPinv=op,
                                            ncv=min(ncv, n - 1))
                break
            except spla.ArpackNoConvergence:
                continue
        if vals is None:
            if n > DENSE_FALLBACK_MAX:
                raise NotConverged(f"lowest eigenpairs: shift-invert Lanczos did not converge "
                                   f"({n} unknowns, bases of up to {max(4 * kk, 60)} "
                                   "vectors)")
            vals, vecs = _sla().eigh(A.toarray(), subset_by_index=[0, kk - 1])
        order = np.argsort(vals)
        vals, vecs = vals[order], vecs[:, order]
    scale = float(abs(A).max()) if n else 1.0
    res = np.linalg.norm(A @ vecs - vecs * vals, axis=0)
    if res.size and float(res.max()) > EIG_RESIDUAL_TOL * scale:
        raise NotConverged(f"lowest eigenpairs: residual {float(res.max()):.3g} exceeds "
                           f"{EIG_RESIDUAL_TOL:g} x max|A| = {EIG_RESIDUAL_TOL * scale:.3g}")
    return vals, vecs


#: Entries of one dense block of right-hand sides in :meth:`ConstrainedFactor.of` (8 MB).
SOLVE_BLOCK_ENTRIES = 1_000_000


@dataclasses.dataclass(frozen=True)
class ConstrainedFactor:
    """Factorisation of ``A`` on the constraints ``G v = 0`` by substructuring, with inertia.

    The unknowns after the first ``border`` (``I``; ``A_II`` must be nonsingular) are
    factorised once by a sparse LU in symmetric mode (diagonal pivots, so ``U``'s diagonal is
    the ``D`` of ``P A_II P^T = L D L^T``), and the ``border`` unknowns with the ``m``
    multipliers of ``G`` form a small dense Schur complement ``S`` of the KKT matrix
    ``[A G^T; G 0]``. Its inertia is ``inertia(A | G v = 0) + (m, m, 0)`` (``G`` of full row
    rank) and, by Haynsworth's additivity, ``inertia(A_II) + inertia(S)``: so ``A`` has
    ``n_negative = neg(A_II) + neg(S) - m`` negative directions on the constraints, and a
    zero one when ``S`` is singular.
    """

    n: int
    border: int
    m: int
    lu: Any
    W: Any  # sparse [A_IJ, G_I^T]
    X: Any  # sparse A_II^-1 W
    S: np.ndarray
    n_negative: int
    singular: bool

    @classmethod
    def of(cls, A: Any, G: Any, border: int) -> ConstrainedFactor:
        """Factorise ``A`` (sparse symmetric ``n x n``) on ``G v = 0`` (sparse ``m x n``)."""
        import scipy.sparse as sp
        import scipy.sparse.linalg as spla

        A = sp.csc_matrix(A)
        G = sp.csr_matrix(G)
        n, m, b = A.shape[0], G.shape[0], border
        try:
            lu = spla.splu(A[b:, b:].tocsc(), permc_spec="MMD_AT_PLUS_A",
                           diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise RodstabInputError(f"A_II is singular: {exc}") from None
        d = lu.U.diagonal()
        if not np.array_equal(lu.perm_r, lu.perm_c) or not np.all(np.isfinite(d)):
            raise RodstabInputError("A_II is singular (no symmetric factorisation)")
        # W and X are sparse when A_II is block diagonal (one block per segment of an FE
        # assembly): the solves leave exact zeros outside the blocks a column touches.
        W = sp.hstack([A[b:, :b], G[:, b:].T]).tocsc()
        # In blocks of columns (one SuperLU call per block: a call per column cost ~3 ms of
        # overhead each at 5000 unknowns), each block dense: O(n) memory per block.
        cols = max(1, SOLVE_BLOCK_ENTRIES // max(n - b, 1))
        X = sp.hstack([sp.csc_matrix(lu.solve(W[:, j:j + cols].toarray()))
                       for j in range(0, W.shape[1], cols)], format="csc") \
            if W.shape[1] else sp.csc_matrix((n - b, 0))
        S = np.zeros((b + m, b + m))
        S[:b, :b] = A[:b, :b].toarray()
        S[:b, b:] = G[:, :b].T.toarray()
        S[b:, :b] = G[:, :b].toarray()
        S -= (W.T @ X).toarray()
        S = 0.5 * (S + S.T)
        s_eig = np.linalg.eigvalsh(S) if S.size else np.zeros(0)
        s_scale = max(float(np.abs(s_eig).max()) if s_eig.size else 0.0, 1e-300)
        return cls(n, b, m, lu, W, X, S, int(np.sum(d < 0)) + int(np.sum(s_eig < 0)) - m,
                   bool(np.any(np.abs(s_eig) <= 1e-13 * s_scale)))

    def solve(self, f: np.ndarray) -> np.ndarray:
        """``y`` with ``A y - f`` in the range of ``G^T`` and ``G y = 0``."""
        b = self.border
        z = self.lu.solve(f[b:])
        g = np.concatenate([f[:b], np.zeros(self.m)]) - self.W.T @ z
        yj = np.linalg.solve(self.S, g) if self.S.size else g
        out = np.empty(self.n)
        out[:b] = yj[:b]
        out[b:] = z - self.X @ yj
        return out


def lowest_eigenpairs_on(A: Any, G: Any, border: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Return the ``k`` lowest eigenpairs of sparse symmetric ``A`` on ``G v = 0``.

    ``(vals (k,), vecs (n, k))``, the vectors orthonormal and in the null space of ``G``.

    The eigenvalues of ``N^T A N`` for an orthonormal basis ``N`` of the null space of ``G``
    (``m x n``, full row rank, ``m`` small: its rows may be dense). Dense up to
    :data:`DENSE_EIG_MAX` unknowns; beyond, shift-invert Lanczos on the constrained inverse
    ``f -> y`` (``A y - sigma y - f`` in the range of ``G^T``, ``G y = 0``: a symmetric operator
    on the null space whose largest eigenvalues are ``1 / (lam - sigma)``), by
    :class:`ConstrainedFactor` (``border``: as there). As in :func:`lowest_eigenpairs` the shift
    is placed below the lowest eigenvalue and certified there by the inertia (no negative
    direction of ``A - sigma I`` on the constraints), so no eigenvalue is missed. Raises
    :class:`~rodstab.errors.NotConverged` when a pair's residual (projected on the null space)
    exceeds :data:`EIG_RESIDUAL_TOL` ``max |A_ij|``.
    """
    import warnings

    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from ..errors import NotConverged

    A = sp.csc_matrix(A)
    G = sp.csr_matrix(G)
    n = A.shape[0]
    if n <= DENSE_EIG_MAX:
        N = _sla().null_space(G.toarray()) if G.shape[0] else np.eye(n)
        w, V = np.linalg.eigh(N.T @ A.toarray() @ N)
        return w[:k], N @ V[:, :k]
    scale = float(abs(A).max())
    eye = sp.identity(n, format="csc")

    def factor(sigma: float) -> ConstrainedFactor | None:
        try:
            return ConstrainedFactor.of(A - sigma * eye, G, border)
        except RodstabInputError:  # singular at this shift: try another
            return None

    def largest(fac: ConstrainedFactor, kk: int, which: str) -> tuple[np.ndarray, np.ndarray]:
        op = spla.LinearOperator((n, n), matvec=fac.solve, dtype=float)
        v0 = fac.solve(np.linspace(1.0, 2.0, n))  # in the null space, fixed (reproducible)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return spla.eigsh(op, k=kk, which=which, tol=1e-10, v0=v0,
                              maxiter=1000 if n <= DENSE_FALLBACK_MAX else 20000)

    def dense() -> tuple[np.ndarray, np.ndarray]:
        # Lanczos stalled on a crowded near-zero cluster (as in lowest_eigenpairs): dense
        # where that is cheap, else say so
        if n > DENSE_FALLBACK_MAX:
            raise NotConverged(f"lowest eigenvalues on the constraints: shift-invert Lanczos "
                               f"did not converge ({n} unknowns)") from None
        N = _sla().null_space(G.toarray()) if G.shape[0] else np.eye(n)
        w, V = np.linalg.eigh(N.T @ A.toarray() @ N)
        return w[:k], N @ V[:, :k]

    sigma = -EIG_SHIFT_FLOOR * scale
    fac = factor(sigma)
    if fac is None:
        sigma *= -1.0
        fac = factor(sigma)
    if fac is None:
        raise NotConverged("lowest eigenvalues on the constraints: singular at two shifts")
    if fac.n_negative > 0:
        # Nearest eigenvalue to the shift first, then below the lowest (doubling steps).
        try:
            mu = largest(fac, 1, "LM")[0][0]
        except spla.ArpackNoConvergence:
            return dense()
        lam0 = sigma + 1.0 / mu
        step = max(abs(lam0), EIG_SHIFT_FLOOR * scale)
        for _ in range(80):
            sigma = min(lam0, 0.0) - 2.0 * step
            fac = factor(sigma)
            if fac is not None and fac.n_negative == 0:
                break
            step *= 2.0
        else:
            raise NotConverged("could not place a Lanczos shift below the lowest eigenvalue "
                               "on the constraints (80 doublings)")
    assert fac is not None
    try:
        mus, vecs = largest(fac, min(k, n - G.shape[0] - 1), "LA")
    except spla.ArpackNoConvergence:
        return dense()
    order = np.argsort(-mus)
    vals = sigma + 1.0 / mus[order]
    vecs = vecs[:, order]
    # Residual on the null space: A y - lam y minus its least-squares part in range(G^T).
    R = A @ vecs - vecs * vals
    Gd = G.T.toarray()
    if Gd.shape[1]:
        R = R - Gd @ np.linalg.lstsq(Gd, R, rcond=None)[0]
    res = np.linalg.norm(R, axis=0)
    if res.size and float(res.max()) > EIG_RESIDUAL_TOL * scale:
        raise NotConverged(f"lowest eigenvalues on the constraints: residual "
                           f"{float(res.max()):.3g} exceeds {EIG_RESIDUAL_TOL:g} x max|A|")
    return vals, vecs


def definite_on(A: Any, constraints: Any = None, border: int = 0) -> bool:
    """Whether the sparse symmetric ``A`` is positive definite on ``constraints @ v = 0``.

    A stability verdict without an eigen solve: the inertia of :class:`ConstrainedFactor`
    (Sylvester, Haynsworth), or for up to :data:`DENSE_EIG_MAX` unknowns the lowest eigenvalue
    of ``N^T A N`` on a null-space basis ``N``, against ``1e-13 max |eig|`` (a zero eigenvalue
    -- the critical load itself -- is not definite).
    """
    import scipy.sparse as sp

    A = sp.csc_matrix(A)
    n = A.shape[0]
    G = sp.csr_matrix((0, n)) if constraints is None else sp.csr_matrix(constraints)
    if n <= DENSE_EIG_MAX:
        N = _sla().null_space(G.toarray()) if G.shape[0] else np.eye(n)
        ev = np.linalg.eigvalsh(N.T @ A.toarray() @ N)
        return bool(ev.size == 0 or ev[0] > 1e-13 * max(abs(ev[0]), abs(ev[-1])))
    try:
        fac = ConstrainedFactor.of(A, G, border)
    except RodstabInputError:
        return False
    return fac.n_negative == 0 and not fac.singular


def pencil_interval_sparse(A, C, *, constraints=None, border: int = 0,
                           error_rtol: float | None = None,
                           n_eig: int = 6, tol: float = 1e-12) -> PencilInterval:
    """Sparse version of :func:`pencil_interval` for large FE pencils, with linear constraints.

    ``C v = theta A v`` on the subspace ``G v = 0`` (``G = constraints``, ``m x n`` sparse of
    full row rank, or None): the few largest and smallest ``theta`` by Lanczos (ARPACK
    ``eigsh`` in generalized mode, ``A``-inner product, one run per end), to relative
    tolerance ``tol``. The extreme values converge fast; the spectrum accumulates at 0 and, for
    strongly anisotropic sections, at other points too (a requested value there never
    converges: the converged part is used). Each end is certified by the inertia
    (:class:`ConstrainedFactor` of ``A - C / theta'`` for a ``theta'`` between the critical
    cluster and the next found value: the count of eigenvalues beyond it must be the
    cluster's), so no extreme eigenvalue is missed and a multiplicity is not under-counted;
    ``n_eig`` doubles while the found values are all one cluster or the certificate fails.
    Multiplicities by :func:`multiplicity_tolerance` with the caller's relative error
    estimate ``error_rtol``. Raises :class:`~rodstab.errors.NotConverged` (with the reason)
    when an end cannot be certified.

    The constrained solve ``[A G^T; G 0] [y; nu] = [f; 0]`` and the definiteness test of ``A``
    on the constraints are those of :class:`ConstrainedFactor` (substructured on the first
    ``border`` unknowns). Up to :data:`DENSE_EIG_MAX` unknowns: :func:`pencil_interval` on a
    null-space basis of ``G``.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    A = sp.csc_matrix(A)
    C = sp.csc_matrix(C)
    n = A.shape[0]
    G = sp.csr_matrix((0, n)) if constraints is None else sp.csr_matrix(constraints)
    m = G.shape[0]
    if n <= DENSE_EIG_MAX:  # the dense solve is O(n^3) and slow on a busy multithreaded BLAS
        N = _sla().null_space(G.toarray()) if m else np.eye(n)
        res = pencil_interval(N.T @ A.toarray() @ N, N.T @ C.toarray() @ N,
                              error_rtol=error_rtol)
        return dataclasses.replace(
            res, mode_lo=None if res.mode_lo is None else N @ res.mode_lo,
            mode_hi=None if res.mode_hi is None else N @ res.mode_hi, n_dof=n - m)
    fac = ConstrainedFactor.of(A, G, border)
    if fac.n_negative != 0 or fac.singular:
        raise RodstabInputError("pencil_interval_sparse: A is not positive definite on the "
                                f"constraints ({fac.n_negative} negative directions)")
    solve, b = fac.solve, border
    Ainv = spla.LinearOperator((n, n), matvec=solve, dtype=float)

    if C.count_nonzero() == 0 or not np.any(C.data):
        # C = 0 (e.g. no natural curvature anywhere): every theta is 0, the interval is the
        # whole line, as the dense pencil_interval says (ARPACK would stop: "Starting vector
        # is zero", found by benchmarks/fuzz.py).
        return PencilInterval(-math.inf, math.inf, 0, 0, None, None, 0.0, True, n - m,
                              "C = 0: no load-dependent term, every eigenvalue theta is 0")
    # A start vector on the constraints, fixed (ARPACK's default is random: results would
    # vary run to run); the Krylov space then stays on them, as solve() maps into them.
    v_start = solve(C @ np.linspace(1.0, 2.0, n))
    k_max = n - m - 2

    def lanczos(which: str, k: int) -> tuple[np.ndarray, np.ndarray, bool]:
        # k values of ``C v = theta A v`` (the A-inner product) at one end ("LA", "SA") or
        # k/2 at each ("BE"), and whether all k converged (else the converged part, possibly
        # empty: a value asked for inside an accumulation point of the spectrum never does).
        try:
            vals, vecs = spla.eigsh(C, k=k, M=A, Minv=Ainv, which=which, tol=tol,
                                    v0=v_start, maxiter=LANCZOS_MAXITER)
            complete = True
        except spla.ArpackNoConvergence as exc:
            vals, vecs, complete = exc.eigenvalues, exc.eigenvectors, False
        except spla.ArpackError as exc:
            raise NotConverged(f"the sparse Lanczos eigen solve ({n} unknowns) failed: "
                               f"{exc}") from None
        return np.asarray(vals), np.asarray(vecs), complete

    def at_end(vals: np.ndarray, vecs: np.ndarray, sign: float
               ) -> tuple[np.ndarray, np.ndarray]:
        # the values of one sign, from the end inwards
        sel = vals * sign > 0
        order = np.argsort(-sign * vals[sel])
        return vals[sel][order], vecs[:, sel][:, order]

    def negative_directions(t: float) -> int | None:
        # Eigenvalues theta beyond t (theta > t for t > 0, theta < t for t < 0) by Sylvester's
        # inertia of A - C / t on the constraints: n_negative(A - p C) = #{p theta > 1}.
        try:
            f = ConstrainedFactor.of(A - C / t, G, border)
        except RodstabInputError:
            return None
        return None if f.singular else f.n_negative

    def certify(vals: np.ndarray, vecs: np.ndarray, sign: float, complete: bool, k: int
                ) -> tuple[int, np.ndarray | None, str | None]:
        # The end's extreme eigenvalue t = vals[0] with its multiplicity (the values within
        # the multiplicity window of 1/t), certified by the inertia at a theta between that
        # cluster and the next found value: the count beyond it must be the cluster's, so no
        # eigenvalue beyond t or inside its window was missed. (0, None, why) to ask again.
        t = float(vals[0])
        window = pencil_window(t, error_rtol)
        close = np.abs(vals - t) <= window
        if complete and close.all() and k < k_max:
            return 0, None, "the found values were one cluster"
        edge = vals[close][-1]
        nxt = vals[~close]
        probe = 0.5 * (edge + nxt[0]) if nxt.size else edge - sign * window
        count = negative_directions(float(probe))
        if count == int(close.sum()):
            return int(close.sum()), vecs[:, close], None
        return 0, None, (f"the inertia counts {count} eigenvalues beyond theta = {probe:.6g}, "
                         f"Lanczos found {int(close.sum())}")

    # One Lanczos run for both ends first (k/2 from each); an end it does not settle is asked
    # again on its own, k doubling.
    k = min(2 * n_eig, k_max)
    vals, vecs, complete = lanczos("BE", k)
    found = {sign: (*at_end(vals, vecs, sign), complete, k // 2) for sign in (1.0, -1.0)}
    scale = max(float(np.max(np.abs(vals))) if vals.size else 0.0, 1e-300)
    out: dict[float, tuple[float, int, np.ndarray | None]] = {}
    thetas: dict[float, np.ndarray] = {}
    near: dict[float, tuple[float, ...]] = {}
    failures: list[str] = []
    for sign, name in ((1.0, "LA"), (-1.0, "SA")):
        ev, V, done, k_end = found[sign]
        why: str | None = None
        for attempt in range(LANCZOS_ATTEMPTS + 1):
            if attempt:
                k_end = min(max(2 * k_end, n_eig), k_max)
                ev, V, done = lanczos(name, k_end)
                ev, V = at_end(ev, V, sign)
                scale = max(scale, float(np.max(np.abs(ev))) if ev.size else 0.0)
            if ev.size == 0:
                if done:  # every eigenvalue found at this end has the other sign
                    why = None
                    out[sign] = (math.inf * sign, 0, None)
                    break
                why = f"no eigenvalue converged at the {name} end ({k_end} asked)"
                continue
            if abs(ev[0]) <= 1e-14 * scale:
                why = None
                out[sign] = (math.inf * sign, 0, None)
                break
            mult, Vc, why = certify(ev, V, sign, done, k_end)
            if why is None:
                out[sign] = (1.0 / float(ev[0]), mult, Vc)
                thetas[sign] = ev[:mult]  # the cluster: ev runs from the end inwards
                near[sign] = tuple(1.0 / ev[:NEAR_VALUES])
                break
            if k_end >= k_max:
                break
        if why is not None:
            failures.append(why)
    if failures:
        raise NotConverged(f"the sparse Lanczos eigen solve ({n} unknowns) could not certify "
                           f"the extreme eigenvalues: {'; '.join(failures)}")
    residual = 0.0
    for sign in (1.0, -1.0):
        modes = out[sign][2]
        if modes is None:
            continue
        for k in range(modes.shape[1]):  # each vector with its own eigenvalue
            # |A^-1 C v / theta - v| / |v| on the constraints: the inverted problem's residual
            v = modes[:, k]
            residual = max(residual, float(np.linalg.norm(solve(C @ v) / thetas[sign][k] - v)
                                           / np.linalg.norm(v)))
    out_hi, out_lo = out[1.0], out[-1.0]
    hi, m_hi, v_hi = out_hi
    lo, m_lo, v_lo = out_lo
    how = (f"substructured: sparse LU of A_II, {b + m}-square Schur complement" if b + m
           else "sparse LU of A")
    return PencilInterval(lo, hi, m_lo, m_hi, v_lo, v_hi, residual,
                          bool(residual < SPARSE_RESIDUAL_TOL), n - m,
                          f"Lanczos (ARPACK eigsh, generalized, each end certified by the "
                          f"inertia; {how})", near_lo=near.get(-1.0, ()),
                          near_hi=near.get(1.0, ()))
