"""Beyond the paper: nonlinear critical loads against the linear engine.

For the straightened rod (Section 3.2), the bi-rod (Section 4) and the folded ring (Section 5).
"""

from __future__ import annotations

from collections.abc import Iterator

from .. import structures
from ..linear.solve import linear_stability
from ..model import Assembly, Segment
from ..sections import Section, circle
from .core import Claim, Run, fmt
from .rules import NONLINEAR_RTOL, REPRODUCED, methods_agree

#: What the project claims for each row of :func:`critical_checks`.
EXPECTED = {"NL-straightened": REPRODUCED, "NL-bi-rod": REPRODUCED, "NL-folded": REPRODUCED}

_NL = "discrete geometrically exact rod, lowest Hessian eigenvalue"


def straightened_rod(section: Section | None = None) -> Assembly:
    """Return the straightened rod of (3.9): unit length, clamped / sliding clamp.

    The default section is a circle (nu = 1/3).
    """
    c = circle() if section is None else section
    s = Segment("rod", 1.0, 0.0, 1.0, c.b1, c.b2, 1.0)
    return Assembly((s,), supports=(("rod", "start", "clamped"),
                                    ("rod", "end", "sliding-clamp")))


def critical_checks(run: Run) -> Iterator[Claim]:
    """For each structure (circle, nu = 1/3): nonlinear vs linear critical load (NL-*)."""
    from ..nonlinear.solve import critical_load_factor

    c = circle()
    structures_ = [("straightened clamped rod", straightened_rod(), 1.0, 8.0, 32),
                   ("bi-rod", structures.birod(c), 0.5, 4.0, 24),
                   ("folded six-sided ring", structures.folded_ring(c), 0.2, 2.0, 8)]
    for name, a, lo, hi, n in structures_:
        engine = linear_stability(a, 64)
        lin = engine.load_factor_critical
        crit = critical_load_factor(a, lo, hi, elements_per_segment=n).load_factor_critical
        yield Claim(
            f"NL-{name.split()[0]}", "beyond", "-", f"{name}: nonlinear vs linear critical load",
            "-", f"{fmt(crit)} ({n} elements/segment)", f"linear engine {fmt(lin)}", _NL,
            methods_agree(crit, lin, NONLINEAR_RTOL),
            f"difference {100 * (crit - lin) / lin:.2f} % (second-order convergence, tests)")
        run.progress()
