"""Minimum energy path between two stable states of one discrete rod: string method, saddle.

The string method of E, Ren and Vanden-Eijnden (J. Chem. Phys. 126, 164103, 2007, the
simplified method: no springs, reparametrisation to equal arclength; the descent restricted to
the plane perpendicular to the string as in their original method, Phys. Rev. B 66, 052301,
2002, with a Newton step on that plane as in the preconditioned NEB of Makri, Ortner and
Kermode, J. Chem. Phys. 150, 094109, 2019), and the saddle refined from a local maximum of the
string's energies by Newton's method on the gradient; its index is checked to be one and its
steepest descents to end on the two states. Entry point: :func:`string_barrier`.

**Chart.** Images live on ``R^(3 N) x SO(3)^M`` (node positions, edge and joint frames). The
difference of two images is taken in the chart of the first (:func:`chart_difference`:
``x_b - x_a`` and the rotation vectors of ``R_a^T R_b``), updates by
:meth:`~rodstab.nonlinear.discrete.DiscreteRod.apply` (``R exp(hat(phi))``), the chart in which
:meth:`~rodstab.nonlinear.discrete.DiscreteRod.energy_terms` gives the exact gradient and Hessian.
Chart sizes (:func:`~rodstab.nonlinear.constraint.chart_size`) are the largest node move over the
mean rod length ``L`` or frame turn in radians; arclength is the Euclidean norm of the free unknowns
with positions over ``L``. All images are in one gauge (:func:`to_gauge`): the gauge joint's
frame and node are the same in every image, so no rigid motion -- a direction of zero energy --
enters the string.

**Initial path** (:func:`belt_path`). Linear interpolation of the unknowns fails (compressed
edges under the stiff stretch/shear penalty, non-finite energies), and so does the geodesic
``R_a exp(t log(R_a^T R_b))`` frame by frame: the frames of the two states differ by rotations
up to a half turn about the plane's normal, the branch of the log jumps between neighbouring
frames, and the planar interpolant cannot close (the states' frame loops differ by whole turns).
For two planar states whose frames differ by the in-plane rotations ``R_z(alpha_e)`` the path
used is

    ``G_e(t) = R_n(e)(pi t) R_m(pi t)``,  ``n(e) = R_z(alpha_e / 2) m``,

``m`` a fixed in-plane axis (the gauge joint's tangent): ``G_e(0) = I`` and ``G_e(1) = R_n(pi)
R_m(pi) = R_z(alpha_e)`` (two half turns about in-plane axes at angle ``alpha_e / 2`` compose to a
turn by ``alpha_e`` about the normal), so every frame goes from A's to B's through the third
dimension. ``alpha_e`` is lifted continuously along the rods (breadth-first from the gauge joint),
and ``G`` depends on ``alpha`` only modulo ``4 pi``: a ring whose two frame loops differ by two
full turns (the folded and one-loop six-rings) closes -- Dirac's belt trick; an odd number of turns
cannot close and is refused (no continuous path of frames exists). The gauge joint itself turns
by ``R_m(2 pi t)``: each image is moved back into A's gauge rigidly (else the first images
were A turned about its own line, a detour of zero energy). Each image is then made inextensible
(:func:`~rodstab.nonlinear.constraint.restore_inextensible`: where the turned frames' tangents do
not close round the ring, positions alone leave a penalty strain -- 7.5e5 B3/L on the hexagram's
star -> daisy path -- which least frame turns remove). Highest initial energies: 99 B3/L
(six-ring), 283 (star -> daisy), against saddles at 14.3 and 7.9.

**String iteration** (:func:`relax_string`). Each interior image takes one step that minimises
the quadratic model ``g . s + 1/2 s^T H s`` on the plane ``tau . s = 0`` perpendicular to its
central tangent ``tau``: a Newton step on that plane. Where the model is not convex on the plane
the Levenberg shift ``H + lam D`` (``D = |diag H|``) is raised until it is; only the plane has
to be convex, not the string's own direction: ``H + lam D`` may keep one negative eigenvalue if
``tau . (H + lam D)^-1 tau < 0`` (the inertia of the bordered matrix), both read off the pivots
of a symmetric factorisation (on the six-ring's string, 8 el./rod, ``H`` had no negative
eigenvalue at 134 of 360 steps, one at 53, more at 173). Every trial state is retracted
(:func:`~rodstab.nonlinear.constraint.retract_step`): a chart step opens the ring's closure at
second order, and at 0.1 rad the penalty strain left (0.83 B3/L, six-ring) swamps the predicted
change (0.04): without it this loop needed 190 iterations where it needs 40. A step is accepted
when the energy falls by a quarter of the model's prediction, else ``lam`` grows 4x
(Levenberg-Marquardt, as :func:`~rodstab.nonlinear.solve.lm_step`); it moves nothing by more
than :data:`STEP_FRACTION` of the image's smaller chart gap to its neighbours (images do not
overtake each other). No springs: when the longest chart segment of the string exceeds
:data:`REPARAM_RATIO` times the shortest, it is reparametrised to equal arclength
(:func:`reparametrise`: piecewise geodesic in the chart, then the retraction; not every
iteration, as E et al.: each interpolation raises the images' strain, which the next step then
undoes). Neighbouring images more than :data:`MAX_GAP` apart refine the string (twice the
images, equal arclength), at most :data:`REFINEMENTS` times, and then stop it as too coarse (an
interpolation near half a turn flips the branch of the log: energies of 1e7 seen).

**Saddle** (:func:`refine_saddle`). Once the string has settled (:data:`SETTLE_RTOL`), every
:data:`SADDLE_TRY_EVERY` iterations copies of the local maxima of its energies are refined by
Newton's method on the gradient, ``s = -H^-1 g``: no merit function, a saddle being no minimum
of the energy (the gradient-norm merit of :func:`~rodstab.multistable.discover.deflated_newton`
stalls at a non-stationary point, residual 0.054 B3/L^2, from the six-ring string's highest
image). Steps are capped at :data:`SADDLE_STEP` and retracted while larger than
:data:`~rodstab.nonlinear.constraint.RETRACT_ABOVE` (the last, small steps are plain Newton,
quadratically convergent; the retraction would remove an equilibrium's own shear strain).
Without the retraction the same iteration converged only with steps capped at 0.01 rad.
Converged at :data:`~rodstab.nonlinear.solve.NEWTON_RTOL` times the stiff force scale, as
:func:`~rodstab.nonlinear.solve.newton`. A stationary point whose index (negative scaled
eigenvalues, :func:`~rodstab.nonlinear.solve.lowest_modes`) is not one is passed over (the
six-ring has one of index 2 at 14.6766 B3/L next to the path, where Newton goes from a string
whose top is still above 14.5), and so is a saddle whose two steepest descents
(:func:`~.barrier.descents_from_saddle`, retracted: 16 .. 24 steps against 458 .. 934
unretracted) do not end on the two states (:func:`~rodstab.multistable.discover.same_state`,
modulo the ring's symmetry).

**What converges.** Not the images' positions: near a state of nearly uniform curvature they
drift along soft modes (the nearly free sliding of the one-loop ring), by 0.02 .. 0.5 rad per
iteration for 150 iterations (six-ring, 8 el./rod, 11 images), while the energy profile stays
put. The string is relaxed until a local maximum of its energies lies in the Newton basin of
an index-1 saddle whose descents end on the two states; that saddle (Newton-converged) is the
result, and its energy is the continuation's to 3e-13 relative (six-ring, 8 el./rod). A string
may also make a detour: between the hexagram's star and daisy (kappa_n R0 = 1.5, 8 el./rod, 17
images) it leaves the star, loops over a hump of 19.3 B3/L (near a stationary point at 19.29)
and comes back to the star itself (image 10, 0.001 B3/L above it, descends to it) before
crossing the saddle at 7.91 to the daisy; every image before the saddle descends to the star.
The barrier reported is the saddle's, which joins the two states; the loop stays in the path.

**Contact** (rods that cannot pass through each other): :mod:`.string_contact`; from a
stacked state, its welds spanning the layers: :func:`~.layered.stacked_band`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable
from concurrent.futures import Executor
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_finite, require_int
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, require_nonlinear
from ..model import Assembly
from ..nonlinear.constraint import chart_size, restore_inextensible
from ..nonlinear.contact import ContactModel, Interpenetration
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.jets import rodrigues
from ..nonlinear.newton import newton
from ..nonlinear.solve import lowest_modes, zero_eigenvalue_tol
from ..numerics import serially
from ..results import Result
from .barrier import MIN_ELEMENTS, Barrier, same_model
from .chain import CHAIN_DEPTH, chain, chain_result
from .discover import Snapshot, common_rod
from .landscape import Landscape
from .layered import stable_end, stacked_band
from .path_chart import (
    arclength,
    chart_difference,
    chart_scale,
    reparametrise,
)
from .saddle import refine_saddle
from .string_step import Terms, step_images

#: Lowest eigenvalues computed to count a stationary point's index.
INDEX_EIGS = 4

#: Images of the string, ends included (11 suffice for the six-ring at 8 el./rod; the
#: hexagram's star -> daisy string becomes too coarse with 11 and converges with 17).
STRING_IMAGES = 17
#: Most string iterations (each: one step of every interior image).
STRING_MAX_ITER = 300
#: A step moves no node (over L) or frame (rad) by more than this times the image's smaller
#: chart gap to its neighbours.
STEP_FRACTION = 0.5
#: Reparametrise when the longest chart segment of the string exceeds this times the shortest.
REPARAM_RATIO = 1.5
#: String iterations between two attempts to refine images to the saddle.
SADDLE_TRY_EVERY = 10
#: A saddle attempt waits until the string has settled: its highest energy ranged over less
#: than SETTLE_RTOL times its height above the lower end in the last SETTLE_ITER iterations.
#: Without this, a saddle found from a string still on its initial path's plateau (daisy ->
#: eight, 8 el., 17 images: 300 .. 400 B3/L for 30 iterations, then 14.47 from iteration 38)
#: joins the two states but is not known to be on the minimum energy path.
SETTLE_RTOL = 0.02
SETTLE_ITER = 5
#: Iterations between two calls of :func:`relax_string`'s ``stop`` (it measures the string).
STOP_EVERY = 5
#: Local maxima of the string's energies refined per attempt (highest first).
SADDLE_CANDIDATES = 3
#: The string stops (too coarse) when neighbouring images differ by a frame turn or node move
#: (over L) above this: past ~pi the chart difference takes the other branch of the log and an
#: interpolated image has neighbouring frames half a turn apart (energies ~1e7 seen at gaps of
#: 3.1 rad, hexagram star -> daisy with 11 images); more images are needed.
MAX_GAP = 2.5
#: Most times a string that would stop as too coarse is instead redistributed over twice the
#: images (:func:`max_string_images`). The hexagram's star -> daisy string (6 el., 17 images)
#: converged with OpenBLAS's SkylakeX kernels and stopped too coarse (2.53 rad) with its Haswell
#: ones: its images drift along soft directions as round-off decides. With 21 or 33 images both
#: converged to one saddle (energies to 1e-14). Refining earlier (at 2 rad) changed runs that
#: converged unrefined (a contact string at 4 el. then missed the model in its soft stages).
REFINEMENTS = 2
#: Largest |frame d3 . gauge normal - 1| and out-of-plane node coordinate of an end state that
#: :func:`belt_path` takes as planar (its path turns frames about that normal). Not the
#: identification's :data:`~.identify.PLANAR_TOL` (which only names states planar).
BELT_PLANAR_TOL = 1e-8


def to_gauge(b: DiscreteRod, a: DiscreteRod) -> None:
    """Move ``b`` rigidly (in place) so that its gauge joint sits where ``a``'s does.

    Held states of one ring built from different assemblies place the gauge joint (held
    position and frame, :func:`~rodstab.nonlinear.discrete.discretise`) differently; a path between
    them must start and end in one gauge, which no free unknown can change.
    """
    j, nd = a.fixed_joints[0], a.fixed_nodes[0]
    Rg = a.R_joint[j] @ b.R_joint[j].T
    b.x = (b.x - b.x[nd]) @ Rg.T + a.x[nd]
    b.R_edge = Rg @ b.R_edge
    b.R_joint = Rg @ b.R_joint
    if a.R_joint_held is not None:
        b.R_joint_held = a.R_joint_held.copy()


def _lifted_angles(a: DiscreteRod, alpha: np.ndarray) -> np.ndarray:
    """Lift the in-plane rotation angles ``alpha`` (per frame) continuously along the rods.

    Breadth-first from the gauge joint over neighbouring frames (consecutive edges, end edge
    and joint); raises when the lift closes with an odd number of turns (module docstring).
    """
    ne = len(a.R_edge)
    adj: dict[int, list[int]] = {i: [] for i in range(len(alpha))}
    for p, q in a.bend_pairs:
        adj[int(p)].append(int(q))
        adj[int(q)].append(int(p))
    for e, j, _, _ in a.end_links:
        adj[int(e)].append(ne + int(j))
        adj[ne + int(j)].append(int(e))
    start = ne + a.fixed_joints[0]
    lift = {start: float(alpha[start])}
    order = [start]
    for u in order:
        for v in adj[u]:
            val = alpha[v] + 2 * math.pi * round((lift[u] - alpha[v]) / (2 * math.pi))
            if v not in lift:
                lift[v] = float(val)
                order.append(v)
            elif abs(lift[v] - val) % (4 * math.pi) > 1.0:
                turns = (lift[v] - val) / (2 * math.pi)
                raise RodstabInputError(
                    f"the two states' frames differ by {turns:.3g} turns round the ring: no "
                    "continuous path of frames joins them (an odd number of turns)")
    return np.array([lift[i] for i in range(len(alpha))])


def _off_gauge_plane(a: DiscreteRod, r: DiscreteRod) -> float:
    """How far state ``r`` leaves the plane of ``a``'s gauge joint: node offset or frame tilt."""
    nrm = a.R_joint[a.fixed_joints[0]][:, 2]
    F = np.concatenate([r.R_edge, r.R_joint])
    return max(float(np.max(np.abs((r.x - r.x[r.fixed_nodes[0]]) @ nrm))),
               float(np.max(np.abs(F[:, :, 2] @ nrm - 1.0))))


