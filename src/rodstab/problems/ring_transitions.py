"""Transitions between the basic states of a ring of welded rods under a stimulus (issue 11).

Each state is loaded, at one load factor where it is stable, by stimuli (tried in order until
one takes it to another state) and followed to where it snaps
(:mod:`rodstab.multistable.transitions`). The ring is a :class:`rodstab.multistable.states.Ring`:
the hexagram's (:func:`hexagram_ring`) or a design's (:func:`rodstab.multistable.states.ring_of`),
walked forwards (:meth:`~rodstab.multistable.states.Ring.forward`). Weld ``i`` joins the ``i``-th
rod along the ring to the next one; for six rods welds 0 and 3 are opposite.

Default stimuli (:func:`default_stimuli`) are the hexagram's :data:`HEXAGRAM_STIMULI`, written in
``kappa_n R0`` (``R0`` the star's arc radius) and carried to any ring of cusp-welded rods that
has a star by scaling the load factor with the star's stress-free load (1 for the hexagram,
``2 pi / 3`` for the six-sided ring of Section 5 in its design's units ``kappa_n L``) and the
weld indices with the number of rods. A ring without a star (e.g. smooth welds) has no default:
its states and stimuli are given.

Units: ``B3 = 1``, rod length ``L = 1`` for the hexagram (a design: its own units): moments are in
``B3 / L``, forces in ``B3 / L^2``, rotations in radians, and the contact thickness ``h`` (the
section's out-of-plane height) is given as ``h / L``: the stiffness ratios of a section fix its
aspect, not its size relative to the rods.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ..errors import RodstabInputError
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, require_nonlinear
from ..model import CONTACT_THICKNESS_RATIO, Assembly
from ..multistable.identify import ring_nodes
from ..multistable.states import Ring, uniform_ring
from ..multistable.transitions import TransitionGraph, transition_graph
from ..nonlinear.discrete import discretise
from ..nonlinear.parameters import parameter
from ..sections import Section
from ..units import SI_UNITS, Units
from . import hexagram as hx

#: The basic states whose transitions are followed by default (those the ring has).
BASIC = hx.STATES
#: The hexagram's stimuli ``(key, stop)`` tried in order for each state (the first one that
#: takes the state to another one is kept): the natural curvature first (thermal or swelling
#: actuation, from the given load factor, ``kappa_n R0``), then the weld stimuli. Weld moments
#: in B3 / L, weld rotations in radians; every range bounded.
HEXAGRAM_STIMULI: dict[str, tuple[tuple[str, float], ...]] = {
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
DEFAULT_THICKNESS = CONTACT_THICKNESS_RATIO


def threshold_units(units: Units, assembly: Assembly,
                    edges: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Return each edge's threshold in SI (a design with units).

    ``edges`` are :meth:`TransitionGraph.to_json`'s; each result has ``from``, ``to``,
    ``stimulus``, ``quantity`` and ``value``, ``unit``: the stimulus in its own SI unit
    (``quantity: "value"``, :func:`rodstab.io.vary.value_kind`), or for the load factor
    ``|kappa_n|`` (1/m) of the reference segment there (``quantity: "natural_curvature"``).
    """
    from ..io.vary import value_kind

    out = []
    for e in edges:
        kind = value_kind(e["stimulus"])
        q = (units.quantity(e["threshold"], kind) if kind is not None else
             {"value": units.natural_curvature(assembly, e["threshold"]),
              "unit": SI_UNITS["curvature"]})
        out.append({"from": e["from"], "to": e["to"], "stimulus": e["stimulus"],
                    "quantity": "value" if kind else "natural_curvature", **q})
    return out


def hexagram_ring(section: Section) -> Ring:
    """Return the hexagram's ring: six rods of length 1 at cusps, load factor ``kappa_n R0``."""
    return uniform_ring(hx.SEGMENTS, weld="cusp", length=1.0, natural_curvature=hx.L_OVER_R0,
                        B1=section.b1, B2=section.b2)


def ring_basic_states(ring: Ring) -> tuple[str, ...]:
    """Return the labels of :data:`BASIC` that ``ring`` has (:meth:`.Ring.states`)."""
    labels = {s.label for s in ring.states().states}
    return tuple(s for s in BASIC if s in labels)


def star_load(ring: Ring) -> float | None:
    """Return the star's stress-free load factor (``None``: no star, or no curvature)."""
    if "star" not in ring_basic_states(ring):
        return None
    return ring.stress_free_load(ring.state("star").theta)


def default_load_factor(ring: Ring) -> float | None:
    """Return the default load factor of :func:`transitions`: twice the star's stress-free load.

    ``kappa_n R0 = 2`` for the hexagram, where its basic states are stable on a section of
    h/t above the threshold; None when the ring has no star (:func:`star_load`).
    """
    unit = star_load(ring)
    return None if unit is None else 2.0 * unit


def default_stimuli(ring: Ring) -> dict[str, tuple[tuple[str, float], ...]]:
    """:data:`HEXAGRAM_STIMULI` carried to ``ring`` (module docstring); empty without a star."""
    unit = star_load(ring)
    if unit is None:
        return {}
    n = ring.segments
    out = {}
    for state in ring_basic_states(ring):
        pairs = []
        for key, stop in HEXAGRAM_STIMULI[state]:
            if key == "load_factor":
                pairs.append((key, stop * unit))
            else:
                key = (key.replace("welds.0,3.", f"welds.0,{n // 2}.")
                       .replace("weld.2.", f"weld.{n // 3}."))
                pairs.append((key, stop))
        out[state] = tuple(pairs)
    return out


