"""Michell's ring of Section 3.3: a straight rod with natural twist closed into an N-loop ring.

Eqs (3.16)-(3.26). Units: radius ``R = 1``, ``B3 = 1``; ``N`` welded loops of length ``2 pi``,
held curvature 1, no natural curvature, natural twist ``mu`` per unit length (the pre-twist
``omega0'`` with ``R = 1``); the paper's load is ``b2 omega0' = b2 mu``. The held (untwisted)
ring is not an equilibrium of a naturally twisted rod, so only the nonlinear model solves this
assembly (the linear engine refuses natural twist): the critical twist is found along the
primary path by continuation.
"""

from __future__ import annotations

import dataclasses
import math

from ..analytic.michell import MichellStability, michell_stability
from ..errors import require_positive_int
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..model import Assembly
from ..sections import Section, circle
from ._common import Method, richardson, segment

#: Elements per loop of the nonlinear rod (the model that solves this assembly).
DEFAULT_ELEMENTS = 32
#: Meshes (elements per loop) Richardson-extrapolated by the nonlinear method of
#: :data:`METHODS`: the twisted ring's mesh error is large (2 % at 32 elements, order 2).
NONLINEAR_MESHES = (16, 32)
#: Window of the twist searched by the nonlinear method, in ``b2 omega0'``: Michell's
#: ``sqrt(3)`` lies inside (report row 3.26c).
TWIST_WINDOW = (1.5, 3.0)


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Michell's ring: ``section`` (default circle, nu = 1/3) and number of ``loops`` N.

    The analysis of Section 3.3 needs isotropic bending (``b1 = 1``); the nonlinear model does
    not.
    """

    section: Section = dataclasses.field(default_factory=circle)
    loops: int = 1

    def __post_init__(self) -> None:
        """Validate: a positive integer number of loops."""
        require_positive_int("loops", self.loops)


def build(params: Params) -> Assembly:
    """Return the ring of ``N`` loops ``"1"..."N"``, natural twist 1 per unit ``mu``."""
    N = int(params.loops)
    segs = tuple(segment(str(i), params.section, 2 * math.pi, 1.0, 0.0, natural_twist=1.0)
                 for i in range(1, N + 1))
    # Each loop's start to the previous loop's end (as in the ring, :mod:`.ring`).
    welds = tuple(((str(i), "start"), (str((i - 2) % N + 1), "end")) for i in range(1, N + 1))
    return Assembly(segments=segs, welds=welds)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``b2_omega0 = b2 omega0' = b2 mu`` (3.26) and ``omega0 = omega0' = mu`` (R = 1)."""
    return {"b2_omega0": params.section.b2 * mu, "omega0": mu}


def analytic_stability(params: Params, limits: Limits = DEFAULT_LIMITS) -> MichellStability:
    """Critical twist by the quadratic form of (3.21) and the modes (3.22)-(3.26).

    :func:`rodstab.analytic.michell.michell_stability`; raises unless ``b1 = 1``.
    """
    return michell_stability(params.section.b2, params.loops, b1=params.section.b1,
                             limits=limits)


def nonlinear_critical_twist(params: Params, elements: int = DEFAULT_ELEMENTS) -> float:
    """Critical ``b2 omega0'`` of the discrete rod: first loss of stability on the primary path.

    :func:`rodstab.nonlinear.continuation.critical_along_primary` over :data:`TWIST_WINDOW`;
    NaN when the ring is unstable already at the window's start (N > 1, end of Section 3.3).
    """
    from ..nonlinear.continuation import critical_along_primary

    b2 = params.section.b2
    mu = critical_along_primary(build(params), TWIST_WINDOW[0] / b2, TWIST_WINDOW[1] / b2,
                                elements_per_segment=elements).load_factor_critical
    return to_paper(mu, params)["b2_omega0"]


def _analytic(params: Params) -> dict[str, float]:
    return {"b2_omega0": analytic_stability(params).b2_omega0_critical}


def _nonlinear(params: Params) -> dict[str, float]:
    coarse, fine = (nonlinear_critical_twist(params, n) for n in NONLINEAR_MESHES)
    return {"b2_omega0": richardson(coarse, fine)}


#: Methods that solve Michell's ring, each returning the critical ``b2 omega0'``.
METHODS: dict[str, Method] = {"analytic": _analytic, "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # Discrete rod, Richardson of NONLINEAR_MESHES (observed 2e-3; row 3.26c: 32/64 el.).
    ("analytic", "nonlinear"): 5e-3,
}