def initial_path(a: DiscreteRod, b: DiscreteRod, n_images: int,
                 via: DiscreteRod | None = None) -> list[DiscreteRod]:
    """Return the string's first path from ``a`` to ``b`` (one model, one gauge), ends included.

    Two states planar in the gauge joint's plane: :func:`belt_path` (it raises when their frame
    loops differ by an odd number of turns). Otherwise the piecewise chart geodesic from ``a``
    through ``via`` (if given) to ``b`` at equal arclength (:func:`~.path_chart.reparametrise`),
    each image retracted. Between the bi-rod's buckled state and its mirror image (load factor
    3, 8 el.) the direct geodesic passed a singular frame (energies not finite) and the string
    from it did not converge in 300 iterations; through the held state it converges.
    """
    if max(_off_gauge_plane(a, a), _off_gauge_plane(a, b)) <= BELT_PLANAR_TOL:
        return belt_path(a, b, n_images)
    return reparametrise([a.copy(), *([] if via is None else [via.copy()]), b.copy()],
                         a.free_dofs(), n_images)


def belt_path(a: DiscreteRod, b: DiscreteRod, n_images: int) -> list[DiscreteRod]:
    """Return the initial string of ``n_images`` states from ``a`` to ``b``, ends included.

    The belt path of the module docstring, every image in ``a``'s gauge.

    Parameters
    ----------
    a, b : DiscreteRod
        Planar states (in the plane of ``a``'s gauge joint) of one model in one gauge
        (:func:`to_gauge`); raises :class:`RodstabInputError` otherwise, or when their frame
        loops differ by an odd number of turns.
    n_images : int
        Images, ends included (copies of ``a`` and ``b``).

    Returns
    -------
    list of DiscreteRod
        The images at ``t = k / (n_images - 1)``.
    """
    nrm = a.R_joint[a.fixed_joints[0]][:, 2]
    Fa, Fb = (np.concatenate([r.R_edge, r.R_joint]) for r in (a, b))
    for r in (a, b):
        off = _off_gauge_plane(a, r)
        if off > BELT_PLANAR_TOL:
            raise RodstabInputError("the band's initial path is built for planar end states; "
                                    f"a state leaves the plane by {off:.3g} L")
    # Lab rotation A -> B of every frame: a rotation about the normal by alpha.
    Dl = Fb @ np.swapaxes(Fa, 1, 2)
    u = a.R_joint[a.fixed_joints[0]][:, 0]
    v = np.cross(nrm, u)
    alpha = np.arctan2(np.einsum("i,fij,j->f", v, Dl, u), np.einsum("i,fij,j->f", u, Dl, u))
    alpha = _lifted_angles(a, alpha)
    m = a.R_joint[a.fixed_joints[0]][:, 1]  # in-plane axis: the gauge joint's tangent
    n = np.cos(alpha / 2)[:, None] * m + np.sin(alpha / 2)[:, None] * np.cross(nrm, m)
    ne = len(a.R_edge)
    band = []
    for t in np.linspace(0.0, 1.0, n_images):
        r = a.copy()
        F = rodrigues(math.pi * t * n) @ rodrigues(np.tile(math.pi * t * m, (len(n), 1))) @ Fa
        r.R_edge, r.R_joint = F[:ne], F[ne:]
        r.x = (1 - t) * a.x + t * b.x
        restore_inextensible(r)
        to_gauge(r, a)  # G turns the gauge joint by R_m(2 pi t): undo it rigidly
        band.append(r)
    band[0], band[-1] = a.copy(), b.copy()
    return band


