"""Is a quadratic form positive on a polyhedral cone? A certified decision.

The question (issue 21: stability with contact at zero gap). ``K`` symmetric ``(n, n)``,
``D`` ``(m, n)``; the cone ``C = {v : D v >= 0}``. Is ``v^T K v > 0`` for every nonzero ``v`` in
``C``? In general a co-NP-complete question (copositivity); here ``K`` has few non-positive
directions, and that makes it exact.

The split. ``K = X diag(lam) X^T``; ``E`` the ``k`` eigenvectors with ``lam`` below
:data:`ZERO_RTOL` ``max |lam|`` (the negative and the near-zero ones), ``X+`` the rest, on which
``K`` is positive definite. Every ``v = E c + p`` with ``p`` orthogonal to ``E``, and ``v^T K v =
sum lam_i c_i^2 + p^T K p``. For ``c = 0`` the form is positive; every other ``v`` scales to
``|c| = 1``. So the form is positive on ``C minus {0}`` if and only if

    F(c) = sum_i lam_i c_i^2 + q(c) > 0  on the unit sphere |c| = 1,
    q(c) = min { p^T K p : p orthogonal to E, D (E c + p) >= 0 }   (+inf when infeasible).

``q`` is a convex quadratic programme. With ``x = diag(lam+)^(1/2) X+^T p`` it is the
least-distance programme ``min |x|^2`` subject to ``W x >= f(c)``, ``W = D X+ diag(lam+)^(-1/2)``,
``f(c) = -D E c``, which non-negative least squares solves exactly, by a finite active-set
method (Lawson & Hanson 1974, *Solving Least Squares Problems*, ch. 23; scipy's ``nnls``):
``u >= 0`` minimising ``|[W^T; f^T] u - e_last|``, residual ``r``; ``r = 0`` proves the
programme infeasible (``W^T u = 0``, ``f^T u = 1``: a Farkas vector); otherwise ``x = -r[:-1] /
r[-1]``.

Certificates. Weak duality of the least-distance programme: every ``z >= 0`` gives, for
*every* ``c'``,

    q(c') >= -(D E c')^T z - |W^T z|^2 / 4,

an affine minorant of ``q``; the optimal ``z = 2 u / (1 - f^T u)`` comes with each solve, and
its minorant touches ``q`` at ``c``. A Farkas vector ``u`` proves ``q = +inf`` wherever ``-(D
E c')^T u > 0``. So every evaluation of ``F`` at one ``c`` bounds ``F`` from below everywhere:

* ``k = 0``: ``K`` is positive definite -- positive.
* ``k = 1``: ``F(+1)`` and ``F(-1)``, exactly.
* ``k = 2``: the unit circle, cut into arcs; on each arc the best minorant plus ``lam_1 cos^2 t
  + lam_2 sin^2 t`` is a trigonometric polynomial of degree 2, bounded below by its values at
  :data:`ARC_SAMPLES` points less ``M2 dt^2 / 8`` (``M2`` a bound on its second derivative).
  Arcs are bisected (the lowest bound first) until every arc's bound is above the floor
  (positive, certified), or ``F < -floor`` at a point (a witness ``v`` in ``C`` with ``v^T K v
  < 0``, returned and checked: not positive), or :data:`MAX_EVALUATIONS` solves are spent
  (undecided).
* ``k >= 3``: undecided (a sphere is not cut into arcs here).

The floor is :data:`FLOOR_RTOL` ``max |lam|``: a form whose minimum on the cone is within it of
zero is undecided, never called positive -- which is what happens exactly at a limit.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..results import Result

#: Eigenvalues below this times ``max |lam|`` count as non-positive directions (into ``E``):
#: dividing by them in ``W`` would amplify round-off by more than 1e5.
ZERO_RTOL = 1e-10
#: ``F`` counts as positive above, negative below ``-``, this times ``max |lam|`` (round-off of
#: the eigen-decomposition and the least-squares solve: ~1e-13 of it measured).
FLOOR_RTOL = 1e-9
#: A witness keeps every gap to within this times ``|D| |v|`` (the solve's round-off).
FEASIBLE_RTOL = 1e-9
#: Points per arc at which the minorant is evaluated (its bound between them: ``M2 dt^2 / 8``).
ARC_SAMPLES = 9
#: Initial arcs of the circle (``k = 2``).
START_ARCS = 8
#: Least-distance solves allowed before the decision is reported undecided.
MAX_EVALUATIONS = 80

POSITIVE, NOT_POSITIVE, UNDECIDED = "positive", "not positive", "undecided"


@dataclasses.dataclass(frozen=True)
class ConeDecision(Result):
    """Whether ``v^T K v > 0`` on ``{D v >= 0} minus {0}`` (module doc).

    Attributes
    ----------
    status : str
        ``"positive"`` (certified: every arc's lower bound above the floor), ``"not positive"``
        (a witness found) or ``"undecided"`` (``message`` says why).
    negative_directions : int
        ``k``, the eigenvectors of ``K`` split off (negative or near zero).
    minimum : float
        The smallest ``F(c)`` evaluated (``+inf`` when none was finite), relative to ``max
        |lam|``.
    lower_bound : float
        A certified lower bound on ``min F`` over the sphere, relative to ``max |lam|``
        (``-inf`` when none is known).
    evaluations : int
        Least-distance solves spent.
    witness : numpy.ndarray or None
        ``(n,)``: ``v`` in ``C`` (to :data:`FEASIBLE_RTOL`) with ``v^T K v < 0``, when not
        positive.
    message : str
    """

    status: str
    negative_directions: int
    minimum: float
    lower_bound: float
    evaluations: int
    witness: np.ndarray | None
    message: str


@dataclasses.dataclass(frozen=True)
class _Eval:
    F: float  # F(c), +inf when infeasible
    slope: np.ndarray  # minorant of q: q(c') >= slope . c' + offset  (or a Farkas direction)
    offset: float
    farkas: bool  # slope is a Farkas direction: q = +inf where slope . c' > 0
    v: np.ndarray | None


class _Split:
    """The eigen-split of ``K`` and the least-distance programme of ``q`` (module doc)."""

    def __init__(self, K: np.ndarray, D: np.ndarray) -> None:
        from scipy.linalg import eigh

        lam, X = eigh(0.5 * (K + K.T))
        self.scale = float(np.max(np.abs(lam))) if lam.size else 1.0
        k = int(np.count_nonzero(lam < ZERO_RTOL * self.scale))
        self.k, self.lam_E, self.E = k, lam[:k], X[:, :k]
        self.P = X[:, k:] / np.sqrt(lam[k:])  # p = P x
        self.D = D
        self.W = D @ self.P
        self.DE = D @ self.E
        self.K = K

    def evaluate(self, c: np.ndarray) -> _Eval:
        from scipy.optimize import nnls

        f = -self.DE @ c
        A = np.vstack([self.W.T, f[None, :]])
        b = np.zeros(A.shape[0])
        b[-1] = 1.0
        u, _ = nnls(A, b, maxiter=50 * max(A.shape))
        u = np.maximum(u, 0.0)  # the certificates below need u >= 0 exactly
        r = A @ u - b
        lam_part = float(self.lam_E @ (c * c))
        Wu = self.W.T @ u
        fu = float(f @ u)
        if abs(r[-1]) <= 1e-12:  # infeasible: W^T u = 0, f^T u = 1 -- checked, not assumed
            tiny = FEASIBLE_RTOL * float(np.linalg.norm(self.W)) * float(np.linalg.norm(u))
            if float(np.linalg.norm(Wu)) <= tiny and fu >= 0.5:
                return _Eval(math.inf, -self.DE.T @ u, 0.0, True, None)
            return _Eval(math.inf, np.zeros(self.k), -math.inf, False, None)  # no bound
        x = -r[:-1] / r[-1]
        v = self.E @ c + self.P @ x
        if 1.0 - fu <= 0.0:  # the dual scaling fails: this solve gives no minorant
            return _Eval(lam_part + float(x @ x), np.zeros(self.k), -math.inf, False, v)
        z = 2.0 * u / (1.0 - fu)
        return _Eval(lam_part + float(x @ x), -self.DE.T @ z,
                     -0.25 * float(np.sum((self.W.T @ z) ** 2)), False, v)


def _arc_bound(lam: np.ndarray, evals: list[_Eval], t0: float, t1: float) -> float:
    """Certified lower bound of ``F`` on the arc ``[t0, t1]`` from every minorant (module doc)."""
    t = np.linspace(t0, t1, ARC_SAMPLES)
    cs = np.stack([np.cos(t), np.sin(t)])
    dt = (t1 - t0) / (ARC_SAMPLES - 1)
    best = -math.inf
    base = lam[0] * cs[0] ** 2 + lam[1] * cs[1] ** 2
    for e in evals:
        s = e.slope @ cs
        if e.farkas:
            # slope . c(t) = |slope| cos(t - t_s): its minimum on the arc is at an end unless
            # the arc holds t_s + pi.
            ts = math.atan2(e.slope[1], e.slope[0]) + math.pi
            inside = ((ts - t0) % (2 * math.pi)) <= (t1 - t0)
            low = -float(np.linalg.norm(e.slope)) if inside else float(min(s[0], s[-1]))
            if low > 0:
                return math.inf
            continue
        g = base + s + e.offset
        m2 = 2.0 * abs(lam[0] - lam[1]) + float(np.linalg.norm(e.slope))
        best = max(best, float(np.min(g)) - m2 * dt * dt / 8.0)
    return best


def positive_on_cone(K: np.ndarray, D: np.ndarray, *,
                     max_evaluations: int = MAX_EVALUATIONS) -> ConeDecision:
    """Decide whether ``v^T K v > 0`` for every nonzero ``v`` with ``D v >= 0`` (module doc).

    Parameters
    ----------
    K : numpy.ndarray
        ``(n, n)`` symmetric (dense).
    D : numpy.ndarray
        ``(m, n)``: the cone's rows (``m = 0``: plain definiteness).
    max_evaluations : int
        Least-distance solves allowed (``k = 2``) before giving up as undecided.

    Returns
    -------
    ConeDecision
        Certified ``positive``, ``not positive`` with a checked witness, or ``undecided``.
    """
    sp = _Split(np.asarray(K, float), np.asarray(D, float).reshape(-1, len(K)))
    floor = FLOOR_RTOL
    if sp.k == 0:
        return ConeDecision(POSITIVE, 0, math.inf, math.inf, 0, None, "K is positive definite")
    if sp.D.shape[0] == 0:  # no cone: the whole space (and no empty least-squares solve)
        lam0 = float(sp.lam_E[0]) / sp.scale
        if lam0 < -floor:
            return ConeDecision(NOT_POSITIVE, sp.k, lam0, -math.inf, 0, sp.E[:, 0].copy(),
                                "no constraints, and K has a negative eigenvalue")
        return ConeDecision(UNDECIDED, sp.k, lam0, lam0, 0, None,
                            "no constraints, and K's lowest eigenvalue is within the floor of 0")
    if sp.k > 2:
        return ConeDecision(UNDECIDED, sp.k, math.nan, -math.inf, 0, None,
                            f"K has {sp.k} non-positive directions; the certified decision "
                            "handles at most 2")
    lam = sp.lam_E / sp.scale
    evals: list[_Eval] = []

    def run(c: np.ndarray) -> _Eval:
        e = sp.evaluate(c)
        e = dataclasses.replace(e, F=e.F / sp.scale, slope=e.slope / sp.scale,
                                offset=e.offset / sp.scale)
        evals.append(e)
        return e

    def witness(e: _Eval) -> ConeDecision | None:
        if e.F >= -floor or e.v is None:
            return None
        v = e.v
        slack = FEASIBLE_RTOL * float(np.linalg.norm(sp.D)) * float(np.linalg.norm(v))
        if sp.D.size and float(np.min(sp.D @ v)) < -slack:
            return None  # round-off broke feasibility: not a witness
        quad = float(v @ sp.K @ v) / sp.scale
        if quad >= -floor * float(v @ v):
            return None
        low = min(x.F for x in evals)
        return ConeDecision(NOT_POSITIVE, sp.k, low, -math.inf, len(evals), v,
                            f"a perturbation in the cone lowers the form: v^T K v = "
                            f"{quad * sp.scale:.3e}")

    if sp.k == 1:
        for sign in (1.0, -1.0):
            found = witness(run(np.array([sign])))
            if found:
                return found
        low = min(e.F for e in evals)
        if low > floor:
            return ConeDecision(POSITIVE, 1, low, low, 2, None, "F(+1), F(-1) > 0, exactly")
        return ConeDecision(UNDECIDED, 1, low, low, 2, None,
                            f"min F = {low:.3e} (relative) within the floor {floor:g} of zero")
    # Every solve's minorant holds on the whole circle: each arc keeps its best bound so far,
    # raised by each new solve (work: solves x arcs, not their square).
    bound: dict[tuple[float, float], float] = {}

    def raise_bounds(new: list[_Eval]) -> None:
        for arc in bound:
            bound[arc] = max(bound[arc], _arc_bound(lam, new, *arc))

    for i in range(START_ARCS):
        t0, t1 = 2 * math.pi * i / START_ARCS, 2 * math.pi * (i + 1) / START_ARCS
        tm = 0.5 * (t0 + t1)
        found = witness(run(np.array([math.cos(tm), math.sin(tm)])))
        if found:
            return found
        bound[(t0, t1)] = -math.inf
    raise_bounds(evals)
    while True:
        open_ = [(b, arc) for arc, b in bound.items() if b <= floor]
        lower = min(bound.values())
        low = min(e.F for e in evals)
        if not open_:
            return ConeDecision(POSITIVE, 2, low, lower, len(evals), None,
                                f"every arc's lower bound above the floor ({len(bound)} arcs)")
        if len(evals) + 2 > max_evaluations:
            return ConeDecision(UNDECIDED, 2, low, lower, len(evals), None,
                                f"{len(open_)} arcs not certified after {len(evals)} solves "
                                f"(lower bound {lower:.3e}, smallest F {low:.3e}, relative)")
        _, (t0, t1) = min(open_, key=lambda x: x[0])
        del bound[(t0, t1)]
        tm = 0.5 * (t0 + t1)
        new = []
        for a, b in ((t0, tm), (tm, t1)):
            tq = 0.5 * (a + b)
            e = run(np.array([math.cos(tq), math.sin(tq)]))
            found = witness(e)
            if found:
                return found
            new.append(e)
        raise_bounds(new)
        for arc in ((t0, tm), (tm, t1)):
            bound[arc] = _arc_bound(lam, evals, *arc)
