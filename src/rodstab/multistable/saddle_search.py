"""Saddles found from one minimum: eigenvector following (issue 22, section 1; issue 21).

The string method (:mod:`.string_method`) needs both ends of a transition and a path between
them. Eigenvector following needs only the state it leaves: from a minimum it climbs along one
of its soft modes, minimising in every other direction, until the followed curvature turns
negative, then converges on the index-1 saddle (Cerjan and Miller, J. Chem. Phys. 75, 2800,
1981; the partitioned rational-function step of Baker, J. Comput. Chem. 7, 385, 1986; Wales,
*Energy Landscapes*, 2003, Sec. 6.2). The two steepest descents from the saddle then say which
minima it joins (:meth:`.landscape.Landscape.judge`).

One step, in the Jacobi-scaled unknowns ``y`` (``q = D y``, ``A = D H D``, the scaling of every
eigenvalue rodstab reports), with ``u`` the followed unit eigenvector of ``A`` (eigenvalue
``b``; tracked from step to step by the largest overlap with the previous one, and its sign
kept) and ``g`` the scaled gradient:

- along ``u``: while ``b`` is positive (the climb out of the basin) a push of the trust radius
  uphill; once negative, the P-RFO step ``g_u / (lambda_p - b)``,
  ``lambda_p = b/2 + sqrt(b^2/4 + g_u^2)``, which moves up to the maximum along ``u``;
- across ``u``: the Newton step ``-(A + mu I)^-1 g_perp`` projected off ``u``, where ``mu``
  lifts any other eigenvalue below the zero band and adds :data:`COMPLEMENT_SHIFT` ``|b|``.
  Without that share of ``|b|`` the near-zero modes of a ring (rods rolling on one another)
  take the whole trust radius and the climb stalls (hexagram star, 8 el.: 1500 steps at
  ~11.4 B3/L); with the full ``|b|`` it rarely reaches the saddle; 0.1 found it from both the
  line and the star;
- each part is capped to the trust radius (largest node displacement over ``L``, or frame
  rotation, :func:`~rodstab.nonlinear.constraint.chart_size`); with contact the step is filtered
  (:func:`~rodstab.nonlinear.newton.contact_fraction`) and retracted as the saddle refinement's
  (:func:`~.saddle.refine_saddle`). A step whose energy change is not within a factor 4 of the
  quadratic model's is halved.

Once the followed curvature is negative, every other one is not, and the step has fallen below
:data:`CLOSE`, Newton's method (:func:`~.saddle.refine_saddle`) converges on the saddle and its
index is counted. A climb can fail: the followed mode may lead into ever stiffer bending
without an inflection (energy far above any saddle), fall into another basin, or run out of
steps; the result says which. Measured (hexagram, rectangle h/t = 4, 8 el./rod, 4 modes x 2
signs from each stable state): at kappa_n R0 = 1 the line -> star saddle (14.2795117 B3/L, the
string method's) from the line's third mode in 103 steps and from the star's in 341; at 1.5
the star -> daisy saddle (7.9138426, barrier 4.69217, the string method's) from six of the
sixteen climbs. The other climbs fail: a failed climb is not evidence that no saddle exists.
"""

from __future__ import annotations

import dataclasses
from concurrent.futures import Executor
from typing import Any, Literal

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import RodstabInputError
from ..nonlinear.constraint import chart_size, mean_length
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.newton import contact_fraction
from ..nonlinear.stability import lowest_modes, scaled_free_hessian, zero_eigenvalue_tol
from ..numerics.eigen import lowest_eigenpairs
from ..results import Result
from .barrier import state_label
from .identify import (
    PLANAR_TOL,
    Invariants,
    Snapshot,
    best_fit_plane,
    invariants,
    same_state,
)
from .landscape import Landscape
from .pair_strings import PairString, pair_strings
from .saddle import _inside, refine_saddle

#: Largest step (trust radius): node displacement over L, or frame rotation (rad).
CLIMB_STEP = 0.02
#: Most steps of one climb (the saddles above took 96-341).
CLIMB_MAX_ITER = 400
#: Eigenpairs computed per step: the followed one is tracked among them.
CLIMB_EIGS = 6
#: Share of the followed eigenvalue's magnitude added to the complement's shift (module doc).
COMPLEMENT_SHIFT = 0.1
#: The trust radius is not halved below this (the model is then wrong at every length).
TRUST_MIN = 1e-5
#: Past the inflection, a step shorter than this hands over to Newton's method.
CLOSE = 1e-3

