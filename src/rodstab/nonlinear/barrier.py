"""Energy barriers between two stable equilibria: minimum energy path, saddle, barrier.

The string method (E, Ren and Vanden-Eijnden, *Simplified and improved string method for
computing the minimum energy paths in barrier-crossing events*, J. Chem. Phys. 126, 164103,
2007), simplified further: a chain of images from one minimum to the other, each moved by a
descent step with its component along the chain removed (as in the nudged elastic band), then
redistributed at equal arclength. The highest image is refined by Newton's method on the
gradient (not the energy) to the saddle, whose Hessian index is checked to be exactly one.

Generic core: :func:`minimum_energy_path` works on any space given by a :class:`PathSpace`
(``log``/``exp`` between states, a descent step, a diagonal metric), so the same code runs on a
Euclidean toy with a known saddle (:class:`EuclideanSpace`) and on the discrete rod
(:class:`RodSpace`: node positions and edge/joint frames, frames interpolated on SO(3) by the log
map, distances mixing positions over a length with rotation angles).

Two held states of one structure at one natural curvature are put in ONE discrete model whose
energy depends on the natural curvature alone by
:func:`rodstab.nonlinear.discover.common_rod` (the one implementation of that idea).

Status (work in progress, not wired to the CLI): the core converges on the Euclidean toy
(tests/test_barrier.py); on the rod, the string between the six-ring's folded and one-loop
states (and the hexagram's pairs) does not converge yet -- images of the initial string are
far from equilibrium (the two states' frames differ by up to half a turn, and per-frame
geodesics put kinks between neighbours; :func:`ring_interpolate` removes the kinks but leaves
a closure defect) and the descent breaks down on a non-finite energy. No barrier is reported
from this module until that is fixed.

Also tried (not kept): minimum-mode following from the folded six-ring (8 el./rod,
kappa_n R0 = 1; dense eigenpairs of the Jacobi-scaled Hessian, a fixed uphill step along the
followed mode and a shifted Newton step in the others, P-RFO once it turns negative). The
lowest pair is nearly double (2.07e-8, 2.23e-8) and the followed eigenvector turns inside it:
following the lowest mode wanders below 0.25 B3/L; following the second by overlap climbs to
1.44 B3/L (above the continuation's saddle, 1.12) with the mode still positive and falls back.
A dimer/mode-following search needs the symmetric subspace of the saddle branch fixed first.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import NotConverged, RodstabInputError, require_int
from ..model import Assembly
from ..numerics import jacobi_scaling
from ..results import Result
from .discover import common_rod
from .discrete import PENALTY, DiscreteRod
from .solve import (
    NEWTON_RTOL,
    lowest_eigenvalues,
    newton,
    vee_log,
    zero_eigenvalue_tol,
)

#: Images of the string, ends included.
N_IMAGES = 13
#: Most iterations of the string (each: one descent step per interior image, one
#: redistribution).
STRING_MAX_ITER = 200
#: The string has converged when no interior image moves (perpendicular to the string) by more
#: than this fraction of the spacing between images in one iteration.
STRING_TOL = 2e-3
#: A descent step is cut to at most this fraction of the spacing between images, so an image
#: cannot jump past its neighbours (or into a basin) in one step.
STEP_FRACTION = 0.5
#: Newton iterations allowed to the saddle refinement.
SADDLE_MAX_ITER = 50
#: A state relaxed by Newton from its held geometry must stay within this fraction of the total
#: length of it (largest node displacement), else it is not the named state at that load.
STATE_DRIFT = 0.05
#: Shift of :meth:`RodSpace.relax_stiff` (Jacobi-scaled Hessian), its step budget, and its
#: stop (relative energy drop of one step).
STIFF_SHIFT = 1e-3
STIFF_ITER = 12
STIFF_RTOL = 1e-4

S = TypeVar("S")


class PathSpace(Protocol[S]):
    """A configuration space on which :func:`minimum_energy_path` runs.

    ``log(a, b)``: tangent vector at ``a`` (shape ``(n,)``) with ``exp(a, log(a, b)) == b``;
    ``exp(a, v)``: the state reached from ``a`` along ``v`` (a new state, ``a`` unchanged);
    ``descent(a, key, tangent, radius)``: the energy at ``a`` and a descent step (tangent
    coordinates at ``a``) with its component along ``tangent`` removed in the metric of the
    step's preconditioner, of metric length at most about ``radius`` (``key``: the image's index,
    for a space that remembers something per image);
    ``energy(a)``; ``weights``: the diagonal metric ``|v|^2 = sum w v^2``, shape ``(n,)``.
    """

    weights: np.ndarray

    def log(self, a: S, b: S) -> np.ndarray:
        """Return the tangent vector at ``a`` pointing to ``b``."""
        ...

    def exp(self, a: S, v: np.ndarray) -> S:
        """Return the state reached from ``a`` along ``v``."""
        ...

    def descent(self, a: S, key: int, tangent: np.ndarray, radius: float
                ) -> tuple[float, np.ndarray]:
        """Return the energy at ``a`` and a descent step with no component along ``tangent``."""
        ...

    def energy(self, a: S) -> float:
        """Return the energy at ``a``."""
        ...

    def interpolate(self, a: S, b: S, t: float) -> S:
        """Return the initial string's state ``t`` of the way from ``a`` to ``b``."""
        ...


