"""A path inside the contact model from one state to another, built by pulling (issue 21).

Two states of one ring that differ in knot type or in the self-linking of their ribbons are
joined by no path along which rods do not cross (:mod:`.linking`); equal invariants are only
necessary. :func:`pulled_path` builds a path where one exists and the pull finds it: every
node of ``start`` is pulled towards its place in ``end`` by springs ``(k / 2) |x_i -
x_i^end|^2`` (node positions only), ``k`` raised in geometric stages; each stage is relaxed
by Newton with contact one step at a time, every step filtered so that no gap closes
(:func:`~rodstab.nonlinear.newton.newton`), and every accepted state is kept. Then the springs
are released and Newton runs on. Neighbouring states are joined by one filtered step, so the
path lies inside the model throughout; ``reached`` says whether the released state is
``end``.

**Early release.** After each stage a copy is released (the springs off, Newton with contact,
at most :data:`RELEASE_STEPS` steps); the first whose release settles on ``end`` ends the
path there: the states so far and the release's, every one joined to the next by a filtered
step. The later stages only climb (the springs drag the rods onto ``end``'s positions with
their frames free, and the twist they leave is what the release removes), so stopping early
lowers the bound: on the hexagram's stacked line (6 el.) from 63.87 to 48.16 B3/L, the release
after stage 22 of 25 (k = 1.78e3) settling on the star (docs/theory/contact.md).

Such a path proves the two states joined; its highest energy bounds the barrier from above. It
is not a minimum energy path: the pull drags the rods along straight lines in position space
and leaves their frames free, and near ``end`` the pulled states can carry twist that the
release removes (measured on the hexagram's stacked line, docs/theory/contact.md "Ribbon
self-linking": 63.87 B3/L above the line with every stage run, 48.16 with the early
release, where the line -> star barrier without contact is 1.12). The springs act on
positions in absolute coordinates, where Newton works; the stability check (Kirchhoff
coordinates) is never run with them on.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..errors import RodstabInputError, require_finite, require_int, require_positive
from ..model import Assembly
from ..nonlinear.contact import ContactModel
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.newton import newton
from ..results import Result

#: Spring stiffness of the stages, in units of the largest bending stiffness over the mean
#: segment length cubed: from where the rods hardly move to where the nodes sit on ``end``'s
#: to 1e-2 of a segment (the hexagram's line, 6 el.: 0.0147 L at 1e4).
STAGES = tuple(float(k) for k in np.geomspace(1e-2, 1e4, 25))
#: Newton steps at most per stage (and for the release).
MAX_STEPS = 400
#: Newton steps at most of a trial release after a stage (:func:`pulled_path`,
#: ``early_release``): a state in ``end``'s basin settles in a few tens (the hexagram's line
#: pulled to its star, 6 el.: 21-24 from the three stage ends that reach it); one that crawls
#: is abandoned.
RELEASE_STEPS = 60


@dataclasses.dataclass
class PulledRod(DiscreteRod):
    """A :class:`DiscreteRod` whose nodes are pulled towards ``target`` by springs ``pull``.

    Fields of the dataclass, so that Newton's trial copies keep the springs. The energy adds
    ``(pull / 2) |x - target|^2`` and its gradient and Hessian (``pull`` on the position
    diagonal) in absolute coordinates.
    """

    target: np.ndarray | None = None
    pull: float = 0.0

    def _evaluate(self, order: int, links: bool, stretch: bool = True,
                  with_contact: bool = True
                  ) -> tuple[float, np.ndarray | None, sp.csr_matrix | None]:
        E, g, H = super()._evaluate(order, links, stretch, with_contact)
        if self.target is None or self.pull == 0.0:
            return E, g, H
        d = (self.x - self.target).ravel()
        if g is not None:
            g[: d.size] += self.pull * d
        if H is not None:
            diag = np.zeros(H.shape[0])
            diag[: d.size] = self.pull
            H = (H + sp.diags(diag)).tocsr()
        return E + 0.5 * self.pull * float(d @ d), g, H


@dataclasses.dataclass(frozen=True)
class PulledPath(Result):
    """A path built by :func:`pulled_path` (module docstring).

    ``states``: every accepted Newton state in order, ``start`` first (plain
    :class:`DiscreteRod` copies, springs off); ``energies``: their energies without the springs
    (energy units of the model); ``stages``: per stage ``(k, converged, steps, largest node
    distance to end, energy)``; ``reached``: the released state is ``end`` (every node within
    ``tolerance`` of it, length); ``end_distance``: its largest node distance to ``end``;
    ``released_after``: the stage (index into ``stages``) after which an early release reached
    ``end`` and ended the path, or -1 (every stage run, released at the end).
    """

    states: tuple[DiscreteRod, ...]
    energies: tuple[float, ...]
    stages: tuple[tuple[float, bool, int, float, float], ...]
    reached: bool
    end_distance: float
    tolerance: float
    released_after: int = -1

    @property
    def highest_energy(self) -> float:
        """The path's highest energy: an upper bound on the barrier from ``start``."""
        return max(self.energies)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: everything but the states."""
        return {"energies": list(self.energies), "stages": [list(s) for s in self.stages],
                "reached": self.reached, "end_distance": self.end_distance,
                "tolerance": self.tolerance, "highest_energy": self.highest_energy,
                "released_after": self.released_after}


def _plain(plain: DiscreteRod, r: DiscreteRod) -> DiscreteRod:
    """Return a copy of ``plain`` (no springs) in ``r``'s state."""
    state = plain.copy()
    state.x, state.R_edge, state.R_joint = r.x.copy(), r.R_edge.copy(), r.R_joint.copy()
    return state