def _tangent(band: list[DiscreteRod], i: int, free: np.ndarray, scale: np.ndarray
             ) -> np.ndarray:
    """Central unit tangent of the string at interior image ``i`` (its chart, free unknowns)."""
    ahead = chart_difference(band[i], band[i + 1])[free]
    back = -chart_difference(band[i], band[i - 1])[free]
    return ahead / np.linalg.norm(scale * ahead) + back / np.linalg.norm(scale * back)


@dataclasses.dataclass(frozen=True)
class StringRun(Result):
    """The string's relaxation and the saddle refined from one of its images.

    ``converged``: Newton from a local maximum of the string's energies converged to a
    stationary point of index one that the caller accepted; ``iterations``: string iterations
    done; ``displacement``: largest chart move of an image in the last iteration (over ``L``,
    rad); ``largest_gap``: largest chart gap (:func:`~rodstab.nonlinear.constraint.chart_size`)
    between neighbouring images at the end; ``too_coarse``: stopped because a gap exceeded
    :data:`MAX_GAP`; ``top_energies``: the highest interior image's energy after each iteration;
    ``saddle_image``: the image the saddle was refined from (-1: none); ``images``: the
    string's images at the end (more than it started with after a refinement, ``refinements``
    of them, :data:`REFINEMENTS`); ``saddle_index``,
    ``residual``: of the last converged Newton run (-1, NaN if none); ``attempts``: Newton runs;
    ``reparametrisations``: times the string was reparametrised; ``contact_stages``: with
    contact, the :class:`~.string_contact.ContactStages` that reached the path;
    ``refused_reparametrisations``: with contact, times a reparametrisation was refused because
    an interpolated image lay outside the model. Then neighbouring images are not joined
    inside it (the chart path between them passes rods through each other), the images bunch
    and the step cap (a fraction of the smaller neighbouring gap) stalls them: measured on the
    stacked line -> star at 6 el. (docs/theory/contact.md).
    """

    converged: bool
    iterations: int
    displacement: float
    largest_gap: float
    too_coarse: bool
    top_energies: tuple[float, ...]
    saddle_image: int
    saddle_index: int
    residual: float
    attempts: int
    reparametrisations: int
    contact_stages: Result | None = None
    refused_reparametrisations: int = 0
    images: int = 0
    refinements: int = 0


