"""Folded ring of Section 5: ``2n`` arcs held straight and stacked into the folded n-loop state.

Strain energy (5.1) with ``Delta kappa_0 = +-kappa_n``; joints (5.2)-(5.6) as in Fig. 8; the
paper's load ``lambda = B3 kappa_n L / sqrt(B1 B2)`` (5.7) and ``kappa_n R0 = lambda sqrt(b1 b2)
/ theta`` for arcs of angle ``theta`` (``L = theta R0``, (5.14): ``L = 2 pi R0 / 3``). Units:
``B3 = 1``; the load factor ``mu`` is ``kappa_n`` (natural curvature ``+-1`` per unit ``mu``).
"""

from __future__ import annotations

import dataclasses
import math

from ..analytic.folded_ring import folded_ring_paper_method
from ..errors import (
    RodstabInputError,
    require_in_range,
    require_positive,
    require_positive_int,
)
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, require_linear_uniform
from ..linear.solve import LinearStability
from ..model import Assembly
from ..sections import Section, circle
from ..transfer import ASSEMBLY_RIGID_NULLITY, FullSystemCritical, full_system_critical
from ._common import Method, engine, nonlinear_critical, segment

#: Elements per segment of the linear engine used by ``rodstab folded-ring``.
DEFAULT_ELEMENTS = 24
#: Elements per segment of the nonlinear rod in :data:`METHODS` (report row NL-folded).
NONLINEAR_ELEMENTS = 8
#: Largest ring the full system of general solutions runs on: its dense 6S x 6S matrix is
#: scanned for singular points on (0, 7] (measured: 1.1 s at 12 segments, 44 s at 24).
FULL_SYSTEM_MAX_SEGMENTS = 12
#: Arc angles accepted (degrees): an arc of more than a full turn is not a segment of a ring;
#: below the minimum its natural radius exceeds 6e7 lengths and kappa_n R0 loses its meaning.
ARC_ANGLE_RANGE_DEG = (1e-6, 360.0)
#: The paper's critical load (5.14): ``lambda_c = 2 pi`` (this project finds ``2 pi / (2n)``).
PAPER_LAMBDA_C = 2 * math.pi


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Parameters of the folded ring: ``section``, ``segments``, ``length``, ``arc_angle_deg``.

    ``segments`` is 2n (even, >= 2), ``length`` L of each segment, ``arc_angle_deg`` the angle of
    each arc in its natural state (it enters only the paper's units, ``kappa_n R0``).
    """

    section: Section = dataclasses.field(default_factory=circle)
    segments: int = 6
    length: float = 1.0
    arc_angle_deg: float = 120.0

    def __post_init__(self) -> None:
        """Validate: an even number of segments >= 2, positive length and arc angle."""
        n_seg = require_positive_int("segments", self.segments)
        if n_seg < 2 or n_seg % 2:
            raise RodstabInputError(
                f"segments must be an even number >= 2, got {self.segments!r}")
        require_positive("length", self.length)
        require_in_range("arc_angle_deg", self.arc_angle_deg, *ARC_ANGLE_RANGE_DEG,
                         "degrees: an arc of at most a full turn, of natural radius at most "
                         "6e7 segment lengths")

    @property
    def theta(self) -> float:
        """Arc angle in radians."""
        return math.radians(self.arc_angle_deg)


def build(params: Params) -> Assembly:
    """Return ``2n`` straight segments stacked into the folded ``n``-loop state.

    Segment ``i`` runs from ``x = 0`` to ``x = L`` with natural curvature (per unit ``mu``)
    ``-1`` for odd ``i``, ``+1`` for even ``i`` (``Delta kappa_0`` of (5.1)); odd segments are
    joined to the next at ``x = L``, even ones at ``x = 0`` (Fig. 8), the last to the first.
    """
    n_seg = int(params.segments)
    L = float(params.length)
    segs = tuple(segment(str(i), params.section, L, 0.0, -1.0 if i % 2 else 1.0)
                 for i in range(1, n_seg + 1))
    welds = tuple(((str(i), "end" if i % 2 else "start"),
                   (str(i % n_seg + 1), "end" if i % 2 else "start"))
                  for i in range(1, n_seg + 1))
    return Assembly(segments=segs, welds=welds, reference_load=0.0)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return the paper's units of load factor ``mu``: ``lambda`` (5.7) and ``kappa_R0``.

    ``lambda = mu L / sqrt(b1 b2)``; ``kappa_R0 = kappa_n R0 = lambda sqrt(b1 b2) / theta``.
    """
    lam = mu * params.length / params.section.sqrt_b1b2
    return {"lambda": lam, "kappa_R0": lam * params.section.sqrt_b1b2 / params.theta}


def paper_critical(params: Params) -> dict[str, float]:
    """Return the paper's claimed (5.14): ``lambda_c = 2 pi``, ``kappa_R0 = 2 pi g / theta``.

    ``g = sqrt(b1 b2)``.
    """
    return {"lambda": PAPER_LAMBDA_C,
            "kappa_R0": 2 * math.pi * params.section.sqrt_b1b2 / params.theta}


def full_system(params: Params) -> FullSystemCritical:
    """``lambda_c`` by the exact general solutions joined by all joint conditions (second method).

    :func:`rodstab.transfer.full_system_critical`, the three rigid motions of the free ring
    declared as known nullity. Refused (``RodstabInputError``) above
    :data:`FULL_SYSTEM_MAX_SEGMENTS` segments.
    """
    if params.segments > FULL_SYSTEM_MAX_SEGMENTS:
        raise RodstabInputError(
            f"segments {params.segments}: the full system of general solutions runs up to "
            f"{FULL_SYSTEM_MAX_SEGMENTS} segments (a dense {6 * params.segments}-square matrix "
            "scanned for singular points; 44 s at 24 segments); use the FE engine")
    return full_system_critical(build(params), params.section.sqrt_b1b2 / params.length,
                                ASSEMBLY_RIGID_NULLITY, 7.0)


def engine_stability(params: Params, elements: int = DEFAULT_ELEMENTS,
                     limits: Limits = DEFAULT_LIMITS) -> LinearStability:
    """Critical load factor ``mu = kappa_n`` by the linear FE engine."""
    # Refused before the segments are built (validating 1e5 welded segments takes seconds).
    n_seg = int(params.segments)
    require_linear_uniform(elements, n_seg, n_seg, f"{elements} elements per segment, segments "
                           f"{n_seg}", limits)
    return engine(build(params), elements, limits)


def _lam(mu: float, params: Params) -> dict[str, float]:
    return {"lambda": to_paper(mu, params)["lambda"]}


def _analytic(params: Params) -> dict[str, float]:
    # The paper's transfer matrices (5.8)-(5.11) with the full criterion on [A1; A2].
    pm = folded_ring_paper_method(0.05, 7.0, 700, pairs=int(params.segments) // 2)
    return {"lambda": pm.lam_critical}


def _transfer(params: Params) -> dict[str, float]:
    return {"lambda": full_system(params).lambda_c}


def _fe(params: Params) -> dict[str, float]:
    return _lam(engine_stability(params).load_factor_critical, params)


def _nonlinear(params: Params) -> dict[str, float]:
    # Scan lambda in (0.2, 2.3): it holds 2 pi / (2n) for 2n >= 4 (pi/3 for the paper's ring).
    mu_per_lam = params.section.sqrt_b1b2 / params.length
    return _lam(nonlinear_critical(build(params), 0.2 * mu_per_lam, 2.3 * mu_per_lam,
                                   NONLINEAR_ELEMENTS), params)


#: Methods that solve the folded ring, each returning the critical ``lambda``. None is the
#: paper's (5.12)-(5.14): its ``2 pi`` (:func:`paper_critical`) is not expected to agree.
METHODS: dict[str, Method] = {"analytic": _analytic, "transfer": _transfer, "fe": _fe,
                              "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # Two exact transfer-matrix formulations (the paper's state vector vs rodstab.transfer).
    ("analytic", "transfer"): 1e-8,
    # FE mesh error at DEFAULT_ELEMENTS (report row 5.14).
    ("transfer", "fe"): 1e-6,
    # Discrete rod at NONLINEAR_ELEMENTS: second-order mesh error (report row NL-folded).
    ("transfer", "nonlinear"): 5e-3,
}
