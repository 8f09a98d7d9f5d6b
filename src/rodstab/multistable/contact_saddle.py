"""Saddles with contact, continued from a saddle without contact (issue 21).

A saddle of the rod energy alone can have rods passing through one another: the hexagram's
line <-> star saddle at kappa_n R0 = 1 has two pairs of elements of non-neighbouring rods
intersecting (docs/theory/contact.md). Under a contact model that state is outside the model,
and the string method with contact cannot start from a path through it. Here the saddle is
**continued into contact**, as a stationary point of index one of a family of energies:

1. every pair of elements that intersects (centrelines closer than :data:`CROSSING` ``L``) is
   pushed apart by :data:`PUSH` ``h`` to a chosen side (``sides``: +1 or -1 along
   ``t_a x t_b``, element ``b`` moving that way). A penalty has no direction at zero
   distance, so the side is the caller's choice, and each choice is its own branch;
2. the rod energy plus a **penalty**: the final model's capsules, reach and exclusions with
   the cubic penalty in place of the barrier (``soft``: C2, and finite for overlaps), whose
   stiffness rises from :data:`STIFFNESS_START` of the one holding the final model's line
   load at ``dhat / 2``, in steps of at most :data:`DECADE_STEP` decades, until every pair
   of non-excluded elements is more than ``h`` apart. At each step Newton's method on the
   gradient (:func:`~.saddle.refine_saddle`) runs from the last point and the index is
   counted;
3. **the index is kept at one.** Where the next eigenvalue crosses zero, the stationary
   point meets another branch. (On the hexagram this happened at 10^-1.05 of the soft
   stiffness with both pairs pushed the same way.) There the branch of index one is taken by
   Newton from kicks along the new negative mode (:data:`KICKS`, largest component, times
   ``L``). If no kick gives index one, or Newton fails, or a pair closer than ``h`` swapped
   sides (the penalty is finite for overlaps, so Newton could carry one rod through
   another), the step is halved, down to :data:`MIN_DECADE_STEP`;
4. then the **barrier** (the final model's form) at the stiffness that holds the penalty's
   largest node force, lowered (or raised) to the final model's in the same steps, each a
   Newton solve with the index kept at one. Switching straight to the final barrier, Newton
   pressed a crossing pair shut (the step filter cut every step to nothing) at 10 el./rod.

What comes out is an index-1 stationary point of rod plus contact energy, inside the model,
joined to the saddle without contact by a path of index-1 stationary points. It is a saddle
the rods can reach. Which minima it joins is for its steepest descents with contact
(:meth:`~.landscape.Landscape.judge`). It need not be the lowest saddle between any two states,
and different side choices can reach different saddles.

Measured (``python benchmarks/contact_saddle.py``; hexagram, rectangle h/t = 4,
kappa_n R0 = 1, h = 0.02 L, dhat = 0.1 h, both pairs to side +1): the saddle lies 0.058, 0.299
and 0.798 B3/L above the one without contact at 6, 8 and 10 el./rod, and it joins a
line-like and a triangle-like state, not the star. The states' energies with contact rise
with the mesh as well. Besides the two crossing pairs, the pairs next to every cusp weld
are pressed together (rods that leave a weld along one line are forced h apart within an
element). So the point cusp weld of capsule rods has no mesh limit; docs/theory/contact.md
has the table. In dhat (6 el.) the saddle converges at order 1.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable, Sequence
from typing import Literal, cast

import numpy as np

from ..errors import RodstabInputError
from ..nonlinear.constraint import restore_positions
from ..nonlinear.contact import (
    ContactModel,
    Interpenetration,
    mesh_of_rod,
    smallest_gap,
    stiffness_for_line_load,
)
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.stability import lowest_modes, zero_eigenvalue_tol
from ..results import Result
from .ring_modes import contact_forces
from .saddle import refine_saddle
from .string_contact import state_distance
from .transitions import judged_pairs, pair_distances

#: Element pairs whose centrelines are closer than this times the mean rod length intersect.
#: A Newton-converged saddle puts a crossing at its position error, not at round-off: the
#: hexagram's line -> star saddle (6 el., same energy to 1e-12) had its two crossing pairs
#: 1.7e-11 and 2.1e-11 L apart with OpenBLAS's SkylakeX kernels, 2.5e-9 and 3.1e-7 L with its
#: Haswell kernels; the next pair is 0.039 L apart.
CROSSING = 1e-5
#: How far each intersecting pair is pushed apart before the penalty acts, times ``h``.
PUSH = 0.02
#: The penalty's first stiffness, times the soft model's first stage's.
STIFFNESS_START = 1e-4
#: Largest step of the penalty's stiffness, in decades (measured: 0.25 jumped branches on the
#: hexagram where 0.05 did not; the step doubles back to this after every accepted one).
DECADE_STEP = 0.05
#: The step is not halved below this many decades.
MIN_DECADE_STEP = 0.05 / 64
#: The penalty's stiffness is not raised past this many decades above the start.
MAX_DECADES = 12.0
#: Kicks along the new negative mode at a branch point, times ``L`` (largest component).
KICKS = (1e-2, 3e-3, 1e-3)
#: Newton iterations per stage.
STAGE_NEWTON = 100
#: Most intersecting pairs (each adds a side choice: 2^k branches in :func:`stiffen_all`).
MAX_CROSSINGS = 4
#: Eigenpairs computed to count the index.
INDEX_EIGS = 4

Outcome = Literal["saddle", "not a saddle", "lost index one", "newton did not converge",
                  "passed rods through each other", "not apart", "outside the model"]


@dataclasses.dataclass(frozen=True)
class StiffenedSaddle(Result):
    """One continuation of a saddle without contact into contact (module docstring).

    ``outcome``: ``"saddle"`` when the final model's Newton converged on index exactly one;
    ``"not a saddle"`` (converged, other index); ``"lost index one"`` (no step keeps it);
    ``"newton did not converge"``; ``"passed rods through each other"`` (every small enough
    step of the penalty carried a close pair through another); ``"not apart"`` (the penalty reached
    :data:`MAX_DECADES` with pairs still within ``h``); ``"outside the model"`` (the state
    reached overlaps under the final model). ``pairs``: the intersecting element pairs pushed
    apart, ``sides`` their sides. ``stiffnesses``: the penalty's at every accepted stage
    (force / length^2), with the energy (``B3 / L``) and the smallest centreline distance of
    non-excluded elements over ``h`` there. ``branch_switches``: how often the index was kept
    by a kick. ``energy``, ``index``, ``gap``: the final state's (gap: the smallest capsule gap
    under the final model, length). ``eigenvalues``: the lowest scaled eigenvalues at the last
    point reached, on every outcome: where a continuation stops with the second of them near
    zero, the index-1 branch met a fold or a branch point there.
    """

    outcome: Outcome
    pairs: tuple[tuple[int, int], ...]
    sides: tuple[int, ...]
    stiffnesses: tuple[float, ...]
    energies: tuple[float, ...]
    distances: tuple[float, ...]
    branch_switches: int
    energy: float | None = None
    index: int | None = None
    gap: float | None = None
    eigenvalues: tuple[float, ...] = ()

    @property
    def found(self) -> bool:
        """Whether the continuation ended on an index-1 saddle with contact."""
        return self.outcome == "saddle"


def crossing_pairs(r: DiscreteRod) -> np.ndarray:
    """Element pairs of ``r`` (non-neighbouring, :func:`~.transitions.judged_pairs`) that intersect.

    ``(k, 2)`` ints: centrelines closer than :data:`CROSSING` times the mean rod length.
    """
    pairs = judged_pairs(r)
    dist = pair_distances(r.x, r.edge_nodes, pairs)[0]
    L = r.assembly.total_length / len(r.assembly.segments)
    return pairs[dist < CROSSING * L]


def _index(r: DiscreteRod) -> tuple[int, np.ndarray, np.ndarray]:
    vals, vecs = lowest_modes(r, INDEX_EIGS)
    return int(np.sum(vals < -zero_eigenvalue_tol(r))), vals, vecs


def _push(r: DiscreteRod, pairs: np.ndarray, sides: Sequence[int], h: float) -> None:
    """Move each pair's elements ``PUSH h`` apart, half each, along ``+-(t_a x t_b)`` (in place)."""
    dx = np.zeros_like(r.x)
    for (a, b), side in zip(pairs, sides, strict=True):
        ea, eb = r.edge_nodes[a], r.edge_nodes[b]
        n = np.cross(r.x[ea[1]] - r.x[ea[0]], r.x[eb[1]] - r.x[eb[0]])
        n /= np.linalg.norm(n)
        dx[eb] += 0.5 * PUSH * h * side * n
        dx[ea] -= 0.5 * PUSH * h * side * n
    r.x = r.x + dx
    r.align_frames()
    restore_positions(r)