def max_string_images(images: int, fit: int) -> int:
    """Return the most images a string of ``images`` may be refined to (``fit``: copies allowed)."""
    return max(images, min((images - 1) * 2 ** REFINEMENTS + 1, fit))


def _index(r: DiscreteRod) -> tuple[int, np.ndarray, np.ndarray]:
    """Hessian index of ``r`` (scaled eigenvalues below ``-zero_eigenvalue_tol``), lowest pairs."""
    vals, vecs = lowest_modes(r, INDEX_EIGS)
    return int(np.sum(vals < -zero_eigenvalue_tol(r))), vals, vecs


@serially
def relax_string(band: list[DiscreteRod], *, max_iter: int = STRING_MAX_ITER,
                 try_every: int = SADDLE_TRY_EVERY,
                 accept: Callable[[DiscreteRod], bool] | None = None,
                 max_images: int | None = None, pool: Executor | None = None,
                 stop: Callable[[list[DiscreteRod]], bool] | None = None
                 ) -> tuple[list[DiscreteRod], DiscreteRod | None, StringRun]:
    """Relax the string ``band`` until one of its images refines to an accepted index-1 saddle.

    The iteration of the module docstring: every interior image takes one perpendicular
    Newton step (:func:`~.string_step.perpendicular_step`), the string is reparametrised when
    uneven (:func:`reparametrise`), and, at least ``try_every`` iterations apart and once the string
    has settled (:data:`SETTLE_RTOL`), copies of the interior local maxima of its energies
    (highest first, at most :data:`SADDLE_CANDIDATES`) are refined by :func:`refine_saddle`.
    The first that converges with index one and that ``accept`` takes ends the relaxation. A
    local maximum, not only the highest image: a string between two states may pass an end
    state again after a loop, and its highest hump need not be the saddle between the ends
    (hexagram star -> daisy, module docstring). With ``max_images`` above the band's length, a
    string whose neighbouring images drift more than :data:`MAX_GAP` apart is redistributed
    over ``2 n - 1`` images (at most ``max_images``), before it would stop as too coarse.

    Parameters
    ----------
    band : list of DiscreteRod
        The string, ends (kept fixed) included, all in one gauge; at least three images.
    max_iter, try_every : int
        Most iterations; iterations between saddle attempts.
    accept : callable, optional
        Takes an index-1 saddle, returns whether it is the one sought (e.g. its descents end
        on the two states); by default every index-1 saddle is.
    max_images : int, optional
        Most images after refinement (:func:`max_string_images`); None: never refined.
    pool : Executor, optional
        The images' steps run in its processes (:func:`~.string_step.step_images`: the same
        string as without it); None: one after another here.
    stop : callable, optional
        Takes the string every :data:`STOP_EVERY` iterations; True ends the relaxation there
        (not converged, no saddle): the soft stages of contact end once their string is
        far enough inside the model (:mod:`.string_contact`).

    Returns
    -------
    tuple
        The relaxed string (new list; the ends are the given objects), the saddle (``None``
        if none was found) and the :class:`StringRun`.
    """
    band = list(band)
    n = len(band)
    free = band[0].free_dofs()
    floor = zero_eigenvalue_tol(band[0])
    scale = chart_scale(band[0])[free]
    lams = [floor] * n
    terms: list[Terms | None] = [None] * n
    ends = [band[0].energy_terms(), band[-1].energy_terms()]
    terms[0], terms[-1] = ends
    tops: list[float] = []
    attempts = reps = refused = refinements = 0
    index, residual, moved, it, last_try = -1, math.nan, math.inf, 0, 0

    def gaps() -> list[float]:
        return [chart_size(band[k], chart_difference(band[k], band[k + 1]))
                for k in range(n - 1)]

    def run(converged: bool, saddle_image: int, too_coarse: bool = False) -> StringRun:
        return StringRun(converged, it, moved, max(gaps()), too_coarse, tuple(tops),
                         saddle_image, index, residual, attempts, reps,
                         refused_reparametrisations=refused, images=n,
                         refinements=refinements)

    for it in range(1, max_iter + 1):
        gap = gaps()
        if max(gap) > MAX_GAP and max_images is not None and 2 * n - 1 <= max_images:
            try:
                band = reparametrise(band, free, count=2 * n - 1)
            except Interpenetration:  # with contact: keep the string, which is inside the model
                refused += 1
            else:
                n, refinements = len(band), refinements + 1
                lams = [floor] * n
                terms = [ends[0]] + [None] * (n - 2) + [ends[1]]
                gap = gaps()
        old = [r.copy() for r in band]
        if max(gap) > MAX_GAP:
            return band, None, run(False, -1, too_coarse=True)
        inner = range(1, n - 1)
        stepped = step_images(band[1:-1], free, terms[1:-1],
                              [_tangent(old, i, free, scale) for i in inner], lams[1:-1],
                              floor, [STEP_FRACTION * min(gap[i - 1], gap[i]) for i in inner],
                              pool)
        for i, (new, lam) in zip(inner, stepped, strict=True):
            terms[i], lams[i] = new, lam
        seg = [float(np.linalg.norm(scale * chart_difference(band[k], band[k + 1])[free]))
               for k in range(n - 1)]
        if max(seg) > REPARAM_RATIO * min(seg):
            try:
                band = reparametrise(band, free)
                terms = [ends[0]] + [None] * (n - 2) + [ends[1]]
                reps += 1
            except Interpenetration:  # with contact: keep the string, which is inside the model
                refused += 1
        moved = max(chart_size(old[i], chart_difference(old[i], band[i]))
                    for i in range(1, n - 1))
        energies = [t[0] if t is not None else r.energy()
                    for t, r in zip(terms, band, strict=True)]
        tops.append(max(energies[1:-1]))
        if stop is not None and it % STOP_EVERY == 0 and stop(band):
            return band, None, run(False, -1)
        window = tops[-1 - SETTLE_ITER:]
        settled = (len(tops) > SETTLE_ITER and max(window) - min(window)
                   <= SETTLE_RTOL * (tops[-1] - min(energies[0], energies[-1])))
        if it < last_try + try_every or not settled:
            continue
        last_try = it
        peaks = [i for i in range(1, n - 1)
                 if energies[i] >= energies[i - 1] and energies[i] >= energies[i + 1]]
        for i in sorted(peaks, key=lambda k: -energies[k])[:SADDLE_CANDIDATES]:
            attempts += 1
            saddle = band[i].copy()
            newton_run = refine_saddle(saddle)
            if not newton_run.converged:
                continue
            index, residual = _index(saddle)[0], newton_run.residual
            if index == 1 and (accept is None or accept(saddle)):
                return band, saddle, run(True, i)
    return band, None, run(False, -1)


