"""Beyond the paper: nonlinear critical loads against the linear engine.

For the straightened rod (Section 3.2), the bi-rod (Section 4) and the folded ring (Section 5).
"""

from __future__ import annotations

from collections.abc import Iterator

from ..linear.solve import linear_stability
from ..problems import birod, folded_ring, straightened_rod
from ..sections import circle
from .core import Claim, Run, fmt
from .rules import NONLINEAR_RTOL, REPRODUCED, methods_agree

#: What the project claims for each row of :func:`critical_checks`.
EXPECTED = {"NL-straightened": REPRODUCED, "NL-bi-rod": REPRODUCED, "NL-folded": REPRODUCED}

_NL = "discrete geometrically exact rod, lowest Hessian eigenvalue"


def critical_checks(run: Run) -> Iterator[Claim]:
    """For each structure (circle, nu = 1/3): nonlinear vs linear critical load (NL-*)."""
    from ..nonlinear.solve import critical_load_factor

    c = circle()
    structures_ = [("straightened clamped rod",
                    straightened_rod.build(straightened_rod.Params()), 1.0, 8.0, 32),
                   ("bi-rod", birod.build(birod.Params(section=c)), 0.5, 4.0, 24),
                   ("folded six-sided ring", folded_ring.build(folded_ring.Params(section=c)), 0.2,
                    2.0, 8)]
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
