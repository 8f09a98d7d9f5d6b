"""Beyond the paper: imperfection sensitivity of the straightened rod and the folded ring."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ..problems import folded_ring, straightened_rod
from ..sections import rectangle
from .core import Claim, Run, fmt
from .rules import KOITER_TOL, REPRODUCED, holds, order_is

#: What the project claims for each row of :func:`imperfection_checks`.
EXPECTED = {"IMP-straight": REPRODUCED, "IMP-folded": REPRODUCED}


def imperfection_checks(run: Run) -> Iterator[Claim]:
    """Limit loads of imperfect structures (imperfection = eps L x critical mode)."""
    from ..nonlinear.continuation import imperfection_sensitivity

    straight = straightened_rod.build(straightened_rod.Params())
    stop = 6.2
    imp = imperfection_sensitivity(straight, "load_factor", 1.0, stop,
                                   epsilons=(1e-3, 4e-3, 1.6e-2), elements_per_segment=12,
                                   n_steps=25)
    run.progress()
    passed = [max(p for p, _ in path) > imp.value_critical for path in imp.paths]
    yield Claim(
        "IMP-straight", "beyond", "-", "Straightened rod: imperfection sensitivity",
        "open question (paper, Section 6)", imp.verdict,
        f"limit loads up to {fmt(stop / imp.value_critical, 3)} mu_c: "
        + ", ".join("none" if math.isnan(v) else fmt(v) for v in imp.limit_value),
        "imperfection = eps L x critical mode in the natural shape; arclength continuation",
        holds(all(math.isnan(v) for v in imp.limit_value) and all(passed)),
        "Consistent with the stable symmetric branch: imperfections only round "
        "the bifurcation off (every imperfect path passes mu_c without a limit point). The "
        "exponent law needs an unstable bifurcation: see IMP-twist.")
    beyond = run.beyond()
    beyond["imperfection"] = {"mu_c": imp.value_critical, "epsilon": imp.epsilon,
                              "paths": [list(p) for p in imp.paths]}
    fold = folded_ring.build(folded_ring.Params(section=rectangle(aspect=4.0)))
    impf = imperfection_sensitivity(fold, "load_factor", 1.0, 6.0,
                                    epsilons=(2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3),
                                    elements_per_segment=8, n_steps=20)
    run.progress()
    kd = np.abs(np.array(impf.limit_value) - impf.value_critical)
    local = float(np.log(kd[1] / kd[0]) / np.log(impf.epsilon[1] / impf.epsilon[0]))
    segment = fold.segments[0].length / fold.total_length  # a segment, in units of L
    yield Claim(
        "IMP-folded", "beyond", "5", "Folded six-sided ring (h/t = 4): imperfection sensitivity",
        "open question (paper, Section 6)",
        "knock-down 1 - mu_max/mu_c = " + ", ".join(fmt(v, 3) for v in kd / impf.value_critical)
        + f" for eps = {', '.join(f'{e:g}' for e in impf.epsilon)} L",
        f"exponent {fmt(impf.exponent, 3)} over the range, {fmt(local, 3)} at the two smallest "
        "amplitudes (Koiter: 2/3)",
        "folds of the imperfect paths (arclength continuation, 8 el./segment)",
        order_is(local, 2 / 3, KOITER_TOL),
        "New: the folded ring is imperfection-sensitive (its bifurcation is unstable, PB-folded):"
        f" an imperfection of {fmt(100 * impf.epsilon[-1], 2)} % of the ring's length L "
        f"({fmt(100 * impf.epsilon[-1] / segment, 2)} % of a segment length) lowers the limit by "
        f"{fmt(100 * kd[-1] / impf.value_critical, 2)} %. The local exponent rises towards "
        "Koiter's 2/3 as eps -> 0.")
    beyond["imperfection_folded"] = {"mu_c": impf.value_critical, "epsilon": impf.epsilon,
                                     "limit": list(impf.limit_value)}