def parse_stimulus(text: str, states: tuple[str, ...]) -> tuple[str, str, float]:
    """Parse ``STATE=KEY:STOP`` (``--stimulus``); the key is checked by :func:`check_stimuli`."""
    state, eq, rest = text.partition("=")
    key, colon, stop = rest.rpartition(":")
    if not eq or not colon or not key:
        raise RodstabInputError(f"--stimulus {text!r} is not STATE=KEY:STOP")
    if state not in states:
        raise RodstabInputError(f"--stimulus {text!r}: state {state!r} is not one of {states}")
    try:
        value = float(stop)
    except ValueError:
        raise RodstabInputError(f"--stimulus {text!r}: STOP {stop!r} is not a number") from None
    if not np.isfinite(value) or value == 0:
        raise RodstabInputError(f"--stimulus {text!r}: STOP {stop!r} must be finite and not 0")
    return state, key, value


def check_stimuli(ring: Ring, stimuli: dict[str, tuple[tuple[str, float], ...]],
                  elements: int) -> None:
    """Refuse a stimulus key that does not name a parameter of the ring (naming it)."""
    for state, pairs in stimuli.items():
        a = ring.held(ring.state(state).theta)
        for key, _ in pairs:
            try:
                parameter(a, key, elements)
            except RodstabInputError as exc:
                raise RodstabInputError(f"--stimulus {state}={key}: "
                                        + str(exc).replace("--vary key", "key")) from None


@dataclasses.dataclass(frozen=True)
class RingTransitions:
    """The graph and each state's node positions in traversal order (for the figure)."""

    graph: TransitionGraph
    shapes: dict[str, np.ndarray]


def transitions(ring: Ring, *, load_factor: float, elements: int = 8,
                thickness: float = DEFAULT_THICKNESS,
                stimuli: dict[str, tuple[tuple[str, float], ...]] | None = None,
                all_stimuli: bool = False, load: tuple[str, ...] | None = None,
                limits: Limits = DEFAULT_LIMITS,
                dhat_fraction: float | None = None,
                layers: dict[str, dict[str, Any]] | None = None,
                cusp_width: float | None = None) -> RingTransitions:
    """Transition graph of the states ``load`` of ``ring`` at ``load_factor`` (module docstring).

    ``load``: labels of :meth:`~rodstab.multistable.states.Ring.states`, each of which must be
    stable at ``load_factor`` (default: its basic states, those unstable there skipped and
    listed in the graph's ``skipped``);
    ``stimuli``: per loaded state, ``(key, stop)`` pairs (default :func:`default_stimuli`; a
    state without any is refused, naming it). The basic states and the loaded ones are the
    references for the identification, whichever are loaded. A model past
    ``limits.max_dof_nonlinear`` unknowns is refused before anything is built.
    ``dhat_fraction``: contact acts (capsules of diameter ``thickness`` x the rod length,
    ``dhat = dhat_fraction h``, :func:`rodstab.nonlinear.equilibrium.rod_contact_model`); a
    basic state outside the model is skipped (listed), a named one refused. None: no contact.
    ``layers[state]``: with contact, that state is stacked in this layer order, its welds
    spanning the layers (:func:`~rodstab.multistable.transitions.transition`).
    ``cusp_width``: cusp welds of that width (in units of ``thickness``) in every state.
    """
    # A closed ring of n rods has n joints.
    require_nonlinear([elements] * ring.segments, ring.segments, f"{elements} elements per rod",
                      limits)
    ring = ring.forward()
    basic = ring_basic_states(ring)
    named = load is not None
    load = basic if load is None else load
    if not load:
        raise RodstabInputError("this ring has none of the states "
                                f"{BASIC}: name the states to load (--state) and their "
                                "stimuli (--stimulus)")
    for state in load:
        ring.state(state)  # raises naming the state and listing the ring's states
    table = default_stimuli(ring) if stimuli is None else stimuli
    missing = [s for s in load if not table.get(s)]
    if missing:
        raise RodstabInputError(f"state {missing[0]!r} has no stimulus: give one with "
                                f"--stimulus {missing[0]}=KEY:STOP")
    stim = {s: table[s] for s in load}
    check_stimuli(ring, stim, elements)
    refs = tuple(dict.fromkeys(basic + tuple(load)))
    assemblies = {s: ring.held(ring.state(s).theta) for s in refs}
    # h / L to h in the ring's length unit (its rods' length L: 1 for the hexagram).
    contact = None
    if dhat_fraction is not None:
        from ..nonlinear.equilibrium import rod_contact_model

        contact = rod_contact_model(assemblies[refs[0]], thickness, dhat_fraction)
    wide = None if cusp_width is None else cusp_width * thickness * ring.length
    graph = transition_graph(assemblies, stim, load_factor=load_factor,
                             thickness=thickness * ring.length,
                             elements_per_segment=elements, all_stimuli=all_stimuli,
                             load=load if named else None, contact=contact, layers=layers,
                             cusp_width=wide)
    shapes = {}
    for s, a in assemblies.items():
        r = discretise(a, elements, load_factor, cusp_width=wide)
        shapes[s] = r.x[ring_nodes(r)]
    return RingTransitions(graph, shapes)
