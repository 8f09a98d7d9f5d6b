"""Straightened rod of Section 3.2: a naturally curved rod held straight, eq. (3.9).

Clamped at ``s = 0``, sliding clamp at ``s = L`` (free along the rod, as the paper's remark
before (3.9) requires). Natural curvature ``kappa_n = mu`` (``B3 = 1``); the paper's limit is
``L kappa_n = 2 pi sqrt(B1 B2) / B3`` (3.9), i.e. ``lambda = L kappa_n / sqrt(b1 b2) = 2 pi``.
"""

from __future__ import annotations

import math

from ..analytic.arc import straight_clamped_critical
from ..linear.solve import LinearStability
from ..model import Assembly
from ..numerics import matrix_roots
from ..transfer import clamped_arc_matrix
from ._common import Method, StraightRodParams, clamped_sliding_rod, engine, nonlinear_critical

#: Elements of the linear engine (the report's NL-straightened row).
DEFAULT_ELEMENTS = 32
#: Elements of the nonlinear rod in :data:`METHODS` (second-order error, ~3e-3).
NONLINEAR_ELEMENTS = 32
#: The paper's critical load (3.9): ``lambda_c = 2 pi``.
PAPER_LAMBDA_C = 2 * math.pi


#: Straightened rod: ``section`` (default circle, nu = 1/3) and ``length`` L.
Params = StraightRodParams


def build(params: Params) -> Assembly:
    """Return the straight rod ``rod``, natural curvature 1 per unit ``mu``, clamped / sliding."""
    return clamped_sliding_rod(params.section, params.length, 1.0)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return ``L_kappa_n = mu L`` and ``lambda = mu L / sqrt(b1 b2)`` of (3.9)."""
    return {"L_kappa_n": mu * params.length,
            "lambda": mu * params.length / params.section.sqrt_b1b2}


def engine_stability(params: Params, elements: int = DEFAULT_ELEMENTS) -> LinearStability:
    """Stable interval of the load factor ``mu = kappa_n`` by the linear FE engine."""
    return engine(build(params), elements)


def _lam(mu: float, params: Params) -> dict[str, float]:
    return {"lambda": to_paper(mu, params)["lambda"]}


def _analytic(params: Params) -> dict[str, float]:
    s = params.section
    return _lam(straight_clamped_critical(s.b1, s.b2) / params.length, params)


def _transfer(params: Params) -> dict[str, float]:
    # Shooting matrix of the clamped straight rod (L/R = 0) in p = L kappa_n; the sliding clamp
    # is a clamp for the linear P2 (remark before (3.9)).
    s = params.section
    roots = matrix_roots(lambda p: clamped_arc_matrix(p, 0.0, s.b1, s.b2), 0.1 * s.sqrt_b1b2,
                         12.0 * s.sqrt_b1b2, n_scan=400).values
    return _lam(roots[0] / params.length if roots else math.nan, params)


def _fe(params: Params) -> dict[str, float]:
    return _lam(engine_stability(params).load_factor_critical, params)


def _nonlinear(params: Params) -> dict[str, float]:
    # From the stress-free straight rod (mu = 0) up to lambda = 4 pi.
    g_over_L = params.section.sqrt_b1b2 / params.length
    return _lam(nonlinear_critical(build(params), 0.0, 4 * math.pi * g_over_L,
                                   NONLINEAR_ELEMENTS), params)


#: Methods that solve the straightened rod, each returning the critical ``lambda`` (3.9).
METHODS: dict[str, Method] = {"analytic": _analytic, "transfer": _transfer, "fe": _fe,
                              "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # (3.9) vs the shooting matrix: both exact, root-finder tolerance.
    ("analytic", "transfer"): 1e-8,
    # FE mesh error at DEFAULT_ELEMENTS (observed 2e-6, fourth order).
    ("analytic", "fe"): 1e-5,
    # Discrete rod at NONLINEAR_ELEMENTS: second-order mesh error (report row NL-straightened).
    ("analytic", "nonlinear"): 5e-3,
}
