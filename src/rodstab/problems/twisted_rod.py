"""Greenhill's twisted rod (beyond the paper, report rows GR-rot, PB-twist, IMP-twist).

A straight rod without natural curvature, clamped at ``s = 0`` and held at ``s = L`` by a clamp
that slides along the rod (zero axial force), twisted by a rotation ``phi`` of that clamp about
the rod's tangent (the parameter :data:`LOAD_KEY` of the continuation). Units: ``B3 = 1``. The
load is the end rotation, not a natural curvature: the held straight state is not an
equilibrium once the end turns, so only the nonlinear model solves this assembly. Paper-style
units: ``phi B2 / (B L)`` (``B = B1 = B3``), Greenhill's ``2 x`` with ``tan x = x``.
"""

from __future__ import annotations

from ..analytic.twisted_rod import greenhill_end_rotation
from ..model import Assembly
from ._common import Method, StraightRodParams, clamped_sliding_rod, richardson

#: Elements of the nonlinear rod (the model that solves this assembly).
DEFAULT_ELEMENTS = 16
#: The continuation parameter: rotation (radians) of the sliding clamp about the tangent.
LOAD_KEY = "support.1.rotation.tangent"
#: Largest ``phi B2 / (B L)`` searched by the nonlinear method (Greenhill's 8.99 is inside),
#: and the number of continuation steps to it.
ROTATION_WINDOW = 10.8
ROTATION_STEPS = 14
#: Meshes Richardson-extrapolated by the nonlinear method of :data:`METHODS` (the mesh error
#: is 2 % at 16 elements, order 2; row GR-rot).
NONLINEAR_MESHES = (16, 32)


#: Twisted rod: ``section`` (default circle, nu = 1/3) and ``length`` L.
Params = StraightRodParams


def build(params: Params) -> Assembly:
    """Return the straight rod ``rod``: clamped at its start, sliding clamp at its end."""
    return clamped_sliding_rod(params.section, params.length, 0.0)


def to_paper(phi: float, params: Params) -> dict[str, float]:
    """Return ``phi`` (radians) and ``phi_B2_over_BL = phi B2 / (B1 L)`` of end rotation ``phi``."""
    return {"phi": phi,
            "phi_B2_over_BL": phi * params.section.b2 / (params.section.b1 * params.length)}


def nonlinear_critical_rotation(params: Params, elements: int = DEFAULT_ELEMENTS) -> float:
    """Critical end rotation ``phi_c`` (radians): first special point of the continuation.

    :func:`rodstab.nonlinear.continuation.continuation` in :data:`LOAD_KEY` from 0 up to
    ``phi B2 / (B L) = ROTATION_WINDOW`` (Hessian eigenvalue sign change, located).
    """
    from ..nonlinear.continuation import continuation

    s = params.section
    stop = ROTATION_WINDOW * s.b1 * params.length / s.b2
    cont = continuation(build(params), LOAD_KEY, 0.0, stop, ROTATION_STEPS,
                        elements_per_segment=elements, branch_steps=0, stop_at_first=True)
    points = cont.special_points
    return float(points[0]["value"]) if points else float("nan")


def _analytic(params: Params) -> dict[str, float]:
    return {"phi_B2_over_BL": greenhill_end_rotation(params.section.b1, params.section.b2)}


def _nonlinear(params: Params) -> dict[str, float]:
    coarse, fine = (to_paper(nonlinear_critical_rotation(params, n), params)["phi_B2_over_BL"]
                    for n in NONLINEAR_MESHES)
    return {"phi_B2_over_BL": richardson(coarse, fine)}


#: Methods that solve the twisted rod, each returning the critical ``phi B2 / (B L)``.
METHODS: dict[str, Method] = {"analytic": _analytic, "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # Discrete rod, Richardson of NONLINEAR_MESHES: second-order mesh error removed.
    ("analytic", "nonlinear"): 5e-3,
}