@dataclasses.dataclass(frozen=True)
class MinimumEnergyPath(Result):
    """A converged (or not) string: images from ``a`` to ``b`` at equal arclength.

    ``images``: the states (left out of :meth:`to_dict`); ``energies`` and ``arclength``
    (metric of the space, from 0) per image; ``highest``: index of the highest image;
    ``max_move``: the last iteration's largest perpendicular move over the spacing.
    """

    energies: tuple[float, ...]
    arclength: tuple[float, ...]
    highest: int
    iterations: int
    converged: bool
    max_move: float
    method: str
    images: tuple = ()

    def to_dict(self) -> dict[str, Any]:
        """JSON form, without the images."""
        d = super().to_dict()
        d.pop("images", None)
        return d


def _norm(space: PathSpace[Any], v: np.ndarray) -> float:
    return float(np.sqrt(np.sum(space.weights * v * v)))


def redistribute(space: PathSpace[S], images: list[S]) -> tuple[list[S], np.ndarray]:
    """Images at equal arclength along the piecewise-geodesic chain; and the arclengths.

    Arclength: the metric length of ``log(q_k, q_(k+1))`` summed; the chain between images
    ``k`` and ``k + 1`` is the space's ``interpolate`` (for the rod, :func:`ring_interpolate`:
    a geodesic of each frame alone would put kinks between neighbouring frames). The ends stay.
    """
    logs = [space.log(images[k], images[k + 1]) for k in range(len(images) - 1)]
    seg = np.array([_norm(space, v) for v in logs])
    s = np.concatenate([[0.0], np.cumsum(seg)])
    targets = np.linspace(0.0, s[-1], len(images))
    out = [images[0]]
    for t in targets[1:-1]:
        k = min(int(np.searchsorted(s, t, side="right")) - 1, len(seg) - 1)
        frac = (t - s[k]) / seg[k] if seg[k] > 0 else 0.0
        out.append(space.interpolate(images[k], images[k + 1], frac))
    out.append(images[-1])
    return out, targets


