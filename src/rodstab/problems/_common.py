"""Shared helpers of the problem modules: segments, the type of a method, engine solves.

A segment in the units of :mod:`rodstab.problems` (``B3 = 1``), the type of an entry of a
module's ``METHODS``, and the linear and nonlinear solves that every module shares.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

from ..errors import require_positive
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..linear.solve import LinearStability, linear_stability
from ..model import Assembly, Segment
from ..sections import Section, circle

#: A solution method of a problem: ``Params -> {paper quantity: critical value}``, the values
#: in the paper's units (the keys of the module's ``to_paper``, possibly suffixed
#: ``_lower``/``_upper`` for the two ends of a stable interval).
Method = Callable[[Any], dict[str, float]]


def segment(name: str, section: Section, L: float, k: float, kn: float,
            start: tuple[float, float] = (0.0, 0.0), angle: float = 0.0,
            natural_twist: float = 0.0) -> Segment:
    """Return a segment with ``B3 = 1`` and the stiffness ratios of ``section``.

    ``L`` length, ``k`` held curvature, ``kn`` natural curvature per unit load factor,
    ``natural_twist`` per unit load factor (nonlinear model only).
    """
    return Segment(name=name, length=L, curvature=k, natural_curvature=kn, B1=section.b1,
                   B2=section.b2, B3=1.0, start=start, angle=angle, natural_twist=natural_twist)


@dataclasses.dataclass(frozen=True, kw_only=True)
class StraightRodParams:
    """A straight rod: ``section`` (default circle, nu = 1/3) and ``length`` L (> 0)."""

    section: Section = dataclasses.field(default_factory=circle)
    length: float = 1.0

    def __post_init__(self) -> None:
        """Validate: positive length."""
        require_positive("length", self.length)


def clamped_sliding_rod(section: Section, L: float, kn: float) -> Assembly:
    """Return the straight rod ``rod``: clamped at its start, sliding clamp at its end.

    Natural curvature ``kn`` per unit load factor. The sliding clamp lets the end move along
    the rod (the paper's modified support before (3.9)), so an inextensible rod can deflect.
    """
    s = segment("rod", section, float(L), 0.0, kn)
    return Assembly(segments=(s,), supports=(("rod", "start", "clamped"),
                                             ("rod", "end", "sliding-clamp")))


def engine(assembly: Assembly, elements: int, limits: Limits = DEFAULT_LIMITS
           ) -> LinearStability:
    """Linear stability of ``assembly`` by the FE engine with ``elements`` per segment."""
    return linear_stability(assembly, elements, limits=limits)


def nonlinear_critical(assembly: Assembly, lo: float, hi: float, elements: int) -> float:
    """First load factor in ``(lo, hi]`` where the held state of the discrete rod loses stability.

    :func:`rodstab.nonlinear.solve.critical_load_factor` (where the lowest Hessian eigenvalue
    crosses zero: the Hessian pencil's first singular load); the held state must be an
    equilibrium at every load (untwisted, no end rotation).
    """
    from ..nonlinear.solve import critical_load_factor

    found = critical_load_factor(assembly, lo, hi, elements_per_segment=elements)
    return found.load_factor_critical


def nonlinear_converged(assembly: Assembly, lo: float, hi: float, start: int) -> float:
    """:func:`nonlinear_critical` Richardson-extrapolated from meshes fine enough for it.

    :func:`rodstab.nonlinear.solve.converged_critical_load_factor` from ``start`` elements per
    segment (doubled until the Richardson estimate of the error is below
    :data:`~rodstab.nonlinear.solve.CONVERGED_RTOL`, relative above 1); returns the
    extrapolated value. Raises :class:`~rodstab.errors.NotConverged` with the estimate reached
    when it does not converge by :data:`~rodstab.nonlinear.solve.CONVERGED_MAX_ELEMENTS`.
    """
    from ..errors import NotConverged
    from ..nonlinear.solve import converged_critical_load_factor

    found = converged_critical_load_factor(assembly, lo, hi, elements_per_segment=int(start))
    if not found.converged:
        raise NotConverged(f"the discrete rod's critical load factor did not settle: "
                           f"{found.method}")
    return found.load_factor_critical


def richardson(coarse: float, fine: float) -> float:
    """Second-order Richardson extrapolation from a mesh and the mesh twice as fine.

    :func:`rodstab.numerics.richardson` with ratio 2, order 2 (the discrete rod's order).
    """
    from ..numerics import richardson as extrapolate

    return extrapolate(coarse, fine, 2.0, 2)[0]
