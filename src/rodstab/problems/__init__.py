"""The paper's structures as problems: parameters, assembly, paper units, methods, mesh.

One module per structure, each with a keyword-only frozen ``Params`` (validated, errors name
the value), ``build(params) -> Assembly``, ``to_paper(mu, params) -> dict`` (the paper's units of
the load factor ``mu``), ``DEFAULT_ELEMENTS`` (elements per segment of the engine that solves
it), ``METHODS`` and ``AGREE_RTOL``; some add ``paper_critical`` (the value the paper prints),
``analytic_stability``/``engine_stability`` (the full result objects) or ``full_system``:

========================  ==========================================  ====================
name                      structure                                   paper
========================  ==========================================  ====================
``ring``                  untwisted N-loop ring                       (3.1)-(3.3), Sec. 3.1
``clamped-arc``           rod bent into a clamped arc of L/R          (3.4)-(3.14), Sec. 3.2
``straightened-rod``      clamped rod held straight                   (3.9), Sec. 3.2
``michell``               Michell's twisted N-loop ring (nonlinear)   (3.16)-(3.26), Sec. 3.3
``bi-rod``                two rods of curvature +-kappa0 welded       (4.1)-(4.8), Sec. 4
``folded-ring``           2n segments in the folded n-loop state      (5.1)-(5.14), Sec. 5
``unfolded-ring``         one-loop ring of 2n arcs with cusps         Fig. 1, Fig. 10
``twisted-rod``           Greenhill's rod twisted by an end rotation  beyond the paper
                          (nonlinear)
``hexagram``              six rods welded at cusps in its four        beyond the paper
                          states (Lu, Leanza, Zhao, Hutchinson)
========================  ==========================================  ====================

``METHODS`` maps method names (``"analytic"``: :mod:`rodstab.analytic`; ``"transfer"``:
:mod:`rodstab.transfer`; ``"fe"``: :mod:`rodstab.linear`; ``"nonlinear"``:
:mod:`rodstab.nonlinear`) to ``Params -> {quantity: critical value}`` in the paper's units;
``AGREE_RTOL`` maps pairs of them to the relative tolerance within which they must agree on
their common quantities (each with its reason, e.g. the mesh error), see :func:`agree`. The
paper's printed value is not a method: where it differs (bi-rod, folded ring: ``2 pi``) it stays
in ``paper_critical``.

Every assembly has ``B3 = 1`` and the stiffness ratios of the section; the load factor ``mu``
multiplies the natural curvature (Michell's ring: the natural twist; the twisted rod's load is
an end rotation).
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Iterator, Mapping
from types import ModuleType

#: name -> module of the problem (in :mod:`rodstab.problems`).
_MODULES = {
    "ring": "ring",
    "clamped-arc": "clamped_arc",
    "straightened-rod": "straightened_rod",
    "michell": "michell",
    "bi-rod": "birod",
    "folded-ring": "folded_ring",
    "unfolded-ring": "unfolded_ring",
    "twisted-rod": "twisted_rod",
    "hexagram": "hexagram",
}


class _Registry(Mapping[str, ModuleType]):
    """The problems by name, each module imported when first asked for.

    A closed-form command (``rodstab ring``) then imports its own problem only, not the linear
    and nonlinear engines the others pull in (issue 12: start-up).
    """

    def __getitem__(self, name: str) -> ModuleType:
        return importlib.import_module(f".{_MODULES[name]}", __name__)

    def __iter__(self) -> Iterator[str]:
        return iter(_MODULES)

    def __len__(self) -> int:
        return len(_MODULES)


#: name -> problem module (``Params``, ``build``, ``to_paper``, ``DEFAULT_ELEMENTS``,
#: ``METHODS``, ``AGREE_RTOL``).
REGISTRY: Mapping[str, ModuleType] = _Registry()


def agree(a: float, b: float, rtol: float) -> bool:
    """Whether two critical values agree: ``|a - b| <= rtol max(|a|, |b|, 1)``.

    Relative for values above 1 in the paper's (order-one) units, absolute below, so that an
    interval end at 0 (the stress-free ring) is compared sensibly. Equal infinities agree.
    """
    if a == b:
        return True
    return abs(a - b) <= rtol * max(abs(a), abs(b), 1.0) if math.isfinite(a - b) else False


__all__ = ["REGISTRY", "agree"]