def minimum_energy_path(space: PathSpace[S], a: S, b: S, *, n_images: int = N_IMAGES,
                        max_iter: int = STRING_MAX_ITER, tol: float = STRING_TOL,
                        progress: Callable[[int, float], None] | None = None
                        ) -> MinimumEnergyPath:
    """Minimum energy path from minimum ``a`` to minimum ``b`` by the string method.

    Start: ``space.interpolate(a, b, t)`` at ``n_images`` equally spaced ``t``. Each
    iteration moves every interior image by the space's descent step with its component along
    the local unit tangent (central difference of the neighbours, metric of the space) removed,
    the move cut to :data:`STEP_FRACTION` of the spacing, then redistributes the images at
    equal arclength (:func:`redistribute`). Converged when the largest move is below ``tol``
    times the spacing. With a preconditioned descent step the fixed point is a minimum energy
    path of the preconditioned metric: a different curve, but through the same saddle, where the
    gradient vanishes -- which is all the barrier needs (the highest image is refined there).
    """
    n_images = require_int("n_images", n_images, 3)
    max_iter = require_int("max_iter", max_iter, 1)
    images = [a] + [space.interpolate(a, b, t) for t in np.linspace(0.0, 1.0, n_images)[1:-1]] \
        + [b]
    images, s = redistribute(space, images)
    energies = [space.energy(q) for q in images]
    move = math.inf
    it = 0
    for it in range(1, max_iter + 1):
        spacing = s[-1] / (n_images - 1)
        new = list(images)
        move = 0.0
        for i in range(1, n_images - 1):
            tau = space.log(images[i], images[i + 1]) - space.log(images[i], images[i - 1])
            cap = STEP_FRACTION * spacing
            energies[i], step = space.descent(images[i], i, tau, cap)
            size = _norm(space, step)
            if size > cap:
                step *= cap / size
            move = max(move, min(size, cap) / spacing)
            new[i] = space.exp(images[i], step)
        images, s = redistribute(space, new)
        if progress is not None:
            progress(it, move)
        if move < tol:
            break
    energies = [space.energy(q) for q in images]
    return MinimumEnergyPath(
        energies=tuple(float(e) for e in energies), arclength=tuple(float(x) for x in s),
        highest=int(np.argmax(energies)), iterations=it, converged=bool(move < tol),
        max_move=float(move),
        method="string method (projected preconditioned descent, equal-arclength "
               "redistribution)", images=tuple(images))


