"""Clamped arc of Section 3.2: a naturally curved rod bent into an arc of ``L/R`` and clamped.

Eqs (3.4)-(3.9) (stable range of ``L kappa_n``) and (3.13)/(3.14) (the longest arc bent from a
straight rod, :func:`max_arc_length`). Units: ``B3 = 1``; for ``L/R > 0`` the radius is
``R = 1`` (``L = L/R``, held curvature 1) and the load factor is ``mu = R kappa_n``; for
``L/R = 0`` (the straightened rod, (3.9)) ``L = 1`` and ``mu = L kappa_n``. Either way the paper's
load is ``L kappa_n`` (:func:`to_paper`), which stays finite in the straight limit.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..analytic.arc import ArcStability, MaxArcLength, clamped_arc_stability
from ..analytic.arc import max_arc_length as _max_arc_length
from ..errors import NotConverged, RodstabInputError, require_finite
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..linear.solve import LinearStability, converged_stability
from ..model import Assembly
from ..numerics import matrix_roots
from ..sections import Section, circle
from ..transfer import (
    ARC_FAMILY_FREE,
    arc_phase,
    arc_root_window,
    clamped_half_arc_matrix,
    phase_grid,
)
from ._common import Method, engine, nonlinear_converged, segment

#: Elements the linear engine starts from (report row E3.2: FE error ~1e-8 at L/R = 2); refined
#: from there until the estimated error is 1e-7 (:func:`engine_stability`: at L/R = 16,
#: b1 = 100, b2 = 1.5 this mesh was 2.1e-3 off).
DEFAULT_ELEMENTS = 96
#: Elements the nonlinear rod of :data:`METHODS` starts from; it doubles them until the
#: Richardson estimate holds (``problems._common.nonlinear_converged``: second-order error ~1e-3
#: at 32 elements, 52 % at b1 = 100, b2 = 30, L/R = 16).
NONLINEAR_ELEMENTS = 32
#: Scan intervals of the transfer method per unit of :func:`rodstab.transfer.arc_phase`.
_TRANSFER_PER_TURN = 8


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Clamped arc: ``section`` (default circle, nu = 1/3) and ``L_over_R`` (>= 0; 0: straight)."""

    section: Section = dataclasses.field(default_factory=circle)
    L_over_R: float = 2.0

    def __post_init__(self) -> None:
        """Validate: finite ``L_over_R >= 0``."""
        if require_finite("L_over_R", self.L_over_R) < 0:
            raise RodstabInputError(f"L_over_R must be >= 0, got {self.L_over_R!r}")


def _geometry(params: Params) -> tuple[float, float, float]:
    """``(L, held curvature, natural curvature per unit mu)`` of the segment."""
    Lb = float(params.L_over_R)
    return (Lb, 1.0, 1.0) if Lb > 0 else (1.0, 0.0, 1.0)