def _kept_index_one(r: DiscreteRod, vecs: np.ndarray) -> DiscreteRod | None:
    """Newton from ``r`` kicked along its second negative mode; the first index-1 point."""
    L = r.assembly.total_length / len(r.assembly.segments)
    v = vecs[:, 1] / np.max(np.abs(vecs[:, 1]))
    for kick, sign in itertools.product(KICKS, (1.0, -1.0)):
        trial = r.copy()
        dq = np.zeros(trial.n_dof)
        dq[trial.free_dofs()] = sign * kick * L * v
        try:
            trial.apply(dq)
            if refine_saddle(trial, max_iter=STAGE_NEWTON).converged and _index(trial)[0] == 1:
                return trial
        except Interpenetration:  # this kick leaves the model
            continue
    return None


def stiffen_saddle(saddle: DiscreteRod, final: ContactModel, sides: Sequence[int]
                   ) -> tuple[StiffenedSaddle, DiscreteRod]:
    """Continue index-1 ``saddle`` (no contact) into the contact model ``final`` (module doc).

    Parameters
    ----------
    saddle : DiscreteRod
        A converged index-1 stationary point of the rod energy without contact (not changed).
    final : ContactModel
        The contact model the saddle is sought under (capsule diameter ``h``).
    sides : sequence of int
        +1 or -1 for each of :func:`crossing_pairs` ``(saddle)``, in order.

    Returns
    -------
    tuple
        The :class:`StiffenedSaddle` record and the state reached (with ``final`` attached
        when the penalty brought every pair apart; on ``"saddle"`` the saddle with contact).
    """
    if saddle.contact is not None:
        raise RodstabInputError("stiffen_saddle continues a saddle without contact; the state "
                                 "given already has a contact model")
    pairs = crossing_pairs(saddle)
    if len(pairs) > MAX_CROSSINGS:
        raise RodstabInputError(f"{len(pairs)} pairs of elements intersect at the saddle; at "
                                f"most {MAX_CROSSINGS} are continued (2^k side choices)")
    if len(sides) != len(pairs) or any(s not in (1, -1) for s in sides):
        raise RodstabInputError(f"sides must be +-1 for each of the {len(pairs)} intersecting "
                                f"pairs {pairs.tolist()}, got {list(sides)!r}")
    h = 2.0 * float(np.max(final.radius))
    load = final.stiffness / stiffness_for_line_load(1.0, final.dhat, 0.5)
    k_ref = 4.0 * load / (3.0 * final.dhat**2)  # the penalty holding ``load`` at dhat / 2
    r = saddle.copy()
    _push(r, pairs, sides, h)
    log: list[tuple[float, float, float]] = []
    switches = [0]

    def record(outcome: str, at: DiscreteRod, **final_state: float | int | None
               ) -> StiffenedSaddle:
        vals = tuple(float(v) for v in _index(at)[1])
        return StiffenedSaddle(cast(Outcome, outcome), tuple((int(a), int(b)) for a, b in pairs),
                               tuple(int(s) for s in sides), tuple(k for k, _, _ in log),
                               tuple(e for _, e, _ in log), tuple(d for _, _, d in log),
                               switches[0], eigenvalues=vals,
                               **final_state)  # type: ignore[arg-type]

    def penalty(t: float) -> ContactModel:
        return dataclasses.replace(final, stiffness=k_ref * STIFFNESS_START * 10.0**t, soft=True)

    def barrier(t: float) -> ContactModel:
        return dataclasses.replace(final, stiffness=final.stiffness * 10.0**t)

    def logged(m: ContactModel, x: DiscreteRod, how: str) -> None:
        log.append((m.stiffness, float(x.energy()), state_distance(x, final) / h))
        switches[0] += how == "switched"

    r, how = _follow(r, penalty, 0.0, MAX_DECADES, lambda x: state_distance(x, final) > h,
                     logged)
    if how != "done":
        return record(how, r), r
    try:
        probe = r.copy()
        probe.contact = mesh_of_rod(probe, final)
        held, final_force = (float(np.max(np.linalg.norm(contact_forces(x), axis=1)))
                             for x in (r, probe))
    except Interpenetration:
        return record("outside the model", r), r
    # start where the barrier holds the penalty's largest node force; nothing in reach: at once
    start = math.log10(held / final_force) if held > 0.0 and final_force > 0.0 else 0.0
    r, how = _follow(r, barrier, start, 0.0, None, logged)
    if how != "done":
        return record(how, r), r
    index = _index(r)[0]
    near = None if r.contact is None else smallest_gap(r.contact, r.x)
    return record("saddle" if index == 1 else "not a saddle", r, energy=float(r.energy()),
                  index=index, gap=None if near is None else float(near[0])), r


