"""The minima and index-1 saddles found on one discrete model, as a graph (issues 21, 22).

A saddle of Hessian index one joins the two minima its steepest descents end on
(:func:`~.barrier.descents_from_saddle`). :class:`Landscape` keeps every minimum met (named:
the caller's states, then ``m1``, ``m2``, ... in the order found; one state modulo rigid motion,
reflection and relabelling, :func:`~.discover.same_state`) and every saddle judged, with the
minima its descents reached. It answers the two questions the string method and the chain ask:

- whether a saddle joins two given minima (:meth:`Landscape.joins`; a saddle met again is not
  descended again: with contact its descents take minutes);
- the lowest barrier between two minima over the saddles found (:meth:`Landscape.lowest_path`):
  the lowest, over the graph's paths, of the highest saddle on the path -- the energy at which
  a disconnectivity graph (Becker and Karplus, J. Chem. Phys. 106, 1495, 1997; Wales, *Energy
  Landscapes*, 2003) joins them. Saddles are added in increasing energy until the two minima are
  connected (union-find); the path is then the one with fewest saddles among the edges added.
"""

from __future__ import annotations

import dataclasses
from collections import deque
from typing import Any

import numpy as np

from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.solve import lowest_modes, zero_eigenvalue_tol
from ..results import Result
from .barrier import INDEX_EIGS, descents_from_saddle, state_label
from .discover import Snapshot, same_state

#: Label of a descent end that is not a converged minimum.
UNRESOLVED = "unresolved"


@dataclasses.dataclass
class Landscape:
    """Minima and saddles of one discrete model found so far (grows as they are met).

    ``minima``: ``(label, state, energy)``; ``rods``: a copy of the model at each minimum (the
    first met); ``saddles``: ``{"state", "energy", "descent_ends", "end_energies",
    "ends_converged", "descent_steps", "eigenvalues"}`` per index-1 saddle judged.
    """

    minima: list[tuple[str, Snapshot, float]]
    rods: dict[str, DiscreteRod]
    saddles: list[dict[str, Any]] = dataclasses.field(default_factory=list)
    #: Keep each judged saddle's two descent curves (``rec["traces"]``: the states in order,
    #: :func:`~.barrier.descents_from_saddle`): with contact they are the path that is joined
    #: inside the model.
    keep_traces: bool = False
    #: Label prefix of a minimum met that was not given (``m1``, ``m2``, ...).
    new_label: str = "m"
    #: A state and its mirror image are two minima (a barrier between exactly these two: the
    #: bi-rod's buckled states, :mod:`.design_states`); else one (:func:`~.identify.same_state`).
    proper: bool = False

    @classmethod
    def of(cls, named: list[tuple[str, DiscreteRod]]) -> Landscape:
        """Start from named minima (each a relaxed model)."""
        return cls([(lab, Snapshot.of(r), r.energy()) for lab, r in named],
                   {lab: r.copy() for lab, r in named})

    def name(self, r: DiscreteRod, *, add: bool = True) -> str:
        """Label of the minimum ``r`` is; a new one (``m<k>``) is added unless ``add`` is false.

        New labels are :attr:`new_label` and a count. ``r`` must be a converged minimum (the
        caller checks); ``"unnamed"`` when not ``add`` and unknown.
        """
        lab = state_label(r, self.minima, self.proper)
        if lab != "unnamed" or not add:
            return lab
        pre = self.new_label
        lab = f"{pre}{sum(lab.startswith(pre) for lab in self.rods) + 1}"
        while lab in self.rods:
            lab += "'"
        self.minima.append((lab, Snapshot.of(r), r.energy()))
        self.rods[lab] = r.copy()
        return lab

    def judge(self, saddle: DiscreteRod) -> dict[str, Any]:
        """Return the record of index-1 saddle ``saddle``: its descents' ends named (memoised).

        A saddle met before (:func:`~.discover.same_state`) returns its record; otherwise both
        steepest descents are followed (retracted steps) and each end that is a converged
        minimum is named (new minima added); an end that is not is :data:`UNRESOLVED`.
        """
        here, e = Snapshot.of(saddle), saddle.energy()
        for rec in self.saddles:
            if same_state(saddle, here, rec["state"], e, rec["energy"], self.proper):
                return rec
        vals, vecs = lowest_modes(saddle, INDEX_EIGS)
        traces: tuple[list[DiscreteRod], list[DiscreteRod]] | None = (
            ([], []) if self.keep_traces else None)
        descents, tips = descents_from_saddle(saddle, vals, vecs, retract=True, traces=traces)
        tol = zero_eigenvalue_tol(saddle)
        ok = tuple(bool(d.converged and d.lowest_eigenvalue > -tol) for d in descents)
        rec = {"state": here, "energy": e,
               "descent_ends": tuple(self.name(r) if c else UNRESOLVED
                                     for r, c in zip(tips, ok, strict=True)),
               "end_energies": tuple(d.energies[-1] for d in descents), "ends_converged": ok,
               "descent_steps": tuple(d.steps for d in descents),
               "eigenvalues": tuple(float(v) for v in vals)}
        if traces is not None:
            rec["traces"] = traces
        self.saddles.append(rec)
        return rec

    def joins(self, saddle: DiscreteRod, a: str, b: str) -> bool:
        """Whether ``saddle``'s two descents end on minima ``a`` and ``b`` (converged)."""
        rec = self.judge(saddle)
        return all(rec["ends_converged"]) and sorted(rec["descent_ends"]) == sorted((a, b))

    def saddle_between(self, a: str, b: str) -> float | None:
        """Energy of the lowest saddle judged so far that joins ``a`` and ``b``, or None."""
        found = [rec["energy"] for rec in self.saddles
                 if all(rec["ends_converged"]) and sorted(rec["descent_ends"]) == sorted((a, b))]
        return min(found) if found else None

    def energy(self, label: str) -> float:
        """Energy of minimum ``label``."""
        return next(e for lab, _, e in self.minima if lab == label)

    def edges(self) -> list[tuple[float, str, str]]:
        """Return ``(energy, a, b)`` of every saddle judged whose descents end on two minima."""
        return [(rec["energy"], *rec["descent_ends"]) for rec in self.saddles
                if all(rec["ends_converged"]) and len(set(rec["descent_ends"])) == 2]

    def graph(self) -> Disconnectivity:
        """Return the disconnectivity graph of the minima by the saddles judged so far."""
        return disconnectivity({lab: e for lab, _, e in self.minima}, self.edges())

    def lowest_path(self, a: str, b: str) -> tuple[float, list[str], list[float]] | None:
        """Lowest highest-saddle path from minimum ``a`` to ``b`` over the saddles found.

        Returns ``(level, minima, saddle energies)`` -- the highest saddle's energy, the minima
        in order from ``a`` to ``b`` and the energy of the saddle between each neighbouring
        pair (the lowest such saddle) -- or None when the saddles found do not connect them.
        """
        edges = self.edges()
        tree = self.graph()
        level = next((lvl for x, y, lvl, _, _ in tree.barriers if {x, y} == {a, b}), None)
        if level is None:
            return None
        best: dict[frozenset[str], float] = {}
        for e, u, v in edges:
            if e <= level:
                key = frozenset((u, v))
                best[key] = min(best.get(key, np.inf), e)
        back = {a: ""}
        todo = deque([a])
        while todo:  # fewest saddles among the edges up to the level
            u = todo.popleft()
            for key in best:
                if u in key:
                    (v,) = key - {u}
                    if v not in back:
                        back[v] = u
                        todo.append(v)
        path = [b]
        while path[-1] != a:
            path.append(back[path[-1]])
        path.reverse()
        return float(level), path, [best[frozenset(p)] for p in zip(path, path[1:], strict=False)]


