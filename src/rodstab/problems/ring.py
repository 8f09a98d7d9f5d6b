"""Untwisted N-loop ring of Section 3.1: a naturally curved rod closed into a circle of N loops.

Eqs (3.1)-(3.3). Units: radius ``R = 1``, ``B3 = 1``; the ring is ``N`` welded loops of length
``2 pi R`` (same mesh per loop), held curvature ``1/R``, natural curvature ``mu / R``: the load
factor is ``mu = R kappa_n``. Paper units: ``M = 1 - R kappa_n = 1 - mu`` (Audoly & Seffen's
parameter) and ``(L / 2 pi) kappa_n = N mu`` (``L = 2 pi N R``).
"""

from __future__ import annotations

import dataclasses
import math

from ..analytic.ring import RingStability, ring_stability
from ..errors import require_positive_int
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..linear.solve import LinearStability, converged_stability
from ..model import Assembly
from ..sections import Section, circle
from ..transfer import ring_interval_transfer
from ._common import Method, engine, nonlinear_converged, segment

#: Elements per loop (one segment per loop) the linear engine starts from (FE error of the
#: interval ~1e-8 relative on the paper's rings, report row E3.1); refined from there until the
#: estimated error is 1e-7 (:func:`engine_stability`: a 9-loop ring reached 8.9e-6 here).
DEFAULT_ELEMENTS = 150
#: Elements per loop the nonlinear rod of :data:`METHODS` starts from; it doubles them until the
#: Richardson estimate holds (``problems._common.nonlinear_converged``; second-order error 2e-3
#: at 32).
NONLINEAR_ELEMENTS = 32


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Untwisted ring: ``section`` (default circle, nu = 1/3) and number of ``loops`` N."""

    section: Section = dataclasses.field(default_factory=circle)
    loops: int = 1

    def __post_init__(self) -> None:
        """Validate: a positive integer number of loops."""
        require_positive_int("loops", self.loops)


def segment_names(params: Params) -> tuple[str, ...]:
    """Names of the loops: ``("ring",)`` for one loop, else ``("ring1", ..., "ringN")``."""
    N = int(params.loops)
    return ("ring",) if N == 1 else tuple(f"ring{i}" for i in range(1, N + 1))


def build(params: Params) -> Assembly:
    """Return the N-loop ring: one segment per loop (:func:`segment_names`), welded in a cycle.

    Every loop ends where the next starts; one loop is welded to itself.
    """
    names = segment_names(params)
    segs = tuple(segment(name, params.section, 2 * math.pi, 1.0, 1.0) for name in names)
    # Each loop's start to the previous loop's end (the weld order of the report's rows).
    welds = tuple(((a, "start"), (b, "end")) for a, b in zip(names, names[-1:] + names[:-1],
                                                             strict=True))
    return Assembly(segments=segs, welds=welds)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``M = 1 - R kappa_n`` (3.3) and ``kappa_L_over_2pi = (L / 2 pi) kappa_n = N mu``."""
    return {"M": 1 - mu, "kappa_L_over_2pi": params.loops * mu}


def analytic_stability(params: Params, limits: Limits = DEFAULT_LIMITS) -> RingStability:
    """Stable interval by the Fourier modes (3.2) and eq (3.3), :func:`.ring_stability`."""
    return ring_stability(params.section.b1, params.section.b2, params.loops, limits=limits)


def engine_stability(params: Params, elements: int | None = None,
                     limits: Limits = DEFAULT_LIMITS) -> LinearStability:
    """Stable interval of the load factor ``mu = R kappa_n`` by the linear FE engine.

    ``elements`` (per loop) fixes the mesh; by default it starts at
    :data:`DEFAULT_ELEMENTS` and is refined until the estimated mesh error is below
    :data:`rodstab.linear.solve.FE_TARGET_RTOL`
    (:func:`rodstab.linear.solve.converged_stability`), so the FE meets :data:`AGREE_RTOL` on
    every accepted design
    (``mesh_error`` and ``elements`` of the result say what was reached).
    """
    if elements is None:
        # one unit of (L/2pi) kappa_n = N mu (problems.agree compares absolutely below it)
        return converged_stability(build(params), DEFAULT_ELEMENTS, unit=1.0 / params.loops,
                                   limits=limits)
    return engine(build(params), elements, limits)


def _interval(lo_mu: float, hi_mu: float, params: Params) -> dict[str, float]:
    """Stable interval of ``mu`` as ``kappa_L_over_2pi_lower`` / ``_upper``."""
    return {"kappa_L_over_2pi_lower": to_paper(lo_mu, params)["kappa_L_over_2pi"],
            "kappa_L_over_2pi_upper": to_paper(hi_mu, params)["kappa_L_over_2pi"]}


def _analytic(params: Params) -> dict[str, float]:
    lo, hi = analytic_stability(params).kappa_L_over_2pi_interval
    return {"kappa_L_over_2pi_lower": lo, "kappa_L_over_2pi_upper": hi}


def _transfer(params: Params) -> dict[str, float]:
    M_lo, M_hi, _ = ring_interval_transfer(params.section.b1, params.section.b2, params.loops)
    return _interval(1 - M_hi, 1 - M_lo, params)


def _fe(params: Params) -> dict[str, float]:
    return _interval(*engine_stability(params).load_factor_interval, params)


def _nonlinear(params: Params) -> dict[str, float]:
    # From the stress-free state (mu = 1) upwards; |M| < 3 max(b1, b2) at every mode bound.
    hi = 1.0 + 3.0 * max(params.section.b1, params.section.b2)
    mu = nonlinear_converged(build(params), 1.0, hi, NONLINEAR_ELEMENTS)
    return {"kappa_L_over_2pi_upper": to_paper(mu, params)["kappa_L_over_2pi"]}


#: Methods that solve the ring, each returning the stable interval in ``(L/2pi) kappa_n``.
METHODS: dict[str, Method] = {"analytic": _analytic, "transfer": _transfer, "fe": _fe,
                              "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # Closed form (3.3) vs the monodromy scan: both exact, root-finder tolerance.
    ("analytic", "transfer"): 1e-8,
    # FE mesh refined until its estimated error is 1e-7 (Richardson, converged_stability).
    ("analytic", "fe"): 1e-6,
    # Discrete rod, Richardson-extrapolated from meshes refined until it holds.
    ("analytic", "nonlinear"): 5e-3,
}