def _crossed(a: DiscreteRod, b: DiscreteRod, h: float) -> bool:
    """Whether a pair of elements closer than ``h`` in ``a`` or ``b`` swapped sides between them.

    The penalty is finite for overlaps, so Newton can carry a pair through another; the
    separation vector of a pair that close reverses then (a stage moves the rods far less
    than ``h``).
    """
    pairs = judged_pairs(a)
    da, wa = pair_distances(a.x, a.edge_nodes, pairs)
    db, wb = pair_distances(b.x, b.edge_nodes, pairs)
    close = np.minimum(da, db) < h
    return bool(np.any(np.einsum("ij,ij->i", wa[close], wb[close]) < 0.0))


def _follow(r: DiscreteRod, model_at: Callable[[float], ContactModel], t0: float, t1: float,
            stop: Callable[[DiscreteRod], bool] | None,
            logged: Callable[[ContactModel, DiscreteRod, str], None]
            ) -> tuple[DiscreteRod, str]:
    """Continue index-1 point ``r`` in the model parameter ``t`` from ``t0`` toward ``t1``.

    Steps of at most :data:`DECADE_STEP`, halved on failure down to :data:`MIN_DECADE_STEP`
    and doubled back after success; each a :func:`_stage`. Ends ``"done"`` at ``t1`` (``stop``
    None) or once ``stop`` holds after a stage; ``"not apart"`` at ``t1`` with ``stop`` not
    holding; else the failing stage's reason. Returns the last accepted point.
    """
    sign = 1.0 if t1 >= t0 else -1.0
    t, step = t0, 0.0
    while True:
        t_next = t + sign * min(step, abs(t1 - t))
        trial, how = _stage(r, model_at(t_next))
        if trial is None:
            if step == 0.0:
                return r, how
            step /= 2.0
            if step < MIN_DECADE_STEP:
                return r, how
            continue
        r, t = trial, t_next
        logged(model_at(t), r, how)
        if stop is not None and stop(r):
            return r, "done"
        if t == t1:
            return r, "done" if stop is None else "not apart"
        step = DECADE_STEP if step == 0.0 else min(2.0 * step, DECADE_STEP)