@dataclasses.dataclass
class EuclideanSpace:
    """``R^n`` with energy ``f`` and gradient ``grad``; descent step ``-step * grad``."""

    f: Callable[[np.ndarray], float]
    grad: Callable[[np.ndarray], np.ndarray]
    step: float
    weights: np.ndarray

    def log(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Return ``b - a``."""
        return np.asarray(b, float) - np.asarray(a, float)

    def exp(self, a: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Return ``a + v``."""
        return np.asarray(a, float) + v

    def descent(self, a: np.ndarray, key: int, tangent: np.ndarray, radius: float
                ) -> tuple[float, np.ndarray]:
        """Return ``f(a)`` and the gradient step ``-step grad f(a)`` normal to ``tangent``."""
        g = np.asarray(self.grad(a), float)
        t = tangent / max(float(np.sqrt(np.sum(self.weights * tangent**2))), 1e-300)
        d = -self.step * g / self.weights  # the steepest descent of the metric
        return float(self.f(a)), d - float(np.sum(self.weights * d * t)) * t

    def energy(self, a: np.ndarray) -> float:
        """Return ``f(a)``."""
        return float(self.f(a))

    def interpolate(self, a: np.ndarray, b: np.ndarray, t: float) -> np.ndarray:
        """Return ``a + t (b - a)``."""
        return np.asarray(a, float) + t * (np.asarray(b, float) - np.asarray(a, float))


# ---------------------------------------------------------------- the discrete rod as a space
def rod_log(a: DiscreteRod, b: DiscreteRod) -> np.ndarray:
    """Increment ``dq`` (``(n_dof,)``) with ``a.apply(dq)`` giving ``b``'s configuration.

    Positions: ``x_b - x_a``; frames: ``log(R_a^T R_b)`` (material rotation vectors, as
    :meth:`DiscreteRod.apply` uses them).
    """
    dx = b.x - a.x
    de = vee_log(np.swapaxes(a.R_edge, 1, 2) @ b.R_edge)
    dj = vee_log(np.swapaxes(a.R_joint, 1, 2) @ b.R_joint)
    return np.concatenate([dx.ravel(), de.ravel(), dj.ravel()])


def rod_exp(a: DiscreteRod, v: np.ndarray) -> DiscreteRod:
    """Return a copy of ``a`` moved by ``v`` (:meth:`DiscreteRod.apply`)."""
    out = a.copy()
    out.apply(v)
    return out


def _ring_walk(rod: DiscreteRod) -> list[int]:
    """Frames of a closed chain in order from the gauge joint (edges ``0..ne-1``, joints ``ne+j``).

    Raises :class:`RodstabInputError` unless every frame has exactly two neighbours (one ring).
    """
    ne = len(rod.R_edge)
    nbr: list[list[int]] = [[] for _ in range(ne + len(rod.R_joint))]
    for e1, e2 in rod.bend_pairs:
        nbr[int(e1)].append(int(e2))
        nbr[int(e2)].append(int(e1))
    for e, j, _, _ in rod.end_links:
        nbr[e].append(ne + j)
        nbr[ne + j].append(e)
    if any(len(v) != 2 for v in nbr):
        raise RodstabInputError("the barrier's initial path needs a closed chain of rods (each "
                                "weld joining two ends, no supports)")
    walk = [ne + (rod.fixed_joints[0] if rod.fixed_joints else 0)]
    seen = set(walk)
    while True:
        nxt = [w for w in nbr[walk[-1]] if w not in seen]
        if not nxt:
            break
        walk.append(nxt[0])
        seen.add(nxt[0])
    if len(walk) != len(nbr):
        raise RodstabInputError("the barrier's initial path needs one closed chain of rods")
    return walk


def ring_interpolate(a: DiscreteRod, b: DiscreteRod, t: float) -> DiscreteRod:
    """Return the configuration ``t`` of the way from ``a`` to ``b`` on a closed chain, no kinks.

    Interpolating each frame on its own geodesic sends neighbouring frames of two distant
    states (a folded ring and a loop: frames turned by up to half a turn) round opposite ways,
    through relative rotations near half a turn, where the Cayley energy is infinite. Here the
    *relative* rotation of each frame to the previous one along the chain (small in both states)
    is interpolated on its geodesic and the frames are chained from the gauge joint; the closure
    defect (rotation and gap, zero at ``t = 0, 1``) is spread along the chain in proportion to
    the distance walked, and node positions follow from the frames (each edge's chord in its
    own frame interpolated linearly between the states). It tends to ``a`` and ``b`` at the
    ends.
    """
    if t <= 0.0:
        return a.copy()
    if t >= 1.0:
        return b.copy()
    from .jets import rodrigues

    walk = _ring_walk(a)
    ne = len(a.R_edge)
    Ra = np.concatenate([a.R_edge, a.R_joint])
    Rb = np.concatenate([b.R_edge, b.R_joint])
    R = np.empty_like(Ra)
    R[walk[0]] = Ra[walk[0]] @ rodrigues(t * vee_log(Ra[walk[0]].T @ Rb[walk[0]])[None])[0]
    chain = walk + [walk[0]]
    end = np.empty((3, 3))
    for k in range(1, len(chain)):
        u, w = chain[k - 1], chain[k]
        Pa, Pb = Ra[u].T @ Ra[w], Rb[u].T @ Rb[w]
        Pt = Pa @ rodrigues(t * vee_log(Pa.T @ Pb)[None])[0]
        if k < len(walk):
            R[w] = R[u] @ Pt
        else:
            end = R[u] @ Pt  # the gauge frame reached round the ring
    defect = vee_log(R[walk[0]] @ end.T)  # lab rotation taking the end onto the start
    n = len(walk)
    for k in range(1, n):
        R[walk[k]] = rodrigues((k / n) * defect[None])[0] @ R[walk[k]]
    out = a.copy()
    out.R_edge, out.R_joint = R[:ne].copy(), R[ne:].copy()
    # Positions: chords along d2 from the gauge node, the closing gap spread along the walk.
    x = np.full_like(a.x, np.nan)
    node = a.fixed_nodes[0] if a.fixed_nodes else int(a.edge_nodes[0, 0])
    x[node] = (1 - t) * a.x[node] + t * b.x[node]
    start, cur = node, node
    order = []
    for w in walk:
        if w < ne:
            i, j = a.edge_nodes[w]
            nxt, sign = (j, 1.0) if i == cur else (i, -1.0)
            ca = a.R_edge[w].T @ (a.x[j] - a.x[i])
            cb = b.R_edge[w].T @ (b.x[j] - b.x[i])
            pos = x[cur] + sign * (R[w] @ ((1 - t) * ca + t * cb))
            if nxt == start:
                gap = pos - x[start]
            else:
                x[nxt] = pos
                order.append(nxt)
            cur = nxt
    for k, nd in enumerate(order):
        x[nd] -= ((k + 1) / (len(order) + 1)) * gap
    out.x = x
    return out


def _pd_solve(A: sp.spmatrix, rhs: np.ndarray, tau: float, floor: float
              ) -> tuple[np.ndarray, float, Any]:
    """Solve ``(A + tau I) y = rhs`` with the smallest ``tau`` (x4 steps) making it positive.

    Positive definiteness is certified by the inertia of SuperLU's symmetric-mode ``L D L^T``
    (as :func:`rodstab.numerics.count_below`): no negative pivot. ``tau`` starts at the given
    value; returns ``(y, tau, the factorisation's solve)``.
    """
    n = A.shape[0]
    for _ in range(200):
        try:
            lu = spla.splu((A + tau * sp.identity(n)).tocsc(), permc_spec="MMD_AT_PLUS_A",
                           diag_pivot_thresh=0.0, options={"SymmetricMode": True})
            d = lu.U.diagonal()
            pd = bool(np.array_equal(lu.perm_r, lu.perm_c) and np.all(d > 0))
        except RuntimeError:
            pd = False
        if pd:
            y = lu.solve(rhs)
            if np.all(np.isfinite(y)):
                return y, tau, lu.solve
        tau = max(4.0 * tau, floor)
    raise NotConverged("no positive definite shift of the Hessian found for a descent step")


class RodSpace:
    """The configuration space of one :class:`DiscreteRod` (positions, edge and joint frames).

    Metric: ``|dq|^2 = sum |dx|^2 / ell^2 + sum |dphi|^2`` with ``ell`` the mean segment
    length: a bending mode of amplitude ``a`` over a segment turns its frames by ~``a / ell``.
    Descent step: ``-(H + tau D)^-1 g`` on the free unknowns (``D = |diag H|``, ``tau`` the
    smallest x4 shift making it positive definite, remembered per image from the last step):
    Newton's step on a convex image, a trust-region-like descent step on a concave one.
    Without it the stiff stretch/shear penalty (:data:`~rodstab.nonlinear.discrete.PENALTY`)
    makes gradient descent crawl.
    """

    def __init__(self, rod: DiscreteRod) -> None:
        self.rod = rod
        a = rod.assembly
        ell = a.total_length / len(a.segments)
        self.weights = np.ones(rod.n_dof)
        self.weights[: 3 * len(rod.x)] = 1.0 / ell**2
        self.free = rod.free_dofs()
        self.floor = zero_eigenvalue_tol(rod)
        self._tau: dict[int, float] = {}

    def log(self, a: DiscreteRod, b: DiscreteRod) -> np.ndarray:
        """:func:`rod_log`."""
        return rod_log(a, b)

    def exp(self, a: DiscreteRod, v: np.ndarray) -> DiscreteRod:
        """:func:`rod_exp`."""
        return rod_exp(a, v)

    def energy(self, a: DiscreteRod) -> float:
        """Energy of the state."""
        return a.energy()

    def interpolate(self, a: DiscreteRod, b: DiscreteRod, t: float) -> DiscreteRod:
        """:func:`ring_interpolate`, its stretch and shear relaxed (:meth:`relax_stiff`)."""
        out = ring_interpolate(a, b, t)
        if 0.0 < t < 1.0:
            self.relax_stiff(out)
        return out

    def relax_stiff(self, a: DiscreteRod) -> None:
        """Relax the stiff stretch/shear of a built configuration, leaving its bending (in place).

        Steps ``-(H + s D)^-1 g`` with the fixed shift ``s =`` :data:`STIFF_SHIFT`: far above
        the Jacobi-scaled bending eigenvalues (~``(l_e/L)^2 / PENALTY``), far below the
        stretch/shear ones (~1), so the step solves the penalty's equations and barely moves the
        soft bending modes; halved until the energy falls, at most :data:`STIFF_ITER` steps.
        """
        free = self.free
        for _ in range(STIFF_ITER):
            E, g, H = a.energy_terms()
            if not np.isfinite(E):
                return
            Hf = H[free][:, free]
            Hf = 0.5 * (Hf + Hf.T)
            d = jacobi_scaling(Hf)
            A = (sp.diags(d) @ Hf @ sp.diags(d)).tocsc()
            y, _, _ = _pd_solve(A, -d * g[free], STIFF_SHIFT, STIFF_SHIFT)
            dq = np.zeros(a.n_dof)
            dq[free] = d * y
            for _ in range(20):
                trial = rod_exp(a, dq)
                Et = trial.energy()
                if Et < E:
                    break
                dq *= 0.5
            else:
                return
            a.x, a.R_edge, a.R_joint = trial.x, trial.R_edge, trial.R_joint
            if E - Et < STIFF_RTOL * E:
                return

    def descent(self, a: DiscreteRod, key: int, tangent: np.ndarray, radius: float
                ) -> tuple[float, np.ndarray]:
        """Energy and the shifted-Newton descent step (class docstring), zero on fixed dofs.

        The component along ``tangent`` is removed in the preconditioner's metric ``P = H + tau
        D``: ``d = -P^-1 g + (g.t / t.P t) t`` (Makri, Ortner and Kermode, J. Chem. Phys. 150,
        094109, 2019), still a descent direction (Cauchy-Schwarz in ``P``); removing it in
        another metric would undo the step's stretch-free balance.
        """
        E, g, H = a.energy_terms()
        free = self.free
        Hf = H[free][:, free]
        Hf = 0.5 * (Hf + Hf.T)
        d = jacobi_scaling(Hf)
        A = (sp.diags(d) @ Hf @ sp.diags(d)).tocsc()
        t = tangent[free]
        ts = t / d  # the tangent in scaled unknowns
        w = self.weights[free]
        tau = 0.25 * self._tau.get(key, 0.0)
        for _ in range(60):
            # Levenberg-Marquardt: the shift grows until the step is inside the radius.
            y, tau, _ = _pd_solve(A, -d * g[free], tau, self.floor)
            tPt = float(ts @ (A @ ts) + tau * ts @ ts)
            sf = d * y + (float(g[free] @ t) / max(tPt, 1e-300)) * t
            if float(np.sqrt(np.sum(w * sf * sf))) <= radius:
                break
            tau = max(4.0 * tau, self.floor)
        self._tau[key] = tau
        step = np.zeros(a.n_dof)
        step[free] = sf
        return E, step


# ---------------------------------------------------------------- the two states
def _rigid_gauge(rod: DiscreteRod, like: DiscreteRod) -> None:
    """Move ``rod`` rigidly so its gauge joint has ``like``'s position and frame (in place)."""
    j = like.fixed_joints[0]
    node = like.fixed_nodes[0]
    Q = like.R_joint[j] @ rod.R_joint[j].T
    rod.x = (rod.x - rod.x[node]) @ Q.T + like.x[node]
    rod.R_edge = Q @ rod.R_edge
    rod.R_joint = Q @ rod.R_joint


def _relaxed_state(rod: DiscreteRod, label: str, mu: float) -> tuple[DiscreteRod, float]:
    """Newton from the configuration; refuse it unless a nearby stable equilibrium.

    Returns the state and its lowest scaled eigenvalue. Raises :class:`RodstabInputError`
    naming ``label`` and the load when Newton fails, the state drifts past
    :data:`STATE_DRIFT`, or a Hessian eigenvalue is not above the zero tolerance.
    """
    start = rod.x.copy()
    ok, _, res = newton(rod)
    if not ok:
        raise RodstabInputError(f"state {label!r} is not an equilibrium at load factor {mu:g} "
                                f"(Newton stalled at residual {res:.3g})")
    drift = float(np.max(np.linalg.norm(rod.x - start, axis=1))) / rod.assembly.total_length
    if drift > STATE_DRIFT:
        raise RodstabInputError(f"state {label!r} is not an equilibrium at load factor {mu:g}: "
                                f"Newton moved it by {drift:.3g} of the total length")
    lam = float(lowest_eigenvalues(rod, 1)[0])
    if not lam > zero_eigenvalue_tol(rod):
        raise RodstabInputError(f"state {label!r} is not stable at load factor {mu:g} (lowest "
                                f"scaled Hessian eigenvalue {lam:.3g})")
    return rod, lam


# ---------------------------------------------------------------- the saddle
def newton_stationary(rod: DiscreteRod, *, max_iter: int = SADDLE_MAX_ITER
                      ) -> tuple[bool, int, float]:
    """Newton's method on the free gradient (any stationary point: a saddle too), in place.

    Steps ``-H^-1 g`` (the Jacobi-scaled free Hessian, LU), halved until the gradient's norm
    falls (a line search on ``|g|``, not on the energy, which a saddle does not minimise).
    Converged when ``max |g_free| <= NEWTON_RTOL x`` the penalty force scale, the criterion of
    :func:`~rodstab.nonlinear.solve.newton`. Returns ``(ok, iterations, residual)``.
    """
    free = rod.free_dofs()
    scale = float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))
    _, g, H = rod.energy_terms()
    res = float(np.max(np.abs(g[free])))
    for it in range(max_iter + 1):
        if res <= NEWTON_RTOL * scale:
            return True, it, res
        if it == max_iter:
            break
        Hf = H[free][:, free]
        Hf = 0.5 * (Hf + Hf.T)
        d = jacobi_scaling(Hf)
        A = (sp.diags(d) @ Hf @ sp.diags(d)).tocsc()
        try:
            step = -d * spla.spsolve(A, d * g[free])
        except RuntimeError:
            return False, it, res
        if not np.all(np.isfinite(step)):
            return False, it, res
        g0 = float(np.linalg.norm(d * g[free]))
        t = 1.0
        for _ in range(30):
            trial = rod.copy()
            dq = np.zeros(rod.n_dof)
            dq[free] = t * step
            trial.apply(dq)
            _, gt, Ht = trial.energy_terms()
            if float(np.linalg.norm(d * gt[free])) < g0 or t < 1e-6:
                break
            t *= 0.5
        rod.x, rod.R_edge, rod.R_joint = trial.x, trial.R_edge, trial.R_joint
        g, H = gt, Ht
        res = float(np.max(np.abs(g[free])))
    return False, max_iter, res


