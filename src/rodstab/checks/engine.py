"""The linear FE engine against the analytic results of Section 3 (a third method for them)."""

from __future__ import annotations

from collections.abc import Iterator

from ..problems import clamped_arc, ring
from ..sections import circle
from .core import Claim, Run, fmt
from .rules import FE_RTOL, REPRODUCED, methods_agree

#: What the project claims for each row of :func:`engine_checks`.
EXPECTED = {"E3.1-N1": REPRODUCED, "E3.1-N3": REPRODUCED, "E3.2": REPRODUCED}

_FE = "FE engine (rodstab.linear), quadratic beta + omega"


def engine_checks(run: Run) -> Iterator[Claim]:
    """N-loop rings (3.3) and a clamped arc (3.7)/(3.8) by the general FE engine."""
    c = circle()
    for N in (1, 3):
        params = ring.Params(section=c, loops=N)
        r = ring.engine_stability(params)  # refined from 150 per loop to its accuracy
        n = r.elements * N
        an = ring.analytic_stability(params).M_interval
        got = tuple(ring.to_paper(mu, params)["M"] for mu in r.load_factor_interval[::-1])
        err = max(abs(g - a) / abs(a) for g, a in zip(got, an, strict=True))
        yield Claim(f"E3.1-N{N}", "3.1", "(3.3)", f"{N}-loop ring interval of M by the engine",
                    f"({fmt(an[0])}, {fmt(an[1])}) (analytic)", f"({fmt(got[0])}, {fmt(got[1])})",
                    f"rel. difference {err:.1e} ({n} elements)", _FE,
                    methods_agree(got, an, FE_RTOL))
    arc_params = clamped_arc.Params(section=c, L_over_R=2.0)
    r = clamped_arc.engine_stability(arc_params)
    an = clamped_arc.analytic_stability(arc_params).L_kappa_interval
    got = tuple(clamped_arc.to_paper(mu, arc_params)["L_kappa_n"]
                for mu in r.load_factor_interval)
    err = max(abs(g - a) / abs(a) for g, a in zip(got, an, strict=True))
    yield Claim("E3.2", "3.2", "(3.7)/(3.8)", "Clamped arc L/R = 2 by the engine",
                f"({fmt(an[0])}, {fmt(an[1])}) (analytic)", f"({fmt(got[0])}, {fmt(got[1])})",
                f"rel. difference {err:.1e} ({r.elements} elements)", _FE,
                methods_agree(got, an, FE_RTOL))
