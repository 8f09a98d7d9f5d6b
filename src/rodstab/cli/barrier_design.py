"""``barrier DESIGN`` on a design that is no ring: its states, found as ``discover`` finds them.

Parsing and checking only; the states come from :mod:`rodstab.multistable.design_states`.
"""

from __future__ import annotations

import math
from typing import Any

from ..errors import RodstabInputError


def design_ends(design: Any, design_file: str, elements: int, load_factor: float | None,
                from_state: str | None, to_state: str | None, options: tuple[Any, ...]
                ) -> tuple[str, str, tuple[Any, Any], list[tuple[str, Any]]]:
    """Return ``(from, to, ends, others)`` of a barrier on a design that is no ring.

    ``options``: ``(contact on, --layers, --into-contact, --cusp-width, --method)``, each
    refused naming it unless off (the design's own contact counts; method string). Its
    stable states at ``load_factor`` (required: no stable interval is known to pick one) are
    found by deflation (:func:`~rodstab.multistable.design_states.design_states`); ``--from`` and
    ``--to`` name two of them (default: the two lowest).
    """
    from ..multistable.design_states import DESIGN_STARTS, design_states, pick_state

    contact, layers, into_contact, cusp_width, method = options
    refused = {"--contact": contact or design.contact is not None, "--layers": bool(layers),
               "--into-contact": into_contact, "--cusp-width": cusp_width is not None,
               f"--method {method}": method != "string"}
    for option, on in refused.items():
        if on:
            raise RodstabInputError(f"{option} needs a ring; {design_file} is not a ring (its "
                                    "states are found by deflation: --method string, no "
                                    "contact)")
    if load_factor is None:
        raise RodstabInputError(f"--load-factor is required for {design_file}, which is not a "
                                "ring: no stable interval of its states is known to choose one")
    states = design_states(design.assembly, elements, load_factor)
    if len(states) < 2 and (from_state is None or to_state is None):
        raise RodstabInputError(
            f"--load-factor {load_factor!r}: {design_file} has "
            f"{len(states)} stable state(s) here ({', '.join(s for s, _ in states) or 'none'}; "
            f"deflated Newton from its held state, {DESIGN_STARTS} starts): a barrier joins two")
    a = states[0] if from_state is None else pick_state(states, from_state, "--from")
    b = states[1] if to_state is None else pick_state(states, to_state, "--to")
    if a[0] == b[0]:
        raise RodstabInputError(f"--to {b[0]!r} is the --from state: a barrier joins two "
                                "different states")
    others = [s for s in states if s[0] not in (a[0], b[0])]
    return a[0], b[0], (a[1], b[1]), others


def chain_link_text(lk: Any) -> str:
    """Return a chain link's saddle, else its path's bound, else its highest image (~)."""
    from .output import fmt

    if lk.converged:
        return fmt(lk.energy_saddle)
    if math.isfinite(lk.energy_bound):
        return "<= " + fmt(lk.energy_bound)
    return "~ " + fmt(lk.energy_highest)


def where_k(design_file: str | None) -> str:
    """Return what the load is called: kappa_n R0 (built-in structure) or the load factor."""
    return "kappa_n R0" if design_file is None else "load factor"
