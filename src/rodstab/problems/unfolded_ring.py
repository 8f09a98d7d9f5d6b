"""Unfolded ring of Section 5 (Fig. 1): the one-loop state of ``segments`` arcs joined at cusps.

Every arc turns left by ``theta`` on radius ``R0``; at each cusp the tangent reverses. Natural
curvature ``kappa_n = mu / R0`` (``B3 = 1``): ``mu = kappa_n R0``, and ``mu = 1`` is the
stress-free one-loop state of the experiment (Fig. 10, Supplemental Fig. 2). The paper's load
(5.7) is ``lambda = kappa_n L / sqrt(b1 b2) = mu theta / sqrt(b1 b2)``.
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import require_positive, require_positive_int
from ..linear.solve import LinearStability
from ..model import Assembly
from ..multistable.states import Ring, uniform_ring
from ..sections import Section, circle
from ._common import Method, engine, nonlinear_critical, segment


def one_loop_ring(section: Section, segments: int = 6) -> Ring:
    """Return the one-loop ring of ``segments`` arcs of radius 1 welded at cusps, as a ring.

    Each rod turns by ``theta = pi - 2 pi / n``, the turning at which ``n`` cusps close one
    loop (120 degrees for the six-ring), so its length on radius 1 is ``theta``; natural
    curvature 1 per unit load (``B3 = 1``): the load factor is ``kappa_n R0``.
    """
    n = require_positive_int("segments", segments)
    return uniform_ring(n, length=math.pi - 2 * math.pi / n, natural_curvature=1.0,
                        B1=section.b1, B2=section.b2)


#: Elements per segment of the linear engine (the report's B.unfold row).
DEFAULT_ELEMENTS = 24
#: Elements per segment of the nonlinear rod in :data:`METHODS` (observed error ~1e-3).
NONLINEAR_ELEMENTS = 8


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Unfolded ring: ``section``, number of arcs ``segments``, ``arc_angle_deg``, ``radius`` R0."""

    section: Section = dataclasses.field(default_factory=circle)
    segments: int = 6
    arc_angle_deg: float = 120.0
    radius: float = 1.0

    def __post_init__(self) -> None:
        """Validate: positive integer segments, positive radius and arc angle."""
        require_positive_int("segments", self.segments)
        require_positive("radius", self.radius)
        require_positive("arc_angle_deg", self.arc_angle_deg)

    @property
    def theta(self) -> float:
        """Arc angle in radians."""
        return math.radians(self.arc_angle_deg)


def build(params: Params) -> Assembly:
    """Return the one-loop ring; raises if the chain of arcs does not close."""
    n = int(params.segments)
    R0 = float(params.radius)
    theta = params.theta
    segs = []
    pos, ang = (0.0, 0.0), 0.0
    for i in range(1, n + 1):
        s = segment(str(i), params.section, theta * R0, 1.0 / R0, 1.0 / R0, pos, ang)
        segs.append(s)
        end = s.end_point("end")
        t = s.tangent(s.length)
        pos, ang = (float(end[0]), float(end[1])), math.atan2(-t[1], -t[0])
    welds = tuple(((str(i), "end"), (str(i % n + 1), "start")) for i in range(1, n + 1))
    return Assembly(segments=tuple(segs), welds=welds)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``kappa_R0 = kappa_n R0 = mu`` and ``lambda = mu theta / sqrt(b1 b2)`` (5.7)."""
    return {"kappa_R0": mu, "lambda": mu * params.theta / params.section.sqrt_b1b2}


def engine_stability(params: Params, elements: int = DEFAULT_ELEMENTS) -> LinearStability:
    """Stable interval of the load factor ``mu = kappa_n R0`` by the linear FE engine."""
    return engine(build(params), elements)


def _fe(params: Params) -> dict[str, float]:
    lo, hi = engine_stability(params).load_factor_interval
    return {"kappa_R0_lower": to_paper(lo, params)["kappa_R0"],
            "kappa_R0_upper": to_paper(hi, params)["kappa_R0"]}


def _nonlinear(params: Params) -> dict[str, float]:
    # Upwards from the stress-free one-loop state (kappa_n R0 = 1).
    mu = nonlinear_critical(build(params), 1.0, 3.0, NONLINEAR_ELEMENTS)
    return {"kappa_R0_upper": to_paper(mu, params)["kappa_R0"]}


#: Methods that solve the unfolded ring (no closed form), each returning its stable interval
#: of ``kappa_n R0`` (the nonlinear method its upper end).
METHODS: dict[str, Method] = {"fe": _fe, "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # Discrete rod at NONLINEAR_ELEMENTS: second-order mesh error (observed 8e-4).
    ("fe", "nonlinear"): 5e-3,
}