Outcome = Literal["saddle", "not a saddle", "fell into another basin", "no step fits the model",
                  "rose past the ceiling",
                  "out of steps", "newton did not converge"]


@dataclasses.dataclass(frozen=True)
class Climb(Result):
    """One eigenvector-following climb from a minimum.

    ``outcome``: ``"saddle"`` when Newton converged on a stationary point of index exactly 1
    (``index`` counted from the :data:`CLIMB_EIGS` lowest scaled eigenvalues); otherwise why
    not. ``energy``: where it ended (units of ``B3 / L``); ``steps``: climbing steps taken;
    ``start``: the label of the minimum it left (set by :func:`search_saddles`).
    """

    mode: int
    sign: int
    outcome: Outcome
    steps: int
    energy: float
    index: int | None
    residual: float | None
    start: str = ""

    @property
    def found(self) -> bool:
        """Whether the climb ended on an index-1 saddle."""
        return self.outcome == "saddle"


def _on_free(r: DiscreteRod, free: np.ndarray, v: np.ndarray) -> np.ndarray:
    dq = np.zeros(r.n_dof)
    dq[free] = v
    return dq


def _capped(r: DiscreteRod, free: np.ndarray, d: np.ndarray, y: np.ndarray, cap: float,
            exactly: bool = False) -> np.ndarray:
    """``y`` scaled so that its step ``D y`` moves nothing by more than (``exactly``) ``cap``."""
    size = chart_size(r, _on_free(r, free, d * y))
    return y * ((cap if exactly else min(cap, size)) / max(size, 1e-300))


#: A planar state's mode is out of its plane when its in-plane part (node displacements in the
#: plane, rotations about the normal) is below this share of it (:func:`mirror_climbs`).
MIRROR_RTOL = 1e-6


def mirror_climbs(rod: DiscreteRod, modes: int) -> tuple[bool, ...]:
    """Return, per softest mode of minimum ``rod``, whether it reverses under the mirror.

    A planar state is its own mirror image in its plane, and its modes split into in-plane ones
    (the reflection keeps them) and out-of-plane ones (it reverses them: node displacements along
    the normal, rotations about in-plane axes). Climbing an out-of-plane mode the other way is
    the mirror image of climbing it this way, and reaches the mirror image of the same saddle,
    which :func:`~.identify.same_state` counts as the same (hexagram star, kappa_n R0 = 1, 8
    el.: modes 1, 3, 5 out of plane, each climbed both ways to the same energy, test). Modes
    whose in-plane part exceeds :data:`MIRROR_RTOL` (a degenerate pair mixed by the eigensolver)
    are climbed both ways. All False for a non-planar state; ``modes`` entries.
    """
    s = Snapshot.of(rod)
    c, n = best_fit_plane(s.x, s.R_edge[:, :, 2])
    if modes == 0 or float(np.max(np.abs((s.x - c) @ n))) >= PLANAR_TOL * mean_length(rod):
        return (False,) * modes
    free, d, A = scaled_free_hessian(rod)
    vecs = lowest_eigenpairs(A, modes)[1]
    nx = len(rod.x)
    frames = np.concatenate([rod.R_edge, rod.R_joint])
    out = []
    for k in range(vecs.shape[1]):
        dq = _on_free(rod, free, d * vecs[:, k])
        dx = dq[: 3 * nx].reshape(-1, 3)
        phi = np.einsum("fij,fj->fi", frames, dq[3 * nx:].reshape(-1, 3))  # world rotations
        kept = np.concatenate([(dx - np.outer(dx @ n, n)).ravel(), phi @ n])
        out.append(bool(np.linalg.norm(kept) <= MIRROR_RTOL * np.linalg.norm(dq)))
    return tuple(out)