def _steps(r: PulledRod, out: list[DiscreteRod], plain: DiscreteRod, max_steps: int
           ) -> tuple[bool, int]:
    """Newton one step at a time, a plain copy of each accepted state appended to ``out``."""
    for its in range(1, max_steps + 1):
        ok, n, _ = newton(r, max_iter=1)
        out.append(_plain(plain, r))
        if ok and n == 0:
            return True, its
    return False, max_steps


def pulled_path(start: DiscreteRod, end: DiscreteRod, *, stages: tuple[float, ...] = STAGES,
                max_steps: int = MAX_STEPS, tolerance: float | None = None,
                early_release: bool = True) -> PulledPath:
    """Build a path inside the contact model from ``start`` towards ``end`` (module docstring).

    Parameters
    ----------
    start, end : DiscreteRod
        Two states of one discrete model in one gauge (same nodes), ``start`` with its contact
        mesh attached (``start.contact``) and inside the model.
    stages : tuple of float
        Spring stiffnesses in turn, in units of ``B / Lm^3`` (``B`` the largest bending
        stiffness ``B3`` of the segments, ``Lm`` the mean segment length); > 0.
    max_steps : int
        Newton steps at most per stage and for the release.
    tolerance : float, optional
        Largest node distance (length, > 0) at which the released state counts as ``end``;
        default ``1e-6 Lm``.
    early_release : bool
        Try a release after every stage and end the path at the first that reaches ``end``
        (module docstring); False: every stage, then the release.

    Raises
    ------
    RodstabInputError
        No contact on ``start`` (a pulled path without it proves nothing), states of different
        node counts, a stage or a tolerance that is not a positive finite number.
    """
    if start.contact is None:
        raise RodstabInputError("start.contact is None: a pulled path proves two states "
                                "joined only inside a contact model; attach one first")
    if end.x.shape != start.x.shape:
        raise RodstabInputError(f"end has {len(end.x)} nodes, start {len(start.x)}: not two "
                                "states of one discrete model")
    bad = [k for k in stages if not (np.isfinite(k) and k > 0)]
    if not stages or bad:
        raise RodstabInputError(f"stages must be positive finite numbers, got {bad or stages!r}")
    steps = require_int("max_steps", max_steps, 1)
    a = start.assembly
    lm = a.total_length / len(a.segments)
    scale = max(s.B3 for s in a.segments) / lm**3
    tol = 1e-6 * lm if tolerance is None else require_positive("tolerance", tolerance)
    base = start.copy()  # Newton moves the pulled rod in place: never start's own arrays
    r = PulledRod(**{f.name: getattr(base, f.name) for f in dataclasses.fields(base) if f.init},
                  target=end.x.copy())
    states: list[DiscreteRod] = [start.copy()]
    record: list[tuple[float, bool, int, float, float]] = []

    def distance(rod: DiscreteRod) -> float:
        return float(np.max(np.linalg.norm(rod.x - end.x, axis=1)))

    def path(dist: float, after: int = -1) -> PulledPath:
        return PulledPath(tuple(states), tuple(float(s.energy()) for s in states),
                          tuple(record), dist <= tol, dist, tol, after)

    for i, k in enumerate(stages):
        r.pull = float(k) * scale
        ok, its = _steps(r, states, start, steps)
        r.pull = 0.0
        record.append((float(k), ok, its, distance(r), float(r.energy())))
        if early_release and i < len(stages) - 1:
            # One Newton run (its damping carried from step to step, as _steps' restarts do
            # not: from the hexagram's line those settled on the star one stage later).
            trial, settled = r.copy(), list[DiscreteRod]()

            def keep(rod: DiscreteRod, kept: list[DiscreteRod] = settled) -> None:
                kept.append(_plain(start, rod))

            newton(trial, max_iter=RELEASE_STEPS, on_step=keep)
            if distance(trial) <= tol:  # in end's basin: the later stages would only climb
                states += settled
                return path(distance(trial), i)
    _steps(r, states, start, steps)
    return path(distance(r))


