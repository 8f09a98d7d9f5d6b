"""Energy barriers between two stable equilibria: the saddle by continuation, path by descent.

A stable state A at load factor ``mu0`` loses stability at ``mu_c``, the upper end of its stable
interval. When that bifurcation is subcritical the branch leaving it runs back towards ``mu0`` as
an unstable equilibrium of Hessian index one -- the saddle (transition state) between A and the
state the branch connects it to. So:

1. **Saddle.** :func:`~rodstab.nonlinear.continuation.arclength_from_bifurcation` traces the
   branch from A's first bifurcation above ``mu0``, with the load factor window ``(mu0, upper)``:
   the tracer lands exactly on ``mu0`` (plain Newton with the load held). The state there is
   refined by :func:`~rodstab.nonlinear.solve.newton` and its index counted (scaled Hessian
   eigenvalues below ``-zero_eigenvalue_tol``); it must be exactly one.
2. **Minimum energy path.** The two steepest-descent curves leaving the saddle along
   ``+-`` its unstable eigenvector (:func:`~rodstab.nonlinear.solve.lowest_modes`). Each is
   followed by :func:`descend`: Levenberg-Marquardt steps ``-(H + lam D)^-1 g``
   (``D = |diag H|``), accepted only when the energy falls by a quarter of the model's
   prediction -- a preconditioned gradient flow whose metric is the shifted Hessian (plain
   Jacobi-preconditioned steepest descent crawls: the stretch/shear penalty makes the scaled
   bending eigenvalues ~1e-8). Large steps are retracted onto the inextensible states
   (:func:`~rodstab.nonlinear.constraint.retract_step`): on the six-ring at 6 el./rod the two
   descents took 15 and 23 steps instead of 359 and 723 unretracted, to the same ends (the
   end's energy equal to 4e-17). The energy is recorded after every step, so the path's energies
   fall monotonically from the saddle on both sides. Each end is Newton-refined, checked to be
   a minimum, and named by :func:`~rodstab.multistable.discover.same_state` against A and the
   other named states (held states put in the same discrete model by
   :func:`~rodstab.multistable.discover.common_rod`).

``barrier_forward = E_saddle - E_A``, ``barrier_backward = E_saddle - E_B``.

A second, independent method is the string method (:func:`~.string_method.string_barrier`, module
:mod:`.string_method`): a path relaxed between the two minima, its saddle refined by Newton from a
local maximum of the path's energies, checked by the same descents (:func:`descents_from_saddle`).
It needs no bifurcation and no continuation, names both ends in one discrete model and is what
``rodstab barrier`` uses by default; on the folded/one-loop six-ring at 8 el./rod the two saddles'
energies agree to 3e-13 relative (asserted to 1e-8, ``tests/test_barrier.py``). Retired (in the
branch's history): an earlier string method whose initial path interpolated the unknowns
linearly (non-finite energies: the held states put the gauge joint in frames 120 degrees apart,
and the frames' loops round the ring differ by whole turns); minimum-mode following from the
folded six-ring, which wandered in its nearly double lowest eigenpair; and a nudged elastic
band from the belt path of :mod:`.string_method`, whose highest image stalled at ~40 B3/L (its
images carried the gauge joint's full turn, and its unretracted steps were accepted only below
~0.03 rad).

A held state curved in its own geometry (the hexagram's) is refused here: the continuation
discretises the held state (:func:`~rodstab.nonlinear.discrete.discretise`), whose model is not the
common one (:func:`same_model`); the string method puts every state in the common model.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_finite, require_int
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, require_nonlinear
from ..model import Assembly
from ..nonlinear.constraint import retract_step
from ..nonlinear.contact import Interpenetration
from ..nonlinear.discrete import PENALTY, DiscreteRod, discretise
from ..nonlinear.solve import NEWTON_RTOL, lm_step, lowest_modes, newton, zero_eigenvalue_tol
from ..results import Result
from .discover import Snapshot, common_rod, same_state

#: Arclength step of the saddle branch (length units) and most steps (as row T-six).
SADDLE_DS = 0.25
SADDLE_STEPS = 50
#: The saddle state must lie on ``mu0`` to this (the tracer lands exactly on the window edge).
LOAD_TOL = 1e-9
#: First step off the saddle along its unstable eigenvector (largest component, length units,
#: times the mean segment length); halved until the energy is below the saddle's.
KICK = 1e-3
#: Most accepted descent steps per side (each a :func:`rodstab.nonlinear.solve.lm_step`).
DESCENT_MAX_STEPS = 3000
#: Lowest eigenvalues computed to count the saddle's index.
INDEX_EIGS = 4
#: Round-off allowed in "the energy falls monotonically" (relative to max(|E|, B3 / L)).
MONOTONE_RTOL = 1e-12
#: Minimum the elements per segment (fewer do not resolve the saddle's shape).
MIN_ELEMENTS = 4


@dataclasses.dataclass(frozen=True)
class Descent(Result):
    """One steepest-descent curve from the saddle: energies after each step, its end.

    ``energies`` start at the kicked state (below the saddle) and end at the Newton-refined
    minimum; ``converged``: the gradient fell below Newton's tolerance and Newton converged;
    ``lowest_eigenvalue``: scaled, at the end (> 0 for a minimum).
    """

    energies: tuple[float, ...]
    steps: int
    converged: bool
    residual: float
    lowest_eigenvalue: float


def _residual_scale(rod: DiscreteRod) -> float:
    """Force scale of the stretch/shear penalty: Newton's residual is relative to it."""
    return float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))