#: The soft stages' (iterations per stage, most stages) with cusp welds of width: with the
#: defaults (20, 8) the star -> daisy string of the hexagram did not get inside the model
#: (6 el.: 16 stages left the cusps' ends 0.89 h apart); with these every image got inside at
#: 6, 8, 12 and 16 el. (docs/theory/contact.md, "The star -> daisy barrier with welds of
#: finite width").
WIDE_CUSP_SOFT = (60, 14)


def _built(a: Assembly, n: int, mu: float, cusp_width: float | None) -> DiscreteRod:
    """:func:`~.discover.common_rod`; with ``cusp_width``, relaxed once without contact.

    Opening the cusps moves only the end nodes, so the built state is no equilibrium; from 12
    el. per rod on, the hexagram's star as built has its first rod's first element through the
    last rod's second-last (0.27 h deep at 12 el., h = 0.02 L, w = 1.15 h), while relaxed
    without contact every pair is at least the weld's 0.15 h clearance apart.
    """
    r = common_rod(a, n, mu, cusp_width=cusp_width)
    if cusp_width:
        newton(r)
    return r


def held_pair(a: Assembly, b: Assembly, mu: float, n: int, names: tuple[str, str],
              contact: ContactModel | None = None, cusp_width: float | None = None
              ) -> tuple[DiscreteRod, DiscreteRod]:
    """Return the two ends of a path: ``a`` and ``b`` in one discrete model, ``b`` in ``a``'s gauge.

    Each built by :func:`_built` (``n`` el. per rod at load factor ``mu``), relaxed and stable
    (:func:`~.layered.stable_end`, with ``contact`` if given); :func:`to_gauge`. Raises
    :class:`~rodstab.errors.RodstabInputError` for states of two models or an end not stable.
    """
    rod_a, rod_b = _built(a, n, mu, cusp_width), _built(b, n, mu, cusp_width)
    if not same_model(rod_a, rod_b):
        raise RodstabInputError(f"states {names[0]!r} and {names[1]!r} are not states of one "
                                "discrete model (rest lengths or natural curvatures differ)")
    for r, label in ((rod_a, names[0]), (rod_b, names[1])):
        stable_end(r, label, contact, f"load factor {mu!r}")
    to_gauge(rod_b, rod_a)
    return rod_a, rod_b


