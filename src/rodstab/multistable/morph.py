"""Carry equilibria to a design that holds no state of its own: a rod's length morphed.

A ring with one rod 10 % longer than the other five has no planar held state of uniform moment
(:meth:`~rodstab.multistable.states.Ring.states` says so): each rod's equilibrium is an
elastica, and no design file can hold it (its held state must be an equilibrium). Its
equilibria are reached from the regular ring's instead (issue 22, section 4): on the one
common discrete rod (:func:`~rodstab.multistable.discover.common_rod`) the rest lengths of
one segment's elements are stepped from the design's length to the target
(:func:`set_segment_length`), and every state is carried along by deflated Newton without
deflation (:func:`~rodstab.multistable.discover.deflated_newton`: it converges to saddles as
well as minima) from the previous step's solution, a failed step halved up to
:data:`HALVINGS` times (:func:`morph_states`). The energy depends on the rest lengths
smoothly (bending ``B |k - k0|^2 l / 2`` with the Cayley curvature over ``l``, stretching
``K |x_j - x_i - l d|^2 / 2 l``), so a state is a smooth function of the length away from
folds; a state that cannot be carried across one says where.

The rod's natural curvature per unit length is the segment's: the morphed rod is the same
material, longer. Its elements get longer with it (same count).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import RodstabInputError, require_positive
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.parameters import SegmentLength
from .discover import deflated_newton
from .identify import Snapshot

#: A step that fails is split in two, at most this many times in a row.
HALVINGS = 4


def set_segment_length(rod: DiscreteRod, name: str, length: float) -> None:
    """Give segment ``name``'s elements of ``rod`` the rest length ``length / elements``.

    :class:`~rodstab.nonlinear.parameters.SegmentLength` (the diagram's parameter too).
    """
    SegmentLength(rod.assembly, name).set(rod, length)


def segment_length(rod: DiscreteRod, name: str) -> float:
    """Segment ``name``'s length on ``rod``: the sum of its elements' rest lengths."""
    return SegmentLength(rod.assembly, name).get(rod)


@dataclasses.dataclass(frozen=True)
class Morphed:
    """One state carried from the design's length to the target.

    ``state``: at the target, or None when a step failed (``reached``: the last length it was
    solved at); ``steps``: Newton runs spent.
    """

    label: str
    state: Snapshot | None
    reached: float
    steps: int


def morph_states(rod: DiscreteRod, states: list[tuple[str, Snapshot]], name: str,
                 target: float, steps: int) -> list[Morphed]:
    """Carry every state of ``states`` from segment ``name``'s length on ``rod`` to ``target``.

    ``steps`` equal steps of the length; each solved by Newton from the previous solution
    (a failed step halved up to :data:`HALVINGS` times). ``rod`` is left at ``target``.
    """
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        raise RodstabInputError(f"morph steps must be an integer >= 1, got {steps!r}")
    start = segment_length(rod, name)
    require_positive(f"segment.{name}.length", target)
    out = []
    for label, s in states:
        here, at, runs = s, start, 0
        ok = True
        for i in range(1, steps + 1):
            goal = start + (target - start) * i / steps
            h = goal - at
            while at != goal:
                nxt = goal if abs(goal - at) <= abs(h) else at + h
                set_segment_length(rod, name, nxt)
                here.put(rod)
                runs += 1
                if deflated_newton(rod, []).converged:
                    here, at = Snapshot.of(rod), nxt
                    continue
                h *= 0.5
                if abs(h) < abs(target - start) / steps / 2**HALVINGS:
                    ok = False
                    break
            if not ok:
                break
        out.append(Morphed(label, here if ok else None, at, runs))
    set_segment_length(rod, name, target)
    return out


def parse_morph(text: str) -> tuple[str, float, int]:
    """Parse ``segment.NAME.length=VALUE[:STEPS]`` (``--morph``); STEPS default 10."""
    key, eq, rest = text.partition("=")
    parts = key.split(".")
    if not eq or len(parts) != 3 or parts[0] != "segment" or parts[2] != "length":
        raise RodstabInputError(f"--morph {text!r} is not segment.NAME.length=VALUE[:STEPS] "
                                "(a rod's length is the one value morphed)")
    value, _, n = rest.partition(":")
    try:
        v = float(value)
        steps = int(n) if n else 10
    except ValueError:
        raise RodstabInputError(f"--morph {text!r}: VALUE must be a number and STEPS an "
                                "integer") from None
    if not (np.isfinite(v) and v > 0) or steps < 1:
        raise RodstabInputError(f"--morph {text!r}: the length must be positive and STEPS "
                                ">= 1")
    return parts[1], v, steps


def morph_seeds(text: str, rod: DiscreteRod, seeds: list[tuple[str, Snapshot]]
                ) -> tuple[list[tuple[str, Snapshot]], str]:
    """Carry ``seeds`` as ``--morph TEXT`` asks (:func:`parse_morph`, :func:`morph_states`).

    Returns the seeds that arrived and a line saying what was carried and what was lost
    (where). Raises :class:`~rodstab.errors.NotConverged` when none arrived.
    """
    from ..errors import NotConverged

    name, value, steps = parse_morph(text)
    start = segment_length(rod, name)
    carried = morph_states(rod, seeds, name, value, steps)
    kept = [(m.label, m.state) for m in carried if m.state is not None]
    lost = [f"{m.label} (at {m.reached:.6g})" for m in carried if m.state is None]
    line = (f"morphed      segment.{name}.length {start:.6g} -> {value:.6g} in {steps} steps: "
            f"{len(kept)} of {len(carried)} seeds carried"
            + (f"; lost {', '.join(lost)}" if lost else ""))
    if not kept:
        raise NotConverged(line)
    return [(lab, s) for lab, s in kept if s is not None], line