def descend(rod: DiscreteRod, lam0: float, *, max_steps: int = DESCENT_MAX_STEPS,
            retract: bool = False, trace: list[DiscreteRod] | None = None) -> Descent:
    """Follow the energy downhill from ``rod`` (in place) to a minimum, recording the energy.

    Steps ``s = -(H + lam D)^-1 g`` on the free unknowns (``D = |diag H|``, ``lam`` starting at
    ``lam0``, on the scale of the scaled eigenvalues), accepted when the energy falls by at least
    a quarter of the quadratic model's prediction; ``lam`` grows by 4 on a rejection (or jumps
    past the lowest scaled eigenvalue when ``s`` is not a descent direction) and shrinks by 4
    after a step the model predicted well. Ends with :func:`newton` once the gradient is below
    its tolerance. ``retract``: large trial steps are retracted onto the inextensible states
    (:func:`~rodstab.nonlinear.constraint.retract_step`), which lets them be larger (module
    :mod:`.string_method`). ``trace``: a copy of the state after every accepted step is
    appended to it (the curve itself, e.g. to join a string to the minimum it reached).
    """
    free = rod.free_dofs()
    tol = NEWTON_RTOL * _residual_scale(rod)
    floor = zero_eigenvalue_tol(rod)
    lam = max(lam0, floor)
    E, g, H = rod.energy_terms()
    energies, steps = [E], 0
    while steps < max_steps and float(np.max(np.abs(g[free]))) > tol:
        Hf = H[free][:, free].tocsc()
        terms, lam = lm_step(rod, free, E, g[free], 0.5 * (Hf + Hf.T), lam, floor,
                             round_off=False, to_newton=False,
                             retract=retract_step if retract else None)
        if terms is None:
            break  # no step lowers the energy: a minimum to round-off, or a flat stall
        E, g, H = terms
        energies.append(E)
        steps += 1
        if trace is not None:
            trace.append(rod.copy())
    ok, _, res = newton(rod)
    energies.append(rod.energy())
    ev = float(lowest_modes(rod, 1)[0][0])
    return Descent(tuple(float(e) for e in energies), steps, bool(ok), float(res), ev)