def hessian_index(rod: DiscreteRod, k: int = 4) -> tuple[int, tuple[float, ...]]:
    """Return the count of scaled eigenvalues below ``-zero_eigenvalue_tol`` and the lowest k."""
    ev = lowest_eigenvalues(rod, k)
    return int(np.sum(ev < -zero_eigenvalue_tol(rod))), tuple(float(v) for v in ev)


@dataclasses.dataclass(frozen=True)
class Barrier(Result):
    """Energy barrier between two stable states of one discrete rod.

    ``barrier_forward = E_saddle - E_from``, ``barrier_backward = E_saddle - E_to``;
    ``saddle_index``: negative scaled Hessian eigenvalues at the saddle (1 for a transition
    state); ``energies``/``arclength``: along the converged string, from ``from`` to ``to``
    (arclength in the space's metric, normalised to 1); ``converged``: string converged, Newton
    converged at the saddle and index 1; ``residual``: the saddle's free-gradient max-norm
    (force units, tolerance ``NEWTON_RTOL`` x the penalty scale). ``shapes`` (node positions of
    the images, the saddle inserted at its arclength) and ``edge_nodes`` are left out of
    :meth:`to_dict`.
    """

    barrier_forward: float
    barrier_backward: float
    saddle_index: int
    energies: tuple[float, ...]
    arclength: tuple[float, ...]
    energy_from: float
    energy_to: float
    energy_saddle: float
    saddle_image: int
    lowest_eigenvalues_saddle: tuple[float, ...]
    converged: bool
    residual: float
    string_iterations: int
    string_converged: bool
    newton_iterations: int
    n_images: int
    n_dof: int
    elements_per_segment: int
    load_factor: float
    method: str
    shapes: tuple = ()
    edge_nodes: Any = None

    def to_dict(self) -> dict[str, Any]:
        """JSON form, without the shapes."""
        d = super().to_dict()
        d.pop("shapes", None)
        d.pop("edge_nodes", None)
        return d