def follow_mode(rod: DiscreteRod, mode: int, sign: int = 1, *, step: float = CLIMB_STEP,
                max_iter: int = CLIMB_MAX_ITER, max_rise: float | None = None) -> Climb:
    """Climb from minimum ``rod`` (in place) along its ``mode``-th softest mode to a saddle.

    Parameters
    ----------
    rod : DiscreteRod
        A converged minimum (with contact, inside the model); left where the climb ended.
    mode : int
        Which of the lowest scaled eigenvectors to follow (0: the softest), < :data:`CLIMB_EIGS`.
    sign : int
        +1 or -1: which way along it.
    step : float
        Trust radius (module docstring).
    max_iter : int
        Most climbing steps.
    max_rise : float, optional
        Stop once the energy is this far above the start's (units of ``B3 / L``): saddles
        higher than that are not sought ("rose past the ceiling"). Most failed climbs rise far
        above every saddle (to 20-80 B3/L from the hexagram's line, whose saddle is 1.1 above
        it) before they run out of steps.

    Returns
    -------
    Climb
        The outcome; on ``"saddle"`` ``rod`` is the Newton-converged saddle.
    """
    if not 0 <= mode < CLIMB_EIGS or sign not in (1, -1):
        raise RodstabInputError(f"mode must be in [0, {CLIMB_EIGS}) and sign +-1, got {mode}, "
                                f"{sign}")
    E, g, H = rod.energy_terms()
    e_start = E
    floor = zero_eigenvalue_tol(rod)
    w: np.ndarray | None = None
    tau = step

    def ended(outcome: Outcome, steps: int) -> Climb:
        return Climb(mode, sign, outcome, steps, float(rod.energy()), None, None)

    for it in range(max_iter):
        free, d, A = scaled_free_hessian(rod, H)
        vals, vecs = lowest_eigenpairs(A, CLIMB_EIGS)
        j = mode if w is None else int(np.argmax(np.abs(vecs.T @ w)))
        u = vecs[:, j] * (sign if w is None else np.sign(vecs[:, j] @ w) or 1.0)
        b = float(vals[j])
        others = float(np.min(np.delete(vals, j)))
        gy = d * g[free]
        gu = float(u @ gy)
        mu = (floor - others if others < floor else 0.0) + COMPLEMENT_SHIFT * abs(b)
        z = -spla.splu((A + mu * sp.identity(A.shape[0])).tocsc()).solve(gy - gu * u)
        z -= (u @ z) * u
        if b > floor:  # still in the basin: push uphill by the trust radius
            along = None
        else:
            lam_p = 0.5 * b + np.sqrt(0.25 * b * b + gu * gu)
            along = -gu / (b - lam_p) * u
        while True:
            up = _capped(rod, free, d, u, tau, exactly=True) if along is None else along
            dy = _capped(rod, free, d, up + _capped(rod, free, d, z, tau), tau)
            dq = _on_free(rod, free, d * dy)
            if rod.contact is not None:
                frac = contact_fraction(rod, free, dq[free])
                dq, dy = dq * frac, dy * frac
            pred = float(gy @ dy + 0.5 * dy @ (A @ dy))
            found = _inside(rod, dq)
            if found is not None:
                trial, (Et, gt, Ht) = found
                flat = abs(Et - E) <= 1e-10 * max(1.0, abs(E))
                rho = (Et - E) / pred if pred != 0.0 else 1.0
                if flat or 0.25 < rho < 4.0:
                    break
            tau /= 2
            if tau < TRUST_MIN:
                return ended("no step fits the model", it)
        rod.x, rod.R_edge, rod.R_joint = trial.x, trial.R_edge, trial.R_joint
        E, g, H = Et, gt, Ht
        if flat or 0.75 < rho < 1.33:
            tau = min(2 * tau, step)
        w = u
        if max_rise is not None and E > e_start + max_rise:
            return ended("rose past the ceiling", it + 1)
        if E < e_start - 1e-6 * max(1.0, abs(e_start)):
            return ended("fell into another basin", it + 1)
        if b < -floor and others > -floor and chart_size(rod, dq) < CLOSE:
            run = refine_saddle(rod)
            if not run.converged:
                return Climb(mode, sign, "newton did not converge", it + 1, float(rod.energy()),
                             None, float(run.residual))
            ev = lowest_modes(rod, CLIMB_EIGS)[0]
            index = int(np.sum(ev < -floor))
            return Climb(mode, sign, "saddle" if index == 1 else "not a saddle", it + 1,
                         float(rod.energy()), index, float(run.residual))
    return ended("out of steps", max_iter)