def stacked_pull(a: Assembly, b: Assembly, load_factor: float, layers: dict[str, Any],
                 contact: ContactModel, *, elements_per_segment: int = 6,
                 names: tuple[str, str] = ("A", "B"), stages: tuple[float, ...] = STAGES
                 ) -> PulledPath:
    """Pull the stacked state ``a`` to ``b`` inside the contact model (:func:`pulled_path`).

    As the string from a stacked state (:func:`~.string_method.string_barrier` with
    ``layers``): both held states in one discrete model at ``load_factor``, relaxed and stable
    without contact, ``b`` in ``a``'s gauge (:func:`~.string_method.held_pair`), both
    lifted into ``a``'s stacked model (:func:`~.layered.stacked_band`: welds spanning the
    layers ``layers``, relaxed with ``contact`` and stable there), then ``a`` pulled to ``b``.
    The path's highest energy bounds the barrier from above both ways
    (:attr:`PulledPath.highest_energy`); the barrier is not computed.

    Parameters
    ----------
    a, b : Assembly
        Held states of one ring; ``a`` the stacked one.
    load_factor : float
        The model's load factor (both states stable there).
    layers : dict
        ``a``'s layer order (:func:`~.layered.stacked_band`).
    contact : ContactModel
        The rods' contact model (capsules).
    elements_per_segment : int
        Elements per rod (>= :data:`~.barrier.MIN_ELEMENTS`).
    names : tuple of str
        Labels of ``a`` and ``b`` in messages.
    stages : tuple of float
        The pull's spring stages (:func:`pulled_path`).

    Raises
    ------
    RodstabInputError
        A bad number, states of two models, an end not stable (with or without contact).
    TopologicallyApart
        The two stacked states differ in knot type or ribbon self-linking: no path joins them
        inside the model (:func:`~.linking.topology`), raised before the pull.
    """
    from .barrier import MIN_ELEMENTS
    from .layered import stacked_band
    from .linking import TopologicallyApart, topology
    from .string_method import held_pair

    mu = require_finite("load_factor", load_factor)
    n = require_int("elements_per_segment", elements_per_segment, MIN_ELEMENTS)
    start, end = stacked_band(list(held_pair(a, b, mu, n, names)), layers, contact, names)
    verdict = topology(start, end, names)
    if verdict.apart:
        raise TopologicallyApart(verdict)
    return pulled_path(start, end, stages=stages)
