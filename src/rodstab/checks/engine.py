"""The linear FE engine against the analytic results of Section 3 (a third method for them)."""

from __future__ import annotations

import math
from collections.abc import Iterator

from ..analytic import arc, ring
from ..linear.solve import linear_stability
from ..model import Assembly, Segment
from ..sections import circle
from .core import Claim, Run, fmt
from .rules import FE_RTOL, REPRODUCED, methods_agree

#: What the project claims for each row of :func:`engine_checks`.
EXPECTED = {"E3.1-N1": REPRODUCED, "E3.1-N3": REPRODUCED, "E3.2": REPRODUCED}

_FE = "FE engine (rodstab.linear), Hermite w + quadratic omega"


def engine_checks(run: Run) -> Iterator[Claim]:
    """N-loop rings (3.3) and a clamped arc (3.7)/(3.8) by the general FE engine."""
    c = circle()
    for N, n in ((1, 150), (3, 450)):
        seg = Segment(name="ring", length=2 * math.pi * N, curvature=1.0, natural_curvature=1.0,
                      B1=c.b1, B2=c.b2, B3=1.0)
        ring_ = Assembly(segments=(seg,), welds=((("ring", "start"), ("ring", "end")),))
        r = linear_stability(ring_, n)
        an = ring.ring_stability(c.b1, c.b2, N).M_interval
        got = (1 - r.load_factor_interval[1], 1 - r.load_factor_interval[0])
        err = max(abs(g - a) / abs(a) for g, a in zip(got, an, strict=True))
        yield Claim(f"E3.1-N{N}", "3.1", "(3.3)", f"{N}-loop ring interval of M by the engine",
                    f"({fmt(an[0])}, {fmt(an[1])}) (analytic)", f"({fmt(got[0])}, {fmt(got[1])})",
                    f"rel. difference {err:.1e} ({n} elements)", _FE,
                    methods_agree(got, an, FE_RTOL))
    seg = Segment(name="arc", length=2.0, curvature=1.0, natural_curvature=1.0, B1=c.b1, B2=c.b2,
                  B3=1.0)
    r = linear_stability(Assembly(segments=(seg,), supports=(("arc", "start", "clamped"),
                                                             ("arc", "end", "clamped"))), 96)
    an = arc.clamped_arc_stability(c.b1, c.b2, 2.0).L_kappa_interval
    got = (2 * r.load_factor_interval[0], 2 * r.load_factor_interval[1])
    err = max(abs(g - a) / abs(a) for g, a in zip(got, an, strict=True))
    yield Claim("E3.2", "3.2", "(3.7)/(3.8)", "Clamped arc L/R = 2 by the engine",
                f"({fmt(an[0])}, {fmt(an[1])}) (analytic)", f"({fmt(got[0])}, {fmt(got[1])})",
                f"rel. difference {err:.1e} (96 elements)", _FE, methods_agree(got, an, FE_RTOL))