@dataclasses.dataclass(frozen=True)
class SaddleFound(Result):
    """One index-1 saddle met by the climbs, deduplicated, and the minima it joins.

    ``joins``: the labels of the minima its two steepest descents end on
    (:func:`~.barrier.descents_from_saddle`, named by :func:`~.identify.same_state`), a label
    ``"new k"`` for a minimum that was not among the given ones, ``"unresolved"`` for a descent
    that did not end on a minimum; ``barriers``: the saddle's energy above each (None when
    unresolved). ``found_from``: the first climb that reached it; ``times_found``: how many did.
    """

    energy: float
    joins: tuple[str, str]
    barriers: tuple[float | None, float | None]
    invariants: Invariants
    found_from: str
    times_found: int


@dataclasses.dataclass(frozen=True)
class SaddleSearch(Result):
    """Every climb from the given minima, the distinct saddles and any new minima reached.

    ``other_stationary``: the distinct stationary points of another index that climbs ended
    on (Newton converged, index not 1, not one of the given minima): ``(energy, index, planar,
    found_from, times_found)``.
    ``mirrored``: climbs not made because they are the mirror images of climbs made (a planar
    minimum's out-of-plane modes, :func:`mirror_climbs`). ``strings``: the pairs of minima
    the string method was run between (or skipped), in order
    (:func:`~.pair_strings.pair_strings`).
    """

    climbs: tuple[Climb, ...]
    saddles: tuple[SaddleFound, ...]
    new_minima: tuple[tuple[str, float], ...]
    modes: int
    method: str
    other_stationary: tuple[tuple[float, int, bool, str, int], ...] = ()
    mirrored: int = 0
    strings: tuple[PairString, ...] = ()

    def outcomes(self) -> dict[str, int]:
        """How many climbs ended each way."""
        out: dict[str, int] = {}
        for c in self.climbs:
            out[c.outcome] = out.get(c.outcome, 0) + 1
        return out