@dataclasses.dataclass(frozen=True)
class Barrier(Result):
    """Energy barrier between stable state ``from_state`` (A) and ``to_state`` (B).

    Two methods fill it: the continuation (:func:`barrier_from_bifurcation`) and the string
    (:func:`~.string_method.string_barrier`), ``method`` says which.

    ``barrier_forward = E_saddle - E_A``, ``barrier_backward = E_saddle - E_B`` (energy units of
    the model: B3 / L with B3 = 1, L = 1); ``saddle_index``: negative scaled Hessian eigenvalues
    at the saddle (1 for a transition state); ``energies``: along the path from A through the
    saddle (``energies[saddle_position]``) to B -- the two steepest descents (continuation), or
    the string's images with its highest image replaced by the saddle refined from it (string,
    at ``path_arclength``: chart arclength normalised to 1; with contact the saddle's two
    descents, whose every step was filtered, so the path is joined inside the model);
    ``to_state``: a named state's label, or ``"unnamed"``; ``converged``: saddle
    Newton-converged (on ``load_factor``), index 1, both descents converged to minima: A and
    the other named state (``descent_ends``).
    ``residual``: the saddle's free-gradient max-norm (tolerance ``NEWTON_RTOL`` x the penalty
    scale). ``load_factor_critical``: the bifurcation the continuation's branch leaves (NaN for
    the string). ``images``, ``iterations``: the string's (0 for the continuation);
    ``string_run``: its :class:`~.string_method.StringRun` (``None`` for the continuation).
    ``other_saddles``: the string's index-1 saddles rejected because their descents do not join
    the two states, each ``{"energy", "descent_ends", "end_energies", "ends_converged"}`` (an
    intermediate state of a chain of transitions, or a saddle between two other states).
    ``chain``: the string's :class:`~.chain.Chain` when it was split at intermediate minima
    (``converged`` is then the chain's; ``energies`` along the links' paths in order, and
    ``saddle_position`` the highest link's saddle in it, or that link's highest point when its
    saddle was one another string had found).
    """

    barrier_forward: float
    barrier_backward: float
    saddle_index: int
    energies: tuple[float, ...]
    saddle_position: int
    from_state: str
    to_state: str
    energy_from: float
    energy_to: float
    energy_saddle: float
    lowest_eigenvalues_saddle: tuple[float, ...]
    load_factor: float
    load_factor_critical: float
    converged: bool
    residual: float
    descent_steps: tuple[int, int]
    elements_per_segment: int
    n_dof: int
    method: str
    descent_ends: tuple[str, ...] = ()
    images: int = 0
    iterations: int = 0
    path_arclength: tuple[float, ...] = ()
    string_run: Result | None = None
    other_saddles: tuple[dict[str, Any], ...] = ()
    chain: Result | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON form; ``from``/``to`` as well as ``from_state``/``to_state``."""
        d = super().to_dict()
        d["from"], d["to"] = self.from_state, self.to_state
        return d


def descents_from_saddle(saddle: DiscreteRod, vals: np.ndarray, vecs: np.ndarray, *,
                         retract: bool = False,
                         traces: tuple[list[DiscreteRod], list[DiscreteRod]] | None = None
                         ) -> tuple[list[Descent], list[DiscreteRod]]:
    """Follow the two steepest descents from ``saddle`` along ``+-`` its unstable eigenvector.

    Each starts from the saddle kicked by :data:`KICK` (largest component, times the mean
    segment length) along ``+-vecs[:, 0]``, halved until the energy is below the saddle's, and
    is followed by :func:`descend` (``lam0 = -1.1 vals[0]``, past the negative eigenvalue).

    Parameters
    ----------
    saddle : DiscreteRod
        The saddle (not changed).
    vals, vecs : numpy.ndarray
        Its lowest scaled eigenvalues and eigenvectors (free unknowns), as
        :func:`~rodstab.nonlinear.solve.lowest_modes` returns them; the first is the unstable one.
    retract : bool
        Passed to :func:`descend`.
    traces : tuple of two lists, optional
        Filled with each descent's states in order: the kicked start, every accepted step
        (:func:`descend`'s ``trace``) and the end. With contact every step between them is
        filtered (the kick, ``KICK`` of a segment, is far below ``h``), so neighbouring states
        are joined inside the model.

    Returns
    -------
    tuple
        The two :class:`Descent` records (``+`` side first) and the two end states.
    """
    e_s = saddle.energy()
    v = vecs[:, 0] / np.max(np.abs(vecs[:, 0]))
    kick = KICK * saddle.assembly.total_length / len(saddle.assembly.segments)
    descents: list[Descent] = []
    ends: list[DiscreteRod] = []
    for sign in (1.0, -1.0):
        r = saddle.copy()
        for _ in range(20):
            r = saddle.copy()
            dq = np.zeros(r.n_dof)
            dq[r.free_dofs()] = sign * kick * v
            r.apply(dq)
            try:
                if r.energy() < e_s:
                    break
            except Interpenetration:  # only with contact: this side leaves the model
                pass
            kick /= 2
        trace = None if traces is None else traces[len(ends)]
        if trace is not None:
            trace.append(r.copy())
        descents.append(descend(r, -1.1 * float(vals[0]), retract=retract, trace=trace))
        if trace is not None:
            trace.append(r.copy())
        ends.append(r)
    return descents, ends


def state_label(r: DiscreteRod, refs: list[tuple[str, Snapshot, float]],
                proper: bool = False) -> str:
    """Return the label of the first reference state that ``r`` is, or ``"unnamed"``.

    ``refs``: ``(label, snapshot, energy)`` triples; one state modulo rigid motion, reflection
    (unless ``proper``) and relabelling (:func:`~.discover.same_state`).
    """
    s, e = Snapshot.of(r), r.energy()
    return next((lab for lab, snap, e_ref in refs
                 if same_state(r, s, snap, e, e_ref, proper)), "unnamed")


#: Two discrete models are one when rest lengths and natural curvatures agree to this
#: (relative to the largest of them).
MODEL_RTOL = 1e-12


def same_model(r1: DiscreteRod, r2: DiscreteRod) -> bool:
    """Whether ``r1`` and ``r2`` have one energy function (rest lengths, natural curvatures).

    Parameters
    ----------
    r1, r2 : DiscreteRod
        Two discretisations of one assembly's topology at one load factor.

    Returns
    -------
    bool
        Rest lengths and the natural Cayley curvatures of every joint and half-joint agree to
        :data:`MODEL_RTOL`.
    """
    def natural(r: DiscreteRod) -> np.ndarray:
        pairs = r._k0(r.k_held_pairs, r.bend_pairs[:, 0], r.load_factor)
        ee = np.array([lk[0] for lk in r.end_links], int)
        links = (r._k0(r.k_held_links, ee, r.load_factor) if r.k0_links is None
                 else r.k0_links[0] + r.load_factor * r.k0_links[1])
        return np.concatenate([pairs.ravel(), links.ravel(), r.rest_length])

    k1, k2 = natural(r1), natural(r2)
    return bool(k1.shape == k2.shape and np.max(np.abs(k1 - k2))
                <= MODEL_RTOL * max(float(np.max(np.abs(k1))), 1.0))


def _held(a: Assembly, n: int, mu: float) -> tuple[DiscreteRod, float]:
    """Held state ``a`` in the common discrete model at ``mu``, Newton-relaxed; its energy."""
    rod = common_rod(a, n, mu)
    if not newton(rod)[0]:
        return rod, math.nan
    return rod, rod.energy()


def barrier_from_bifurcation(a: Assembly, load_factor: float, *, upper: float,
                             elements_per_segment: int = 8, name: str = "A",
                             named: Mapping[str, Assembly] | None = None,
                             n_steps: int = SADDLE_STEPS,
                             limits: Limits = DEFAULT_LIMITS) -> Barrier:
    """Energy barrier out of held state ``a`` at ``load_factor`` (module docstring).

    ``upper``: the bifurcation that ends ``a``'s stable interval is searched in
    ``(load_factor, upper]``. ``named``: other held states (same structure, rods in the same
    order) that the far end of the path may be; ``name``: ``a``'s label. Raises
    :class:`RodstabInputError` naming the value when ``a`` is not stable at ``load_factor``, no
    bifurcation lies below ``upper``, or its branch does not come back to ``load_factor``
    (a supercritical bifurcation: no saddle on this branch). A model past
    ``limits.max_dof_nonlinear`` unknowns is refused before it is built.
    """
    mu0 = require_finite("load_factor", load_factor)
    upper = require_finite("upper", upper)
    n = require_int("elements_per_segment", elements_per_segment, MIN_ELEMENTS)
    require_nonlinear([n] * len(a.segments), len(a.joints()), f"{n} elements per rod", limits)
    if not upper > mu0:
        raise RodstabInputError(f"upper must exceed load_factor {mu0!r}, got {upper!r}")
    from ..nonlinear.continuation import arclength_from_bifurcation

    rod_a = discretise(a, n, mu0)
    if not same_model(rod_a, common_rod(a, n, mu0)):
        raise RodstabInputError(
            f"state {name!r} is curved in its held geometry: the continuation's discrete model "
            "of it (rest lengths = the held arc's chords, natural curvature shifted by the held "
            "Cayley curvature) is not the common model in which the other states are named, "
            "so the barrier's two ends would be energies of different models; use the string "
            "method (rodstab barrier --method string), which puts every state in the common "
            "model")
    ok_a = newton(rod_a)[0]
    if not ok_a or lowest_modes(rod_a, 1)[0][0] < -zero_eigenvalue_tol(rod_a):
        raise RodstabInputError(f"load factor {mu0!r}: state {name!r} is not a stable "
                                "equilibrium there (outside its stable interval)")
    e_a = rod_a.energy()
    path = arclength_from_bifurcation(a, mu0, upper, elements_per_segment=n, ds=SADDLE_DS,
                                      n_steps=n_steps, mu_window=(mu0, upper),
                                      stop_at_special=True, stop_kinds=())
    mu_end, saddle = path.end_states[0]
    if abs(mu_end - mu0) > LOAD_TOL:
        raise RodstabInputError(
            f"load factor {mu0!r}: the branch from the bifurcation of {name!r} at "
            f"{path.value_critical:.6g} does not come back to it (it is supercritical, or "
            f"left the window at {mu_end:.6g}): no saddle on it")
    ok_s, _, res = newton(saddle)
    vals, vecs = lowest_modes(saddle, INDEX_EIGS)
    index = int(np.sum(vals < -zero_eigenvalue_tol(saddle)))
    e_s = saddle.energy()
    descents, ends = descents_from_saddle(saddle, vals, vecs, retract=True)
    # Name each end: A, one of the named states, or unnamed.
    refs = [(name, Snapshot.of(rod_a), e_a)]
    for label, asm in (named or {}).items():
        rod_n, e_n = _held(asm, n, mu0)
        if math.isfinite(e_n):
            refs.append((label, Snapshot.of(rod_n), e_n))
    labels = [state_label(r, refs) for r in ends]
    i_a = labels.index(name) if name in labels else 0
    da, db = descents[i_a], descents[1 - i_a]
    e_b = db.energies[-1]
    energies = list(da.energies[::-1]) + [e_s] + list(db.energies)
    tol_min = zero_eigenvalue_tol(saddle)
    converged = bool(ok_s and index == 1 and name in labels and da.converged and db.converged
                     and min(da.lowest_eigenvalue, db.lowest_eigenvalue) > -tol_min)
    return Barrier(
        barrier_forward=float(e_s - e_a), barrier_backward=float(e_s - e_b),
        saddle_index=index, energies=tuple(float(e) for e in energies),
        saddle_position=len(da.energies), from_state=name, to_state=labels[1 - i_a],
        energy_from=float(e_a), energy_to=float(e_b), energy_saddle=float(e_s),
        lowest_eigenvalues_saddle=tuple(float(x) for x in vals), load_factor=mu0,
        load_factor_critical=float(path.value_critical), converged=converged,
        residual=float(res), descent_steps=(da.steps, db.steps), elements_per_segment=n,
        n_dof=len(saddle.free_dofs()), descent_ends=tuple(labels),
        method="saddle = the subcritical branch from A's bifurcation (pseudo-arclength), "
               "refined by Newton; path = steepest descent from it (Levenberg-Marquardt steps "
               "in the shifted-Hessian metric, energy decreasing), both ends named by "
               "same_state")


def monotone_from_saddle(b: Barrier) -> bool:
    """Whether ``b``'s energies fall monotonically from the saddle towards both ends."""
    e = np.asarray(b.energies)
    slack = MONOTONE_RTOL * max(float(np.max(np.abs(e))), 1.0)
    k = b.saddle_position
    return bool(np.all(np.diff(e[: k + 1]) >= -slack) and np.all(np.diff(e[k:]) <= slack))


def path_contact(a: Assembly, elements_per_segment: int, xs: np.ndarray, thickness: float,
                 rod: DiscreteRod | None = None, model: Any = None
                 ) -> tuple[Any, np.ndarray, np.ndarray]:
    """Contact along a path of ``a``'s states: the transitions' judgement, and the topology.

    ``xs`` (n_states, n_nodes, 3): node positions of the path's states in order, on the
    discrete rod of ``a`` at ``elements_per_segment`` (:func:`~.string_method.string_barrier`'s
    snapshots); ``thickness``: ``h / L`` (``L`` the rod length). Judged as a stretch of a
    transition (:class:`~.transitions.ContactTracker`: pairs stacked in the first state may
    touch but not swap layers; any other pair must not pass through another). Returns the
    :class:`~.transitions.ContactReport` (distances over ``h``), the elements' node index
    pairs and their rest lengths. ``rod``: the discrete model of the path when it is not
    ``a``'s plain one (a stacked model, :func:`~.layered.stacked_model`). ``model``: judge
    every pair this contact model sees (:func:`~.transitions.judged_pairs`; for cusp welds of
    width, whose two ends the default leaves out).
    """
    from .transitions import ContactTracker, judged_pairs

    n = require_int("elements_per_segment", elements_per_segment, 1)
    rod = discretise(a, n) if rod is None else rod
    h = require_finite("thickness", thickness) * a.total_length / len(a.segments)
    tracker = ContactTracker(rod, h, xs[0], None if model is None else judged_pairs(rod, model))
    report = tracker.stretch("path", [(float(i), x) for i, x in enumerate(xs)])
    return report, rod.edge_nodes.copy(), rod.rest_length.copy()
