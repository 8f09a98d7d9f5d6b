"""Straightened rod of Section 3.2: a naturally curved rod held straight, eq. (3.9).

Clamped at ``s = 0``, sliding clamp at ``s = L`` (free along the rod, as the paper's remark
before (3.9) requires). Natural curvature ``kappa_n = mu`` (``B3 = 1``); the paper's limit is
``L kappa_n = 2 pi sqrt(B1 B2) / B3`` (3.9), i.e. ``lambda = L kappa_n / sqrt(b1 b2) = 2 pi``.
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import require_positive
from ..model import Assembly
from ..sections import Section, circle
from ._common import segment

#: Elements of the linear engine (the report's NL-straightened row).
DEFAULT_ELEMENTS = 32
#: The paper's critical load (3.9): ``lambda_c = 2 pi``.
PAPER_LAMBDA_C = 2 * math.pi


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Straightened rod: ``section`` (default circle, nu = 1/3) and ``length`` L."""

    section: Section = dataclasses.field(default_factory=circle)
    length: float = 1.0

    def __post_init__(self) -> None:
        """Validate: positive length."""
        require_positive("length", self.length)


def build(params: Params) -> Assembly:
    """Return the straight rod ``rod``, natural curvature 1 per unit ``mu``, clamped / sliding."""
    s = segment("rod", params.section, float(params.length), 0.0, 1.0)
    return Assembly(segments=(s,), supports=(("rod", "start", "clamped"),
                                             ("rod", "end", "sliding-clamp")))


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``L_kappa_n = mu L`` and ``lambda = mu L / sqrt(b1 b2)`` of (3.9)."""
    return {"L_kappa_n": mu * params.length,
            "lambda": mu * params.length / params.section.sqrt_b1b2}