def _stage(r: DiscreteRod, model: ContactModel) -> tuple[DiscreteRod | None, str]:
    """Newton from ``r`` under ``model`` to a stationary point of index one (module doc, 3.).

    Returns the point (None if none) and how: ``"newton"``, ``"switched"`` (by a kick), or why
    not (``"lost index one"``, ``"newton did not converge"``, ``"passed rods through each
    other"``).
    """
    trial = r.copy()
    trial.contact = mesh_of_rod(trial, model)
    try:
        ok = refine_saddle(trial, max_iter=STAGE_NEWTON).converged
    except Interpenetration:
        ok = False
    if not ok:
        return None, "newton did not converge"
    index, _, vecs = _index(trial)
    how = "newton"
    if index == 2:
        kept = _kept_index_one(trial, vecs)
        trial, index, how = (trial, 2, how) if kept is None else (kept, 1, "switched")
    if index != 1:
        return None, "lost index one"
    if _crossed(r, trial, 2.0 * float(np.max(model.radius))):
        return None, "passed rods through each other"
    return trial, how


def stiffen_all(saddle: DiscreteRod, final: ContactModel
                ) -> list[tuple[StiffenedSaddle, DiscreteRod]]:
    """Run :func:`stiffen_saddle` for every choice of sides (``2^k``, ``k`` intersecting pairs).

    Equal saddles from different choices are the caller's to merge (e.g. by
    :func:`~.identify.same_state`). With no intersecting pair the one continuation is run.
    """
    k = len(crossing_pairs(saddle))
    return [stiffen_saddle(saddle, final, sides)
            for sides in itertools.product((1, -1), repeat=k)]
