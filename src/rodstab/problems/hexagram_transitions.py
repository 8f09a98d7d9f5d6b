"""Transitions between the hexagram's four basic states under a stimulus (issue 11, part 3).

Each state is loaded, at one load factor ``mu = kappa_n R0`` where it is stable, by the
stimuli of :data:`STIMULI` (tried in order until one takes it to another state) and followed
to where it snaps (:mod:`rodstab.nonlinear.transitions`). Weld ``i`` is rod ``i+1``'s end
welded to rod ``i+2``'s start (``rodstab.states.ring_assembly``); welds 0 and 3 are opposite.

Units: ``B3 = 1``, rod length ``L = 1``: moments are in ``B3 / L``, rotations in radians, and
the contact thickness ``h`` (the section's out-of-plane height) is given as ``h / L``: the
stiffness ratios of a section fix its aspect, not its size relative to the rods.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import RodstabInputError
from ..nonlinear.discrete import discretise
from ..nonlinear.parameters import parameter
from ..nonlinear.transitions import TransitionGraph, ring_nodes, transition_graph
from ..sections import Section
from .hexagram import STATES, Params, build

#: Stimuli ``(key, stop)`` tried in order for each state (the first one that takes the state
#: to another one is kept): the natural curvature first (thermal or swelling actuation, from
#: the given load factor), then the weld stimuli. Weld moments in B3 / L, weld rotations in
#: radians; every range bounded.
STIMULI: dict[str, tuple[tuple[str, float], ...]] = {
    "line": (("load_factor", 4.0), ("weld.2.moment.binormal", 12.0),
             ("welds.0,3.rotation.binormal", 3.0)),
    "star": (("load_factor", 4.0), ("welds.0,3.rotation.binormal", 3.0),
             ("weld.2.moment.binormal", 12.0)),
    "daisy": (("load_factor", 0.2), ("load_factor", 4.0),
              ("welds.0,3.rotation.binormal", 3.0)),
    "eight": (("load_factor", 0.2), ("welds.0,3.rotation.binormal", 3.0),
              ("weld.2.moment.binormal", 12.0)),
}
#: Default out-of-plane thickness over the rod length, ``h / L``.
DEFAULT_THICKNESS = 0.02


def parse_stimulus(text: str) -> tuple[str, str, float]:
    """Parse ``STATE=KEY:STOP`` (``--stimulus``); the key is checked by :func:`check_stimuli`."""
    state, eq, rest = text.partition("=")
    key, colon, stop = rest.rpartition(":")
    if not eq or not colon or not key:
        raise RodstabInputError(f"--stimulus {text!r} is not STATE=KEY:STOP")
    if state not in STATES:
        raise RodstabInputError(f"--stimulus {text!r}: state {state!r} is not one of {STATES}")
    try:
        value = float(stop)
    except ValueError:
        raise RodstabInputError(f"--stimulus {text!r}: STOP {stop!r} is not a number") from None
    if not np.isfinite(value) or value == 0:
        raise RodstabInputError(f"--stimulus {text!r}: STOP {stop!r} must be finite and not 0")
    return state, key, value


def check_stimuli(section: Section, stimuli: dict[str, tuple[tuple[str, float], ...]],
                  elements: int) -> None:
    """Refuse a stimulus key that does not name a parameter of the hexagram (naming it)."""
    for state, pairs in stimuli.items():
        a = build(Params(section=section, state=state))
        for key, _ in pairs:
            try:
                parameter(a, key, elements)
            except RodstabInputError as exc:
                raise RodstabInputError(f"--stimulus {state}={key}: "
                                        + str(exc).replace("--vary key", "key")) from None


@dataclasses.dataclass(frozen=True)
class HexagramTransitions:
    """The graph and each basic state's node positions in traversal order (for the figure)."""

    graph: TransitionGraph
    shapes: dict[str, np.ndarray]


def transitions(section: Section, *, load_factor: float, elements: int = 8,
                thickness: float = DEFAULT_THICKNESS,
                stimuli: dict[str, tuple[tuple[str, float], ...]] | None = None,
                all_stimuli: bool = False, load: tuple[str, ...] = STATES
                ) -> HexagramTransitions:
    """Transition graph of the basic states ``load`` at ``load_factor`` (module docstring).

    All four states are references for the identification, whichever are loaded.
    """
    for state in load:
        if state not in STATES:
            raise RodstabInputError(f"--state {state!r} is not one of {STATES}")
    stim = {s: (STIMULI if stimuli is None else stimuli)[s] for s in load}
    check_stimuli(section, stim, elements)
    assemblies = {s: build(Params(section=section, state=s)) for s in STATES}
    graph = transition_graph(assemblies, stim, load_factor=load_factor, thickness=thickness,
                             elements_per_segment=elements, all_stimuli=all_stimuli,
                             load=load)
    shapes = {}
    for s, a in assemblies.items():
        r = discretise(a, elements, load_factor)
        shapes[s] = r.x[ring_nodes(r)]
    return HexagramTransitions(graph, shapes)
