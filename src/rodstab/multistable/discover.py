"""Discovery of equilibria nobody named: deflated Newton on one discrete rod.

Farrell, Beentjes and Birkisson, *Deflation techniques for finding distinct solutions of
nonlinear partial differential equations*, SIAM J. Sci. Comput. 37 (2015) A2026 (arXiv 2014,
"2016" in the issue). Having found equilibria ``q_1 .. q_k`` of the free gradient ``g(q) = 0``,
Newton is run on the deflated system ``M(q) g(q) = 0`` with the deflation operator

    ``M(q) = prod_i (d(q, q_i)^-p + shift)``,  ``p = 2``, ``shift = 1``   (their eq. 2.4, 4.1),

which has the same roots as ``g`` except the ``q_i`` (``M g -> inf`` there), so Newton is driven
to new ones. Its Jacobian is ``M H + g (grad M)^T``; with the undeflated step ``delta = -H^-1 g``
the deflated step is ``tau delta``, ``tau = 1 / (1 - grad(log M) . delta)`` (Sherman-Morrison,
their eq. 3.5): one factorisation of ``H`` per step, as for Newton.

The distance ``d`` is measured in the gauged unknowns of the rod (the rigid motion is removed by
the gauge joint, :meth:`~rodstab.nonlinear.discrete.DiscreteRod.free_dofs`): node positions over
the mean segment length ``L`` and chordal frame distances,
``d^2 = mean_nodes |x - x_i|^2 / L^2 + mean_frames |R - R_i|_F^2 / 4``. Symmetric images of a
state (the ring's rods relabelled cyclically, the traversal reversed, a reflection) are distinct
points there: every converged solution is deflated, and the list reported is deduplicated
afterwards by energy, Hessian index and the aligned distance minimised over those images
(:func:`~rodstab.multistable.identify.same_state`, Kabsch with reflections allowed).

One rod for every state: all equilibria must be states of the *same* discrete model. A rod
discretised from a curved held state carries that state in its discrete natural curvature (the
held Cayley curvature, :mod:`rodstab.nonlinear.discrete`) and in its edge rest lengths (the arc's
chords), both ``O(k^2 l_e^2)`` away from another state's. :func:`common_rod` replaces them by the
state-free ones -- rest length = arc length / elements, natural Cayley curvature ``mu kappa_n`` at
every joint and half-joint (exactly what the straight held state gives) -- so the energy depends
only on the natural curvature, whichever held state was discretised (tested).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Iterator
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import RodstabInputError
from ..model import Assembly
from ..nonlinear.constraint import (
    RETRACT_ABOVE,
    chart_size,
    mean_length,
    restore_positions,
    retract_step,
)
from ..nonlinear.contact import Interpenetration
from ..nonlinear.discrete import PENALTY, DiscreteRod, discretise
from ..nonlinear.jets import vee_skew
from ..nonlinear.newton import contact_fraction
from ..nonlinear.solve import NEWTON_RTOL, lowest_eigenvalues, max_strain, zero_eigenvalue_tol
from ..numerics import jacobi_scaling
from ..results import Result
from .identify import (
    SAME_STATE_DISTANCE,
    SAME_STATE_ENERGY,
    Invariants,
    Snapshot,
    best_fit_plane,
    invariants,
    same_state,
    segment_nodes,
)
from .states import Ring

#: Deflation power ``p`` and shift of ``M(q) = prod (d^-p + shift)`` (Farrell et al.'s defaults).
DEFLATION_POWER = 2.0
DEFLATION_SHIFT = 1.0
#: Iterations of one deflated Newton run.
DEFLATED_MAX_ITER = 80
#: A step moves no node by more than this times the mean segment length and turns no frame by
#: more than :data:`MAX_STEP_ROTATION` rad (Newton on a far, flat landscape overshoots).
MAX_STEP_DISPLACEMENT = 0.25
MAX_STEP_ROTATION = 0.5
#: Levenberg-Marquardt shifts tried per deflated Newton step before the run gives up.
LM_TRIES = 30
#: A found state takes a known state's label when its turning number is within this of it
#: (and its distinct weld points and planarity agree).
TURNING_TOL = 0.05
#: Lowest eigenvalues computed to count the Hessian index (a larger index is reported as >=).
INDEX_EIGS = 8


# ---------------------------------------------------------------------------------------------
# One rod for every state
def common_rod(a: Assembly, elements_per_segment: int, load_factor: float,
               layers: dict[str, Any] | None = None,
               cusp_width: float | None = None,
               end_offsets: dict[tuple[str, str], Any] | None = None) -> DiscreteRod:
    """Discretise ``a`` with the held-state-free rest lengths and natural curvatures.

    The state (positions, frames) is the held state of ``a``; the model (rest length
    ``L_seg / elements``, natural Cayley curvature ``(0, 0, mu kappa_n)`` at every joint and
    half-joint) is the one the straight held state gives, so any two rods built from states of
    the same ring have the same energy function (module docstring). Natural twist is refused
    (the held twisted ring is not a state of the discrete model). ``layers``: the stacked
    state with welds spanning its layers (``discretise``'s ``layers``); ``cusp_width``: welds of
    that width at the cusps, ``end_offsets`` segment ends moved (``discretise``'s, not an
    equilibrium until relaxed).
    """
    rod = discretise(a, elements_per_segment, load_factor, layers=layers,
                     cusp_width=cusp_width, end_offsets=end_offsets)
    if rod.edge_tw is not None:
        raise RodstabInputError("discover: segments with natural twist are not supported")
    seg_len = np.repeat([s.length for s in a.segments], elements_per_segment)
    rod.rest_length = seg_len / elements_per_segment
    pairs = rod.bend_pairs[:, 0]
    k_held = np.zeros((len(pairs), 3))
    k_held[:, 2] = rod.edge_k[pairs]  # cancels the "- k" of DiscreteRod._k0: k0 = mu kappa_n
    rod.k_held_pairs = k_held
    ee = np.array([lk[0] for lk in rod.end_links], int)
    per_mu = np.zeros((len(ee), 3))
    per_mu[:, 2] = rod.edge_kn[ee]
    rod.k0_links = (np.zeros((len(ee), 3)), per_mu)
    return rod


# ---------------------------------------------------------------------------------------------
# Deflation operator
def distance_sq(rod: DiscreteRod, ref: Snapshot) -> tuple[float, np.ndarray]:
    """``d^2`` from ``rod``'s state to ``ref`` (module docstring) and its gradient (n_dof,).

    The gradient is with respect to the rod's chart increments (:meth:`DiscreteRod.apply`:
    ``x + dx``, ``R exp(hat(phi))``) at ``phi = 0``: ``2 (x - x_i) / (n L^2)`` for a node and,
    from ``|R - R_i|^2 = 6 - 2 tr(R_i^T R)``, ``vee(A - A^T) / (2 n_f)`` with ``A = R_i^T R``
    for a frame.
    """
    L = mean_length(rod)
    nx, nf = len(rod.x), len(rod.R_edge) + len(rod.R_joint)
    dx = rod.x - ref.x
    R = np.concatenate([rod.R_edge, rod.R_joint])
    Ri = np.concatenate([ref.R_edge, ref.R_joint])
    d2 = float(np.sum(dx**2)) / (nx * L**2) + float(np.sum((R - Ri) ** 2)) / (4 * nf)
    A = np.swapaxes(Ri, 1, 2) @ R
    grad = np.concatenate([(2.0 / (nx * L**2)) * dx.ravel(),
                           (vee_skew(A) / (2.0 * nf)).ravel()])
    return d2, grad


def deflation(rod: DiscreteRod, known: list[Snapshot], *, power: float = DEFLATION_POWER,
              shift: float = DEFLATION_SHIFT) -> tuple[float, np.ndarray]:
    """Deflation operator ``M(q)`` and the gradient of ``log M`` (n_dof,) at ``rod``'s state.

    ``M = prod_i (d_i^-p + shift)``; ``grad log M = sum_i -(p/2) d_i^(-p-2) grad(d_i^2) /
    (d_i^-p + shift)``. ``M = 1`` and a zero gradient with nothing known.
    """
    M = 1.0
    glog = np.zeros(rod.n_dof)
    for ref in known:
        d2, g2 = distance_sq(rod, ref)
        d2 = max(d2, 1e-60)  # at a known state M is infinite: keep it finite, huge
        m = d2 ** (-0.5 * power) + shift
        M *= m
        glog += (-0.5 * power * d2 ** (-0.5 * power - 1.0) / m) * g2
    return M, glog


# ---------------------------------------------------------------------------------------------
# Deflated Newton
@dataclasses.dataclass(frozen=True)
class NewtonRun(Result):
    """One deflated Newton run: converged or not, iterations, undeflated residual max|g_free|."""

    converged: bool
    iterations: int
    residual: float


def _residual_scale(rod: DiscreteRod) -> float:
    """Force scale of the stiff stretch/shear terms (as :func:`rodstab.nonlinear.solve.newton`)."""
    return float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))


def _solve(Hf: sp.spmatrix, rhs: np.ndarray, dg: np.ndarray, lam_floor: float) -> np.ndarray:
    """``H^-1 rhs``, shifting ``H`` by ``lam D`` (``D = |diag H|``) if it is singular."""
    lam = 0.0
    for _ in range(12):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                s = spla.spsolve((Hf + lam * sp.diags(dg)).tocsc(), rhs)
                if np.all(np.isfinite(s)):
                    return s
            except RuntimeError:
                pass
        lam = max(10 * lam, lam_floor)
    raise FloatingPointError("the Hessian stayed singular under shifts")


def _cap(rod: DiscreteRod, dq: np.ndarray) -> float:
    """Largest factor <= 1 keeping ``dq`` within the step caps."""
    nx = len(rod.x)
    disp = float(np.max(np.linalg.norm(dq[: 3 * nx].reshape(-1, 3), axis=1)))
    rot = float(np.max(np.linalg.norm(dq[3 * nx:].reshape(-1, 3), axis=1)))
    L = mean_length(rod)
    return min(1.0, MAX_STEP_DISPLACEMENT * L / max(disp, 1e-300),
               MAX_STEP_ROTATION / max(rot, 1e-300))


def _trials(rod: DiscreteRod, dq: np.ndarray, known: list[Snapshot]
            ) -> Iterator[tuple[DiscreteRod, np.ndarray, Any, float, np.ndarray]]:
    """Yield the state after step ``dq`` back on the Kirchhoff constraint, and its terms.

    First with the nodes moved onto their frames (:func:`restore_positions`), then, for a large
    step, with the frames turned onto their edges
    (:func:`~rodstab.nonlinear.constraint.retract_step`): the caller takes the first whose merit
    falls. Each is needed somewhere: restored positions find the hexagram's daisy from its held
    geometry at 16 el. (retracted first, deflated Newton lost it); retracted frames carry the
    bi-rod's buckled branch from 2.8 to 2.81 (its first Newton step turns frames by 0.1 rad;
    restored, the merit rose 250x and Newton stalled at residual 2e-3). With contact a way
    that leaves the model is skipped.
    """
    ways = [lambda t, _: restore_positions(t)]
    if chart_size(rod, dq) > RETRACT_ABOVE:
        ways.append(retract_step)
    for back in ways:
        trial = rod.copy()
        trial.apply(dq)
        try:
            back(trial, dq)
            _, gt, Ht = trial.energy_terms()
        except Interpenetration:  # only with contact: this trial left the model
            continue
        Mt, glog_t = deflation(trial, known)
        yield trial, gt, Ht, Mt, glog_t


def deflated_newton(rod: DiscreteRod, known: list[Snapshot], *,
                    max_iter: int = DEFLATED_MAX_ITER) -> NewtonRun:
    """Solve ``M(q) g(q) = 0`` from ``rod``'s state (in place) by damped deflated Newton.

    Each step is ``tau delta`` (module docstring), ``delta = -(H + lam D)^-1 g`` with a
    Levenberg-Marquardt ``lam`` (``D = |diag H|``; ``lam = 0``, pure Newton, while steps
    succeed), capped by :data:`MAX_STEP_DISPLACEMENT` and :data:`MAX_STEP_ROTATION`, brought
    back onto the Kirchhoff constraint (:func:`_trials`); it is taken when the merit
    ``M |S g|`` (``S`` the Jacobi scaling of ``H``) falls, else ``lam`` grows. Converged when the
    *undeflated* residual ``max |g_free|`` is below ``NEWTON_RTOL`` times the stiff force scale
    (as :func:`rodstab.nonlinear.solve.newton`) at a point farther than
    :data:`SAME_STATE_DISTANCE` from every known state: ``M`` is finite there, so the root is an
    equilibrium. With ``known`` empty this is damped Newton on ``g``, which converges to saddles
    as well as minima (unlike :func:`rodstab.nonlinear.solve.newton`). With contact
    (``rod.contact``) each step is also filtered so that no gap closes, and a trial outside the
    model is rejected (``lam`` grows).
    """
    if any(distance_sq(rod, s)[0] <= SAME_STATE_DISTANCE**2 for s in known):
        return NewtonRun(False, 0, math.nan)  # started on a known state: M g is 0 x inf
    if np.max(rod.shear()) > 1e-2:
        rod.align_frames()
    free = rod.free_dofs()
    tol = NEWTON_RTOL * _residual_scale(rod)
    lam_floor = zero_eigenvalue_tol(rod)
    lam = 0.0
    res = math.inf
    _, g, H = rod.energy_terms()
    M, glog = deflation(rod, known)
    for it in range(max_iter + 1):
        gf = g[free]
        res = float(np.max(np.abs(gf))) if gf.size else 0.0
        if res <= tol:
            near = [distance_sq(rod, s)[0] for s in known]
            return NewtonRun(min(near, default=1.0) > SAME_STATE_DISTANCE**2, it, res)
        if it == max_iter:
            break
        Hf = H[free][:, free].tocsc()
        Hf = 0.5 * (Hf + Hf.T)
        d = jacobi_scaling(Hf)
        merit = M * float(np.linalg.norm(d * gf))
        for _ in range(LM_TRIES):
            try:
                delta = _solve(Hf + lam * sp.diags(1.0 / d**2), -gf, 1.0 / d**2, lam_floor)
            except FloatingPointError:
                return NewtonRun(False, it, res)
            eta = float(glog[free] @ delta)
            # Farrell et al.: tau = 1 / (1 - eta); near eta = 1 the deflated step runs off to
            # infinity (deflation pushes away): take the undeflated step, the merit decides.
            tau = 1.0 / (1.0 - eta) if abs(1.0 - eta) > 1e-3 else 1.0
            dq = np.zeros(rod.n_dof)
            dq[free] = tau * delta
            dq *= _cap(rod, dq)
            if rod.contact is not None:  # the step filter: no gap closes along the step
                dq *= contact_fraction(rod, free, dq[free])
            taken = next((t for t in _trials(rod, dq, known)
                          if t[3] * float(np.linalg.norm(d * t[1][free])) < (1.0 - 1e-4) * merit),
                         None)
            if taken is not None:
                trial, g, H, M, glog = taken
                rod.x, rod.R_edge, rod.R_joint = trial.x, trial.R_edge, trial.R_joint
                lam = 0.0 if lam <= lam_floor else lam / 4
                break
            lam = max(4 * lam, lam_floor)
        else:
            return NewtonRun(False, it, res)
    return NewtonRun(False, max_iter, res)


# ---------------------------------------------------------------------------------------------
# The search
@dataclasses.dataclass(frozen=True)
class KnownState:
    """A named state to recognise: label, turning number, distinct weld points (planar)."""

    label: str
    turning_number: float
    distinct_weld_points: int


@dataclasses.dataclass(frozen=True)
class FoundState(Result):
    """One equilibrium found, deduplicated.

    Attributes
    ----------
    label : str
        The known state it is (:class:`KnownState` matched by turning number, weld points and
        planarity), else ``"unnamed"``.
    energy : float
        Stored energy (units of ``B3 / L``).
    index : int
        Negative eigenvalues of the scaled free Hessian (below ``-zero_eigenvalue_tol``);
        ``index_at_least`` when all :data:`INDEX_EIGS` computed ones are negative.
    stable : bool
        Index 0 and no zero eigenvalue.
    lowest_eigenvalues : tuple of float
        The lowest scaled Hessian eigenvalues over the zero tolerance.
    invariants : Invariants
        Weld points, turning number, out-of-plane extent.
    found_from : str
        The start that reached it first (a seed or a perturbed start, its amplitude).
    times_found : int
        Converged runs that reached it (symmetric images included).
    residual, max_strain : float
        ``max |g_free|`` and the largest stretch/shear strain at the solution.
    zero_modes, members : int
        Zero eigenvalues beyond the rigid motions (a continuous family of equilibria when
        positive) and how many members of the family were found (listed once).
    """

    label: str
    energy: float
    index: int
    index_at_least: bool
    stable: bool
    lowest_eigenvalues: tuple[float, ...]
    invariants: Invariants
    found_from: str
    times_found: int
    residual: float
    max_strain: float
    #: Hessian eigenvalues within the zero tolerance beyond the rigid motions: more than 0
    #: means the state is one of a continuous family of equilibria ...
    zero_modes: int = 0
    #: ... of which this many were found (same index, same energy; listed once).
    members: int = 1


@dataclasses.dataclass(frozen=True)
class Discovery(Result):
    """Every distinct equilibrium found, by increasing energy, and the search's accounting."""

    states: tuple[FoundState, ...]
    load_factor: float
    elements_per_segment: int
    n_dof: int
    starts: int
    runs: int
    converged_runs: int
    seeds: tuple[str, ...]
    method: str
    #: With contact: the starts whose state lies outside the contact model (not run).
    outside_contact: tuple[str, ...] = ()
    #: Seeds from which the first deflated Newton run did not converge (onto a state found
    #: before them, which deflation repels, or nowhere: a mesh too coarse for their shape).
    unconverged_seeds: tuple[str, ...] = ()


