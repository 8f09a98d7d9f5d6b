"""Beyond the paper: Greenhill's twisted rod under end rotation.

Continuation in a rotation, and the one unstable bifurcation found, with Koiter's 2/3 law measured.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from ..analytic.twisted_rod import greenhill_end_rotation
from ..problems import twisted_rod
from ..sections import circle
from .core import Claim, Run, fmt
from .rules import KOITER_TOL, REPRODUCED, RICHARDSON_RTOL, holds, methods_agree, order_is

#: What the project claims for each row of :func:`twisted_rod_checks`.
EXPECTED = {"GR-rot": REPRODUCED, "PB-twist": REPRODUCED, "IMP-twist": REPRODUCED}


def twisted_rod_checks(run: Run) -> Iterator[Claim]:
    """Greenhill's threshold phi_c B2 / (B L) = 2 x (root of tan x = x), and beyond it."""
    from ..nonlinear.continuation import continuation, imperfection_sensitivity

    params = twisted_rod.Params(section=circle(nu=0.3))  # b1 = 1, b2 = 1/1.3
    b2 = params.section.b2
    rod = twisted_rod.build(params)
    key = twisted_rod.LOAD_KEY
    exact = greenhill_end_rotation(params.section.b1, b2)
    x = exact / 2
    vals = []
    for n in (16, 32, 64):
        cont = continuation(rod, key, 0.0, 14.0, 14, elements_per_segment=n, branch_steps=0,
                            stop_at_first=True)
        vals.append(twisted_rod.to_paper(cont.special_points[0]["value"],
                                         params)["phi_B2_over_BL"])
    run.progress()
    rich = vals[2] + (vals[2] - vals[1]) / 3
    yield Claim(
        "GR-rot", "beyond", "-", "Twisted clamped rod (Greenhill) by end rotation",
        f"phi_c B2 / (B L) = 2 x {fmt(x, 5)} = {fmt(exact, 5)} (tan x = x, closed form)",
        f"{fmt(vals[0], 5)}, {fmt(vals[1], 5)}, {fmt(vals[2], 5)} (16/32/64 elements); "
        f"Richardson {fmt(rich, 5)}",
        f"closed form {fmt(exact, 6)}",
        "pseudo-arclength continuation in the end rotation, Hessian eigenvalue sign change",
        methods_agree(rich, exact, RICHARDSON_RTOL),
        "Continuation in an end rotation (rotation control, end free to slide, zero axial "
        "force) reaches Greenhill's threshold at second order; one end rotation of "
        f"{fmt(exact / b2, 4)} rad for a circle with nu = 0.3.")
    cont = continuation(rod, key, 0.0, 13.0, 13, elements_per_segment=16, branch_steps=8)
    (br,) = cont.branches
    run.progress()
    fall = min(br.value) / br.value_critical
    yield Claim(
        "PB-twist", "beyond", "-", "Twisted rod: initial post-buckling under rotation control",
        "-", br.verdict,
        f"end rotation falls to {fmt(fall, 5)} phi_c at amplitude "
        f"{fmt(max(np.abs(br.amplitude)), 3)} L",
        "branch switching along the critical mode (phase of the double mode pinned)",
        holds(fall < 1 and "subcritical" in br.verdict),
        "Unlike the three structures of the paper, the twisted rod buckles subcritically: "
        "once buckled it needs less rotation (it snaps towards a loop).")
    imp = imperfection_sensitivity(rod, key, 0.0, 13.0,
                                   epsilons=(2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3),
                                   elements_per_segment=16, n_steps=20)
    run.progress()
    yield Claim(
        "IMP-twist", "beyond", "-", "Twisted rod: imperfection sensitivity exponent",
        "Koiter: 2/3 for an unstable symmetric bifurcation", f"{fmt(imp.exponent, 4)}",
        "limit rotations / phi_c: " + ", ".join(fmt(v / imp.value_critical, 5)
                                                for v in imp.limit_value)
        + f" for eps = {', '.join(f'{e:g}' for e in imp.epsilon)} L",
        "folds of the imperfect paths (arclength continuation); slope of log |phi_c - phi_max|",
        order_is(imp.exponent, 2 / 3, KOITER_TOL),
        "The knock-down follows Koiter's law: 1 - phi_max/phi_c = C eps^(2/3).")
    run.beyond()["twisted"] = {"phi_c": imp.value_critical, "epsilon": imp.epsilon,
                               "limit": list(imp.limit_value), "exponent": imp.exponent}