def barrier(a: Assembly, b: Assembly, *, load_factor: float, elements_per_segment: int = 16,
            n_images: int = N_IMAGES, max_iter: int = STRING_MAX_ITER,
            labels: tuple[str, str] = ("from", "to")) -> tuple[Barrier, DiscreteRod]:
    """Energy barrier between held states ``a`` and ``b`` of one structure at ``load_factor``.

    1. :func:`~rodstab.nonlinear.discover.common_rod`: both states in one discrete model
       (natural curvature only), ``b`` moved rigidly onto ``a``'s gauge joint;
    2. each relaxed by Newton and refused unless a nearby stable equilibrium
       (:class:`RodstabInputError` naming ``labels[i]``);
    3. :func:`minimum_energy_path` on :class:`RodSpace`;
    4. the highest image refined by :func:`newton_stationary` to the saddle, whose index is
       counted (:func:`hessian_index`).

    Returns the :class:`Barrier` and the saddle state.
    """
    rod_a = common_rod(a, elements_per_segment, load_factor)
    rod_b = common_rod(b, elements_per_segment, load_factor)
    _rigid_gauge(rod_b, rod_a)
    rod_a, _ = _relaxed_state(rod_a, labels[0], load_factor)
    rod_b, _ = _relaxed_state(rod_b, labels[1], load_factor)
    # Newton keeps the gauge joint where it was: both states share it (_rigid_gauge).
    space = RodSpace(rod_a)
    path = minimum_energy_path(space, rod_a, rod_b, n_images=n_images, max_iter=max_iter)
    top = path.highest
    saddle = path.images[top].copy()
    ok, its, res = newton_stationary(saddle)
    index, ev = hessian_index(saddle)
    e_a, e_b, e_s = path.energies[0], path.energies[-1], saddle.energy()
    s = np.asarray(path.arclength) / path.arclength[-1]
    shapes = [q.x.copy() for q in path.images]
    # The saddle's place on the path: its nearest image's arclength (for the animation).
    shapes.insert(top + 1, saddle.x.copy())
    result = Barrier(
        barrier_forward=float(e_s - e_a), barrier_backward=float(e_s - e_b),
        saddle_index=index, energies=path.energies, arclength=tuple(float(v) for v in s),
        energy_from=float(e_a), energy_to=float(e_b), energy_saddle=float(e_s),
        saddle_image=top, lowest_eigenvalues_saddle=ev,
        converged=bool(ok and path.converged and index == 1), residual=res,
        string_iterations=path.iterations, string_converged=path.converged,
        newton_iterations=its, n_images=n_images, n_dof=len(rod_a.free_dofs()),
        elements_per_segment=elements_per_segment, load_factor=load_factor,
        method=f"{path.method}; highest image refined by Newton on the gradient; index by "
               "certified lowest eigenvalues of the Jacobi-scaled Hessian",
        shapes=tuple(shapes), edge_nodes=rod_a.edge_nodes.copy())
    return result, saddle
