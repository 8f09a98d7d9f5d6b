"""Transfer-matrix (shooting) methods: P2's Euler-Lagrange equations integrated exactly.

Independent of the paper's closed forms and of the FE, one module per kind of structure:

* :mod:`.arc` -- the clamped arc of Section 3.2 (``y' = S y``, ``T = expm(S)``; the derivation
  is in its docstring), its root windows and phase;
* :mod:`.ring` -- the N-loop ring of Section 3.1 (periodic solutions of eq. 3.1);
* :mod:`.straight` -- assemblies of straight segments (Sections 4 and 5);
* :mod:`.cyclic` -- rings of n identical arcs welded end to start, by the Bloch method.

Every public name is re-exported here (``from rodstab.transfer import clamped_arc_matrix``).
"""

from __future__ import annotations

from .arc import (
    ARC_FAMILY_FREE,
    arc_phase,
    arc_root_window,
    arc_system_matrix,
    clamped_arc_matrix,
    clamped_arc_mode,
    clamped_half_arc_matrix,
    expm,
    null_space,
    phase_grid,
)
from .cyclic import (
    CUSP_JOINT_MAP,
    CYCLIC_PER_TURN,
    RIGID_SV_RTOL,
    CyclicRingInterval,
    arc_end_matrix,
    cyclic_ring_interval,
    cyclic_ring_matrix,
    weld_joint_map,
)
from .ring import (
    RING_DEFORMATION_BASIS,
    RING_RIGID_BASIS,
    RING_RIGID_NULLITY,
    RING_SCAN_PER_TURN,
    ring_interval_transfer,
    ring_matching_matrix,
    ring_periodic_null_vectors,
    ring_periodicity_measure,
    ring_root_window,
    ring_scan_grid,
    ring_system_matrix,
)
from .straight import (
    ASSEMBLY_RIGID_NULLITY,
    FullSystemCritical,
    full_system_critical,
    straight_assembly_matrix,
    straight_assembly_modes,
    straight_segment_system,
)

__all__ = [
    "ARC_FAMILY_FREE",
    "ASSEMBLY_RIGID_NULLITY",
    "CUSP_JOINT_MAP",
    "CYCLIC_PER_TURN",
    "CyclicRingInterval",
    "FullSystemCritical",
    "RIGID_SV_RTOL",
    "RING_DEFORMATION_BASIS",
    "RING_RIGID_BASIS",
    "RING_RIGID_NULLITY",
    "RING_SCAN_PER_TURN",
    "arc_end_matrix",
    "arc_phase",
    "arc_root_window",
    "arc_system_matrix",
    "clamped_arc_matrix",
    "clamped_arc_mode",
    "clamped_half_arc_matrix",
    "cyclic_ring_interval",
    "cyclic_ring_matrix",
    "expm",
    "full_system_critical",
    "null_space",
    "phase_grid",
    "ring_interval_transfer",
    "ring_matching_matrix",
    "ring_periodic_null_vectors",
    "ring_periodicity_measure",
    "ring_root_window",
    "ring_scan_grid",
    "ring_system_matrix",
    "straight_assembly_matrix",
    "straight_assembly_modes",
    "straight_segment_system",
    "weld_joint_map",
]