def build(params: Params) -> Assembly:
    """Return the arc ``arc`` clamped at both ends (see the module docstring for its units)."""
    L, k, kn = _geometry(params)
    return Assembly(segments=(segment("arc", params.section, L, k, kn),),
                    supports=(("arc", "start", "clamped"), ("arc", "end", "clamped")))


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``L_kappa_n = L kappa_n`` of load factor ``mu`` (the load of (3.7)-(3.9))."""
    L, _, kn = _geometry(params)
    return {"L_kappa_n": L * kn * mu}


def analytic_stability(params: Params) -> ArcStability:
    """Stable interval of ``L kappa_n`` by (3.7)/(3.8), :func:`.clamped_arc_stability`."""
    return clamped_arc_stability(params.section.b1, params.section.b2, params.L_over_R)


def max_arc_length(section: Section) -> MaxArcLength:
    """Longest stable clamped arc bent from a straight rod, ``L/R max`` of (3.13)/(3.14).

    The arc of :func:`build` with ``kappa_n = 0`` (load factor 0): Fig. 5,
    :func:`rodstab.analytic.arc.max_arc_length`.
    """
    return _max_arc_length(section.b1, section.b2)


def engine_stability(params: Params, elements: int | None = None,
                     limits: Limits = DEFAULT_LIMITS) -> LinearStability:
    """Stable interval of the load factor by the linear FE engine.

    ``elements`` (per arc) fixes the mesh; by default it starts at
    :data:`DEFAULT_ELEMENTS` and is refined until the estimated mesh error is below
    :data:`rodstab.linear.solve.FE_TARGET_RTOL`
    (:func:`rodstab.linear.solve.converged_stability`), so the FE meets :data:`AGREE_RTOL` on
    every accepted design
    (``mesh_error`` and ``elements`` of the result say what was reached).
    """
    if elements is None:
        # one unit of L kappa_n (problems.agree compares absolutely below it) in load factor
        L, _, kn = _geometry(params)
        return converged_stability(build(params), DEFAULT_ELEMENTS, unit=1.0 / (L * kn),
                                   limits=limits)
    return engine(build(params), elements, limits)


def _analytic(params: Params) -> dict[str, float]:
    lo, hi = analytic_stability(params).L_kappa_interval
    return {"L_kappa_n_lower": lo, "L_kappa_n_upper": hi}


def transfer_interval(params: Params) -> tuple[float, float]:
    """Stable interval of ``L kappa_n`` by the shooting matrices of the two families.

    Each side of the stress-free load ``L/R`` is searched outwards in windows that double
    (overlapping by a tenth), every window scanned on a grid resolving the phase of the
    solutions (:func:`rodstab.transfer.phase_grid`, :func:`rodstab.transfer.arc_phase`) for
    the symmetric and the antisymmetric family separately
    (:func:`rodstab.transfer.clamped_half_arc_matrix`); the first window with a root holds
    the nearest one. The search stops at the bound :func:`rodstab.transfer.arc_root_window`
    proves from test fields; no root by then raises :class:`~rodstab.errors.NotConverged`
    (never an infinite end reported as a result).
    """
    s, Lb = params.section, float(params.L_over_R)
    bound = arc_root_window(Lb, s.b1, s.b2)

    def phase(p: np.ndarray) -> np.ndarray:
        return arc_phase(p, Lb, s.b1, s.b2)

    ends = []
    for side, limit in ((-1.0, bound[0]), (1.0, bound[1])):
        reach, width, nearest = 0.0, 1.0, None
        while nearest is None and reach < abs(limit - Lb):
            a, b = sorted((Lb + side * max(reach - 0.1 * width, 0.0),
                           Lb + side * min(reach + width, abs(limit - Lb))))
            grid = phase_grid(phase, a, b, _TRANSFER_PER_TURN, base=16)
            for family in ARC_FAMILY_FREE:
                def shooting(p: float, f: str = family) -> np.ndarray:
                    return clamped_half_arc_matrix(p, Lb, s.b1, s.b2, f)

                found = matrix_roots(shooting, a, b, grid=grid,
                                     method_name=f"half-arc shooting, {family} family")
                xs = [r.x for r in found.roots if (r.x - Lb) * side > 0]
                if xs:
                    x = min(xs, key=lambda v: abs(v - Lb))
                    if nearest is None or abs(x - Lb) < abs(nearest - Lb):
                        nearest = x
            reach += width
            width *= 2.0
        if nearest is None:
            raise NotConverged(f"clamped arc transfer (b1 = {s.b1:g}, b2 = {s.b2:g}, "
                               f"L/R = {Lb:g}): no load {'below' if side < 0 else 'above'} "
                               f"L/R up to {limit:g}, where test fields prove one")
        ends.append(nearest)
    return ends[0], ends[1]


def _transfer(params: Params) -> dict[str, float]:
    lo, hi = transfer_interval(params)
    return {"L_kappa_n_lower": lo, "L_kappa_n_upper": hi}


def _fe(params: Params) -> dict[str, float]:
    lo, hi = engine_stability(params).load_factor_interval
    return {"L_kappa_n_lower": to_paper(lo, params)["L_kappa_n"],
            "L_kappa_n_upper": to_paper(hi, params)["L_kappa_n"]}


def _nonlinear(params: Params) -> dict[str, float]:
    # Upwards from the stress-free state; the analytic scan window bounds the first root.
    L, _, kn = _geometry(params)
    p0 = float(params.L_over_R)
    span = 4.0 * math.pi * max(params.section.sqrt_b1b2, 1.0) + p0
    mu = nonlinear_converged(build(params), p0 / (L * kn), (p0 + span) / (L * kn),
                             NONLINEAR_ELEMENTS)
    return {"L_kappa_n_upper": to_paper(mu, params)["L_kappa_n"]}


#: Methods that solve the clamped arc, each returning the stable interval of ``L kappa_n``.
METHODS: dict[str, Method] = {"analytic": _analytic, "transfer": _transfer, "fe": _fe,
                              "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # (3.7)/(3.8) vs the shooting matrix: both exact, root-finder tolerance.
    ("analytic", "transfer"): 1e-8,
    # FE mesh refined until its estimated error is 1e-7 (Richardson, converged_stability).
    ("analytic", "fe"): 1e-6,
    # Discrete rod, Richardson-extrapolated from meshes refined until it holds (at 32
    # elements alone 6 of 350 random arcs with b1 >= 80 were off by more than 5e-3).
    ("analytic", "nonlinear"): 5e-3,
}
