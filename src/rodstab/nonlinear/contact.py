"""Contact between rods (issue 21): a smooth barrier on the gaps between capsules.

The public names of the contact model, gathered from :mod:`.contact_model` (the model, its
exact energy, gradient and Hessian: read its docstring first) and :mod:`.contact_step` (the
step filter and the events where the energy is only C1). The nonlinear engine adds the energy
when ``DiscreteRod.contact`` is set (:mod:`.discrete`); Newton (:mod:`.newton`) filters its
steps and rejects trials outside the model.
"""

from __future__ import annotations

from .contact_model import (
    EE_NODE_EXCESS,
    EE_SIN2_OFF,
    EE_SIN2_ON,
    EXCLUSION_FACTOR,
    PHANTOM_FRACTION,
    START_GAP_FRACTION,
    TAPER_FRACTION,
    TAPER_MAX_TURN,
    ContactMesh,
    ContactModel,
    Interpenetration,
    _active,
    _bounds,
    barrier,
    candidate_pairs,
    contact_energy,
    contact_energy_value,
    contact_mesh,
    contact_terms,
    mesh_of_rod,
    penalty,
    segment_distance,
    stiffness_for_line_load,
)
from .contact_step import (
    ContactState,
    SwitchReport,
    active_gap_gradients,
    attach_contact,
    contact_state,
    max_step_fraction,
    near_type_switch,
    smallest_gap,
    type_switch_crossings,
)

__all__ = ["EE_NODE_EXCESS", "EE_SIN2_OFF", "EE_SIN2_ON", "EXCLUSION_FACTOR", "PHANTOM_FRACTION",
           "START_GAP_FRACTION", "TAPER_FRACTION", "TAPER_MAX_TURN", "ContactMesh",
           "ContactModel", "ContactState", "Interpenetration", "SwitchReport", "_active",
           "_bounds", "active_gap_gradients", "attach_contact", "barrier", "candidate_pairs",
           "contact_energy",
           "contact_state", "contact_energy_value", "contact_mesh", "contact_terms",
           "max_step_fraction", "mesh_of_rod", "near_type_switch", "penalty",
           "segment_distance", "type_switch_crossings", "smallest_gap", "stiffness_for_line_load"]
