"""The paper's structures as problems: parameters, assembly, paper units, default mesh.

One module per structure, each with a keyword-only frozen ``Params``, ``build(params) ->
Assembly``, ``to_paper(mu, params) -> dict`` (the paper's units of the load factor ``mu``) and
``DEFAULT_ELEMENTS`` (elements per segment of the linear engine):

========================  ==========================================  =================
name                      structure                                   paper
========================  ==========================================  =================
``straightened-rod``      clamped rod held straight                   (3.9), Sec. 3.2
``bi-rod``                two rods of curvature +-kappa0 welded       (4.1)-(4.8), Sec. 4
``folded-ring``           2n segments in the folded n-loop state      (5.1)-(5.14), Sec. 5
``unfolded-ring``         one-loop ring of 2n arcs with cusps         Fig. 1, Fig. 10
========================  ==========================================  =================

Every assembly has ``B3 = 1`` and the stiffness ratios of the section; the load factor ``mu``
multiplies the natural curvature.
"""

from __future__ import annotations

from types import ModuleType

from . import birod, folded_ring, straightened_rod, unfolded_ring

#: name -> problem module (``Params``, ``build``, ``to_paper``, ``DEFAULT_ELEMENTS``).
REGISTRY: dict[str, ModuleType] = {
    "straightened-rod": straightened_rod,
    "bi-rod": birod,
    "folded-ring": folded_ring,
    "unfolded-ring": unfolded_ring,
}

__all__ = ["REGISTRY", "birod", "folded_ring", "straightened_rod", "unfolded_ring"]