def search_saddles(rod: DiscreteRod, minima: list[tuple[str, Snapshot]], modes: int, *,
                   directions: tuple[int, ...] | None = None, step: float = CLIMB_STEP,
                   max_iter: int = CLIMB_MAX_ITER, max_rise: float | None = None,
                   keep: list[Snapshot] | None = None,
                   known: list[tuple[str, Snapshot]] | None = None,
                   strings: int = 0, pool: Executor | None = None) -> SaddleSearch:
    """Climb from every minimum along its ``modes`` softest modes, both ways, and judge the saddles.

    Parameters
    ----------
    rod : DiscreteRod
        The discrete model all states belong to (its state is changed; with contact, the
        climbs and descents are filtered).
    minima : list of (str, Snapshot)
        Labelled stable states to climb from (also the names the descents' ends are matched to).
    modes : int
        Modes per minimum, 1 .. :data:`CLIMB_EIGS` (each followed with both signs; 0: none, with
        ``strings``).
    directions : tuple of int, optional
        As in :func:`~.identify.invariants`.
    step, max_iter, max_rise : float, int, float or None
        Passed to :func:`follow_mode`.
    keep : list of Snapshot, optional
        The saddles' states are appended to it, in the order of ``saddles``.
    known : list of (str, Snapshot), optional
        Index-1 equilibria found another way (discover's deflation: the bi-rod's held state
        past its buckling load, the saddle between the buckled state and its mirror image,
        which no climb from the buckled state reached): judged like the climbs' saddles, found
        from ``"deflation: <label>"`` unless a climb reached them first.
    strings : int
        Then run the string method between at most this many pairs of the minima that the
        saddles found do not connect (:func:`~.pair_strings.pair_strings`); each saddle it
        finds is found from ``"string: <a> - <b>"``.
    pool : Executor, optional
        The climbs run in its processes (:func:`~rodstab.numerics.threads.process_pool`), and
        the strings' images are stepped there: the same results; None: in this process.

    Returns
    -------
    SaddleSearch
        Climbs in order; saddles by increasing energy, each with the minima it joins.
    """
    if not 0 <= modes <= CLIMB_EIGS or (modes == 0 and not strings):
        raise RodstabInputError(f"modes must lie in 1..{CLIMB_EIGS} (0 with strings), got "
                                f"{modes!r}")
    climbs: list[Climb] = []
    found: list[list[Any]] = []  # [snapshot, energy, found_from, count]
    other: list[list[Any]] = []  # [snapshot, energy, found_from, count, index, planar]
    named = [(lab, snap, _energy(rod, snap)) for lab, snap in minima]
    mirrored = 0
    tasks, meta = [], []
    for label, snap in minima:
        snap.put(rod)
        mirror = mirror_climbs(rod, modes)
        for mode in range(modes):
            for sign in (1, -1):
                if sign < 0 and mirror[mode]:
                    mirrored += 1
                    continue
                snap.put(rod)
                tasks.append((rod.copy(), mode, sign,
                              {"step": step, "max_iter": max_iter, "max_rise": max_rise}))
                meta.append((label, mode, sign))
    # Each climb is independent and deterministic: in a pool the same climbs, in parallel.
    ends = list(map(_climb_from, tasks) if pool is None else pool.map(_climb_from, tasks))
    for (label, mode, sign), (climb, end) in zip(meta, ends, strict=True):
        end.put(rod)
        climb = dataclasses.replace(climb, start=label)
        climbs.append(climb)
        if climb.outcome == "not a saddle" and state_label(rod, named) != "unnamed":
            continue  # Newton fell back to a given minimum
        if not (climb.found or climb.outcome == "not a saddle"):
            continue
        here = Snapshot.of(rod)
        into = found if climb.found else other
        for rec in into:
            if same_state(rod, here, rec[0], climb.energy, rec[1]):
                rec[3] += 1
                break
        else:
            into.append([here, climb.energy, f"{label} mode {mode}{'+' if sign > 0 else '-'}",
                         1, climb.index, invariants(rod, here, directions).planar])
    for label, snap in known or ():
        E = _energy(rod, snap)
        same = [r for r in found if same_state(rod, snap, r[0], E, r[1])]
        if same:
            same[0][3] += 1
        else:
            found.append([snap, E, f"deflation: {label}", 1, 1, None])
    land = Landscape.of([(lab, _at(rod, snap)) for lab, snap in minima])
    land.new_label = "new "
    pairs: list[PairString] = []
    if strings:
        for rec in found:
            rec[0].put(rod)
            land.judge(rod)
        pairs, joined = pair_strings(land, [lab for lab, _ in minima], strings, pool=pool)
        for r, pair in zip(joined, (p for p in pairs if p.outcome == "saddle"), strict=True):
            found.append([Snapshot.of(r), float(r.energy()), f"string: {pair.states[0]} - "
                          f"{pair.states[1]}", 1, 1, None])
    saddles = []
    for here, energy, src, count, _, _ in sorted(found, key=lambda rec: rec[1]):
        here.put(rod)
        judged = land.judge(rod)  # both descents, each end named (a new minimum: "new k")
        ups = [float(energy - e) if ok else None
               for e, ok in zip(judged["end_energies"], judged["ends_converged"], strict=True)]
        here.put(rod)
        saddles.append(SaddleFound(float(energy), judged["descent_ends"], (ups[0], ups[1]),
                                   invariants(rod, here, directions), src, count))
        if keep is not None:
            keep.append(here)
    given = {lab for lab, _ in minima}
    new = [(lab, float(e)) for lab, _, e in land.minima if lab not in given]
    return SaddleSearch(
        tuple(climbs), tuple(saddles), tuple(new), modes,
        ("; ".join(
            ([f"eigenvector following (P-RFO, trust radius {step:g}) along the {modes} softest "
              "modes of each minimum both ways (one way along a planar minimum's out-of-plane "
              "modes: the other is its mirror image), Newton on the saddle"] if modes else [])
            + ([f"the string method between up to {strings} pairs of minima no saddle found "
                "connects"] if strings else []))
         + "; each saddle's index counted, its two steepest descents named"),
        tuple((float(e), int(idx), bool(planar), src, int(n))
              for _, e, src, n, idx, planar in sorted(other, key=lambda rec: rec[1])),
        mirrored, tuple(pairs))


def _climb_from(task: tuple[DiscreteRod, int, int, dict[str, Any]]) -> tuple[Climb, Snapshot]:
    """:func:`follow_mode` from the task's rod (its own copy); the climb and where it ended."""
    rod, mode, sign, kw = task
    climb = follow_mode(rod, mode, sign, **kw)
    return climb, Snapshot.of(rod)


def _energy(rod: DiscreteRod, s: Snapshot) -> float:
    """Energy of state ``s`` in model ``rod`` (its state is changed)."""
    s.put(rod)
    return float(rod.energy())


def _at(rod: DiscreteRod, s: Snapshot) -> DiscreteRod:
    """Return a copy of model ``rod`` in state ``s`` (``rod``'s state is changed)."""
    s.put(rod)
    return rod.copy()
