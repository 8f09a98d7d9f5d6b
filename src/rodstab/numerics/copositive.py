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
* ``k = 3``: the unit sphere, cut into spherical triangles (the octahedron's 8 faces,
  each split in 4 at its edges' normalised midpoints). On each face the best minorant plus
  ``sum lam_i c_i^2`` is bounded below by its values at the points of a grid of the face
  (:data:`PATCH_DIVISIONS`, normalised) less ``L rho``: ``L = 2 max |lam| + |slope|`` bounds
  its gradient on the sphere and ``rho`` bounds the angle from a point of the face to its
  nearest grid point (:func:`_face_samples`). The faces with the lowest bound are split
  first; as for ``k = 2`` the outcome is certified, a checked witness, or undecided after
  :data:`MAX_EVALUATIONS_3` solves.
* ``k >= 4``: undecided.

The floor is :data:`FLOOR_RTOL` ``max |lam|``: a form whose minimum on the cone is within it of
zero is undecided, never called positive -- which is what happens exactly at a limit.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

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
#: ... with three non-positive directions (a sphere: four solves per split face); scaled with
#: ``max_evaluations`` of :func:`positive_on_cone`.
MAX_EVALUATIONS_3 = 240
#: Divisions of a face's edges for its sample grid (``k = 3``): ``(m + 1)(m + 2) / 2`` points.
PATCH_DIVISIONS = 8

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


def _unit(x: np.ndarray) -> np.ndarray:
    return x / np.linalg.norm(x, axis=-1, keepdims=True)


def _face_samples(face: np.ndarray) -> tuple[np.ndarray, float]:
    """Grid points of a spherical triangle (rows of ``face``) and their covering angle.

    The flat triangle's points ``(i a + j b + l c) / m`` (``i + j + l = m``,
    :data:`PATCH_DIVISIONS`), normalised. A point ``P`` of the flat triangle lies in a
    sub-triangle of the grid, within its longest edge ``d`` (the flat edge over ``m``) of a grid
    point ``Q``; with ``|P|, |Q| >= r`` (the flat plane's distance from the origin) the angle
    between them has ``sin <= d / r`` (``|P x Q| <= |Q| |P - Q|``) and is below 90 degrees
    (a face lies in an octant). Returns the points and ``arcsin(min(1, d / r))``.
    """
    m = PATCH_DIVISIONS
    w = np.array([(i, j, m - i - j) for i in range(m + 1) for j in range(m + 1 - i)], float) / m
    pts = _unit(w @ face)
    a, b, c = face
    d = max(float(np.linalg.norm(a - b)), float(np.linalg.norm(b - c)),
            float(np.linalg.norm(c - a))) / m
    normal = np.cross(b - a, c - a)
    r = abs(float(normal @ a)) / float(np.linalg.norm(normal))
    return pts, math.asin(min(1.0, d / r))


def _face_bound(lam: np.ndarray, evals: list[_Eval], face: np.ndarray) -> float:
    """Certified lower bound of ``F`` on a spherical triangle from every minorant (module doc)."""
    pts, rho = _face_samples(face)
    base = pts**2 @ lam
    best = -math.inf
    for e in evals:
        s = pts @ e.slope
        slope = float(np.linalg.norm(e.slope))
        if e.farkas:
            if float(np.min(s)) - slope * rho > 0:
                return math.inf
            continue
        lip = 2.0 * float(np.max(np.abs(lam))) + slope
        best = max(best, float(np.min(base + s + e.offset)) - lip * rho)
    return best


def _octahedron() -> list[np.ndarray]:
    faces = []
    for sx in (1.0, -1.0):
        for sy in (1.0, -1.0):
            for sz in (1.0, -1.0):
                faces.append(np.array([[sx, 0, 0], [0, sy, 0], [0, 0, sz]]))
    return faces


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
        Least-distance solves allowed (``k = 2``; ``k = 3``: that times
        ``MAX_EVALUATIONS_3 / MAX_EVALUATIONS``) before giving up as undecided.

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
    if sp.k > 3:
        return ConeDecision(UNDECIDED, sp.k, math.nan, -math.inf, 0, None,
                            f"K has {sp.k} non-positive directions; the certified decision "
                            "handles at most 3")
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
    if sp.k == 2:
        # arcs (t0, t1) of the circle, halved at their middles
        regions: list[Any] = [(2 * math.pi * i / START_ARCS, 2 * math.pi * (i + 1) / START_ARCS)
                              for i in range(START_ARCS)]

        def centre(arc: Any) -> np.ndarray:
            tm = 0.5 * (arc[0] + arc[1])
            return np.array([math.cos(tm), math.sin(tm)])

        def split(arc: Any) -> list[Any]:
            tm = 0.5 * (arc[0] + arc[1])
            return [(arc[0], tm), (tm, arc[1])]

        return _refine(2, regions, centre, split, lambda ev, arc: _arc_bound(lam, ev, *arc), run,
                       witness, evals, floor, max_evaluations, "arcs")
    faces = _octahedron()  # k = 3: spherical triangles, split in four

    def split_face(face: Any) -> list[Any]:
        a, b, c = face
        ab, bc, ca = _unit(a + b), _unit(b + c), _unit(c + a)
        return [np.array(f) for f in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))]

    return _refine(3, faces, lambda face: _unit(face.sum(axis=0)), split_face,
                   lambda ev, face: _face_bound(lam, ev, face), run, witness, evals, floor,
                   max_evaluations * MAX_EVALUATIONS_3 // MAX_EVALUATIONS, "faces")


def _refine(k: int, regions: list[Any], centre: Any, split: Any, bound: Any, run: Any,
            witness: Any, evals: list[_Eval], floor: float, budget: int, what: str
            ) -> ConeDecision:
    """Certify ``F > 0`` on the circle or sphere region by region (module doc).

    ``F`` is solved at each region's ``centre`` (a witness ends the search); every solve's
    minorant holds everywhere, so each region keeps its best ``bound`` so far, raised by each
    new solve (work: solves x regions, not their square). The region with the lowest bound is
    ``split`` first, until every bound is above ``floor`` or ``budget`` solves are spent.
    """
    for region in regions:
        found = witness(run(centre(region)))
        if found:
            return found
    live = [(bound(evals, r), r) for r in regions]
    while True:
        open_ = [i for i, (b, _) in enumerate(live) if b <= floor]
        lower = min(b for b, _ in live)
        low = min(e.F for e in evals)
        if not open_:
            return ConeDecision(POSITIVE, k, low, lower, len(evals), None,
                                f"the lower bounds of all {len(live)} {what} above the "
                                "floor")
        worst = min(open_, key=lambda i: live[i][0])
        pieces = split(live[worst][1])
        if len(evals) + len(pieces) > budget:
            return ConeDecision(UNDECIDED, k, low, lower, len(evals), None,
                                f"{len(open_)} {what} not certified after {len(evals)} solves "
                                f"(lower bound {lower:.3e}, smallest F {low:.3e}, relative)")
        live.pop(worst)
        new = []
        for piece in pieces:
            e = run(centre(piece))
            found = witness(e)
            if found:
                return found
            new.append(e)
        live = [(max(b, bound(new, r)), r) for b, r in live]
        live += [(bound(evals, p), p) for p in pieces]
