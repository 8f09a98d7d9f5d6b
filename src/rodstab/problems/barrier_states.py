"""Named held states of the multistable rings whose energy barriers ``rodstab barrier`` computes.

Two structures, each a ring of six cusp-welded rods whose states are held geometries of ONE
assembly (same segments, orientations, welds and natural curvature), so that
:func:`rodstab.nonlinear.barrier.barrier_from_bifurcation` can name the states its path
reaches in one discrete model:

* ``hexagram`` (:mod:`.hexagram`): ``line``, ``star``, ``daisy``, ``eight``; load factor
  ``kappa_n R0``, ``R0 = 3 L / (2 pi)``;
* ``six-ring`` (Section 5, :mod:`.folded_ring`): ``folded`` (the folded ring's own assembly) and
  ``one-loop`` (:func:`one_loop_assembly`: the same six rods held as 120-degree arcs closing
  into one loop, the unfolded ring of :mod:`.unfolded_ring` in the folded ring's topology).
  Load factor ``kappa_n R0`` with ``R0 = L / theta`` the one-loop ring's radius, as in row
  T-six (the discrete model's ``mu = kappa_n L`` is ``theta kappa_n R0``).

The six-ring's folded state is the hexagram's line mirrored (the folded ring's natural
curvatures alternate in sign on alternately oriented rods), and its one-loop state the mirror
star: the two structures give the same barrier at the same section and load.
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import RodstabInputError
from ..model import Assembly, Segment
from ..sections import Section
from . import folded_ring, hexagram

#: States of each structure.
STRUCTURE_STATES: dict[str, tuple[str, ...]] = {"hexagram": hexagram.STATES,
                                                 "six-ring": ("folded", "one-loop")}
STRUCTURES = tuple(STRUCTURE_STATES)


def _tangent_angle(s: Segment, end: str) -> float:
    t = s.tangent(0.0 if end == "start" else s.length)
    return math.atan2(float(t[1]), float(t[0]))


def rechain(template: Assembly, curvature: dict[str, float]) -> Assembly:
    """Return ``template`` with new held curvatures, its rods re-chained along its welds.

    Segment 1 keeps its start and angle; each weld ``(s1, e1), (s2, e2)`` (in order; each weld
    two ends, the welds a chain) places ``s2`` so that its end ``e2`` sits at ``s1``'s end ``e1``
    with the tangents turned as in the template (welds keep full rotational continuity). The
    model's validation refuses a chain that does not close.
    """
    placed = {template.segments[0].name: dataclasses.replace(
        template.segments[0], curvature=curvature[template.segments[0].name])}
    for weld in template.welds:
        (n1, e1), (n2, e2) = weld
        if n2 in placed:
            continue  # the closing weld: checked by the model's validation
        s1, t1, t2 = placed[n1], template.segment(n1), template.segment(n2)
        turn = _tangent_angle(t2, e2) - _tangent_angle(t1, e1)
        ang = _tangent_angle(s1, e1) + turn  # tangent of s2 at its end e2
        k = curvature[n2]
        p = s1.end_point(e1)
        if e2 == "start":
            placed[n2] = dataclasses.replace(t2, curvature=k, start=(float(p[0]), float(p[1])),
                                             angle=ang)
        else:
            start_angle = ang - k * t2.length
            probe = dataclasses.replace(t2, curvature=k, start=(0.0, 0.0), angle=start_angle)
            q = p - probe.end_point("end")
            placed[n2] = dataclasses.replace(probe, start=(float(q[0]), float(q[1])))
    return Assembly(segments=tuple(placed[s.name] for s in template.segments),
                    welds=template.welds, reference_load=template.reference_load)


def one_loop_assembly(params: folded_ring.Params) -> Assembly:
    """Return the folded ring's rods held as arcs of turning ``theta``, curved as their natural one.

    Each rod's held curvature is ``sign(kappa_n) theta / L``: stress-free at ``kappa_n L =
    theta`` (``kappa_n R0 = 1``), the experiment's one-loop ring (Fig. 10).
    """
    folded = folded_ring.build(params)
    k = params.theta / params.length
    return rechain(folded, {s.name: math.copysign(k, s.natural_curvature)
                            for s in folded.segments})


def check_state(structure: str, state: str, option: str = "state") -> str:
    """Return ``state`` if ``structure`` has it, else raise naming both."""
    if structure not in STRUCTURE_STATES:
        raise RodstabInputError(f"structure must be one of {STRUCTURES}, got {structure!r}")
    if state not in STRUCTURE_STATES[structure]:
        raise RodstabInputError(f"{option} {state!r}: the {structure} has the states "
                                f"{list(STRUCTURE_STATES[structure])}")
    return state


def state_assembly(structure: str, section: Section, state: str) -> Assembly:
    """Held state ``state`` of ``structure`` (module docstring), rods of length 1."""
    check_state(structure, state)
    if structure == "hexagram":
        return hexagram.build(hexagram.Params(section=section, state=state))
    p = folded_ring.Params(section=section)
    return folded_ring.build(p) if state == "folded" else one_loop_assembly(p)


def model_load_factor(structure: str, kappa_R0: float) -> float:
    """Return the discrete model's load factor at ``kappa_n R0`` (module docstring)."""
    if structure == "hexagram":
        return kappa_R0
    return kappa_R0 * folded_ring.Params().theta / folded_ring.Params().length
