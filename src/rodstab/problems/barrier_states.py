"""Named held states of the multistable rings whose energy barriers ``rodstab barrier`` computes.

Two structures, each a ring of six cusp-welded rods whose states are held geometries of ONE
assembly (same segments, orientations, welds and natural curvature), so that
:func:`rodstab.multistable.barrier.barrier_from_bifurcation` can name the states its path
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

from ..errors import RodstabInputError
from ..model import Assembly
from ..multistable.states import ring_of
from ..sections import Section
from . import folded_ring, hexagram

#: States of each structure.
STRUCTURE_STATES: dict[str, tuple[str, ...]] = {"hexagram": hexagram.STATES,
                                                 "six-ring": ("folded", "one-loop")}
STRUCTURES = tuple(STRUCTURE_STATES)


def one_loop_assembly(params: folded_ring.Params) -> Assembly:
    """Return the folded ring's rods held as arcs of turning ``theta``, curved as their natural one.

    Each rod's held curvature is ``sign(kappa_n) theta / L``: stress-free at ``kappa_n L =
    theta`` (``kappa_n R0 = 1``), the experiment's one-loop ring (Fig. 10). The folded ring is
    read as a ring (:func:`rodstab.multistable.states.ring_of`: its natural curvature is positive
    along the ring) and held with every rod turning by ``theta`` along it (:meth:`.Ring.held`), in
    the folded ring's own segments, ends and welds.
    """
    folded = folded_ring.build(params)
    held = ring_of(folded).held(params.theta)
    # the folded ring's segment order and weld list: the two states are one discrete rod
    return Assembly(segments=tuple(held.segment(s.name) for s in folded.segments),
                    welds=folded.welds, reference_load=folded.reference_load)


#: The hexagram state each state is (mirrored, at the same ``kappa_n R0``: module docstring),
#: so that both structures take their stable intervals from the hexagram's ring.
HEXAGRAM_STATE = {"six-ring": {"folded": "line", "one-loop": "star"},
                  "hexagram": {s: s for s in hexagram.STATES}}


def common_load(structure: str, ring: object, states: tuple[str, str]
                ) -> tuple[float, tuple[float, float]]:
    """Return the default ``kappa_n R0`` of a barrier between ``states``: both stable there.

    The middle of their common stable interval (:func:`rodstab.multistable.atlas.common_load`
    on ``ring``, the hexagram's ring of the section: the six-ring's folded and one-loop states
    are its line and star mirrored, with the same intervals in ``kappa_n R0``). States never
    stable together are an input error naming both intervals, in this structure's labels.
    """
    from ..multistable.atlas import common_load as ring_common_load

    names = HEXAGRAM_STATE[structure]
    try:
        return ring_common_load(ring, tuple(names[s] for s in states))  # type: ignore[arg-type]
    except RodstabInputError as exc:
        text = str(exc)
        for own, hexa in names.items():
            text = text.replace(f"'{hexa}'", f"'{own}'").replace(f"{hexa} (", f"{own} (")
        text = text.replace("of the load factor", "of kappa_n R0")
        raise RodstabInputError(f"the {structure}'s {text}") from None


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


def structure_load(structure: str, load_factor: float) -> float:
    """Return ``kappa_n R0`` at the discrete model's ``load_factor``.

    :func:`model_load_factor` inverted: it is proportional, so divided by its value at 1.
    """
    return load_factor / model_load_factor(structure, 1.0)
