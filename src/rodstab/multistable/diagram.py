"""Deflated continuation: the bifurcation diagram of a ring in its load factor.

Farrell, Beentjes and Birkisson's deflated continuation (SIAM J. Sci. Comput. 37, 2015; the
algorithm of their ``defcon`` and of BifurcationKit.jl's ``DefCont``) on one discrete rod
(:func:`~rodstab.multistable.discover.common_rod`), whose energy depends on the load factor
``mu`` only through the natural curvature ``mu kappa_n`` (``g`` affine in ``mu``):

1. At the first value the branches are the seeds (every closed held state of uniform moment of
   the ring, each an equilibrium at every ``mu``: its shape is fixed by closure, its moment
   ``B (k - mu kappa_n)`` uniform) and whatever :func:`~.discover.discover` finds besides them.
2. A branch is extended one grid step at a time, in both directions, by Newton from its last
   point moved by the tangent predictor, with every solution already known at the new value
   deflated (so two branches cannot land on one solution); a step that fails is retried
   through 1, 3, .. ``2^HALVINGS - 1`` stepping stones (solved, not recorded: points lie on
   the grid only, where every branch is deflated) before the branch is said to end there (a
   fold, or a branch the grid's natural parameter cannot follow).
3. Search (the deflation step): from the last point of a branch whose shape changed in the
   step, deflated Newton with everything known at the new value deflated (a new solution
   starts a new branch); where a branch's Hessian index changes between two points (an
   eigenvalue crossed zero: a branch point), deflated Newton from both bracket ends and from
   near the located crossing, perturbed both ways along the crossing (softest) modes; and
   likewise from a branch's last point where it ends.
4. Every new solution that is not a symmetric image (rigid motion, reflection, relabelling of
   the rods, :func:`~.identify.same_state`) of a point already known at its value starts a new
   branch, itself extended both ways; the run stops when no branch can be extended (or at
   :data:`MAX_BRANCHES`, said in the output).

Along every branch: energy (``B3/L``), Hessian index (negative eigenvalues of the scaled free
Hessian), planarity and the invariants of :func:`~.identify.invariants`. An index change is
located by the project's bracketed root finder (:func:`rodstab.numerics.refine_root`) on the
eigenvalue that crosses zero (Newton at every trial value, :func:`eigenvalue_at`); a
branch end is given as the bracket between its last point and the first value it could not
reach. The stability bands (index 0) of the held states are then intervals the linear
engine's :mod:`~.atlas` gives independently (:func:`~.diagram_check.held_band_ends`).
Where a stable branch loses stability, :func:`snaps` says what it snaps to; a landing that is
no branch yet becomes one.

What this finds is what the starts reach: a branch disconnected from every branch found, born
at a fold inside the range with no branch nearby, is found only if a deflation run reaches it.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable, Sequence

import numpy as np
import scipy.sparse.linalg as spla

from ..errors import RodstabInputError
from ..nonlinear.constraint import mean_length
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.parameters import LoadFactor, Parameter
from ..nonlinear.solve import lowest_eigenvalues, lowest_modes, zero_eigenvalue_tol
from ..numerics.roots import refine_root
from ..results import Result
from .discover import (
    DEFLATED_MAX_ITER,
    INDEX_EIGS,
    MAX_STEP_DISPLACEMENT,
    KnownState,
    _label,
    deflated_newton,
    discover,
    distance_sq,
    moved_along,
)
from .identify import SAME_STATE_DISTANCE, Snapshot, aligned_distance, invariants, same_state

#: A failed step is retried through 1, 3, .. 2^HALVINGS - 1 stepping stones before the branch
#: is said to end.
HALVINGS = 3
#: Largest node displacement of the starts that leave a branch along a crossing mode, over L.
SWITCH_AMPLITUDES = (0.01, 0.03, 0.1)
#: Crossing modes tried at a branch point or branch end (both signs each).
SWITCH_MODES = 2
#: Branches are sought at an index change only where the lower index is below this (new
#: branches there have index <= 2: the minima and the saddles that join them).
SWITCH_MAX_INDEX = 2
#: The switch runs at the bracket's ends and at the located crossing +- this fraction of the
#: bracket, from the bracket's end on that side: the straightened rod's buckled branch (8 el.,
#: grid 0.1 mu_c) is reached from 0.1 past the crossing, the hexagram's line-star saddle (8 el.,
#: grid 0.1) from the bracket's end 2.2 (+-0.03 L along the softest mode; not from 2.2412,
#: not with 0.003 or 0.01 L).
SWITCH_OFFSET = 0.1
#: Iterations of one deflated search run (a continuation step has DEFLATED_MAX_ITER). The
#: switch runs that converge took 4-11 (hexagram's line at 2.2, the straightened rod); most
#: that fail use them all, and they are most of a diagram's time.
SEARCH_MAX_ITER = 15
#: The run stops growing at this many branches.
MAX_BRANCHES = 60
#: Relative tolerance of a located index change, in the parameter.
LOCATE_RTOL = 1e-6


@dataclasses.dataclass(frozen=True)
class BranchPoint(Result):
    """One equilibrium on a branch.

    ``value``: the parameter; ``energy`` in ``B3/L``; ``index``: negative eigenvalues of the
    scaled free Hessian (``index_at_least`` when all :data:`INDEX_EIGS` computed are);
    ``lowest_eigenvalue``; invariants as in :class:`~.identify.Invariants`.
    """

    value: float
    energy: float
    index: int
    index_at_least: bool
    lowest_eigenvalue: float
    planar: bool
    max_out_of_plane: float
    turning_number: float
    distinct_weld_points: int


@dataclasses.dataclass(frozen=True)
class Branch(Result):
    """A branch: its points by increasing parameter, where it came from, how it ends.

    ``label``: the held state it is (by its invariants at its first point, as
    :func:`~.discover.discover` names states), else ``"unnamed"``; ``found_from``: the seed or
    search that found it; ``begins`` / ``ends``: ``"range"`` (it reaches the end of the
    range) or ``"ends between a and b"`` (no equilibrium reached past it: a fold, or a branch
    the natural parameter cannot follow; the bracket is where).
    """

    id: int
    label: str
    found_from: str
    points: tuple[BranchPoint, ...]
    begins: str
    ends: str


@dataclasses.dataclass(frozen=True)
class SpecialPoint(Result):
    """An index change on a branch (a branch point or a fold) or a branch end.

    ``kind``: ``"index change"`` (located: ``value`` with bracket ``between``) or
    ``"branch end"`` (``value`` the last point reached, ``between`` the bracket);
    ``index_before`` / ``index_after`` by increasing parameter; ``branches``: the branches
    found from it by the switch search (they meet the branch there).
    """

    kind: str
    branch: int
    value: float
    between: tuple[float, float]
    index_before: int
    index_after: int | None
    branches: tuple[int, ...]
    #: At a branch end: the branch whose point at ``value`` is nearest (RMS node distance
    #: over L modulo the ring's symmetry), that distance, and the energy above it (B3/L).
    nearest: int | None = None
    nearest_distance: float | None = None
    energy_above_nearest: float | None = None


@dataclasses.dataclass(frozen=True)
class Snap(Result):
    """Where a stable branch ends its band, and the state it snaps to.

    ``branch`` loses stability at ``value`` (its located index change); from its point at the
    grid value ``from_value`` just past it, pushed ``SNAP_PUSH`` L both ways along its most
    unstable mode and relaxed (:func:`rodstab.nonlinear.solve.relax`), it lands on
    ``lands_on`` (branch ids, one per push; None when the relaxed state is no branch's point
    there, or the relaxation did not converge), each ``energy_drop`` below the start (B3/L).
    """

    branch: int
    value: float
    from_value: float
    lands_on: tuple[int | None, ...]
    energy_drop: tuple[float | None, ...]


#: Push along the unstable mode before a snap is relaxed, largest node displacement over L.
SNAP_PUSH = 0.01


@dataclasses.dataclass(frozen=True)
class Diagram(Result):
    """Every branch found over the range, the special points, the stable bands.

    ``bands``: for each branch the intervals where its index is 0 (ends located as the special
    points are; a band reaching the end of the range ends there). ``stopping``: the rule the
    search stopped by.
    """

    key: str
    values: tuple[float, ...]
    branches: tuple[Branch, ...]
    special_points: tuple[SpecialPoint, ...]
    bands: dict[int, tuple[tuple[float, float], ...]]
    elements_per_segment: int
    n_dof: int
    runs: int
    stopping: str
    method: str
    #: The saddle searches run: value, climbs' outcomes, saddles (energy, the two branches
    #: their descents end on, the branch each was traced as or None when already known).
    saddle_searches: tuple[dict, ...] = ()
    #: Solutions of index above SWITCH_MAX_INDEX a search found: deflated, not followed.
    unfollowed: int = 0
    #: Where a stable branch loses stability, what it snaps to (:func:`snaps`).
    snaps: tuple[Snap, ...] = ()
    #: Seeds Newton reached at no value of the range (a seed reached only past the first
    #: value starts its branch there).
    unconverged_seeds: tuple[str, ...] = ()


@dataclasses.dataclass
class _Branch:
    label: str
    found_from: str
    points: dict[float, tuple[Snapshot, BranchPoint]]
    ends: dict[int, tuple[float, float] | None] = dataclasses.field(default_factory=dict)
    joins: dict[int, int] = dataclasses.field(default_factory=dict)


class _Run:
    """The state of one deflated continuation (the module docstring's steps)."""

    def __init__(self, rod: DiscreteRod, known: list[KnownState], values: np.ndarray,
                 directions: tuple[int, ...] | None,
                 progress: Callable[[], None] | None, param: Parameter) -> None:
        self.rod, self.known, self.values, self.directions = rod, known, values, directions
        self.param = param
        self.progress = progress
        self.h = float(values[1] - values[0]) if len(values) > 1 else 1.0
        self.tol = zero_eigenvalue_tol(rod)
        self.here: dict[float, list[Snapshot]] = {}
        self.branches: list[_Branch] = []
        self.specials: list[SpecialPoint] = []
        self.queue: list[tuple[int, int]] = []
        self.grid = {float(v) for v in values}
        self.runs = 0
        self.unfollowed = 0
        self.saddle_searches: list[dict] = []
        self.full = False

    # -- one point --------------------------------------------------------------------------
    def _point(self, p: float) -> tuple[BranchPoint, np.ndarray]:
        rod = self.rod
        ev, vecs = lowest_modes(rod, INDEX_EIGS)
        idx = int(np.sum(ev < -self.tol))
        inv = invariants(rod, None, self.directions)
        return BranchPoint(
            value=float(p), energy=float(rod.energy()), index=idx,
            index_at_least=idx == len(ev), lowest_eigenvalue=float(ev[0]),
            planar=inv.planar, max_out_of_plane=inv.max_out_of_plane,
            turning_number=inv.turning_number,
            distinct_weld_points=inv.distinct_weld_points), vecs if vecs.size else ev

    def _solve(self, start: Snapshot, p: float, max_iter: int | None) -> Snapshot | None:
        self.param.set(self.rod, float(p))
        start.put(self.rod)
        self.runs += 1
        r = deflated_newton(self.rod, self.here.get(p, []),
                            max_iter=DEFLATED_MAX_ITER if max_iter is None else max_iter)
        return Snapshot.of(self.rod) if r.converged else None

    def _slope(self, s: Snapshot, p: float) -> np.ndarray | None:
        """``dq/dp = -H^-1 dg/dp`` at state ``s`` (free unknowns), None where ``H`` is singular.

        The predictor of a step (Newton from the previous point alone fails on branches
        whose shape moves fast: the hexagram's line-star saddle at 8 el. from kappa_n R0 = 1 to
        1.01, where the predicted start converges in 3 iterations up to 1.1).
        """
        rod = self.rod
        self.param.set(rod, float(p))
        s.put(rod)
        free = rod.free_dofs()
        terms = rod.energy_terms()
        gp = self.param.dgrad(rod, terms)[free]
        if not np.any(gp):
            return None
        Hf = terms[2][free][:, free].tocsc()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a singular H gives non-finite values, checked
            v = spla.spsolve(0.5 * (Hf + Hf.T), -gp)
        return v if np.all(np.isfinite(v)) else None

    def _image_of_known(self, s: Snapshot, p: float, but: int | None = None) -> int | None:
        """Return the branch (other than ``but``) whose point at ``p`` is ``s`` or its image."""
        self.param.set(self.rod, float(p))
        E = _energy(self.rod, s)
        for j, b in enumerate(self.branches):
            if j != but and p in b.points and same_state(self.rod, s, b.points[p][0], E,
                                                         b.points[p][1].energy):
                return j
        return None

    def add_branch(self, s: Snapshot, p: float, label: str | None, found_from: str,
                   seed: bool = False) -> int | None:
        """Start a branch at ``s`` (value ``p``), both directions queued; None if an image.

        ``seed``: a held state, never an image (two held states can be images of each other
        at one value only, where that value makes the energy symmetric: the daisy and its
        mirror at zero natural curvature).
        """
        if not seed and self._image_of_known(s, p) is not None:
            self.here.setdefault(p, []).append(s)  # deflated, not a branch of its own
            return None
        if len(self.branches) >= MAX_BRANCHES:
            self.full = True
            return None
        s.put(self.rod)
        self.param.set(self.rod, float(p))
        pt, _ = self._point(p)
        if label is None:
            inv = invariants(self.rod, s, self.directions)
            label = _label(inv, self.known)
        self.branches.append(_Branch(label, found_from, {float(p): (s, pt)}))
        self.here.setdefault(float(p), []).append(s)
        k = len(self.branches) - 1
        self.queue += [(k, +1), (k, -1)]
        if self.progress is not None:
            self.progress()
        return k

    # -- extending a branch -----------------------------------------------------------------
    def _grid_next(self, p: float, direction: int) -> float | None:
        """Return the next grid value after ``p`` (which may lie between grid values)."""
        v = self.values
        if direction > 0:
            nxt = v[v > p + 1e-12 * self.h]
            return float(nxt[0]) if nxt.size else None
        nxt = v[v < p - 1e-12 * self.h]
        return float(nxt[-1]) if nxt.size else None

    def _reach(self, s: Snapshot, p: float, target: float) -> Snapshot | None:
        """Solve at grid value ``target`` from state ``s`` at ``p``, deflated there.

        Predicted (:meth:`_slope`) and, failing that, unpredicted; then through
        ``2^k - 1`` evenly spaced stepping stones (``k = 1 ..`` :data:`HALVINGS`), solved
        without deflation and not recorded: only grid values hold points, where every branch
        is deflated (off the grid a branch could slide onto another unnoticed).
        """
        slope = self._slope(s, p)
        got = self._solve(_predicted(self.rod, s, slope, target - p), target, None)
        if got is None and slope is not None:  # near a branch point dq/dp is large
            got = self._solve(s, target, None)
        for depth in range(1, HALVINGS + 1):
            if got is not None:
                return got
            cur, cur_p = s, p
            for i in range(1, 2**depth):
                q = p + (target - p) * i / 2**depth
                start = _predicted(self.rod, cur, self._slope(cur, cur_p), q - cur_p)
                self.param.set(self.rod, q)  # after the slope, which is taken at cur_p
                start.put(self.rod)
                self.runs += 1
                if not deflated_newton(self.rod, [], max_iter=SEARCH_MAX_ITER).converged:
                    break
                cur, cur_p = Snapshot.of(self.rod), q
            else:
                got = self._solve(_predicted(self.rod, cur, self._slope(cur, cur_p),
                                             target - cur_p), target, None)
        return got

    def extend(self, k: int, direction: int) -> None:
        """Extend branch ``k`` from its last point in ``direction`` until it ends."""
        b = self.branches[k]
        while True:
            p = max(b.points) if direction > 0 else min(b.points)
            s, pt = b.points[p]
            target = self._grid_next(p, direction)
            if target is None:
                b.ends[direction] = None
                return
            got = self._reach(s, p, target)
            if got is None:
                b.ends[direction] = (p, target)
                self._end(k, p, target, pt)
                return
            q = target
            self.here.setdefault(q, []).append(got)
            new_pt, _ = self._point(q)
            b.points[q] = (got, new_pt)
            if self.progress is not None:
                self.progress()
            # deflation repels a known state, not its mirror image: a branch that reaches the
            # image of another's point is that branch's image from there on (the bi-rod's
            # buckled branch and its mirror, found from two places), or jumped onto it (a
            # state near the hexagram's eight onto the daisy's image, 15.8 lower, in a step of
            # 0.02 of a rod's length): it ends before that point, which is the other's
            j = self._image_of_known(got, q, but=k)
            if j is not None:
                del b.points[q]
                self.here[q] = [x for x in self.here[q] if x is not got]
                b.ends[direction] = (p, q)
                b.joins[direction] = j
                return
            if new_pt.index != pt.index:
                self._index_change(k, p, q)
            if q in self.grid and new_pt.index <= SWITCH_MAX_INDEX \
                    and distance_sq(self.rod, s)[0] > SAME_STATE_DISTANCE**2:
                # DefCon's search: from the last point, everything known at q deflated
                found = self._solve(s, q, SEARCH_MAX_ITER)
                if found is not None:
                    self._offer(found, q, q, f"deflation from branch {k + 1} at {q:.6g}")

    def _offer(self, s: Snapshot, p: float, grid: float, found_from: str) -> int | None:
        """Offer ``s`` (an equilibrium at ``p``) as a new branch, at grid value ``grid``.

        Branches begin on the grid, where every branch has a point and a symmetric image of
        one of them is recognised; off it, ``s`` is first carried to ``grid`` by Newton with
        everything known there deflated. A state of index above :data:`SWITCH_MAX_INDEX` is
        deflated but not followed.
        """
        if p != grid:
            got = self._solve(s, grid, None)
            if got is None:
                return None
            s = got
        s.put(self.rod)
        self.param.set(self.rod, float(grid))
        if int(np.sum(lowest_eigenvalues(self.rod, SWITCH_MAX_INDEX + 1) < -self.tol)) \
                > SWITCH_MAX_INDEX:
            self.here.setdefault(grid, []).append(s)
            self.unfollowed += 1
            return None
        return self.add_branch(s, grid, None, found_from)

    def _switch(self, k: int, base: float, p: float, modes: int, grid: float) -> list[int]:
        """Deflated runs at ``p`` from branch ``k``'s point at ``base`` along its soft modes.

        The ``modes`` eigenvectors (at most :data:`SWITCH_MODES`) whose eigenvalues are nearest
        zero at ``base``, both signs, each largest node displacement in
        :data:`SWITCH_AMPLITUDES`; every solution is offered as a new branch.
        """
        s = self.branches[k].points[base][0]
        self.param.set(self.rod, float(base))
        s.put(self.rod)
        ev, vecs = lowest_modes(self.rod, INDEX_EIGS)
        order = np.argsort(np.abs(ev))[:max(1, min(modes, SWITCH_MODES))]
        born = []
        for j in order:
            for amp in SWITCH_AMPLITUDES:
                for sign in (1.0, -1.0):
                    start = moved_along(self.rod, s, vecs[:, j], sign * amp)
                    got = self._solve(start, p, SEARCH_MAX_ITER)
                    if got is not None:
                        nb = self._offer(got, p, grid,
                                         f"branch {k + 1} at {p:.6g} along its mode "
                                         f"{int(j) + 1} ({sign * amp:+g} L)")
                        if nb is not None:
                            born.append(nb)
        return born

    def _index_change(self, k: int, p: float, q: float) -> None:
        b = self.branches[k]
        lo, hi = min(p, q), max(p, q)
        i_lo, i_hi = b.points[lo][1].index, b.points[hi][1].index
        at = self._locate(k, lo, hi, min(i_lo, i_hi))
        born: list[int] = []
        if min(i_lo, i_hi) < SWITCH_MAX_INDEX:
            m = abs(i_hi - i_lo)
            # both sides of the crossing (a branch leaves on one side only)
            off = SWITCH_OFFSET * (hi - lo)
            for base, where in ((lo, lo), (lo, max(lo, at - off)), (hi, min(hi, at + off)),
                                (hi, hi)):
                born += self._switch(k, base, where, m, base)
        self.specials.append(SpecialPoint("index change", k, at, (lo, hi), i_lo, i_hi,
                                          tuple(born)))

    def _end(self, k: int, p: float, q: float, pt: BranchPoint) -> None:
        born = self._switch(k, p, p, 1, p) if pt.index <= SWITCH_MAX_INDEX \
            else []
        lo, hi = min(p, q), max(p, q)
        s = self.branches[k].points[p][0]
        near = [(aligned_distance(self.rod, s, b.points[p][0]), j)
                for j, b in enumerate(self.branches) if j != k and p in b.points]
        dist, j = min(near, default=(None, None))
        gap = None if j is None else pt.energy - self.branches[j].points[p][1].energy
        self.specials.append(SpecialPoint("branch end", k, p, (lo, hi), pt.index, None,
                                          tuple(born), j, dist, gap))

    def _locate(self, k: int, lo: float, hi: float, idx: int) -> float:
        """Where eigenvalue ``idx`` (0-based) of branch ``k`` crosses zero in ``[lo, hi]``."""
        b = self.branches[k]

        def f(p: float) -> float:
            near = b.points[lo if abs(p - lo) <= abs(p - hi) else hi][0]
            return eigenvalue_at(self.rod, near, p, idx, self.param)

        try:
            return refine_root(f, lo, hi, rel_xtol=LOCATE_RTOL)
        except (RodstabInputError, _Unlocated):
            return 0.5 * (lo + hi)  # no clean sign change (a double crossing): the midpoint

    def saddles(self, p: float, modes: int, max_rise: float | None) -> None:
        """Climb to the index-1 saddles from every stable point at grid value ``p``; offer each."""
        from .saddle_search import search_saddles

        if p not in self.grid:
            raise RodstabInputError(f"saddles are sought on the grid; {p!r} is not a value of "
                                    "it")
        minima = [(f"branch {k + 1}", b.points[p][0]) for k, b in enumerate(self.branches)
                  if p in b.points and b.points[p][1].index == 0]
        if not minima:
            return
        self.param.set(self.rod, float(p))
        kept: list[Snapshot] = []
        result = search_saddles(self.rod, minima, modes, directions=self.directions,
                                max_rise=max_rise, keep=kept)
        traced = [self._offer(s, p, p, f"saddle search at {p:.6g}: {sd.found_from}, joins "
                                       f"{' and '.join(sd.joins)}")
                  for sd, s in zip(result.saddles, kept, strict=True)]
        self.saddle_searches.append({
            "value": p, "outcomes": result.outcomes(), "method": result.method,
            "saddles": [{"energy": sd.energy, "joins": list(sd.joins),
                         "barriers": list(sd.barriers),
                         "branch": None if k is None else k + 1}
                        for sd, k in zip(result.saddles, traced, strict=True)]})

    # -- the whole run ----------------------------------------------------------------------
    def run(self) -> None:
        """Extend every queued branch both ways until nothing is left to extend."""
        while self.queue:
            k, d = self.queue.pop(0)
            self.extend(k, d)


def eigenvalue_at(rod: DiscreteRod, s: Snapshot, p: float, idx: int,
                  param: Parameter | None = None) -> float:
    """Eigenvalue ``idx`` (0-based, ascending) of the equilibrium near ``s`` at value ``p``.

    Newton first, also on a held state: the common rod's rest lengths are the arc's length
    over the elements, not its chords, so its relaxed held state moves with the load factor by
    the mesh's error, and the eigenvalue of the state frozen at a grid value crosses zero
    elsewhere (the hexagram's star, upper end at 8 el.: 2.35766 frozen at 2.2 or 2.4, 2.35794
    relaxed at every trial value; at 16 el. 2.35822 against 2.35743, which converge to the
    Bloch method's 2.357247 with order 2). Raises :class:`_Unlocated` if Newton fails.
    ``param``: what ``p`` is (default the load factor).
    """
    (param or LoadFactor()).set(rod, float(p))
    s.put(rod)
    if not deflated_newton(rod, []).converged:
        raise _Unlocated
    return float(lowest_modes(rod, idx + 1)[0][idx])


class _Unlocated(Exception):
    """Newton did not converge at a trial value while locating an index change."""


def _energy(rod: DiscreteRod, s: Snapshot) -> float:
    s.put(rod)
    return float(rod.energy())


def _predicted(rod: DiscreteRod, s: Snapshot, slope: np.ndarray | None, dp: float
               ) -> Snapshot:
    """``s`` moved by ``dp`` along ``slope`` (free unknowns per unit parameter), or ``s``.

    The move is capped at :data:`~.discover.MAX_STEP_DISPLACEMENT` L of largest node
    displacement (a predictor is a start, not a solution).
    """
    if slope is None:
        return s
    v = slope * dp
    dq = np.zeros(rod.n_dof)
    dq[rod.free_dofs()] = v
    disp = float(np.max(np.linalg.norm(dq[: 3 * len(rod.x)].reshape(-1, 3), axis=1)))
    cap = MAX_STEP_DISPLACEMENT * mean_length(rod)
    return moved_along(rod, s, v, min(disp, cap) / mean_length(rod)) if disp > 0 else s


def deflated_diagram(rod: DiscreteRod, seeds: list[tuple[str, Snapshot]],
                     known: list[KnownState], values: Sequence[float], *,
                     starts: int = 8, seed: int = 0,
                     directions: tuple[int, ...] | None = None,
                     saddles_at: Sequence[float] = (), saddle_modes: int = 2,
                     max_rise: float | None = None,
                     progress: Callable[[], None] | None = None,
                     param: Parameter | None = None) -> Diagram:
    """Bifurcation diagram of ``rod`` in ``param`` (default its load factor) over ``values``.

    ``seeds``: the held states (label, state), each a branch; ``known``: the held states to
    name branches by; :func:`~.discover.discover` with ``starts`` perturbed starts (seeded
    by ``seed``) adds what it finds at ``values[0]``. The algorithm is the module docstring's.
    ``saddles_at``: grid values where, after the branches are traced, the index-1 saddles are
    sought by eigenvector following from every stable point there
    (:func:`~.saddle_search.search_saddles`, ``saddle_modes`` modes both ways, climbs stopped
    ``max_rise`` above their start) and each is traced as a branch too.
    ``param``: the continued value (``set(rod, p)``, ``dgrad(rod, terms)``, ``key``), e.g.
    :class:`~.morph.SegmentLength`; the seeds must be states at ``values[0]``.
    ``rod`` is left in an unspecified state of the model.
    """
    vals = np.asarray(sorted(float(v) for v in values))
    if len(vals) < 2 or not np.all(np.isfinite(vals)) or np.any(np.diff(vals) <= 0):
        raise RodstabInputError(f"a diagram needs at least two distinct finite values, got "
                                f"{[float(v) for v in values]!r}")
    param = param or LoadFactor()
    run = _Run(rod, known, vals, directions, progress, param)
    p0 = float(vals[0])
    param.set(rod, p0)
    pending = []
    for lab, s in seeds:
        s.put(rod)
        got = run._solve(s, p0, max_iter=None)
        if got is not None:
            run.add_branch(got, p0, lab, f"seed {lab}", seed=True)
        else:
            pending.append((lab, s))
    found, states = discover(rod, seeds, known, starts=starts, seed=seed, directions=directions)
    run.runs += found.runs
    for st, s in zip(found.states, states, strict=True):
        run.add_branch(s, p0, None, f"discover at {p0:.6g}: {st.found_from}")
    run.run()
    # A seed Newton cannot reach at the first value (a coarse mesh for its shape, or a state
    # deflation repels there) starts its branch at the first grid value it reaches, with every
    # branch point there deflated (so it is new) and images checked.
    unconverged = []
    for lab, s in pending:
        for p in vals[1:]:
            s.put(rod)
            got = run._solve(s, float(p), max_iter=None)
            if got is not None:
                if run.add_branch(got, float(p), lab, f"seed {lab}") is not None:
                    run.run()
                break
        else:
            unconverged.append(lab)
    for v in saddles_at:
        run.saddles(float(v), saddle_modes, max_rise)
        run.run()
    return dataclasses.replace(_result(run, rod, snaps(run)),
                               unconverged_seeds=tuple(unconverged))


def _bands(b: _Branch, specials: list[SpecialPoint], k: int) -> tuple[tuple[float, float], ...]:
    """Intervals of ``b`` where the index is 0, ends at its located index changes."""
    ps = sorted(b.points)
    where = {sp.between: sp.value for sp in specials if sp.branch == k
             and sp.kind == "index change"}
    out: list[tuple[float, float]] = []
    start = None
    for i, p in enumerate(ps):
        stable = b.points[p][1].index == 0
        if stable and start is None:
            start = ps[0] if i == 0 else where.get((ps[i - 1], p), 0.5 * (ps[i - 1] + p))
        if not stable and start is not None:
            out.append((start, where.get((ps[i - 1], p), 0.5 * (ps[i - 1] + p))))
            start = None
    if start is not None:
        out.append((start, ps[-1]))
    return tuple(out)


def snaps(run: _Run) -> tuple[Snap, ...]:
    """Every band end of a stable branch inside the range, and where it snaps to (:class:`Snap`).

    The landing is named by :func:`~.identify.same_state` against every branch's point at
    the same grid value. A landing the diagram does not hold there is an equilibrium it
    missed (the buckled branch of the bi-rod's pitchfork, which the switch runs at the index
    change do not reach at 8 el.): it becomes a branch, found from the snap, and is extended
    both ways; the snaps are then taken again (the new branch may end too), until no landing
    is new or the diagram is full (a landing then left unnamed, None).
    """
    while True:
        before = len(run.branches)
        out = _snaps_once(run)
        if len(run.branches) == before:
            return out
        run.run()


def _snaps_once(run: _Run) -> tuple[Snap, ...]:
    """One pass of :func:`snaps`: new landings added as branches (not yet extended)."""
    from ..nonlinear.solve import relax

    out = []
    rod = run.rod
    for sp in list(run.specials):
        if sp.kind != "index change" or 0 not in (sp.index_before, sp.index_after):
            continue
        past = sp.between[1] if sp.index_before == 0 else sp.between[0]
        b = run.branches[sp.branch]
        if past not in b.points:
            continue
        s = b.points[past][0]
        run.param.set(rod, float(past))
        s.put(rod)
        E0 = float(rod.energy())
        ev, vecs = lowest_modes(rod, 1)
        lands: list[int | None] = []
        drops: list[float | None] = []
        for sign in (1.0, -1.0):
            moved_along(rod, s, vecs[:, 0], sign * SNAP_PUSH)
            run.param.set(rod, float(past))
            if not relax(rod)[0]:
                lands.append(None)
                drops.append(None)
                continue
            here, E = Snapshot.of(rod), float(rod.energy())
            hit = [j for j, o in enumerate(run.branches) if past in o.points
                   and same_state(rod, here, o.points[past][0], E, o.points[past][1].energy)]
            if not hit:
                k = run.add_branch(here, float(past), None,
                                   f"snap from branch {sp.branch + 1} at {float(past):.6g}")
                hit = [] if k is None else [k]
            lands.append(hit[0] if hit else None)
            drops.append(E0 - E)
        out.append(Snap(sp.branch, sp.value, past, tuple(lands), tuple(drops)))
    return tuple(out)


def _result(run: _Run, rod: DiscreteRod, found_snaps: tuple[Snap, ...] = ()) -> Diagram:
    def end(b: _Branch, d: int) -> str:
        e = b.ends.get(d)
        if e is not None and d in b.joins:
            return (f"ends between {e[0]:.6g} and {e[1]:.6g}, where it reaches branch "
                    f"{b.joins[d] + 1} (modulo symmetry)")
        return "range" if e is None else f"ends between {e[0]:.6g} and {e[1]:.6g}"

    branches = [Branch(k, b.label, b.found_from, tuple(b.points[p][1] for p in sorted(b.points)),
                       end(b, -1), end(b, +1)) for k, b in enumerate(run.branches)]
    bands = {k: _bands(b, run.specials, k) for k, b in enumerate(run.branches)}
    stopping = ("every branch extended both ways until it ended or reached the range's ends; "
                "no search left to run" if not run.full else
                f"stopped growing at {MAX_BRANCHES} branches (MAX_BRANCHES): more may exist")
    return Diagram(
        key=run.param.key, values=tuple(float(v) for v in run.values),
        branches=tuple(branches), special_points=tuple(run.specials), bands=bands,
        elements_per_segment=len(rod.R_edge) // len(rod.assembly.segments),
        n_dof=len(rod.free_dofs()), runs=run.runs, stopping=stopping,
        method="deflated continuation (Farrell, Beentjes, Birkisson) on one discrete rod: "
               "natural-parameter steps with a tangent predictor, retried through up to "
               f"{2**HALVINGS - 1} stepping stones, deflated searches "
               f"from every moving branch and along the soft modes ({SWITCH_AMPLITUDES} L) "
               "at index changes and branch ends",
        saddle_searches=tuple(run.saddle_searches), unfollowed=run.unfollowed,
        snaps=found_snaps)
