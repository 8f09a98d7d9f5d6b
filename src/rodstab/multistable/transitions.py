"""Transitions under a stimulus: load a stable state until it snaps, see where it goes.

From a stable equilibrium ``A`` the stimulus (any continuation parameter,
:mod:`rodstab.nonlinear.parameters`) is increased by
:func:`rodstab.nonlinear.continuation.continuation` until the path first loses stability (a fold or
a branch point, ``stop_at_first``). Just past that threshold the state is perturbed along its
critical mode and relaxed (:func:`rodstab.nonlinear.solve.relax`) to a stable state, the stimulus is
taken back to its start in small steps (relaxing again if stability is lost on the way), the welds
are let go (a free ring again: the weld parameters' constraints removed), and the state reached
``B`` is identified against the reference states by its aligned geometry, else named by its
invariants (:func:`~rodstab.multistable.identify.identify`).

Without a contact model (the default) rods pass through each other freely; with one
(``contact``: capsules that cannot pass through each other, :mod:`rodstab.nonlinear.contact`)
every step of the loading, the snap and the release is filtered so that no gap closes. Along
every sampled state (the loading path, the snap -- without contact only its two ends and the
straight interpolation of the node positions between them, the snap's true path being dynamic;
with contact every step of it, each filtered -- and the release, with contact every step)
the smallest distance between judged pairs of rod centreline elements is measured
(:func:`pair_distances`) and compared with the section's out-of-plane thickness ``h``:

* judged pairs: elements of two rods that share no joint, and elements of one rod at least
  :data:`SAME_ROD_GAP` elements apart (neighbouring rods meet at their weld by construction);
* **stacked** pairs: pairs already closer than ``h`` in the start state (the line and the
  eight have rods lying on top of each other by construction: the planar model puts them on
  one curve, the real rods are stacked out of plane and touch). They may touch and slide across
  each other in the plane throughout; for them a **pass-through** is a reversal of their
  out-of-plane order (the sign of the closest-point separation along the ring's best-fit
  normal) between two consecutive samples while the pair is closer than ``h`` at both. Their
  order is the one of the first resolved out-of-plane separation (the planar model has no
  thickness to say which rod lies on top), so a planar path never passes a stacked pair
  through;
* for every other pair a pass-through is the closest-point separation vector reversing
  (negative dot product) between two consecutive samples while the pair is closer than ``h``
  at both;
* for either kind, a reversal is a pass-through too where the pair is further apart than
  ``h`` at a sample but the straight interpolation of the node positions between the two
  samples brings it closer than ``h`` (:data:`BETWEEN_SAMPLES` states). With contact every
  sample keeps its pairs at least ``h`` apart, so only this can see rods pass through each
  other between two samples (measured: neighbouring images of a stacked string, 1.02-1.09
  ``h`` apart at both, separations reversed, the straight path 0.2 ``h`` apart). A reversal
  whose straight path stays ``h`` apart is a pair going round the other. Where the samples
  are joined by filtered steps (with contact: the loading, the relaxed snap and the release)
  the straight interpolation is not the path, and this is not judged;
* **touching** stretches: where a pair that was not stacked comes closer than ``h``.

An edge is reported physical only if no pass-through was found on any sampled stretch; the
snap's verdict rests on its interpolated proxy and is labelled as such.

**A double critical eigenvalue** (a symmetric ring: the hexagram's line and eight) has a plane
of critical modes, and the snap's target depends on the direction of the push within it (the
line reached the star or the daisy with different BLAS kernels). The edge's own snap pushes
along the eigen solver's first vector, as at a simple one; besides it, the state is pushed
along every branch direction of the eigenspace
(:func:`~rodstab.nonlinear.continuation.branches.branch_directions`: the stationary points of
the reduced equations' quartic form, independent of the solver's basis), each both ways, with
the same push, relaxation and release, and every state reached is listed
(:attr:`Transition.reachable`; where the directions' probe does not converge, along both
vectors of the solver's pair instead).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import NotConverged, RodstabInputError
from ..model import Assembly
from ..nonlinear.contact import ContactModel, Interpenetration, attach_contact
from ..nonlinear.continuation import continuation
from ..nonlinear.discrete import DiscreteRod, discretise
from ..nonlinear.newton import contact_fraction
from ..nonlinear.parameters import parameter
from ..nonlinear.solve import lowest_modes, newton, relax, zero_eigenvalue_tol
from ..results import Result
from .identify import Invariants, identify, invariants, mean_radius

if TYPE_CHECKING:  # layered imports nothing of this module; typing only
    from .layered import WeldSpans

#: Elements of one rod closer than this many elements along it are not judged for contact.
SAME_ROD_GAP = 3
#: Separations shorter than this times the rod length are unresolved (no direction).
RESOLVED = 1e-9
#: States of the straight interpolation between two samples at which a pair whose separation
#: reversed is measured (module docstring).
BETWEEN_SAMPLES = 33
#: Past the threshold the stimulus is increased by this fraction of it (at least
#: :data:`OVERSHOOT_MIN`) before relaxing: the state there has nothing nearby to stay on.
OVERSHOOT = 0.02
OVERSHOOT_MIN = 1e-3
#: Initial push along the critical mode, largest node displacement over the rod length.
PUSH = 0.01
#: Steps of the release (the stimulus taken back to its start) and of the snap's proxy.
RELEASE_STEPS = 12
SNAP_SAMPLES = 8
#: Relaxations (each up to RELAX_MAX_ITER Newton steps) allowed to the snap past a threshold.
SNAP_RELAXES = 3


# ---------------------------------------------------------------------------- contact
def judged_pairs(rod: DiscreteRod, model: ContactModel | None = None) -> np.ndarray:
    """Pairs ``(a, b)`` of elements judged for contact (module docstring), ``(n_pairs, 2)``.

    ``model``: judge instead every pair the contact model sees on ``rod`` (its mesh's
    exclusions: neighbours along the structure within the capsules' reach). For cusp welds of
    width (``discretise``'s ``cusp_width``) the two ends of a cusp are separate capsules the
    model keeps apart, which the default, all pairs of rods sharing a joint left out, misses.
    """
    if model is not None:
        from ..nonlinear.contact_model import mesh_of_rod

        i, j = np.triu_indices(len(rod.R_edge), 1)
        keep = ~mesh_of_rod(rod, model).excluded_elements(i, j)
        return np.stack([i[keep], j[keep]], axis=1)
    n_seg = len(rod.assembly.segments)
    n = len(rod.R_edge) // n_seg
    joints = [{rod.end_links[2 * s][1], rod.end_links[2 * s + 1][1]} for s in range(n_seg)]
    a, b = np.triu_indices(len(rod.R_edge), 1)
    sa, sb = a // n, b // n
    share = np.array([[bool(joints[i] & joints[j]) for j in range(n_seg)]
                      for i in range(n_seg)])
    keep = np.where(sa == sb, (b - a) >= SAME_ROD_GAP, ~share[sa, sb])
    return np.stack([a[keep], b[keep]], axis=1)


def pair_distances(x: np.ndarray, edge_nodes: np.ndarray, pairs: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Closest distance and separation vector (b minus a) of element pairs.

    ``x`` (n_nodes, 3), ``edge_nodes`` (n_edges, 2), ``pairs`` (n_pairs, 2). Returns the
    distances (n_pairs,) and the vectors between the closest points (n_pairs, 3): the clamped
    closest points of two segments (Ericson, *Real-Time Collision Detection*, 5.1.9).
    """
    p1, q1 = x[edge_nodes[pairs[:, 0], 0]], x[edge_nodes[pairs[:, 0], 1]]
    p2, q2 = x[edge_nodes[pairs[:, 1], 0]], x[edge_nodes[pairs[:, 1], 1]]
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    den = a * e - b * b
    s = np.where(den > 1e-14 * a * e, np.clip((b * f - c * e) / np.where(den > 0, den, 1.0),
                                               0.0, 1.0), 0.0)
    t = (b * s + f) / e
    lo, hi = t < 0, t > 1
    s = np.where(lo, np.clip(-c / a, 0, 1), np.where(hi, np.clip((b - c) / a, 0, 1), s))
    t = np.clip(t, 0.0, 1.0)
    w = (p2 + d2 * t[:, None]) - (p1 + d1 * s[:, None])
    return np.linalg.norm(w, axis=1), w


@dataclasses.dataclass(frozen=True)
class ContactReport(Result):
    """Contact along one stretch of a transition (module docstring), lengths over ``h``.

    ``min_distance``: the smallest distance of a non-stacked judged pair over ``h`` (inf if
    none); ``touching``: ``[value_from, value_to]`` intervals of the stimulus where a
    non-stacked pair is closer than ``h``; ``pass_through``: a pair reversed its separation
    while closer than ``h``; ``stacked_pairs``: pairs closer than ``h`` at the start.
    """

    stretch: str
    min_distance: float
    touching: tuple[tuple[float, float], ...]
    pass_through: bool
    pass_through_at: float | None
    stacked_pairs: int
    samples: int


class ContactTracker:
    """Accumulate contact over sampled states of one rod (module docstring)."""

    def __init__(self, rod: DiscreteRod, thickness: float, start_x: np.ndarray,
                 pairs: np.ndarray | None = None) -> None:
        """``pairs`` (n, 2): the element pairs judged; default :func:`judged_pairs`."""
        self.edges = rod.edge_nodes
        self.pairs = judged_pairs(rod) if pairs is None else np.asarray(pairs, dtype=int)
        self.h = thickness
        self.L = rod.assembly.total_length / len(rod.assembly.segments)
        d0, w0 = pair_distances(start_x, self.edges, self.pairs)
        self.stacked = d0 < thickness
        self.w = np.zeros_like(w0)
        self._resolve(start_x, d0, w0)
        self.d = d0
        self.x = start_x

    def _separation(self, x: np.ndarray, w: np.ndarray) -> np.ndarray:
        """``w``, with a stacked pair's replaced by its out-of-plane part (module docstring)."""
        c = x - x.mean(axis=0)
        normal = np.linalg.svd(c, full_matrices=False)[2][2]
        out = (w @ normal)[:, None] * normal
        return np.where(self.stacked[:, None], out, w)

    def _resolve(self, x: np.ndarray, d: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Update the kept separations; return which pairs were resolved in ``x``."""
        sep = self._separation(x, w)
        resolved = np.linalg.norm(sep, axis=1) > RESOLVED * self.L
        self.w = np.where(resolved[:, None], sep, self.w)
        return resolved

    def _closest_between(self, xa: np.ndarray, xb: np.ndarray, which: np.ndarray
                         ) -> np.ndarray:
        """Smallest distance of pairs ``which`` along the straight path from ``xa`` to ``xb``."""
        pairs = self.pairs[which]
        out = np.full(len(which), np.inf)
        for t in np.linspace(0.0, 1.0, BETWEEN_SAMPLES):
            out = np.minimum(out, pair_distances((1 - t) * xa + t * xb, self.edges, pairs)[0])
        return out

    def stretch(self, name: str, samples: Sequence[tuple[float, np.ndarray]], *,
                joined_inside: bool = False) -> ContactReport:
        """Judge the sampled states ``(value, x)`` of one stretch, in order.

        ``joined_inside``: every motion between two samples was a sequence of steps filtered
        by the contact model (no gap closed along any of them), so the samples are joined
        inside it and the straight interpolation between them, which is not the path, is not
        judged (module docstring).
        """
        dmin, touching, passed, at = math.inf, [], False, None
        run: list[float] | None = None
        for value, x in samples:
            d, w = pair_distances(x, self.edges, self.pairs)
            before = self.w.copy()
            sep = self._separation(x, w)
            reversed_ = np.einsum("ij,ij->i", sep, before) < 0
            flipped = reversed_ & (d < self.h) & (self.d < self.h)
            apart = np.flatnonzero(reversed_ & ~flipped)
            if apart.size and not joined_inside:
                flipped[apart] = self._closest_between(self.x, x, apart) < self.h
            if np.any(flipped) and not passed:
                passed, at = True, float(value)
            self._resolve(x, d, w)
            self.d, self.x = d, x
            free = d[~self.stacked]
            low = float(np.min(free)) / self.h if free.size else math.inf
            dmin = min(dmin, low)
            if low < 1.0:
                run = [float(value), float(value)] if run is None else [run[0], float(value)]
            elif run is not None:
                touching.append((run[0], run[1]))
                run = None
        if run is not None:
            touching.append((run[0], run[1]))
        return ContactReport(name, dmin, tuple(touching), passed, at, int(self.stacked.sum()),
                             len(samples))


# ---------------------------------------------------------------------------- transitions
@dataclasses.dataclass(frozen=True)
class SampledPath:
    """The sampled states of a transition, in order, for :mod:`rodstab.io.path_file`.

    ``x`` (n_states, n_nodes, 3): node positions (length of the assembly); ``edges``,
    ``rest_length``: the elements; ``stretches``: ``(name, number of states)`` in order
    (loading, the snap's interpolated proxy, release).
    """

    x: np.ndarray
    edges: np.ndarray
    rest_length: np.ndarray
    stretches: tuple[tuple[str, int], ...]


@dataclasses.dataclass(frozen=True)
class Transition(Result):
    """One loading of state ``source`` in stimulus ``stimulus`` and where it went.

    ``target`` is None when the path stayed stable up to ``stop`` (``threshold`` NaN).
    ``kind``: the special point's kind; ``under_load``: the state reached just past the
    threshold; ``target``: the state after the release; ``contact``: one report per stretch.
    """

    source: str
    stimulus: str
    stop: float
    threshold: float
    kind: str
    under_load: str
    target: str | None
    target_rms: float
    target_invariants: Invariants | None
    contact: tuple[ContactReport, ...]
    physical: bool
    converged: bool
    message: str
    #: Mean node distance from the centroid of the target, over ``L`` (NaN without a target).
    target_mean_radius: float = math.nan
    #: The states sampled along the way (not in the JSON: ``rodstab transitions --out``
    #: writes them to a path file per edge).
    path: SampledPath | None = dataclasses.field(default=None, repr=False,
                                                 metadata={"json": False})
    #: A stacked source's spanning welds checked against one another
    #: (:func:`~.layered.weld_spans`, at its relaxed stacked state); None for a planar source.
    welds: WeldSpans | None = None
    #: With contact: the C1 switches of the contact energy the loading path crossed
    #: (:func:`~rodstab.nonlinear.contact.type_switch_crossings`, each with its bracket), and
    #: whether the threshold's bracket meets one (its eigenvalue's sign change may then be the
    #: Hessian's jump there, not a smooth loss of stability).
    contact_events: tuple[dict, ...] = ()
    at_contact_event: bool = False
    #: The critical eigenvalue at the threshold is double (its second lowest within the zero
    #: tolerance): the snap pushed along one direction of the eigenspace, which round-off
    #: picks, so the target is not known to be the only one (the folded six-ring's line
    #: reached the star or the daisy with different BLAS kernels, docs/development.md).
    double_mode: bool = False
    #: At a double critical eigenvalue: the states reached by pushing along every branch
    #: direction of the eigenspace (:func:`~rodstab.nonlinear.continuation.branches.
    #: branch_directions`, basis-free), each both ways, relaxed and released as the edge's
    #: own snap; sorted names. Empty at a simple one.
    reachable: tuple[str, ...] = ()


def _let_go(rod: DiscreteRod, a: Assembly, n: int, cusp_width: float | None = None
            ) -> DiscreteRod:
    """Return the state of ``rod`` on a fresh discretisation (free gauge, no loads).

    The contact model, if any, is kept (one topology, one mesh).
    """
    free = discretise(a, n, rod.load_factor, cusp_width=cusp_width)
    free.x, free.R_edge, free.R_joint = rod.x.copy(), rod.R_edge.copy(), rod.R_joint.copy()
    free.contact = rod.contact
    return free


def _stacked_source(a: Assembly, source: str, n: int, load_factor: float,
                    layers: dict[str, Any], contact: ContactModel | None) -> DiscreteRod:
    """Return ``source`` held with its rods on ``layers`` (welds spanning them), relaxed.

    The planar state in the common model (:func:`~.discover.common_rod`) lifted into its
    stacked model (:func:`~.layered.stacked_model`, :func:`~.layered.lift`) and relaxed with
    ``contact`` (:func:`~.layered.stable_end`: refused unless stable).
    """
    from .discover import common_rod
    from .layered import lift, stable_end, stacked_model

    planar = common_rod(a, n, load_factor)
    if not newton(planar)[0]:
        raise NotConverged(f"state {source!r}: no equilibrium at load factor {load_factor:g}")
    rod = lift(stacked_model(planar, layers, contact), planar, planar)
    stable_end(rod, source, contact, f"layers = {layers}, load factor {load_factor:g}")
    return rod


class _Snap:
    """Push the critical state ``at`` along a mode, relax it past the threshold, release it.

    Called with a mode (free unknowns), returns ``(ok, stable, under, snapped_x, steps,
    release, free)``: whether every relaxation converged, whether the state relaxed under load
    is stable, its name (identified against ``references``), its node positions, the snap's
    filtered steps (``record``: with contact), the release's samples ``(value, x)`` and the
    released state relaxed free of loads.
    """

    def __init__(self, at: DiscreteRod, param: Any, past: float, start: float, length: float,
                 let_go: Any, references: Mapping[str, DiscreteRod], record: bool) -> None:
        self.at, self.param, self.past, self.start = at, param, past, start
        self.length, self.let_go, self.references, self.record = (length, let_go, references,
                                                                   record)

    def __call__(self, mode: np.ndarray) -> tuple:
        at, param = self.at, self.param
        snapped = at.copy()
        dq = np.zeros(snapped.n_dof)
        dq[snapped.free_dofs()] = mode
        disp = float(np.max(np.linalg.norm(dq[: 3 * len(snapped.x)].reshape(-1, 3), axis=1)))
        dq *= PUSH * self.length / max(disp, 1e-300)
        if snapped.contact is not None:  # the push closes no gap (the step filter)
            dq *= contact_fraction(snapped, np.arange(snapped.n_dof), dq)
        snapped.apply(dq)
        param.set(snapped, self.past)
        # With contact the snap is recorded step by step: every step is filtered, so
        # neighbouring states are joined inside the model, and so is the written path.
        steps = [at.x.copy(), snapped.x.copy()] if self.record else None
        # The snap crosses a flat, strongly nonlinear landscape: one relax (600 Newton steps)
        # may stop on the way (residual ~3e2 on the line at 8 el./rod); carry on from there.
        ok = False
        for _ in range(SNAP_RELAXES):
            ok = relax(snapped, trace=steps)[0]
            if ok:
                break
        stable = ok and lowest_modes(snapped, 1)[0][0] > zero_eigenvalue_tol(snapped)
        snapped_x = snapped.x.copy()
        under, _ = identify(self.let_go(snapped), self.references)
        release: list[tuple[float, np.ndarray]] = []
        for p in np.linspace(self.past, self.start, RELEASE_STEPS + 1)[1:]:
            param.set(snapped, float(p))
            trace: list | None = [] if self.record else None
            ok = relax(snapped, trace=trace)[0] and ok
            release.extend((float(p), x) for x in trace or [])
            release.append((float(p), snapped.x.copy()))
        free = self.let_go(snapped)
        trace = [] if self.record else None
        ok = relax(free, trace=trace)[0] and ok
        release.extend((self.start, x) for x in trace or [])
        release.append((self.start, free.x.copy()))
        return ok, stable, under, snapped_x, steps, release, free


def transition(a: Assembly, source: str, key: str, stop: float, *, load_factor: float,
               references: dict[str, DiscreteRod], thickness: float,
               elements_per_segment: int = 8, n_steps: int = 16,
               contact: ContactModel | None = None,
               layers: dict[str, Any] | None = None,
               cusp_width: float | None = None) -> Transition:
    """Load state ``source`` (assembly ``a``) in ``key`` from 0 to ``stop`` (module docstring).

    ``references``: the stable states to identify the target against (discretised alike);
    ``thickness``: the out-of-plane thickness ``h`` in the length unit of ``a``. ``contact``:
    the rods are capsules that cannot pass through each other throughout (the source relaxed
    with it, the continuation's, the snap's and the release's steps filtered); the snap is then
    recorded by its two ends, every step between them being filtered, instead of the
    interpolated proxy. Raises :class:`~rodstab.nonlinear.contact.Interpenetration` when the
    source lies outside the model. ``layers`` (with ``contact``, stimulus ``load_factor``):
    the source is a stacked state with this layer order (:func:`_stacked_source`), loaded,
    snapped and released in its stacked model (welds spanning the layers); the state reached
    is identified against ``references`` by its ring nodes
    (:func:`~.identify.identify`). ``cusp_width``: cusp welds of that width (length;
    :func:`~rodstab.nonlinear.discrete.discretise`), the source relaxed without contact before
    contact judges it (as built, only its end nodes moved); ``references`` must be
    discretised with it too, and every pair the contact model sees is judged
    (:func:`judged_pairs`; a model of capsules ``thickness`` when ``contact`` is None).
    """
    n = elements_per_segment
    if layers is not None and cusp_width:
        raise RodstabInputError(f"cusp_width {cusp_width!r} with layers: the stacked model has "
                                "no cusp welds of width; give one of the two")
    if layers is not None:
        if key != "load_factor":
            raise RodstabInputError(f"layers = {layers!r}: a stacked state is loaded in "
                                    f"load_factor only, got {key!r}")
        rod = _stacked_source(a, source, n, load_factor, layers, contact)
        from .layered import weld_spans

        welds = weld_spans(rod, thickness)
    else:
        welds = None
        rod = discretise(a, n, load_factor, cusp_width=cusp_width)
        if cusp_width:  # only the end nodes were moved: relaxed before contact judges it
            newton(rod)
        if contact is not None:
            try:
                attach_contact(rod, contact)
            except RodstabInputError as exc:
                raise Interpenetration(f"state {source!r}: {exc}") from None
        if not newton(rod)[0]:
            raise NotConverged(f"state {source!r}: no equilibrium at load factor "
                               f"{load_factor:g}")
    if lowest_modes(rod, 1)[0][0] <= zero_eigenvalue_tol(rod):
        raise RodstabInputError(f"state {source!r} is not stable at load factor "
                                f"{load_factor:g}: choose a load inside its stable interval")
    param = parameter(a, key, n)
    is_lf = key == "load_factor"
    start = load_factor if is_lf else 0.0
    judge = None
    if cusp_width:  # the cusps' two ends are separate capsules: every pair the model sees
        from ..nonlinear.equilibrium import rod_contact_model

        L = a.total_length / len(a.segments)
        judge = judged_pairs(rod, contact or rod_contact_model(a, thickness / L))
    tracker = ContactTracker(rod, thickness, rod.x.copy(), judge)
    samples: list[tuple[float, np.ndarray]] = []
    work = rod.copy()
    param.prepare(work)
    path = continuation(a, key, start, stop, n_steps, elements_per_segment=n, rod=work,
                        stop_at_first=True, branch_steps=0, contact=contact,
                        progress=lambda: samples.append((param.get(work), work.x.copy())))
    inside = contact is not None  # every step below is filtered by the contact model
    events = tuple((path.contact or {}).get("events", ()))
    reports = [tracker.stretch("loading", samples, joined_inside=inside)]
    lost = [(p, s) for p, s in zip(path.special_points, path.states, strict=False)]
    if not path.special_points or not path.states:
        return Transition(source, key, stop, math.nan, "", "", None, math.nan, None,
                          tuple(reports), not reports[0].pass_through, path.converged,
                          f"stable up to {key} = {path.value[-1]:.6g}"
                          + ("" if path.converged else " (the path stopped there)"),
                          welds=welds, contact_events=events)
    point, (value, at) = lost[0][0], lost[0][1]
    direction = math.copysign(1.0, stop - start)
    past = value + direction * max(OVERSHOOT * abs(value - start), OVERSHOOT_MIN)
    pair = lowest_modes(at, 2)[0]
    double = bool(pair[1] <= zero_eigenvalue_tol(at))
    # The push's vector from its own one-mode solve, as before the flag: a two-mode solve
    # returns another vector of a double eigenspace, and so another target (the flag's point).
    _, vec = lowest_modes(at, 1)
    let_go = ((lambda r: r.copy()) if layers is not None else
              (lambda r: _let_go(r, a, n, cusp_width)))
    L = a.total_length / len(a.segments)
    snap = _Snap(at, param, past, start, L, let_go, references, contact is not None)
    ok, stable, under, snapped_x, steps, release, free = snap(vec[:, 0])
    if contact is None:
        snap_name = "snap (interpolated proxy)"
        proxy = [(past, (1 - f) * at.x + f * snapped_x)
                 for f in np.linspace(0, 1, SNAP_SAMPLES)]
    else:  # every step of the push and the relaxation, filtered
        snap_name = "snap (relaxed with contact)"
        proxy = [(past, x) for x in steps or []]
    reports.append(tracker.stretch(snap_name, proxy, joined_inside=inside))
    reports.append(tracker.stretch("release", release, joined_inside=inside))
    reachable: tuple[str, ...] = ()
    if double:  # every branch direction of the eigenspace, both ways (module docstring)
        from ..nonlinear.continuation.branches import branch_directions

        try:
            modes = [d.mode for d in branch_directions(at, param, -direction, L)]
        except RuntimeError:  # the directions' probe did not converge: the solver's pair
            modes = list(lowest_modes(at, 2)[1].T)
        reachable = tuple(sorted({identify(snap(sign * m)[6], references)[0]
                                  for m in modes for sign in (1.0, -1.0)}))
    target, rms = identify(free, references)
    physical = not any(r.pass_through for r in reports)
    at_event = bool(point.get("at_contact_event"))
    msg = (f"{point['kind']} at {key} = {value:.6g}; snapped to {under} under load"
           + ("" if stable else " (the relaxed state under load is not stable)")
           + ("; AT A C1 CONTACT EVENT: the eigenvalue's sign change may be the contact "
              "Hessian's jump there" if at_event else ""))
    stretches = (("loading", samples), (snap_name, proxy), ("release", release))
    sampled = SampledPath(np.stack([x for _, part in stretches for _, x in part]),
                          rod.edge_nodes.copy(), rod.rest_length.copy(),
                          tuple((name, len(part)) for name, part in stretches))
    return Transition(source, key, stop, float(value), point["kind"], under, target, rms,
                      invariants(free), tuple(reports), physical, bool(ok and path.converged),
                      msg, mean_radius(free, free.x), sampled, welds, events, at_event, double,
                      tuple(sorted(set(reachable) | {target})) if double else ())


def _invariants_json(e: Transition) -> dict | None:
    """Return the target's invariants under the keys of ``rodstab transitions --json``.

    ``planarity`` is :attr:`~.identify.Invariants.max_out_of_plane`; ``mean_radius`` the
    target's size (:func:`~.identify.mean_radius`).
    """
    inv = e.target_invariants
    if inv is None:
        return None
    return {"distinct_weld_points": inv.distinct_weld_points,
            "turning_number": inv.turning_number, "mean_radius": e.target_mean_radius,
            "planarity": inv.max_out_of_plane}


@dataclasses.dataclass(frozen=True)
class TransitionGraph(Result):
    """Nodes (states) and edges (transitions) of a structure at one load factor."""

    states: tuple[str, ...]
    edges: tuple[Transition, ...]
    load_factor: float
    elements_per_segment: int
    thickness: float
    method: str
    #: States not loaded, with why: unstable at ``load_factor`` (only when every state is
    #: loaded by default; a state asked for by name that is unstable is an input error).
    skipped: tuple[tuple[str, str], ...] = ()

    def to_json(self) -> dict:
        """Return the ``rodstab transitions --json`` form: states and edges (from, to, ...)."""
        return {"states": list(self.states),
                "edges": [{"from": e.source, "to": e.target, "stimulus": e.stimulus,
                           "threshold": e.threshold, "kind": e.kind,
                           "under_load": e.under_load, "physical": e.physical,
                           "contact": [c.to_dict() for c in e.contact],
                           "target_invariants": _invariants_json(e),
                           "target_rms": e.target_rms, "converged": e.converged,
                           "message": e.message, "contact_events": list(e.contact_events),
                           "at_contact_event": e.at_contact_event,
                           "double_mode": e.double_mode, "reachable": list(e.reachable)}
                          for e in self.edges if e.target is not None],
                "no_transition": [{"from": e.source, "stimulus": e.stimulus, "stop": e.stop,
                                   "message": e.message,
                                   "contact_events": list(e.contact_events)}
                                  for e in self.edges if e.target is None],
                "skipped": [{"state": s, "why": why} for s, why in self.skipped],
                "load_factor": self.load_factor,
                "elements_per_segment": self.elements_per_segment,
                "thickness": self.thickness, "method": self.method}


def transition_graph(assemblies: dict[str, Assembly],
                     stimuli: Mapping[str, Sequence[tuple[str, float]]], *, load_factor: float,
                     thickness: float, elements_per_segment: int = 8,
                     n_steps: int = 16, all_stimuli: bool = False,
                     load: Sequence[str] | None = None,
                     contact: ContactModel | None = None,
                     layers: Mapping[str, dict[str, Any]] | None = None,
                     cusp_width: float | None = None) -> TransitionGraph:
    """Transitions out of every state of ``assemblies`` (one discretised ring, many states).

    ``stimuli[state]``: ``(key, stop)`` tried in order until one gives a transition to another
    state (all of them with ``all_stimuli``); a loading that stays stable is kept as an edge
    without a target (reported under ``no_transition``). ``load``: the states loaded (default
    all: then a state unstable at ``load_factor`` is skipped and listed in ``skipped``; one
    named in ``load`` must be stable); every state of ``assemblies`` is a reference for the
    identification. ``contact``: passed to :func:`transition`; a state whose rods overlap
    under it (stacked layers on one curve) is skipped (listed), or refused when named.
    ``layers[state]``: that state is stacked in this layer order (:func:`transition`).
    ``cusp_width``: cusp welds of that width in every state (:func:`transition`).
    """
    refs = {}
    for name, a in assemblies.items():
        r = discretise(a, elements_per_segment, load_factor, cusp_width=cusp_width)
        newton(r)
        refs[name] = r
    edges, states, skipped = [], list(assemblies), []
    for name in (list(assemblies) if load is None else load):
        a = assemblies[name]
        if load is None and lowest_modes(refs[name], 1)[0][0] <= zero_eigenvalue_tol(refs[name]):
            skipped.append((name, f"not stable at load factor {load_factor:g}"))
            continue
        for key, stop in stimuli.get(name, ()):
            try:
                t = transition(a, name, key, stop, load_factor=load_factor, references=refs,
                               thickness=thickness, elements_per_segment=elements_per_segment,
                               n_steps=n_steps, contact=contact,
                               layers=(layers or {}).get(name), cusp_width=cusp_width)
            except Interpenetration as exc:
                if load is not None:
                    raise
                skipped.append((name, f"outside the contact model: {exc}"))
                break
            edges.append(t)
            if t.target is not None and t.target not in states:
                states.append(t.target)
            if not all_stimuli and t.target is not None and t.target != name:
                break
    if skipped and len(skipped) == len(assemblies):
        if all(why.startswith("not stable") for _, why in skipped):
            raise RodstabInputError(f"no state is stable at load factor {load_factor:g} "
                                    f"(states {list(assemblies)}): choose a load inside a "
                                    "stable interval (rodstab atlas lists them)")
        raise RodstabInputError(f"no state can be loaded at load factor {load_factor:g}: "
                                + "; ".join(f"{name} {why}" for name, why in skipped)
                                + " (rods that leave a cusp along one line overlap under the "
                                "contact model at fine meshes: give the cusp welds a width, "
                                "rodstab transitions --cusp-width)")
    return TransitionGraph(tuple(states), tuple(edges), load_factor, elements_per_segment,
                           thickness,
                           "pseudo-arclength continuation to the first loss of stability, "
                           "relaxation along the critical mode past it, release of the "
                           "stimulus, identification by aligned geometry and invariants",
                           tuple(skipped))
