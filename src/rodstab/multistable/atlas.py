"""Stability atlas of a ring's closed held states against a design parameter (issue 11).

For a ring of ``n`` identical welded rods (:func:`rodstab.multistable.states.ring_of`) and each
chosen closed held state of uniform moment (:meth:`rodstab.multistable.states.Ring.states`), the
stable interval of the load factor around the state's stress-free load, by two independent methods:

* ``transfer`` -- the exact solution of P2 on one rod with the weld's joint map and a Bloch
  phase per harmonic ``m = 0 .. n/2`` (:func:`rodstab.transfer.cyclic_ring_interval`; cusp
  or smooth welds only). It names the harmonic of the mode at each limit: ``m = 0`` every rod
  deforms alike, ``0 < m < n/2`` a symmetry-breaking pair (harmonics ``m`` and ``n - m``
  together: multiplicity 2), ``m = n/2`` neighbouring rods opposite (``rho = -1``).
* ``fe`` -- the linear FE engine on the whole ring (:meth:`Ring.held`), its mesh refined from
  :data:`FE_MESHES` until the Richardson estimate (order :data:`FE_ORDER`) of each end's
  error meets :data:`rodstab.linear.solve.FE_TARGET_RTOL`; multiplicities by the one
  multiplicity rule with those errors (:func:`rodstab.linear.solve.with_mesh_error`), no
  harmonic.

The **load factor** is the design's: the multiplier of its natural curvature (natural
curvature = load factor x the segments' ``natural_curvature``). A held state of turning
``theta`` per rod is stress-free at ``theta / (L kappa_n)``; there the second variation is the
strain energy of the perturbation, zero only on the ring's three rigid out-of-plane motions
(:data:`RING_RIGID_MOTIONS`), so every state is stable at its stress-free load and both
methods check it (rigid null space counted by the Bloch matrices; FE: the pencil is positive
definite there).

Across a parameter (:func:`ring_atlas`): for each value the maximal sets of mutually stable
states (intervals with a common point, :func:`mutual_sets`), and for each ``k`` the parameter
ranges in which some ``k`` states are mutually stable: the sign changes on the grid of the
best ``k``-overlap width (:func:`best_overlap`), each refined by the package's root finder
(:func:`rodstab.numerics.refine_root`) to :data:`RANGE_RTOL` times the grid spacing.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Sequence
from typing import Any

from ..errors import RodstabInputError
from ..executor import run_points
from ..io.design import Design
from ..io.vary import design_at
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..linear.solve import FE_ORDER, converged_stability
from ..numerics import refine_root
from ..results import Result
from ..transfer import CyclicRingInterval, cyclic_ring_interval
from .states import HeldState, Ring, ring_of, step_angle, weld_name

#: Mode types at a limit, by Bloch harmonic ``m`` of an ``n``-rod ring.
ALL_ALIKE = "all rods alike"
PAIR = "symmetry-breaking pair"
ALTERNATING = "alternating"
#: The two methods of :func:`state_interval`.
METHODS = ("transfer", "fe")
#: Starting meshes (elements per rod) of the FE method: quadratic beta and omega converge as
#: h^4 (:data:`rodstab.linear.solve.FE_ORDER`, measured on the hexagram, problems/hexagram.py);
#: :func:`fe_interval` refines from this pair until the Richardson estimate meets the FE's
#: target error.
FE_MESHES = (32, 64)
#: Null space of a planar ring's out-of-plane problem at a stable load: translation along e3
#: and rotations about the two in-plane axes.
RING_RIGID_MOTIONS = 3
#: Endpoints of the coexistence ranges are refined to this times the grid spacing.
RANGE_RTOL = 1e-10
#: What the load factor is, for tables, JSON and help texts.
LOAD_FACTOR_UNITS = ("the design's load factor: natural curvature = load factor x each "
                     "segment's natural_curvature")


def mode_type(harmonic: int, segments: int) -> str:
    """Name the Bloch harmonic ``m`` of an ``n``-rod ring's mode (module docstring).

    Returns :data:`ALL_ALIKE` (``m = 0``), :data:`ALTERNATING` (``m = n/2``) or :data:`PAIR`.
    Raises :class:`RodstabInputError` naming ``harmonic`` outside ``0 .. n/2``.
    """
    if not 0 <= harmonic <= segments // 2:
        raise RodstabInputError(f"harmonic must be in 0..{segments // 2}, got {harmonic!r}")
    if harmonic == 0:
        return ALL_ALIKE
    return ALTERNATING if 2 * harmonic == segments else PAIR


@dataclasses.dataclass(frozen=True)
class Limit(Result):
    """One end of a stable interval.

    Attributes
    ----------
    load_factor : float
        The load factor (:data:`LOAD_FACTOR_UNITS`) at which the state loses stability;
        ``-inf``/``+inf`` if the method found no limit on that side.
    multiplicity : int
        Dimension of the critical null space (0 when there is no limit).
    harmonic : int or None
        Bloch harmonic ``m`` (the pair ``m, n - m``) of the mode; ``None`` by FE.
    mode_type : str or None
        :func:`mode_type` of ``harmonic``; ``None`` by FE.
    """

    load_factor: float
    multiplicity: int
    harmonic: int | None
    mode_type: str | None


@dataclasses.dataclass(frozen=True)
class StateInterval(Result):
    """Stable interval of the load factor of one held state of a ring.

    ``theta``: each rod's turning (radians); ``stress_free_load``: the reference inside the
    interval; ``stable_at_stress_free``: the null space there is the rigid motions alone.
    """

    label: str
    theta: float
    stress_free_load: float
    lower: Limit
    upper: Limit
    stable_at_stress_free: bool
    residual: float
    converged: bool
    method: str
    #: Why the interval is not converged (empty when it is).
    reason: str = ""

    @property
    def interval(self) -> tuple[float, float]:
        """``(lower, upper)`` load factors."""
        return self.lower.load_factor, self.upper.load_factor


def stress_free_load(ring: Ring, theta: float) -> float:
    """Load factor at which the held state ``theta`` is stress-free; raise if there is none."""
    ref = ring.stress_free_load(theta)
    if ref is None:
        raise RodstabInputError("the ring's natural_curvature is 0: no held state is stress-free "
                                "and the load factor acts on nothing")
    return ref


def bloch_interval(ring: Ring, theta: float) -> CyclicRingInterval:
    """Stable interval of the load factor of the held state ``theta`` by the Bloch method.

    :func:`rodstab.transfer.cyclic_ring_interval` in the ring's units: arc ``L / R = theta``,
    load ``L kappa_n = L natural_curvature`` per unit load factor, ``b1 = B1 / B3``,
    ``b2 = B2 / B3`` (P2 depends on the stiffnesses only through these). Welds of any angle:
    the joint map turns the rotation and moment vectors and carries the end term of the exact
    second variation (:func:`rodstab.transfer.weld_joint_map`). Refuses, naming ``theta``, a
    turning at which the rods do not close into the ring (``n psi`` not a multiple of 2 pi),
    and a ring whose rods or welds differ
    (:meth:`~rodstab.multistable.states.Ring.require_identical`: the Bloch phase needs one rod
    repeated).
    """
    ring.require_identical("the Bloch method (--method transfer)")
    turns = ring.segments * step_angle(theta, ring.weld) / (2 * math.pi)
    if not math.isfinite(turns) or abs(turns - round(turns)) > 1e-9 * max(1.0, abs(turns)):
        raise RodstabInputError(f"theta = {theta!r} is no held state of this ring: "
                                f"{ring.segments} rods turning by it and "
                                f"{weld_name(ring.weld)} welds do not close")
    return cyclic_ring_interval(theta, ring.length * ring.natural_curvature, ring.B1 / ring.B3,
                                ring.B2 / ring.B3, ring.segments, ring.weld,
                                stress_free_load(ring, theta))


def covered_circle_interval(ring: Ring, theta: float) -> tuple[float, float] | None:
    """Stable interval of the load factor of held state ``theta`` as an N-covered circle, or None.

    A measured equivalence (docs/theory/covered-circles.md), not a derived one: a ring of
    identical arcs (turning ``theta`` each) held with uniform moment has, by the Bloch method,
    the stable interval of the ``N``-loop ring of eq. (3.3), ``N = n theta / (2 pi)``, with
    ``M = 1 - R kappa_n``, ``R = L / theta`` (:func:`rodstab.analytic.ring.ring_stability`),
    for cusp welds with ``N >= 2``, smooth welds, and welds at any angle when ``B1 = B2``
    (to 1e-12; hexagram star, daisy, eight = 2-, 4-, 6-loop rings; random cusp rings of the
    differential test). The natural argument (rotate each rod's perturbation by the welds'
    frame turns) fails: a cusp keeps the out-of-plane displacement and reverses its slope and
    the twist, and no map makes both continuous. Returns None elsewhere: another weld angle
    with ``B1 != B2`` (3 arcs of 240 degrees with 120-degree welds, ``b1 = 2``, ``b2 = 1.5``:
    lower end 0.15473 against (3.3)'s 0.15139 in ``R kappa_n``); cusp welds at ``N = 1``
    (the Bloch method and the FE engine give the lower end ``R kappa_n = 1 - b2``, (3.3)
    ``1 - b1``; found by the differential test); ``N`` not a whole number of at least 1; a
    ring whose rods or welds differ (not measured here). Load factor as in
    :func:`bloch_interval`.
    """
    from ..analytic.ring import ring_stability

    if not ring.identical:
        return None
    turns = ring.segments * theta / (2 * math.pi)
    n_loops = round(turns)
    angle_ok = ring.weld in ("cusp", "smooth") or ring.B1 == ring.B2
    if not angle_ok or n_loops < 1 or abs(turns - n_loops) > 1e-9 * turns:
        return None
    if ring.weld == "cusp" and n_loops == 1 and ring.B1 != ring.B2:
        return None
    m_lo, m_hi = ring_stability(ring.B1 / ring.B3, ring.B2 / ring.B3, n_loops).M_interval
    per_rkn = theta / (ring.natural_curvature * ring.length)  # load factor per unit R kappa_n
    return (1.0 - m_hi) * per_rkn, (1.0 - m_lo) * per_rkn


def _limit(x: float, multiplicity: int, harmonic: int | None, segments: int) -> Limit:
    if not math.isfinite(x):
        return Limit(float(x), 0, None, None)
    kind = None if harmonic is None else mode_type(harmonic, segments)
    return Limit(float(x), int(multiplicity), harmonic, kind)


def transfer_interval(ring: Ring, state: HeldState) -> StateInterval:
    """:class:`StateInterval` of ``state`` by :func:`bloch_interval`, harmonics named."""
    r = bloch_interval(ring, state.theta)
    n = ring.segments
    return StateInterval(
        label=state.label, theta=state.theta, stress_free_load=stress_free_load(ring, state.theta),
        lower=_limit(r.lo, r.multiplicity_lo, r.harmonic_lo, n),
        upper=_limit(r.hi, r.multiplicity_hi, r.harmonic_hi, n),
        stable_at_stress_free=sum(r.rigid_nullity) == RING_RIGID_MOTIONS,
        residual=r.residual, converged=r.converged, method=r.method, reason=r.reason)


def fe_interval(ring: Ring, state: HeldState, limits: Limits = DEFAULT_LIMITS) -> StateInterval:
    """:class:`StateInterval` of ``state`` by the FE engine, on a mesh refined to its accuracy.

    :func:`rodstab.linear.solve.converged_stability` from :data:`FE_MESHES` (half, whole):
    the mesh is refined until the Richardson estimate of each end's error is below
    :data:`rodstab.linear.solve.FE_TARGET_RTOL` (relative above 1); ``converged=False`` with
    the error reached if it cannot be. A fixed 32/64 pair extrapolated was 1.1e-5 off the Bloch
    method on a 6-rod cusp ring's eight (differential test, cusp-rings seed 0 index 29: the
    pair not yet in the asymptotic range). Raises :class:`RodstabInputError` (from the
    engine) if the state is not stable at its stress-free load.
    """
    ref = stress_free_load(ring, state.theta)
    a = ring.held(state.theta, reference_load=ref)
    # The multiplicities by the one rule with the mesh's Richardson error estimates
    # (with_mesh_error): a symmetry pair the mesh splits by its own error is one double
    # eigenvalue (the "8" of a 4-rod cusp ring, b1 = 92, b2 = 1.6: split 2e-6 at 64 elements,
    # Bloch: double).
    fine = converged_stability(a, FE_MESHES[1], limits=limits)
    lo, hi = fine.load_factor_interval
    n = ring.segments
    assert fine.mesh_error is not None
    err = max((e / max(abs(x), 1.0) for x, e in zip((lo, hi), fine.mesh_error, strict=True)
               if math.isfinite(x)), default=0.0)
    return StateInterval(
        label=state.label, theta=state.theta, stress_free_load=ref,
        lower=_limit(lo, fine.multiplicity_lo, None, n),
        upper=_limit(hi, fine.multiplicity, None, n),
        stable_at_stress_free=bool(lo < ref < hi)
        and fine.n_rigid_modes == RING_RIGID_MOTIONS,
        residual=fine.residual, converged=fine.converged,
        method=f"FE engine, {fine.elements} el./rod, estimated mesh error {err:.2g} "
               f"(relative; order {FE_ORDER})",
        reason="" if fine.converged else fine.reason or
        f"FE eigen solve residual {fine.residual:.3g} above tolerance")


def state_interval(ring: Ring, state: HeldState, method: str = "transfer",
                   limits: Limits = DEFAULT_LIMITS) -> StateInterval:
    """Stable interval of ``state`` of ``ring`` by ``method`` (one of :data:`METHODS`)."""
    if method == "transfer":
        return transfer_interval(ring, state)
    if method == "fe":
        return fe_interval(ring, state, limits)
    raise RodstabInputError(f"method must be one of {METHODS}, got {method!r}")


def default_states(ring: Ring, max_turns: float = 1.0) -> tuple[str, ...]:
    """Labels of the states an atlas follows by default: those with ``theta >= 0``.

    A mirror state (``theta < 0``) at load factor ``-mu`` is the state at ``mu`` reflected, so
    its interval is the negated one and adds nothing (``tests/test_atlas.py`` checks it). Every
    state is stable at its stress-free load (module docstring); :class:`StateInterval` reports
    the check.
    """
    return tuple(s.label for s in ring.states(max_turns=max_turns).states if s.theta >= 0)


def select_states(ring: Ring, labels: Sequence[str], max_turns: float = 1.0
                  ) -> tuple[HeldState, ...]:
    """Return the states called ``labels``; raise naming an unknown label and listing the states."""
    listed = {s.label: s for s in ring.states(max_turns=max_turns).states}
    for label in labels:
        if label not in listed:
            raise RodstabInputError(f"state {label!r} does not exist for this ring of "
                                    f"{ring.segments} {weld_name(ring.weld)}-welded rods "
                                    f"(|kL| <= {max_turns:g} turns); the states are "
                                    f"{list(listed)}")
    if len(set(labels)) != len(labels):
        raise RodstabInputError(f"states {list(labels)} name a state twice")
    return tuple(listed[label] for label in labels)


@dataclasses.dataclass(frozen=True)
class Overlap(Result):
    """The best set of ``k`` mutually stable states.

    ``width = min(upper) - max(lower)`` over ``members`` (positive iff they are mutually
    stable), maximal over the sets of ``k`` states; ``binding``: the largest lower and the
    smallest upper limit of the set, as ``("<state>.lower", "<state>.upper")``.
    """

    k: int
    width: float
    members: tuple[str, ...]
    load_interval: tuple[float, float]
    binding: tuple[str, str]


def best_overlap(intervals: dict[str, tuple[float, float]], k: int) -> Overlap:
    """Return the ``k`` intervals with the widest common part (a clique of the interval graph).

    The best set's largest lower limit is some state's lower limit ``lo_i``; given it, the best
    companions are the ``k - 1`` states with ``lo_j <= lo_i`` and the largest upper limits. So
    ``O(n^2 log n)`` instead of all subsets. Raises naming ``k`` outside ``1 .. n``.
    """
    names = list(intervals)
    if not 1 <= k <= len(names):
        raise RodstabInputError(f"k must be in 1..{len(names)}, got {k!r}")
    best: Overlap | None = None
    for i, name in enumerate(names):
        lo_i, hi_i = intervals[name]
        # ties in the lower limit go to the earlier state (each set is counted once)
        others = [m for j, m in enumerate(names) if j != i and (
            intervals[m][0] < lo_i or (intervals[m][0] == lo_i and j < i))]
        if len(others) < k - 1:
            continue
        others.sort(key=lambda m: -intervals[m][1])
        chosen = others[:k - 1]
        hi = min([hi_i] + [intervals[m][1] for m in chosen])
        width = hi - lo_i
        if best is None or width > best.width:
            low_end = min([name] + chosen, key=lambda m: intervals[m][1])
            members = tuple(m for m in names if m == name or m in chosen)
            best = Overlap(k, float(width), members, (float(lo_i), float(hi)),
                           (f"{name}.lower", f"{low_end}.upper"))
    assert best is not None  # the state with the largest lower limit has n - 1 companions
    return best


def common_load(ring: Ring, labels: Sequence[str]) -> tuple[float, tuple[float, float]]:
    """Return a load factor at which every state ``labels`` of ``ring`` is stable, and the overlap.

    The middle of the common part of their stable intervals by the transfer (Bloch) method
    (:func:`transfer_interval`): the default load of a command that needs the states together
    (``rodstab barrier DESIGN``), away from either end so that a discrete rod's mesh error
    does not decide it. Raises naming each state's interval when they have no common part.
    """
    states = select_states(ring, labels)
    found = {s.label: transfer_interval(ring, s) for s in states}
    intervals = {k: v.interval for k, v in found.items()}
    over = best_overlap(intervals, len(labels))
    if not over.width > 0 or not all(math.isfinite(x) for x in over.load_interval):
        shown = ", ".join(f"{k} ({lo:.6g}, {hi:.6g})" for k, (lo, hi) in intervals.items())
        raise RodstabInputError(f"states {list(labels)} are never stable together: stable "
                                f"intervals of the load factor {shown}")
    lo, hi = over.load_interval
    return 0.5 * (lo + hi), (lo, hi)


def mutual_sets(intervals: dict[str, tuple[float, float]]) -> tuple[Overlap, ...]:
    """Every maximal set of mutually stable states, by increasing common load interval.

    A common point of a set of intervals can be taken as the largest lower limit, so each
    maximal set is the states stable just above some state's lower limit.
    """
    sets: dict[tuple[str, ...], Overlap] = {}
    for name, (lo, _) in intervals.items():
        members = tuple(m for m, (a, b) in intervals.items() if a <= lo < b)
        if not members:
            continue
        hi = min(intervals[m][1] for m in members)
        low_end = min(members, key=lambda m: intervals[m][1])
        sets.setdefault(members, Overlap(len(members), float(hi - lo), members,
                                         (float(lo), float(hi)),
                                         (f"{name}.lower", f"{low_end}.upper")))
    maximal = [o for o in sets.values()
               if not any(set(o.members) < set(p.members) for p in sets.values())]
    return tuple(sorted(maximal, key=lambda o: o.load_interval))


@dataclasses.dataclass(frozen=True)
class CoexistenceRanges(Result):
    """Parameter ranges in which at least ``k`` of the states are mutually stable.

    ``ranges``: ``(start, end)`` pairs, increasing; an end strictly inside the grid is a root
    of the best ``k``-overlap width refined to ``tolerance`` in its grid ``brackets`` entry; an
    end at the grid's end is that grid value (``None`` bracket). A range narrower than one grid
    spacing, or one the width only touches, can be missed.
    """

    k: int
    ranges: tuple[tuple[float, float], ...]
    brackets: tuple[tuple[tuple[float, float] | None, tuple[float, float] | None], ...]
    tolerance: float


@dataclasses.dataclass(frozen=True)
class RingAtlas(Result):
    """Stable intervals of the chosen states of a ring against one design parameter.

    ``intervals[i][j]``: state ``states[j]`` at ``values[i]``; ``mutual[i]``: the maximal sets
    of mutually stable states at ``values[i]`` (:func:`mutual_sets`); ``coexistence``: the
    parameter ranges of ``k`` mutually stable states for each ``k`` solved for
    (:class:`CoexistenceRanges`, increasing ``k``).
    """

    key: str
    values: tuple[float, ...]
    states: tuple[str, ...]
    intervals: tuple[tuple[StateInterval, ...], ...]
    mutual: tuple[tuple[Overlap, ...], ...]
    coexistence: tuple[CoexistenceRanges, ...]
    load_factor: str
    method: str
    #: Where the grid values were solved (:func:`rodstab.executor.run_points`).
    executor: str = "serial"

    def limit_runs(self, state: str, side: str) -> list[tuple[float, float, str]]:
        """Return the runs of the grid with one kind of mode at ``state``'s ``side`` limit.

        ``(first value, last value, kind)``, kind e.g. ``"symmetry-breaking pair m=2 (x2)"``
        (by FE: the multiplicity alone), in grid order.
        """
        j = self.states.index(state)
        runs: list[tuple[float, float, str]] = []
        for p, row in zip(self.values, self.intervals, strict=True):
            lim: Limit = getattr(row[j], side)
            if lim.multiplicity == 0:
                kind = "none found"
            elif lim.harmonic is None:
                kind = f"multiplicity {lim.multiplicity}"
            else:
                kind = f"{lim.mode_type} m={lim.harmonic} (x{lim.multiplicity})"
            if runs and runs[-1][2] == kind:
                runs[-1] = (runs[-1][0], p, kind)
            else:
                runs.append((p, p, kind))
        return runs

    def tables(self) -> dict[str, Any]:
        """Return the atlas as columns over the grid (atlas.json's ``states``, ...).

        ``states``: per state, ``theta_deg`` and ``stress_free_load``, and per grid value
        ``stable_at_stress_free``, ``converged`` and for each limit (``lower``, ``upper``) the
        load factor, ``*_multiplicity``, ``*_harmonic`` and ``*_mode``; ``mutually_stable``:
        per value the maximal sets of mutually stable states and their common load interval;
        ``coexistence``: per ``k`` its parameter ranges and their tolerance.
        """
        states: dict[str, Any] = {}
        for j, label in enumerate(self.states):
            col = [row[j] for row in self.intervals]
            entry: dict[str, Any] = {
                "theta_deg": math.degrees(col[0].theta),
                "stress_free_load": col[0].stress_free_load,
                "stable_at_stress_free": [c.stable_at_stress_free for c in col],
                "converged": [c.converged for c in col]}
            for side in ("lower", "upper"):
                lims = [getattr(c, side) for c in col]
                entry[side] = [lim.load_factor for lim in lims]
                entry[f"{side}_multiplicity"] = [lim.multiplicity for lim in lims]
                entry[f"{side}_harmonic"] = [lim.harmonic for lim in lims]
                entry[f"{side}_mode"] = [lim.mode_type for lim in lims]
            states[label] = entry
        return {"states": states,
                "mutually_stable": [[{"states": list(o.members),
                                      "load_factor": list(o.load_interval)} for o in sets]
                                    for sets in self.mutual],
                "coexistence": [{"k": c.k, "ranges": [list(r) for r in c.ranges],
                                 "tolerance": c.tolerance} for c in self.coexistence]}

    def bands(self) -> dict[str, list[float]]:
        """``{"value": [...], "<state>.lower": [...], "<state>.upper": [...]}`` for a chart.

        When the ranges of all the states mutually stable were solved for (``k`` =
        ``len(states)`` in ``coexistence``), their refined ends as well:
        ``"all_stable.start"``, ``"all_stable.end"`` (a chart hatches from the root, not
        from the next grid value).
        """
        data: dict[str, list[float]] = {"value": list(self.values)}
        for j, s in enumerate(self.states):
            data[f"{s}.lower"] = [row[j].lower.load_factor for row in self.intervals]
            data[f"{s}.upper"] = [row[j].upper.load_factor for row in self.intervals]
        for c in self.coexistence:
            if c.k == len(self.states):
                data["all_stable.start"] = [r[0] for r in c.ranges]
                data["all_stable.end"] = [r[1] for r in c.ranges]
        return data


def _finite_width(w: float) -> float:
    """Return an overlap width for the root finder: an infinite one as a large finite one."""
    return w if math.isfinite(w) else math.copysign(1e300, w)


def coexistence_ranges(width: Callable[[float], float], values: Sequence[float],
                       widths: Sequence[float], k: int,
                       rel_xtol: float = RANGE_RTOL) -> CoexistenceRanges:
    """Ranges of the parameter where ``width(p) > 0``, from its values ``widths`` on ``values``.

    Each sign change between neighbouring grid values is refined by
    :func:`rodstab.numerics.refine_root` (Brent) to ``rel_xtol`` times that spacing.
    """
    xs = [float(v) for v in values]
    ws = [_finite_width(float(w)) for w in widths]
    order = sorted(range(len(xs)), key=lambda i: xs[i])
    xs, ws = [xs[i] for i in order], [ws[i] for i in order]
    ranges: list[tuple[float, float]] = []
    brackets: list[tuple[tuple[float, float] | None, tuple[float, float] | None]] = []
    start: float | None = xs[0] if ws[0] > 0 else None
    start_bracket: tuple[float, float] | None = None
    for i in range(len(xs) - 1):
        a, b = xs[i], xs[i + 1]
        if (ws[i] > 0) == (ws[i + 1] > 0):
            continue
        if ws[i] == 0.0 or ws[i + 1] == 0.0:
            root = a if ws[i] == 0.0 else b  # the width vanishes on the grid itself
        else:
            root = refine_root(lambda p: _finite_width(width(p)), a, b, rel_xtol=rel_xtol)
        if ws[i + 1] > 0:
            start, start_bracket = root, (a, b)
        else:
            assert start is not None
            ranges.append((start, root))
            brackets.append((start_bracket, (a, b)))
            start = None
    if start is not None:
        ranges.append((start, xs[-1]))
        brackets.append((start_bracket, None))
    spacing = min(b - a for a, b in zip(xs, xs[1:], strict=False))
    return CoexistenceRanges(k, tuple(ranges), tuple(brackets), rel_xtol * spacing)


def ring_atlas(ring_at: Callable[[float], Ring], values: Sequence[float],
               states: Sequence[str] | None = None, *, key: str = "parameter",
               method: str = "transfer", max_turns: float = 1.0,
               limits: Limits = DEFAULT_LIMITS, ks: Sequence[int] | None = None,
               progress: Callable[[], object] | None = None, workers: int | None = None,
               scheduler: str | None = None, client: Any = None,
               points_per_task: int | None = None) -> RingAtlas:
    """Stable intervals of the states of a ring against a parameter, and their coexistence.

    Parameters
    ----------
    ring_at : callable
        The ring at a parameter value (raises :class:`RodstabInputError` naming the value if
        the design is not a ring there).
    values : sequence of float
        At least two distinct parameter values (the grid).
    states : sequence of str, optional
        State labels (:meth:`Ring.states`); default :func:`default_states` at ``values[0]``.
    key : str
        Name of the parameter (messages, the result).
    method : {"transfer", "fe"}
        :func:`state_interval`'s method.
    max_turns : float
        The states' largest turning per rod, in full turns.
    limits : Limits
        Size limits of the FE engine.
    ks : sequence of int, optional
        The numbers ``k`` of mutually stable states whose parameter ranges are solved for
        (default ``1 .. len(states)``; each range end inside the grid costs a root search).
    progress : callable, optional
        Called once per grid value.
    workers, scheduler, client, points_per_task
        Where the grid values are solved, each value one point
        (:func:`rodstab.executor.run_points`): 0 in this process, N >= 1 on a local dask
        cluster of N workers; default (all None) as a sweep's: the first values are solved
        here and timed, and workers are started only if the rest would take over
        :data:`~rodstab.executor.AUTO_MIN_SECONDS`. On workers, ``ring_at`` must pickle (a
        closure does, by value). The root refinement of the coexistence ranges runs here.

    Returns
    -------
    RingAtlas
        Load factors in the design's units (:data:`LOAD_FACTOR_UNITS`); coexistence ranges for
        each of ``ks``, their ends inside the grid refined by the root finder.
    """
    if method not in METHODS:
        raise RodstabInputError(f"method must be one of {METHODS}, got {method!r}")
    vals = [float(v) for v in values]
    if len(vals) < 2 or len(set(vals)) != len(vals):
        raise RodstabInputError(f"{key}: an atlas needs at least 2 distinct values, got "
                                f"{len(vals)} ({len(set(vals))} distinct)")
    labels = tuple(default_states(ring_at(vals[0]), max_turns) if states is None else states)
    if not labels:
        raise RodstabInputError("an atlas needs at least one state, got none")
    select_states(ring_at(vals[0]), labels, max_turns)  # unknown labels fail before solving
    cache: dict[float, tuple[StateInterval, ...]] = {}
    at_values = functools.partial(grid_values, ring_at, labels, method, max_turns, limits)

    def solve(p: float) -> tuple[StateInterval, ...]:
        if p not in cache:
            cache[p] = at_values([p])[0][1]
        return cache[p]

    def as_dict(row: tuple[StateInterval, ...]) -> dict[str, tuple[float, float]]:
        return {r.label: r.interval for r in row}

    def record(results: list[tuple[float, tuple[StateInterval, ...]]]) -> None:
        for p, row in results:
            cache[p] = row
            if progress is not None:
                progress()

    where = run_points(at_values, vals, record, workers=workers, scheduler=scheduler,
                       client=client, points_per_task=points_per_task)
    rows = [cache[p] for p in vals]
    ks = tuple(range(1, len(labels) + 1)) if ks is None else tuple(ks)
    for k in ks:
        if not 1 <= k <= len(labels):
            raise RodstabInputError(f"ks: {k!r} is not in 1..{len(labels)}")
    coexistence = []
    for k in ks:
        def width(p: float, k: int = k) -> float:
            return best_overlap(as_dict(solve(p)), k).width

        coexistence.append(coexistence_ranges(width, vals, [width(p) for p in vals], k))
    return RingAtlas(key=key, values=tuple(vals), states=labels, intervals=tuple(rows),
                     mutual=tuple(mutual_sets(as_dict(r)) for r in rows),
                     coexistence=tuple(coexistence), load_factor=LOAD_FACTOR_UNITS,
                     method=rows[0][0].method if rows[0] else method, executor=where)


@dataclasses.dataclass
class DesignRings:
    """The ring of ``design`` with the design value ``key`` set to each value (callable).

    What :func:`ring_atlas` solves at a grid value: ``rings(value)`` is
    :func:`~rodstab.multistable.states.ring_of` of :func:`~rodstab.io.vary.design_at`, each
    value's design parsed once and its ring kept (the ends checked before a run, the first
    value read twice, are not parsed again). Picklable, for a dask worker. An invalid design
    at a value raises :class:`RodstabInputError` naming ``--vary KEY = VALUE``.
    """

    design: Design
    key: str
    unit: str | None = None
    _rings: dict[float, Ring] = dataclasses.field(default_factory=dict, repr=False,
                                                  compare=False)
    _designs: dict[float, Design] = dataclasses.field(default_factory=dict, repr=False,
                                                      compare=False)

    def design_at(self, value: float) -> Design:
        """Return the design at ``value`` (in ``unit``), parsed once."""
        if value not in self._designs:
            self._designs[value] = design_at(self.design, self.key, value, self.unit)
        return self._designs[value]

    def __call__(self, value: float) -> Ring:
        """Return the ring at ``value`` (in ``unit``)."""
        if value not in self._rings:
            try:
                self._rings[value] = ring_of(self.design_at(value).assembly)
            except RodstabInputError as exc:
                msg = str(exc)
                raise RodstabInputError(msg if msg.startswith("--vary") else
                                        f"--vary {self.key} = {value:g}: {msg}") from None
        return self._rings[value]


def atlas_units(rings: DesignRings, atlas: RingAtlas, unit: str | None) -> dict[str, Any]:
    """Return the ``"units"`` block of an atlas of a design with units.

    Parameters
    ----------
    rings : DesignRings
        The rings the atlas solved (its base design has units).
    atlas : RingAtlas
        The atlas.
    unit : str or None
        The unit of the varied values (:func:`rodstab.io.vary.axis_unit`).

    Returns
    -------
    dict
        :meth:`rodstab.units.Units.reference` of the base design; ``values`` in ``unit``;
        ``natural_curvature_per_load_factor``: at each value, the reference segment's
        ``|kappa_n|`` (1/m) at load factor 1 (its own design's, which the varied key may
        change); ``stable_natural_curvature``: per state, its ``lower`` and ``upper`` limits as
        that segment's natural curvature (1/m, :func:`rodstab.units.load_factor_curvatures`:
        negative curved the other way); ``mutually_stable``: each set's common interval so.
    """
    from ..units import SI_UNITS, load_factor_curvatures

    base = rings.design.units
    if base is None:
        raise RodstabInputError(f"{rings.design.source} has no units")
    designs = [rings.design_at(v) for v in atlas.values]

    def curvatures(d: Design, load_factors: Sequence[float]) -> list[float]:
        assert d.units is not None  # a design with units stays one at every value
        return load_factor_curvatures(d.units, d.assembly, load_factors)

    per = [curvatures(d, [1.0])[0] for d in designs]
    states = {label: {side: [curvatures(d, [getattr(row[j], side).load_factor])[0]
                             for d, row in zip(designs, atlas.intervals, strict=True)]
                      for side in ("lower", "upper")}
              for j, label in enumerate(atlas.states)}
    mutual = [[{"states": list(o.members), "natural_curvature": curvatures(d, o.load_interval)}
               for o in sets] for d, sets in zip(designs, atlas.mutual, strict=True)]
    curvature = SI_UNITS["curvature"]
    return base.block(
        values={"value": list(atlas.values), "unit": unit},
        natural_curvature_per_load_factor={"value": per, "unit": curvature},
        stable_natural_curvature={"value": states, "unit": curvature},
        mutually_stable={"value": mutual, "unit": curvature})


def grid_values(ring_at: Callable[[float], Ring], labels: Sequence[str], method: str,
                max_turns: float, limits: Limits, values: Sequence[float]
                ) -> list[tuple[float, tuple[StateInterval, ...]]]:
    """Solve the states ``labels`` at each of ``values``: one task of :func:`ring_atlas`.

    A module-level function, so that a dask worker can run it
    (:func:`rodstab.executor.run_points`). Returns ``(value, intervals)`` pairs.
    """
    out = []
    for p in values:
        ring = ring_at(p)
        out.append((p, tuple(state_interval(ring, s, method, limits)
                             for s in select_states(ring, labels, max_turns))))
    return out
