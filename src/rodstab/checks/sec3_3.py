"""Section 3.3 of the paper: Michell's twisted ring, eqs. (3.21)-(3.26)."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ..analytic import michell
from ..numerics import richardson
from ..problems import michell as michell_problem
from ..sections import circle
from .core import Claim, Run, fmt
from .rules import (
    DIFFERS,
    FD_TOL,
    QUADRATURE_TOL,
    REPRODUCED,
    RICHARDSON_RTOL,
    ROOT_RTOL,
    ROUNDOFF_RTOL,
    agrees_to_printed,
    every,
    holds,
    methods_agree,
    typo_shown_by,
)

#: What the project claims for each row of :func:`michell_checks`.
EXPECTED = {"3.26": REPRODUCED, "3.24a": REPRODUCED, "3.24b": DIFFERS, "3.26c": REPRODUCED,
            "3.26b": REPRODUCED}

#: Points of the periodic grid on which gamma(theta) is differentiated numerically.
_N_THETA = 4096


def beta_gamma_prime_errors(j: int = 2, r: float = -math.sqrt(3) / 2) -> tuple[float, float]:
    """Test the expression for ``(beta gamma')^2`` in (3.24): ``(printed, corrected)`` errors.

    From the mode (3.23), ``beta cos(gamma) = b j cos(j theta)``, ``beta sin(gamma) =
    -a (j^2 - 1) sin(j theta)`` with ``b j = 1``, ``a (j^2 - 1) = r``: ``gamma`` by ``atan2``
    (unwrapped), ``gamma'`` by fourth-order central differences on a periodic grid. Returns the
    largest relative error of the printed ``(bj)^2 j^4 r^2 / (cos^2 + r^2 sin^2)`` and of the
    corrected ``(bj)^2 j^2 r^2 / (cos^2 + r^2 sin^2)``.
    """
    th = np.linspace(0.0, 2 * np.pi, _N_THETA, endpoint=False)
    h = th[1]
    x, y = np.cos(j * th), -r * np.sin(j * th)
    gamma = np.unwrap(np.arctan2(y, x))
    # gamma is periodic up to a multiple of 2 pi: difference the periodic part.
    winding = (gamma[-1] + (gamma[1] - gamma[0]) - gamma[0]) / (2 * np.pi)
    per = gamma - np.round(winding) * th
    dper = (np.roll(per, 2) - 8 * np.roll(per, 1) + 8 * np.roll(per, -1)
            - np.roll(per, -2)) / (12 * h)
    measured = (x * x + y * y) * (dper + np.round(winding)) ** 2
    den = np.cos(j * th) ** 2 + r * r * np.sin(j * th) ** 2
    printed, corrected = (k * r * r / den for k in (j**4, j**2))
    return (float(np.max(np.abs(printed - measured) / measured)),
            float(np.max(np.abs(corrected - measured) / measured)))


def michell_checks(run: Run) -> Iterator[Claim]:
    """Rows of Section 3.3 (Michell's problem)."""
    params = michell_problem.Params(section=circle())  # b2 = 0.75 (nu = 1/3), one loop
    m = michell_problem.analytic_stability(params)
    t_paper = michell.michell_critical_paper_route(2)
    yield Claim("3.26", "3.3", "(3.26)", "Michell: b2 omega0' = sqrt(3), j = 2, r = -sqrt(3)/2",
                f"{fmt(math.sqrt(3))}, j = 2, r = {fmt(-math.sqrt(3) / 2)}",
                f"{fmt(m.b2_omega0_critical)}, j = {m.mode_j}, r = {fmt(m.r_critical)}",
                fmt(t_paper), "quadrature of (3.21) along the paper's polar route (3.23)-(3.24)",
                every(methods_agree(m.b2_omega0_critical, math.sqrt(3), ROUNDOFF_RTOL),
                      methods_agree(t_paper, math.sqrt(3), ROOT_RTOL),
                      agrees_to_printed(m.mode_j, 2, 0),
                      methods_agree(m.r_critical, -math.sqrt(3) / 2, ROUNDOFF_RTOL)))
    th = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    rr = 0.7
    integral = float(np.mean(np.sin(th) ** 2 * np.cos(th) ** 2
                             / (np.cos(th) ** 2 + rr**2 * np.sin(th) ** 2)) * 2)
    yield Claim("3.24a", "3.3", "after (3.24)", "(1/pi) int sin^2 cos^2/(cos^2 + r^2 sin^2) "
                "= (1 + |r|)^-2", f"{fmt((1 + rr) ** -2)} (r = 0.7)", fmt(integral),
                "trapezoid rule", "quadrature",
                methods_agree(integral, (1 + rr) ** -2, 0.0, QUADRATURE_TOL))
    printed, corrected = beta_gamma_prime_errors()
    yield Claim("3.24b", "3.3", "(3.24)", "(beta gamma')^2 = (bj)^2 j^4 r^2 / (...)",
                "j^4", "j^2 (from beta^2 gamma' = -(bj)^2 j r and beta^2)",
                f"gamma' differentiated from (3.23), j = 2: rel. error {printed:.1e} with j^4, "
                f"{corrected:.1e} with j^2; (3.25)/(3.26) use j^2 and are right",
                "atan2 of (3.23), 4th-order differences; quadrature (claim 3.26)",
                typo_shown_by(printed, corrected, FD_TOL),
                "Typo in (3.24) only; (3.25) and the result are correct.")
    v32, v64 = (michell_problem.nonlinear_critical_twist(params, n) for n in (32, 64))
    rich = richardson(v32, v64, 2.0, 2)[0]
    yield Claim("3.26c", "3.3", "(3.26)", "Michell by the nonlinear rod (third method)",
                fmt(math.sqrt(3)), f"{fmt(v64, 5)} (64 el.), {fmt(v32, 5)} (32 el.)",
                f"Richardson (order 2): {fmt(rich, 5)}",
                "discrete geometrically exact ring with natural twist, continuation along the "
                "primary path", methods_agree(rich, math.sqrt(3), RICHARDSON_RTOL))
    m3 = michell_problem.analytic_stability(michell_problem.Params(section=circle(), loops=3))
    # (3.26) with j -> j/N, r = 0: N (k^2 - 1) < 0 whatever the twist t = b2 omega0'.
    closed = tuple(j for j in range(1, 7) if all(
        michell.michell_p2_closed_form(t, j, 0.0, loops=3) < 0 for t in (-5.0, 0.0, 5.0)))
    yield Claim("3.26b", "3.3", "end of 3.3", "3-loop ring unstable at every twist (j = 1, 2)",
                "unstable for any omega0'",
                f"unstable modes j = {list(m3.unstable_modes)} at zero twist",
                f"(3.26) with j/N: k^2 - 1 < 0 for j = {list(closed)}", "closed form",
                holds(not m3.stable_at_zero_twist and m3.unstable_modes == closed == (1, 2)))
