"""Ready-made assemblies of the paper and beyond: bi-rod, folded and unfolded 2n-sided rings.

Every builder returns a :class:`rodstab.model.Assembly` in consistent units chosen so that the
load factor ``mu`` multiplies the natural curvature given here: ``B3 = 1`` and the stiffness
ratios of the section; lengths as stated. The paper's load factor is
``lam = B3 kappa_n L / sqrt(B1 B2) = mu kappa_n L / sqrt(b1 b2)`` (:func:`paper_load_factor`).
"""

from __future__ import annotations

import math

from .errors import RodstabInputError, require_positive, require_positive_int
from .model import Assembly, Segment
from .sections import Section


def _seg(name: str, section: Section, L: float, k: float, kn: float,
         start=(0.0, 0.0), angle: float = 0.0) -> Segment:
    return Segment(name, L, k, kn, section.b1, section.b2, 1.0, tuple(start), angle)


def paper_load_factor(section: Section, kappa_n: float, L: float) -> float:
    """``lam = B3 kappa_n L / sqrt(B1 B2)`` of Sections 4-5 for ``B3 = 1``."""
    return kappa_n * L / section.sqrt_b1b2


def birod(section: Section, *, length: float = 1.0, clamp: str | None = "start") -> Assembly:
    """Section 4: rods of natural curvature +1 and -1 (per unit ``mu``), welded at both ends.

    ``clamp``: ``"start"`` (the paper: one end clamped), ``"both"``, or ``None`` (free; the
    three rigid motions are gauged out).
    """
    L = require_positive("length", length)
    segs = (_seg("upper", section, L, 0.0, 1.0), _seg("lower", section, L, 0.0, -1.0))
    welds = ((("upper", "start"), ("lower", "start")), (("upper", "end"), ("lower", "end")))
    if clamp not in ("start", "both", None):
        raise RodstabInputError(f"clamp must be 'start', 'both' or None, got {clamp!r}")
    sup: tuple[tuple[str, str, str], ...] = (
        () if clamp is None else (("upper", "start", "clamped"),))
    if clamp == "both":
        sup += (("upper", "end", "clamped"),)
    return Assembly(segs, welds=welds, supports=sup, reference_load=0.0)


def folded_ring(section: Section, *, segments: int = 6, length: float = 1.0) -> Assembly:
    """Section 5: ``2n`` straight segments stacked into the folded ``n``-loop state.

    Segment ``i`` runs from ``x = 0`` to ``x = L`` with natural curvature (per unit ``mu``)
    ``-1`` for odd ``i``, ``+1`` for even ``i`` (``Delta kappa_0`` of (5.1)); odd segments are
    joined to the next at ``x = L``, even ones at ``x = 0`` (Fig. 8), the last to the first.
    """
    n_seg = require_positive_int("segments", segments)
    if n_seg < 2 or n_seg % 2:
        raise RodstabInputError(f"segments must be an even number >= 2, got {segments!r}")
    L = require_positive("length", length)
    segs = tuple(_seg(str(i), section, L, 0.0, -1.0 if i % 2 else 1.0)
                 for i in range(1, n_seg + 1))
    welds = tuple(((str(i), "end" if i % 2 else "start"),
                   (str(i % n_seg + 1), "end" if i % 2 else "start"))
                  for i in range(1, n_seg + 1))
    return Assembly(segs, welds=welds, reference_load=0.0)


def unfolded_ring(section: Section, *, segments: int = 6, arc_angle_deg: float = 120.0,
                  radius: float = 1.0) -> Assembly:
    """Return the one-loop state of a ring of ``segments`` circular arcs joined at cusps (Fig. 1).

    Every arc turns left by ``arc_angle_deg`` on radius ``R0``; at each cusp the tangent
    reverses. Natural curvature ``1/R0`` per unit ``mu`` (``mu = 1``: stress-free one-loop
    state). Raises if the chain of arcs does not close.
    """
    n = require_positive_int("segments", segments)
    R0 = require_positive("radius", radius)
    theta = math.radians(require_positive("arc_angle_deg", arc_angle_deg))
    segs = []
    pos, ang = (0.0, 0.0), 0.0
    for i in range(1, n + 1):
        s = _seg(str(i), section, theta * R0, 1.0 / R0, 1.0 / R0, pos, ang)
        segs.append(s)
        end = s.end_point("end")
        t = s.tangent(s.length)
        pos, ang = (float(end[0]), float(end[1])), math.atan2(-t[1], -t[0])
    welds = tuple(((str(i), "end"), (str(i % n + 1), "start")) for i in range(1, n + 1))
    return Assembly(tuple(segs), welds=welds)