def _named(named: dict[str, Assembly], n: int, mu: float, contact: ContactModel | None,
           cusp_width: float | None = None) -> list[tuple[str, DiscreteRod]]:
    """Return the states of ``named`` that are stable minima at ``mu`` (``contact``), as models."""
    out = []
    for label, asm in named.items():
        r = _built(asm, n, mu, cusp_width)
        try:
            stable_end(r, label, contact, "")
        except (RodstabInputError, Interpenetration):
            continue  # not a minimum here: it names nothing
        out.append((label, r))
    return out


def string_barrier(a: Assembly, b: Assembly, load_factor: float, *,
                   elements_per_segment: int = 8, images: int = STRING_IMAGES,
                   name_a: str = "A", name_b: str = "B", max_iter: int = STRING_MAX_ITER,
                   limits: Limits = DEFAULT_LIMITS, contact: ContactModel | None = None,
                   layers: dict[str, Any] | None = None, chain_depth: int = CHAIN_DEPTH,
                   named: dict[str, Assembly] | None = None, cusp_width: float | None = None,
                   soft: tuple[int, int] | None = None, pool: Executor | None = None,
                   ends: tuple[DiscreteRod, DiscreteRod] | None = None,
                   named_states: list[tuple[str, DiscreteRod]] | None = None
                   ) -> tuple[Barrier, list[Snapshot]]:
    """Energy barrier between held states ``a`` and ``b`` of one ring by the string method.

    Both are put in one discrete model (:func:`~.discover.common_rod`) at ``load_factor`` and
    relaxed by Newton; ``b`` is moved into ``a``'s gauge (:func:`to_gauge`); the string runs
    from the belt path (:func:`belt_path`) until its highest image refines to an index-1 saddle
    (:func:`relax_string`); the two steepest descents from that saddle
    (:func:`~.barrier.descents_from_saddle`, retracted steps) must end on ``a`` and ``b``
    (:func:`~.discover.same_state`).

    Parameters
    ----------
    a, b : Assembly
        Held states of one ring (same segments in the same order and orientation).
    load_factor : float
        The model's load factor, at which both must be stable.
    elements_per_segment : int
        Elements per rod (>= :data:`~.barrier.MIN_ELEMENTS`).
    images : int
        Images of the string at the start, ends included (>= 3). Where its images drift more
        than :data:`MAX_GAP` apart the string is redistributed over twice as many, at most
        :data:`REFINEMENTS` times and within ``limits`` (:func:`max_string_images`); the
        barrier's ``images`` and ``string_run.refinements`` say what it ended with.
    name_a, name_b : str
        Labels of ``a`` and ``b``.
    max_iter : int
        Most string iterations.
    limits : Limits
        The images are relaxed together: their unknowns in total are at most
        ``limits.max_dof_nonlinear`` (:func:`rodstab.limits.require_nonlinear`), checked before
        anything is built.
    contact : ContactModel, optional
        Rods that cannot pass through each other: both states relaxed with it, the string
        brought inside it (:func:`~.string_contact.relax_with_contact`, recorded in
        ``string_run.contact_stages``). None: no contact (every number as before).
    layers : dict, optional
        With ``contact``: ``a`` is a stacked state and this its layer order; the path runs in
        the stacked model, welds spanning the layers (:func:`~.layered.stacked_band`), from
        the planar path relaxed without contact to its first index-1 saddle, lifted.
    chain_depth : int
        When the string finds no saddle joining the two states, it is split into a chain of
        saddles between the minima its images descend to (:func:`~.chain.chain`), at most this
        many splits deep; 0: not split.
    named : dict, optional
        Other held states of the ring, by label: those stable at ``load_factor`` in the same
        discrete model name the minima a descent or the chain reaches (else ``m1``, ``m2``, ...).
        Not used with ``layers`` (the stacked model is another model).
    cusp_width : float, optional
        Welds of this width at the cusps (length; :func:`~.discover.common_rod`), the two
        rods' ends held apart across the tangent; None: point welds.
    soft : tuple of int, optional
        With ``contact``: the soft stages' ``(iterations per stage, most stages)``
        (:func:`~.string_contact.relax_with_contact`); None: its defaults, or
        :data:`WIDE_CUSP_SOFT` with ``cusp_width``.
    pool : Executor, optional
        The images' steps run in its processes
        (:func:`~rodstab.numerics.threads.process_pool`; the same string, faster on several
        cores); None: in this process.
    ends : tuple of DiscreteRod, optional
        The two states as relaxed stable states of one discrete model (a design that is no
        ring: its states found by deflation, :mod:`.design_states`), used instead of ``a`` and
        ``b`` built and relaxed here; ``a`` then only sizes the model, and ``a``'s held state
        in that model is the point the first path passes (:func:`initial_path`). Not with
        ``layers`` or ``cusp_width``.
    named_states : list of (str, DiscreteRod), optional
        With ``ends``: other stable states of that model, to name the minima a path passes.

    Returns
    -------
    tuple
        The :class:`~.barrier.Barrier` (``converged`` false when no index-1 saddle was found or
        its descents do not end on the two states; the barriers are then those of the highest
        image; when the string was split, ``chain`` holds the :class:`~.chain.Chain`, the path
        is its links' paths in order and the barrier its highest saddle) and the path's states
        (string images, the highest replaced by the saddle).

    Raises
    ------
    RodstabInputError
        Naming the value: a bad number, two states of different models, a state not stable at
        ``load_factor``, a non-planar state, or frame loops an odd number of turns apart;
        with contact, a state whose rods overlap under the model (an Interpenetration).
    NotConverged
        With contact: no path inside the model was reached (the reason named).
    TopologicallyApart
        With contact: the two states differ in knot type or in the self-linking of their
        ribbons (:func:`~.linking.topology`), so no path joins them inside the model; raised
        before the string is run.
    """
    mu = require_finite("load_factor", load_factor)
    n = require_int("elements_per_segment", elements_per_segment, MIN_ELEMENTS)
    n_img = require_int("images", images, 3)
    max_iter = require_int("max_iter", max_iter, 1)
    if soft is None and cusp_width:
        soft = WIDE_CUSP_SOFT
    if soft is not None:  # before any work (relax_with_contact checks them again)
        soft = (require_int("soft[0] (stage iterations)", soft[0], 1),
                require_int("soft[1] (most stages)", soft[1], 0))
    if layers is not None and cusp_width:  # the stacked model's welds span its layers
        raise RodstabInputError(f"cusp_width {cusp_width!r} with layers: the stacked model "
                                "has no cusp welds of width; give one of the two")
    one = require_nonlinear([n] * len(a.segments), len(a.joints()),
                            f"images {n_img}, {n} elements per rod", limits,
                            copies=n_img) // n_img
    relax = functools.partial(relax_string, pool=pool,
                              max_images=max_string_images(n_img, limits.max_dof_nonlinear // one))
    if ends is None:
        rod_a, rod_b = held_pair(a, b, mu, n, (name_a, name_b),
                                 contact if layers is None else None, cusp_width)
    elif layers is not None or cusp_width:
        raise RodstabInputError("ends are relaxed states of one model: no layers or cusp_width")
    else:
        rod_a, rod_b = ends[0].copy(), ends[1].copy()
        to_gauge(rod_b, rod_a)
    start = initial_path(rod_a, rod_b, n_img, None if ends is None else common_rod(a, n, mu))
    if layers is not None:  # the planar path without contact, lifted: the belt path lifted
        # stalled in the soft stages (hexagram line -> star, 6 el.), this one did not
        start = relax(start, max_iter=max_iter, accept=None)[0]
        start = stacked_band(start, layers, contact, (name_a, name_b))
        rod_a, rod_b = start[0], start[-1]
    if contact is not None:  # rods that cannot cross keep both invariants: check before work
        from .linking import TopologicallyApart, topology

        verdict = topology(rod_a, rod_b, (name_a, name_b))
        if verdict.apart:
            raise TopologicallyApart(verdict)
    e_a, e_b = rod_a.energy(), rod_b.energy()
    land = Landscape.of([(name_a, rod_a), (name_b, rod_b)]
                        + ([] if layers is not None
                           else _named(named or {}, n, mu, contact, cusp_width))
                        + list(named_states or ()))
    land.keep_traces = contact is not None
    land.proper = ends is not None  # given states may be mirror images (design_states)

    def joins_the_states(saddle: DiscreteRod) -> bool:
        # The saddle sought is the one whose two descents end on a and b (modulo the ring's
        # symmetry); another index-1 saddle of the string joins other states. The string
        # refines the same saddle again and again: its descents (minutes with contact) once.
        return land.joins(saddle, name_a, name_b)

    if contact is None:
        band, saddle, run = relax(start, max_iter=max_iter, accept=joins_the_states)
    else:
        from .string_contact import relax_with_contact

        band, saddle, run, stages = relax_with_contact(
            start, contact, relax, max_iter=max_iter, accept=joins_the_states,
            **({} if soft is None else {"stage_iter": soft[0], "max_stages": soft[1]}))
        run = dataclasses.replace(run, contact_stages=stages)
    chained = None
    if saddle is None and not run.too_coarse and chain_depth > 0:
        links, paths, basins = chain(band, land, (name_a, name_b), relax, images=run.images,
                                     max_iter=max_iter, max_depth=chain_depth)
        chained = chain_result(links, basins, land, (name_a, name_b))
    labels: tuple[str, ...]
    if chained is not None and chained.converged:
        band = [r for p in paths for r in p]
        k = int(np.nanargmax([lk.energy_saddle for lk in chained.links]))
        i = chained.links[k].saddle_image
        # a saddle the landscape held: its link's path is its start, marked at its highest point
        top = sum(len(p) for p in paths[:k]) + (
            i if i >= 0 else int(np.argmax([r.energy() for r in paths[k]])))
        rec = min(land.saddles, key=lambda r: abs(r["energy"] - chained.energy_saddle))
        saddle, index = band[0].copy(), 1
        rec["state"].put(saddle)
        residual = float(np.max(np.abs(saddle.energy_terms()[1][saddle.free_dofs()])))
        saddle = band[top]
        vals, labels, steps = rec["eigenvalues"], rec["descent_ends"], rec["descent_steps"]
    elif saddle is None:
        energies = [r.energy() for r in band]
        top = 1 + int(np.argmax(energies[1:-1]))
        saddle = band[top]
        vals = lowest_modes(saddle, INDEX_EIGS)[0]
        index = int(np.sum(vals < -zero_eigenvalue_tol(saddle)))
        residual = float(np.max(np.abs(saddle.energy_terms()[1][saddle.free_dofs()])))
        labels = ()
        steps = (0, 0)
    else:
        top, index, residual = run.saddle_image, run.saddle_index, run.residual
        rec = land.judge(saddle)
        vals, labels, steps = rec["eigenvalues"], rec["descent_ends"], rec["descent_steps"]
    on_path = [(lk.energy_saddle, {lk.from_state, lk.to_state})
               for lk in (chained.links if chained is not None else ())]

    def other(rec: dict[str, Any]) -> bool:  # neither the saddle sought nor a chain's link
        ends = set(rec["descent_ends"])
        return ends != {name_a, name_b} and not any(
            ends == pair and abs(rec["energy"] - e) <= 1e-12 * abs(e) for e, pair in on_path)

    others = tuple({k: rec[k] for k in ("energy", "descent_ends", "end_energies",
                                         "ends_converged")}
                   for rec in land.saddles if other(rec))
    path = band[:top] + [saddle] + band[top + 1:]
    if chained is None and run.converged and contact is not None:
        # With contact the string's images are joined by chart segments that no filter
        # checked; the saddle's two descents are joined inside the model step by step.
        to_a, to_b = (rec["traces"] if labels[0] == name_a else rec["traces"][::-1])
        path, top = to_a[::-1] + [saddle] + to_b, len(to_a)
    energies = [r.energy() for r in path]
    method = ("string: belt path, perpendicular Newton steps retracted onto the inextensible "
              "states, reparametrised to equal chart arclength; saddle = Newton from a local "
              "maximum of its energies, index 1, whose steepest descents end on the two "
              "states (same_state)")
    if chained is None and run.converged and contact is not None:
        method += ("; with contact the path is the saddle's two steepest descents, every step "
                   "filtered, so it is joined inside the model")
    if chained is not None:
        method += ("; no saddle joined the two states: the string split at the minima its "
                   "images descend to, a string and saddle per neighbouring pair (chain.py), "
                   "the barrier the chain's highest saddle")
    e_s = energies[top] if chained is None or not chained.converged else chained.energy_saddle
    return Barrier(
        barrier_forward=float(e_s - e_a), barrier_backward=float(e_s - e_b),
        saddle_index=index, energies=tuple(float(e) for e in energies), saddle_position=top,
        from_state=name_a, to_state=name_b, energy_from=float(e_a), energy_to=float(e_b),
        energy_saddle=float(e_s), lowest_eigenvalues_saddle=tuple(float(x) for x in vals),
        load_factor=mu, load_factor_critical=math.nan,
        converged=run.converged if chained is None else chained.converged, residual=residual,
        descent_steps=steps, elements_per_segment=n, n_dof=len(saddle.free_dofs()),
        method=method,
        descent_ends=labels, images=run.images, iterations=run.iterations,
        path_arclength=tuple(float(x) for x in arclength(path)), string_run=run,
        other_saddles=others, chain=chained), \
        [Snapshot.of(r) for r in path]
