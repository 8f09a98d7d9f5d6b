"""Section 2 of the paper: kinematics (2.1)-(2.11) and the quadratic energy (2.12)."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from .. import kinematics, transfer
from ..analytic import ring
from .core import Claim, Run, fmt
from .rules import (
    DIFFERS,
    FD_TOL,
    ORDER_TOL,
    REPRODUCED,
    ROOT_RTOL,
    ROUNDOFF_RTOL,
    every,
    methods_agree,
    order_is,
    residual_below,
    typo_shown_by,
)

#: What the project claims for each row of :func:`section2_checks`.
EXPECTED = {
    "2.1": REPRODUCED,
    "2.10": REPRODUCED,
    "2.11": DIFFERS,
    "2.12a": REPRODUCED,
    "2.12b": DIFFERS,
    "2.12c": REPRODUCED,
}

#: Radius of the reference circle of the displacement-field check of (2.11).
_R_2_11 = 1.7
#: Step of the fourth-order central differences along s (see ``rules.FD_TOL``).
_FD_STEP = 1e-3


def _large_state(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """O(1) smooth Euler angles (alpha, beta, gamma)(s): a genuinely nonlinear state."""
    a = 0.9 * np.sin(1.3 * s + 0.4) + 0.3
    b = 0.7 * np.cos(0.8 * s) - 0.2 * s
    g = 1.1 * np.sin(0.6 * s - 1.0) + 0.5 * np.cos(2.1 * s)
    return a, b, g


def _reference_displacement(s: np.ndarray, R: float) -> np.ndarray:
    """``(u_r, u_theta, u_3)`` at ``s``, shape ``(len(s), 3)``, on the rotating basis.

    The centreline ``r(s) = R i_r(0) + int_0^s e2 ds'`` (40-point Gauss-Legendre, exact to
    round-off for this smooth tangent) with ``e2`` of the frame (2.1); ``u = r - R i_r(s/R)``.
    """
    x, w = np.polynomial.legendre.leggauss(40)
    nodes = 0.5 * s[:, None] * (x + 1.0)
    e2 = (kinematics.frame(*_large_state(nodes)) @ kinematics.reference_basis(nodes / R))[..., 1, :]
    r = np.array([R, 0.0, 0.0]) + np.einsum("sn,snc->sc", 0.5 * s[:, None] * w, e2)
    basis = kinematics.reference_basis(s / R)
    return np.einsum("sic,sc->si", basis, r - R * basis[:, 0, :])


def phi3_sign_errors(R: float = _R_2_11) -> tuple[float, float]:
    """Test (2.11)'s middle member against an integrated displacement field.

    Returns ``(printed, corrected)``: ``max |D - phi_3|`` (as printed in (2.11),
    ``phi_3 = du_r/ds - u_theta/R``) and ``max |D + phi_3|`` (the definition in (2.5)), with
    ``D = du_r/ds - u_theta/R`` from :func:`_reference_displacement` by fourth-order central
    differences and ``phi_3 = -sin(beta) sin(gamma)`` from :func:`rodstab.kinematics.axis_strains`.
    """
    s, h = np.linspace(0.2, 3.0, 15), _FD_STEP
    u = _reference_displacement(s, R)
    um2, um1, up1, up2 = (_reference_displacement(s + k * h, R) for k in (-2, -1, 1, 2))
    du = (um2 - 8 * um1 + 8 * up1 - up2) / (12 * h)
    D = du[:, 0] - u[:, 1] / R
    _, beta, gamma = _large_state(s)
    phi3 = kinematics.axis_strains(beta, gamma)[2]
    return float(np.max(np.abs(D - phi3))), float(np.max(np.abs(D + phi3)))


def section2_checks(run: Run) -> Iterator[Claim]:
    """Rows of Section 2: the frame (2.1), the expansions (2.10), (2.11) and the energy (2.12)."""
    rng = np.random.default_rng(1)
    ang = rng.uniform(-1.5, 1.5, size=(200, 3))
    F = kinematics.frame(ang[:, 0], ang[:, 1], ang[:, 2])
    orth = float(np.max(np.abs(F @ np.swapaxes(F, -1, -2) - np.eye(3))))
    dets = np.linalg.det(F)
    yield Claim("2.1", "2", "(2.1)", "Embedded basis e_i from the Euler angles is orthonormal",
                "orthonormal, right-handed", f"max|F F^T - I| = {orth:.1e}",
                f"min det F = {dets.min():.15f}", "determinant",
                every(residual_below(orth, ROUNDOFF_RTOL),
                      methods_agree(dets, 1.0, ROUNDOFF_RTOL)))
    orders = kinematics.remainder_orders()
    orders_inf = kinematics.remainder_orders(R=math.inf)
    names = ("kappa1", "kappa2", "kappa3")
    yield Claim(
        "2.10", "2.1", "(2.10)",
        "kappa1, kappa2 have no quadratic terms (error O3); kappa3 has no cubic terms (O4)",
        "orders 3, 3, 4", "measured orders " + ", ".join(fmt(orders[k], 3) for k in names),
        "straight state: " + ", ".join(fmt(orders_inf[k], 3) for k in names),
        "log-log slope of |(2.8) - (2.10)| vs amplitude; symbolic (sympy) in the tests",
        order_is([orders[k] for k in names] + [orders_inf[k] for k in names],
                 [3, 3, 4, 3, 3, 4], ORDER_TOL))
    printed, corrected = phi3_sign_errors()
    yield Claim(
        "2.11", "2.1", "(2.11)", "phi_3 = (du_r/ds - u_theta/R) = -beta gamma",
        "(du_r/ds - u_theta/R) = -beta gamma", "du_r/ds - u_theta/R = +beta gamma",
        f"max |D - phi_3| = {printed:.1e} (as printed), max |D + phi_3| = {corrected:.1e} "
        "(as (2.5)), D = du_r/ds - u_theta/R",
        "displacement field integrated from e2 of (2.1), 4th-order differences",
        typo_shown_by(printed, corrected, FD_TOL),
        "Sign typo in the middle member: (2.5) gives phi_3 = -(du_r/ds - u_theta/R) "
        "= -beta gamma. No consequence: phi_3 plays no role in the bifurcation problems.")
    en = kinematics.energy_remainder_order()
    yield Claim(
        "2.12a", "2.2", "(2.12)", "SE = SE0 + P2 is accurate to O4 (no cubic terms)",
        "O4", f"measured order {fmt(en['energy'], 3)}", "sympy: cubic terms vanish (tests)",
        "log-log slope of |SE(2.9) - SE0 - P2| for a generic state with M != 0",
        order_is(en["energy"], 4, ORDER_TOL),
        "True for any state, not only symmetric ones: the density is even in the angles.")
    yield Claim(
        "2.12b", "2.2", "(2.12)", "End term of P2: + 2 B3 M alpha beta / R |_0^L",
        "coefficient 2", "coefficient 1: + B3 M alpha beta / R |_0^L",
        f"with the printed 2 the energy error is O{fmt(en['energy_printed_end_term'], 2)} "
        f"instead of O4 (O{fmt(en['energy'], 2)} with 1)",
        "sympy exact-derivative term (tests) and measured remainder order",
        typo_shown_by(abs(en["energy_printed_end_term"] - 4), abs(en["energy"] - 4), ORDER_TOL),
        "Coefficient typo; it vanishes for rings and clamped arcs, so no result of "
        "the paper depends on it.")
    yield _uniform_twist_claim()


def _uniform_twist_claim() -> Claim:
    """End of Section 2.2: the integrand of P2 for uniform twist and the threshold M = b1."""
    b1, b2, R = 1.0, 0.75, 1.0
    r = ring.ring_stability(b1, b2, 1)
    j0 = next(m for m in r.modes if m.j == 0)
    mono = transfer.ring_interval_transfer(b1, b2, 1)[1]
    # (2.12) with beta = 0, omega = const: the braces are (b1 - M) omega^2 / R^2 (B3 = 1).
    Ms, omega = np.linspace(-2.0, 2.0, 9), 0.3
    braces = [2 * float(kinematics.p2_density(0.0, 0.0, omega, 0.0, R=R, B1=b1, B2=b2, B3=1.0,
                                              M=M)) for M in Ms]
    return Claim(
        "2.12c", "2.2", "end of 2.2",
        "Uniform axisymmetric twist: integrand (b1 - M) alpha^2, unstable iff M > b1",
        "M < b1", f"j = 0 mode stable for M < {fmt(j0.upper)} (b1 = 1)",
        f"monodromy root at M = {fmt(mono)}",
        "periodic solutions of (3.1) (transfer matrix)",
        every(methods_agree(braces, (b1 - Ms) * omega**2 / R**2, ROUNDOFF_RTOL, ROUNDOFF_RTOL),
              methods_agree([j0.upper, mono], b1, ROOT_RTOL)))