#: Largest node displacement of the perturbed starts, in mean segment lengths, cycled through
#: (each amplitude used for a pair of starts, +v and -v). Deflated Newton on the discrete rod
#: converges from about 0.01-0.03 L; from 0.1 L and beyond it mostly stalls in flat valleys of
#: the energy (measured on the hexagram at 16 elements per rod), so large ones are few.
START_AMPLITUDES = (0.01, 0.03, 0.1, 0.3)
#: Deflated runs from one start: after each success it is rerun from the same start with the new
#: solution deflated too (Farrell et al.), at most this many times.
RUNS_PER_START = 3


def _label(inv: Invariants, known: list[KnownState]) -> str:
    if not inv.planar:
        return "unnamed"
    for k in known:
        if abs(inv.turning_number - k.turning_number) <= TURNING_TOL \
                and inv.distinct_weld_points == k.distinct_weld_points:
            return k.label
    return "unnamed"


def _perturbed(rod: DiscreteRod, base: Snapshot, amplitude: float, weights: np.ndarray
               ) -> Snapshot:
    """Perturb ``base`` by a mix of its softest modes and return it on the constraint.

    The mix ``weights`` of its :data:`INDEX_EIGS` softest modes (chart increment) is scaled to a
    largest node displacement ``|amplitude|`` x L (signed), then put back onto the Kirchhoff
    constraint (frames on their chords, :func:`restore_positions`).
    """
    from ..nonlinear.solve import lowest_modes

    trial = rod.copy()
    base.put(trial)
    _, vecs = lowest_modes(trial, INDEX_EIGS)
    return moved_along(trial, base, vecs @ weights[: vecs.shape[1]], amplitude)


