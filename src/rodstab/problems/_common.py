"""Shared helper of the problem modules: a segment in the units of :mod:`rodstab.problems`."""

from __future__ import annotations

from ..model import Segment
from ..sections import Section


def segment(name: str, section: Section, L: float, k: float, kn: float,
            start: tuple[float, float] = (0.0, 0.0), angle: float = 0.0) -> Segment:
    """Return a segment with ``B3 = 1`` and the stiffness ratios of ``section``."""
    return Segment(name=name, length=L, curvature=k, natural_curvature=kn, B1=section.b1,
                   B2=section.b2, B3=1.0, start=start, angle=angle)