@dataclasses.dataclass(frozen=True)
class Merge:
    """Two superbasins joined at a saddle energy: the members (minimum labels) of each."""

    energy: float
    left: tuple[str, ...]
    right: tuple[str, ...]


@dataclasses.dataclass(frozen=True)
class Disconnectivity(Result):
    """The disconnectivity graph of minima joined by index-1 saddles (Becker and Karplus).

    ``minima``: label -> energy; ``merges``: in increasing energy, each joining two superbasins
    (sets of minima connected by saddles no higher than it); ``order``: the leaves left to
    right so that every superbasin is contiguous (for drawing); ``barriers``: for every pair
    of minima the merge joins, ``(a, b, level, level - E_a, level - E_b)`` -- the lowest, over
    the saddles found, of the highest saddle on a path between them, and the barriers out of
    each. Pairs no saddle path joins are absent.
    """

    minima: dict[str, float]
    merges: tuple[Merge, ...]
    order: tuple[str, ...]
    barriers: tuple[tuple[str, str, float, float, float], ...]


def disconnectivity(minima: dict[str, float], saddles: list[tuple[float, str, str]]
                    ) -> Disconnectivity:
    """Join ``minima`` (label -> energy) by ``saddles`` ``(energy, a, b)`` in increasing energy.

    A saddle whose two minima are already in one superbasin adds nothing; one naming a label
    not in ``minima`` is an error of the caller (KeyError).
    """
    members: dict[str, tuple[str, ...]] = {lab: (lab,) for lab in minima}
    root = {lab: lab for lab in minima}

    def find(x: str) -> str:
        while root[x] != x:
            root[x] = root[root[x]]
            x = root[x]
        return x

    merges: list[Merge] = []
    barriers = []
    for e, a, b in sorted(saddles):
        ra, rb = find(a), find(b)
        if ra == rb:
            continue
        left, right = members.pop(ra), members.pop(rb)
        merges.append(Merge(float(e), left, right))
        barriers += [(x, y, float(e), float(e - minima[x]), float(e - minima[y]))
                     for x in left for y in right]
        root[rb] = ra
        members[ra] = left + right
    order = tuple(lab for group in sorted(members.values(), key=lambda g: min(
        minima[x] for x in g)) for lab in group)
    return Disconnectivity(dict(minima), tuple(merges), order, tuple(barriers))