def moved_along(rod: DiscreteRod, s: Snapshot, v: np.ndarray, amplitude: float) -> Snapshot:
    """Move ``s`` along free-unknown vector ``v`` to a largest node displacement ``amplitude`` L.

    A chart increment of ``rod`` (its state is changed), signed by ``amplitude``, then put back
    onto the Kirchhoff constraint (frames on their chords, :func:`restore_positions`).
    """
    s.put(rod)
    dq = np.zeros(rod.n_dof)
    dq[rod.free_dofs()] = v
    disp = float(np.max(np.linalg.norm(dq[: 3 * len(rod.x)].reshape(-1, 3), axis=1)))
    rod.apply(dq * (amplitude * mean_length(rod) / max(disp, 1e-300)))
    rod.align_frames()
    restore_positions(rod)
    return Snapshot.of(rod)


def discover(rod: DiscreteRod, seeds: list[tuple[str, Snapshot]], known: list[KnownState], *,
             starts: int = 8, seed: int = 0, directions: tuple[int, ...] | None = None
             ) -> tuple[Discovery, list[Snapshot]]:
    """Find distinct equilibria of ``rod`` by deflated Newton from seeds and perturbed starts.

    1. Every seed state (e.g. a held state) is a start.
    2. ``starts`` perturbed starts, in pairs ``+v``, ``-v``: seed ``(i // 2) mod n_seeds`` plus
       a random mix ``v`` (generator seeded by ``seed``) of its softest modes, largest
       displacement cycling through :data:`START_AMPLITUDES` x L.

    From each start deflated Newton runs with every solution found so far deflated; after a
    success it runs again from the same start (:data:`RUNS_PER_START` runs at most). Returns
    the deduplicated states by increasing energy and their snapshots. ``rod`` is left in the
    last state tried. ``directions``: as in :func:`invariants` (labels by turning number).
    With contact (``rod.contact``) a start outside the model is not run (listed in
    ``outside_contact``).
    """
    rng = np.random.default_rng(seed)
    deflated: list[Snapshot] = []
    distinct: list[tuple[Snapshot, float, str, int]] = []  # snapshot, energy, from, count
    runs = converged = 0
    plan: list[tuple[str, Snapshot | None, int, float]] = [(f"seed {lab}", s, -1, 0.0)
                                                          for lab, s in seeds]
    for i in range(starts):
        amp = START_AMPLITUDES[(i // 2) % len(START_AMPLITUDES)] * (1 if i % 2 == 0 else -1)
        b = (i // 2) % len(seeds)
        plan.append((f"start {i + 1}: seed {seeds[b][0]} perturbed by {amp:+g} L", None, b,
                     amp))
    weights = rng.standard_normal(INDEX_EIGS)
    outside: list[str] = []
    failed_seeds: list[str] = []
    for name, snap, b, amp in plan:
        if snap is None and amp > 0:
            weights = rng.standard_normal(INDEX_EIGS)  # a new mix for each +/- pair
        try:
            start = snap if snap is not None else _perturbed(rod, seeds[b][1], amp, weights)
            if rod.contact is not None:
                start.put(rod)
                rod.energy()  # raises outside the contact model
        except Interpenetration:
            outside.append(name)
            continue
        for attempt in range(RUNS_PER_START):
            start.put(rod)
            runs += 1
            r = deflated_newton(rod, deflated)
            if not r.converged:
                if snap is not None and attempt == 0:
                    failed_seeds.append(name.removeprefix("seed "))
                break
            converged += 1
            s = Snapshot.of(rod)
            deflated.append(s)
            E = rod.energy()
            for k, (t, Et, src, cnt) in enumerate(distinct):
                if same_state(rod, s, t, E, Et):
                    distinct[k] = (t, Et, src, cnt + 1)
                    break
            else:
                distinct.append((s, E, name, 1))
    distinct.sort(key=lambda item: item[1])
    tol = zero_eigenvalue_tol(rod)
    out: list[FoundState] = []
    kept: list[Snapshot] = []
    for s, E, src, cnt in distinct:
        s.put(rod)
        ev = lowest_eigenvalues(rod, INDEX_EIGS)
        index = int(np.sum(ev < -tol))
        zero = int(np.sum(np.abs(ev) <= tol))
        scale = max(abs(E), float(np.max(rod.edge_B[:, 2])) / mean_length(rod))
        family = next((k for k, f in enumerate(out) if zero and f.zero_modes == zero
                       and f.index == index
                       and abs(f.energy - E) <= SAME_STATE_ENERGY * scale), None)
        if family is not None:
            # a zero mode beyond the rigid motions: a continuous family of equilibria, whose
            # members deflation finds one by one at one energy (the hexagram at kappa_n R0 = 2,
            # 8 el.: four index-1 saddles at 11.849190 +- 2e-7); one entry
            f = out[family]
            out[family] = dataclasses.replace(f, members=f.members + 1,
                                              times_found=f.times_found + cnt)
            continue
        g = rod.gradient()
        inv = invariants(rod, s, directions)
        label = _label(inv, known)
        if not known and src.startswith("seed "):
            label = src.removeprefix("seed ")  # no names to recognise: the seed's own
        out.append(FoundState(
            label=label, energy=E, index=index, index_at_least=index == len(ev),
            stable=bool(ev[0] > tol), lowest_eigenvalues=tuple(float(v) for v in ev[:4]),
            invariants=inv, found_from=src, times_found=cnt,
            residual=float(np.max(np.abs(g[rod.free_dofs()]))), max_strain=max_strain(rod),
            zero_modes=zero))
        kept.append(s)
    return Discovery(
        states=tuple(out), load_factor=rod.load_factor,
        elements_per_segment=len(rod.R_edge) // len(rod.assembly.segments),
        n_dof=len(rod.free_dofs()), starts=starts, runs=runs, converged_runs=converged,
        seeds=tuple(lab for lab, _ in seeds),
        method=f"deflated Newton (Farrell, Beentjes, Birkisson; p = {DEFLATION_POWER:g}, shift "
               f"= {DEFLATION_SHIFT:g}) on one discrete rod, deduplicated modulo rigid motion, "
               "reflection and relabelling", outside_contact=tuple(outside),
        unconverged_seeds=tuple(failed_seeds)), kept


def search_start(ring: Ring | None, a: Assembly | None, state: str, elements_per_segment: int,
                 load_factor: float, seed_states: bool = True, cusp_width: float | None = None
                 ) -> tuple[DiscreteRod, list[tuple[str, Snapshot]], list[KnownState],
                            tuple[int, ...]]:
    """Return the common rod, the seeds, the known states and the rods' directions.

    A ring (``ring`` not None): :func:`ring_seeds` from held state ``state``. Any other design
    ``a`` the nonlinear engine takes (a bi-rod, a clamped arc, rods with supports): its held
    state at ``load_factor`` is the one seed, ``"held"``, and no state is known, so equilibria
    are named ``held`` (the one reached from it) or ``unnamed`` (:func:`discover`); the
    directions are the walk's over its joints (:func:`~.identify.ring_directions`).
    """
    if ring is not None:
        rod, seeds, known = ring_seeds(ring, state, elements_per_segment, load_factor,
                                       seed_states, cusp_width)
        return rod, seeds, known, tuple(d for _, d in ring.order)
    from .identify import ring_directions

    if a is None:
        raise RodstabInputError("search_start needs a ring or a design's assembly")
    rod = common_rod(a, elements_per_segment, load_factor)
    return rod, [("held", Snapshot.of(rod))], [], ring_directions(rod)


# ---------------------------------------------------------------------------------------------
# Rings of welded rods (the hexagram, the six-sided ring of Section 5, a design's ring)
def ring_seeds(ring: Ring, state: str, elements_per_segment: int, load_factor: float,
               seed_states: bool, cusp_width: float | None = None
               ) -> tuple[DiscreteRod, list[tuple[str, Snapshot]], list[KnownState]]:
    """Return the common rod (built from held state ``state``), the seeds and the known states.

    ``ring``: :func:`rodstab.multistable.states.ring_of` of a design, or
    :func:`rodstab.multistable.states.uniform_ring`. Seeds: the held geometry of ``state``, and with
    ``seed_states`` that of every other closed planar held state of uniform moment with ``|k L| <= 2
    pi`` (:meth:`Ring.states`: the basic states, their mirrors and the others), each put into the
    one common rod. Raises naming ``state`` if it is not a closed state of the ring.
    ``cusp_width``: cusp welds of that width (length, :func:`common_rod`); each held geometry
    is then relaxed by Newton (as built only its end nodes moved, which can put its rods
    into one another at fine meshes), so it is a seed a contact model can take.
    """
    theta = ring.state(state).theta
    listed = ring.states().states

    def build(th: float) -> DiscreteRod:
        r = common_rod(ring.held(th), elements_per_segment, load_factor, cusp_width=cusp_width)
        if cusp_width:
            from ..nonlinear.solve import newton

            newton(r)
        return r

    rod = build(theta)
    seeds = [(state, Snapshot.of(rod))]
    if seed_states:
        for st in listed:
            if st.label != state:
                seeds.append((st.label, Snapshot.of(build(st.theta))))
    known = [KnownState(st.label, st.turning_number, st.distinct_weld_points) for st in listed]
    return rod, seeds, known


def shape_2d(rod: DiscreteRod, s: Snapshot) -> list[np.ndarray]:
    """Centreline of every rod of state ``s`` projected on its best-fit plane, ``(n + 1, 2)``."""
    c, nrm = best_fit_plane(s.x, s.R_edge[:, :, 2])
    e1 = np.cross(nrm, [0.0, 0.0, 1.0])
    if np.linalg.norm(e1) < 0.5:
        e1 = np.array([1.0, 0.0, 0.0]) - nrm[0] * nrm
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(nrm, e1)
    return [np.stack([(s.x[ids] - c) @ e1, (s.x[ids] - c) @ e2], axis=1)
            for ids in (segment_nodes(rod, k) for k in range(len(rod.assembly.segments)))]
