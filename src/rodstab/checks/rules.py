"""The named rules that turn a computed comparison into a report status.

Every status in the report comes from one of these functions; none is written as a constant.

* ``reproduced``: the computation confirms the paper's statement (value, equation, verdict).
* ``differs``: the computation confirms a corrected form and refutes the printed one (a typo or
  an error of the paper; the row's note gives the evidence and the consequence). A reproduction
  rule (:func:`agrees_to_printed`, :func:`methods_agree`, ...) also returns it when its
  comparison fails.
* ``unresolved``: the evidence supports neither the printed form nor rodstab's correction
  (only :func:`typo_shown_by` returns it): rodstab's own check is broken.

The tolerances are named below with their meaning; each rule takes the one that fits.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

REPRODUCED = "reproduced"
DIFFERS = "differs"
UNRESOLVED = "unresolved"
STATUSES = (REPRODUCED, DIFFERS, UNRESOLVED)

#: A measured power-law exponent (log-log slope of an error against the amplitude) against the
#: theoretical one: findiff's convention, observed = expected +- 0.2.
ORDER_TOL = 0.2
#: Two evaluations of one closed form or identity in double precision (a few hundred ulps).
ROUNDOFF_RTOL = 1e-12
#: Two independent root solvers of one eigenproblem (closed form or a pencil eigen solve vs a
#: transfer-matrix singular-value scan refined to ``numerics.XTOL``); observed <= 1e-13.
ROOT_RTOL = 1e-8
#: Trapezoid or Gauss quadrature of a smooth (periodic) integrand vs its closed form.
QUADRATURE_TOL = 1e-10
#: Fourth-order central differences (step 1e-3) of an integrated field: truncation ~h^4 and
#: round-off ~1e-16/h both stay below it.
FD_TOL = 1e-8
#: A first variation computed from P2 (2.12) vs the one predicted by a printed ODE system, relative
#: to its size: polynomial fields, exact Gauss quadrature, so only round-off separates them.
VARIATION_RTOL = 1e-10
#: FE engine (quadratic beta and omega) vs an exact eigenvalue at the meshes used in the
#: report (error ~h^4, observed <= 5e-7 relative).
FE_RTOL = 1e-6
#: A critical mode from the shooting null vector vs its closed form (3.10), pointwise, both
#: normalised to u3 = 1 at mid-span.
MODE_TOL = 1e-6
#: Discrete nonlinear rod (second order in the element size, coarse meshes) vs the linear engine.
NONLINEAR_RTOL = 5e-3
#: A Richardson-extrapolated discrete value vs its exact or analytic value.
RICHARDSON_RTOL = 1e-3
#: Koiter's imperfection-sensitivity exponent 2/3 vs the measured slope of log |p_c - p_max|.
KOITER_TOL = 0.02


def _status(ok: bool) -> str:
    return REPRODUCED if ok else DIFFERS


def agrees_to_printed(value: float, printed: float, digits: int) -> str:
    """Return ``reproduced`` if ``value`` agrees with the printed number, else ``differs``.

    Agreement means to one unit of its last printed decimal (``digits`` decimals).

    The paper sometimes truncates (-0.86156 printed as -0.861), sometimes rounds; both pass.
    """
    return _status(abs(value - printed) < 10.0**-digits)


def methods_agree(a: ArrayLike, b: ArrayLike, rtol: float, atol: float = 0.0) -> str:
    """``reproduced`` when two computations agree elementwise, ``|a - b| <= atol + rtol |b|``.

    ``a`` and ``b`` are numbers or sequences of equal length (e.g. all roots found by two
    methods; a number is compared with every entry of a sequence); different lengths (one
    method found a root the other did not) never agree.
    """
    x, y = np.atleast_1d(np.asarray(a, dtype=float)), np.atleast_1d(np.asarray(b, dtype=float))
    if x.shape != y.shape and 1 not in (x.size, y.size):
        return DIFFERS
    return _status(bool(np.all(np.abs(x - y) <= atol + rtol * np.abs(y))))


def order_is(measured: float | Sequence[float], expected: float | Sequence[float],
             tol: float = ORDER_TOL) -> str:
    """Return ``reproduced`` if every measured exponent is within ``tol`` of the expected one.

    An exponent is the order of a remainder or the slope of a power law.
    """
    m, e = np.atleast_1d(np.asarray(measured, dtype=float)), np.asarray(expected, dtype=float)
    return _status(bool(np.all(np.abs(m - e) <= tol)))


def residual_below(residual: float, tol: float) -> str:
    """Return ``reproduced`` if a computed residual of the paper's statement is at most ``tol``.

    The residual of an identity, an ODE or a closed form evaluated on independently computed data.
    """
    return _status(bool(residual <= tol))


def typo_shown_by(printed_error: ArrayLike, corrected_error: ArrayLike, tol: float) -> str:
    """Status of a printed equation or value tested against rodstab's correction of it.

    ``printed_error`` and ``corrected_error`` measure, on the same computed evidence (one number
    per independent method), how far the printed form and the corrected form miss it. Returns
    ``reproduced`` when the printed form passes (every error <= ``tol``), ``differs`` when it
    fails and the corrected form passes, ``unresolved`` when neither passes.
    """
    printed_ok = bool(np.all(np.asarray(printed_error, dtype=float) <= tol))
    corrected_ok = bool(np.all(np.asarray(corrected_error, dtype=float) <= tol))
    if printed_ok:
        return REPRODUCED
    return DIFFERS if corrected_ok else UNRESOLVED


def holds(condition: bool | np.bool_) -> str:
    """Return ``reproduced`` if a computed comparison holds.

    Inequalities between computed values, e.g. a stability margin or the sign of a load change along
    a branch.
    """
    return _status(bool(condition))


def every(*statuses: str) -> str:
    """Combine the statuses of several comparisons that together check one statement.

    ``reproduced`` only if all are; ``unresolved`` if any is; ``differs`` otherwise.
    """
    if all(s == REPRODUCED for s in statuses):
        return REPRODUCED
    return UNRESOLVED if UNRESOLVED in statuses else DIFFERS

