"""Pure bending of naturally curved rods clamped at their ends (paper Section 3.2).

Equations (3.5)-(3.10) and (3.13)-(3.15). Non-dimensional: ``x = s/L``, ``Lbar = L/R``,
``M = 1 - R kappa_n``, ``b1 = B1/B3``, ``b2 = B2/B3``; the load reported to users is
``L kappa_n = Lbar (1 - M)``, which stays finite in the straight limit ``Lbar -> 0``.

The characteristic equations are written with ``lam2 = lam^2`` (eq 3.6), which is negative when
``(b1 - M)(b2 - M) < 0``; the functions below are entire in ``lam2``, so (3.7) and (3.14) are
one function and no branch switch is needed. Factors that vanish without being eigenvalues are
divided out (each removal is confirmed by the transfer-matrix method, which has no such roots):

* ``M = 0`` (the stress-free state: ``lam = q = 1``) zeroes both (3.7) and (3.8) for every
  ``Lbar``, because two functions of the general solution (3.5) coincide there;
* ``M = b2`` (``lam = q = 0``): (3.7) carries the exact factor ``q``, and (3.8) vanishes there
  too, because ``cos(lam Lbar x)`` merges with the constant of (3.5);
* (3.8) has a factor ``lam``.

The transfer-matrix method of :mod:`rodstab.transfer` (no general solution, no factorisation)
is the independent check of every root found here.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from ..errors import RodstabInputError, require_in_range, require_positive
from ..numerics import XTOL, Root, find_roots, multiplicity_tolerance
from ..results import Result

#: Largest argument of sinh/cosh evaluated (beyond it the value overflows a double).
_EXP_CAP = 700.0
#: Distance (relative) kept from the removable singularities M = 0 and M = b2.
_SINGULAR_GUARD = 1e-9


def arc_wavenumbers(M: float, b1: float, b2: float) -> tuple[float, float]:
    """Return ``(lam2, q)`` of eq (3.6): ``lam2 = (b1 - M)(b2 - M)/(b1 b2)``, ``q = (b2 - M)/b2``.

    ``lam2 < 0`` is the case of eq (3.14) (``lam`` imaginary, hyperbolic functions).
    """
    return (b1 - M) * (b2 - M) / (b1 * b2), (b2 - M) / b2


def _sinc_lam(lam2: float, z: float) -> float:
    """``sin(lam z) / lam``, entire in ``lam2`` (``sinh(mu z)/mu`` for ``lam2 = -mu^2``)."""
    if lam2 > 0:
        lam = math.sqrt(lam2)
        return math.sin(lam * z) / lam
    if lam2 < 0:
        mu = math.sqrt(-lam2)
        if mu * abs(z) > _EXP_CAP:  # overflow: the scan treats non-finite values as no data
            return math.copysign(math.inf, z)
        return math.sinh(mu * z) / mu
    return z


def _cos_lam(lam2: float, z: float) -> float:
    """``cos(lam z)``, entire in ``lam2`` (``cosh(mu z)`` for ``lam2 = -mu^2``)."""
    if lam2 >= 0:
        return math.cos(math.sqrt(lam2) * z)
    if math.sqrt(-lam2) * abs(z) > _EXP_CAP:
        return math.inf
    return math.cosh(math.sqrt(-lam2) * z)


def _symmetric_bracket(M: float, L_over_R: float, b1: float, b2: float) -> float:
    """``((b1 - M)/b1) sin(lam a)/lam cos(a) - cos(lam a) sin(a)``: (3.7) divided by ``q``."""
    lam2, _ = arc_wavenumbers(M, b1, b2)
    a = 0.5 * L_over_R
    return (b1 - M) / b1 * _sinc_lam(lam2, a) * math.cos(a) - _cos_lam(lam2, a) * math.sin(a)


def _antisymmetric_bracket(M: float, L_over_R: float, b1: float, b2: float) -> float:
    """(3.8) divided by ``lam``."""
    lam2, q = arc_wavenumbers(M, b1, b2)
    a = 0.5 * L_over_R
    s_l, c_l = _sinc_lam(lam2, a), _cos_lam(lam2, a)
    return (2 * (1 - q) * math.sin(a) * s_l - L_over_R * math.sin(a) * c_l
            + q * L_over_R * math.cos(a) * s_l)


def symmetric_function(M: float, L_over_R: float, b1: float, b2: float) -> float:
    """Left side of the symmetric-mode equation (3.7) (= (3.14) when ``lam2 < 0``), reduced.

    (3.7) is ``lam sin(lam a) cos(a) - q cos(lam a) sin(a)``, ``a = Lbar/2``; it equals
    ``q [((b1 - M)/b1) sin(lam a)/lam cos(a) - cos(lam a) sin(a)]``. The factor ``q`` and the
    spurious simple zero at ``M = 0`` are removed: the bracket is divided by ``M``.
    """
    return _symmetric_bracket(M, L_over_R, b1, b2) / M


def antisymmetric_function(M: float, L_over_R: float, b1: float, b2: float) -> float:
    """Left side of the antisymmetric-mode equation (3.8), divided by ``lam M (b2 - M)``.

    (3.8) is ``2(1 - q) sin(a) sin(lam a) - lam Lbar sin(a) cos(lam a)
    + q Lbar cos(a) sin(lam a)``; see the module docstring for the removed factors.
    """
    return _antisymmetric_bracket(M, L_over_R, b1, b2) / (M * (b2 - M))


def _guarded(M: float, b1: float, b2: float) -> float:
    """Nudge ``M`` off the removable singularities ``M = 0`` and ``M = b2``."""
    for s in (0.0, b2):
        g = _SINGULAR_GUARD * (1.0 + abs(s))
        if abs(M - s) < g:
            return s + (g if M >= s else -g)
    return M


#: Largest accepted L/R (about 1600 turns). Checked up to here: an 8x denser scan gives the
#: same interval to 1e-11 (tests/test_arc.py); beyond, the phase of (3.7)/(3.8), ~ L/R, costs
#: the characteristic functions more digits than their roots can spare (|f| at the roots grows
#: past 1e-2 at L/R = 1e5).
L_OVER_R_MAX = 1e4
#: Smallest accepted L/R > 0 (0 itself is the straight limit, solved by its own equations).
#: The reduced functions divide by L/R: at 1e-14 they lost every digit and the interval came
#: out 5600x too narrow, reported converged; at 1e-200 they overflowed (math domain error).
#: Found by benchmarks/fuzz.py; at 1e-10 the interval still agrees with the straight limit.
L_OVER_R_MIN = 1e-8
#: Root kinds of :func:`rodstab.numerics.find_roots` that are bracketed and refined to its
#: tolerance (a "touching" root is a minimum of |f| and needs its residual checked instead).
_BRACKETED = ("sign-change", "grid-point")


@dataclasses.dataclass(frozen=True)
class ArcStability(Result):
    """Stable range of the natural curvature of a clamped arc (Section 3.2).

    ``L_kappa_interval = (lower, upper)``: the arc of ``L/R`` is stable for
    ``lower < L kappa_n < upper``; ``upper`` is the branch ``kappa_n > 1/R`` plotted in Fig. 3,
    ``lower`` the branch ``kappa_n < 1/R``. ``critical_mode`` names the family (``"symmetric"``
    or ``"antisymmetric"``) that sets ``upper``; ``lower_mode`` the one that sets ``lower``.
    """

    L_over_R: float
    b1: float
    b2: float
    L_kappa_interval: tuple[float, float]
    M_interval: tuple[float, float]
    critical_mode: str
    lower_mode: str
    residual: float
    converged: bool
    method: str


#: Doublings of :func:`_first_root`'s window before it gives up.
_MAX_DOUBLINGS = 6


def _first_root(fun, p0: float, direction: float, span: float,
                max_doublings: int = _MAX_DOUBLINGS):
    """First root of ``fun(p)`` beyond ``p0`` in ``direction``; the window doubles if empty."""
    # The scan starts a little away from p0 (M = 0): the reduced functions have a removable
    # singularity there whose value is swamped by round-off and could fake a sign change. The
    # stress-free state is stable with a finite margin (P2 is positive definite at M = 0), so no
    # critical load lies that close to it.
    for _ in range(max_doublings + 1):
        delta = 1e-6 * span
        lo, hi = (p0 + delta, p0 + span) if direction > 0 else (p0 - span, p0 - delta)
        found = find_roots(fun, lo, hi, n_scan=400)
        roots = [r for r in found.roots if (r.x - p0) * direction > 10 * delta]
        if roots:
            return min(roots, key=lambda r: abs(r.x - p0))
        span *= 2.0
    return None


def clamped_arc_stability(b1: float, b2: float, L_over_R: float) -> ArcStability:
    """Stable interval of ``L kappa_n`` for a rod bent into an arc ``L/R`` and clamped (3.7/3.8).

    Both families are searched with the one root finder, outward from the stress-free state
    ``L kappa_n = L/R`` (``M = 0``), in the load variable ``p = L kappa_n``
    (``M = 1 - p / Lbar``). ``L_over_R = 0`` is the straight limit (3.9) and is solved with the
    limiting equations ``sin(lam/2) = 0`` (symmetric) and ``tan(lam/2) = lam/2``
    (antisymmetric), ``lam = L kappa_n / sqrt(b1 b2)``.
    """
    b1 = require_positive("b1", b1)
    b2 = require_positive("b2", b2)
    Lb = require_in_range("L_over_R", L_over_R, 0.0, L_OVER_R_MAX,
                          "at most ~1600 turns, where the characteristic equations keep "
                          "their digits")
    if 0.0 < Lb < L_OVER_R_MIN:
        raise RodstabInputError(
            f"L_over_R must be 0 (the straight limit) or in [{L_OVER_R_MIN:g}, "
            f"{L_OVER_R_MAX:g}] (below, the characteristic equations lose their digits), "
            f"got {L_over_R!r}")
    g = math.sqrt(b1 * b2)
    # The critical loads lie within ~2 pi sqrt(b1 b2) of the stress-free L/R for every L/R
    # (|L kappa_n - L/R| -> 5.3856 for b1 = 1, b2 = 0.75 as L/R grows), so the first window
    # does not grow with L/R: a window ~ L/R scanned at 400 points stepped over them (at
    # L/R = 1e9 the "roots" were 2.5e6 away, with |f| = 1.5e4, reported converged).
    span = 4.0 * math.pi * max(g, 1.0) + min(Lb, 4.0 * math.pi)
    if Lb == 0.0:
        # Clamped-clamped column u"" + lam^2 u'' = 0, lam = p / sqrt(b1 b2): symmetric
        # sin(lam/2) = 0; antisymmetric tan(lam/2) = lam/2 in its pole-free product form.
        funs = {
            "symmetric": lambda p: math.sin(0.5 * p / g),
            "antisymmetric": lambda p: (math.sin(0.5 * p / g)
                                        - 0.5 * p / g * math.cos(0.5 * p / g)),
        }
        p0 = 0.0
    else:
        funs = {
            "symmetric": lambda p: symmetric_function(_guarded(1 - p / Lb, b1, b2), Lb, b1, b2),
            "antisymmetric": lambda p: antisymmetric_function(_guarded(1 - p / Lb, b1, b2),
                                                              Lb, b1, b2),
        }
        p0 = Lb
    upper: dict[str, Root | None] = {}
    lower: dict[str, Root | None] = {}
    for name, fun in funs.items():
        upper[name] = _first_root(fun, p0, +1.0, span)
        lower[name] = _first_root(fun, p0, -1.0, span)

    bracketed = all(r.kind in _BRACKETED for d in (upper, lower) for r in d.values()
                    if r is not None)

    def pick(d: dict[str, Root | None], direction: float) -> tuple[float, str, float]:
        cands = [(r.x, n, r.residual) for n, r in d.items() if r is not None]
        if not cands:
            return (math.inf * direction, "none", 0.0)
        best = min(cands, key=lambda c: abs(c[0] - p0))
        # Both families at the same load (L/R = 2 pi: the ends meet) is a double eigenvalue,
        # by the one multiplicity rule with the roots' tolerance (find_roots' Brent
        # refinement, XTOL times the scanned window, which reaches 2^6 span).
        if len(cands) == 2 and abs(cands[0][0] - cands[1][0]) <= multiplicity_tolerance(
                best[0], XTOL * span * 2 ** _MAX_DOUBLINGS):
            return best[0], "symmetric+antisymmetric", best[2]
        return best

    up, up_mode, up_res = pick(upper, +1.0)
    dn, dn_mode, dn_res = pick(lower, -1.0)
    if Lb == 0.0:
        M_int = (-math.inf, math.inf)
    else:
        M_int = (1 - up / Lb, 1 - dn / Lb)
    return ArcStability(
        L_over_R=Lb, b1=b1, b2=b2, L_kappa_interval=(dn, up), M_interval=M_int,
        critical_mode=up_mode, lower_mode=dn_mode, residual=max(up_res, dn_res),
        converged=bracketed and math.isfinite(up) and (Lb == 0.0 or math.isfinite(dn)),
        method="characteristic equations (3.7)/(3.14) and (3.8), scan + Brent",
    )


@dataclasses.dataclass(frozen=True)
class MaxArcLength(Result):
    """Longest straight rod (``kappa_n = 0``) that can be bent into a stable clamped arc."""

    b1: float
    b2: float
    L_over_R_max: float
    critical_mode: str
    residual: float
    method: str


def max_arc_length(b1: float, b2: float, *, L_over_R_cap: float = 40.0) -> MaxArcLength:
    """Largest stable ``L/R`` of a clamped arc bent from a straight rod, eqs (3.13)/(3.14).

    ``M = 1``. Both the symmetric (3.13/3.14) and the antisymmetric (3.8 at ``M = 1``) families
    are searched over ``0 < L/R <= L_over_R_cap``; the lower root wins. For ``b1 = 1``
    (``lam = 0``) the symmetric equation reduces to ``q sin(L/2R) = 0``: ``L/R = 2 pi``.
    """
    b1 = require_positive("b1", b1)
    b2 = require_positive("b2", b2)
    best: tuple[float, str, float] | None = None
    # The reduced forms are used (not the raw brackets): near b2 = 1 the raw (3.8) carries the
    # factor (b2 - M) -> 0 for every L/R and would be numerically zero. M is nudged off the
    # removable points M = b2 (and b1 = b2 = 1, where both factors vanish together).
    for name, fn in (("symmetric", symmetric_function), ("antisymmetric", antisymmetric_function)):
        # Only (3.8) is divided by (b2 - M): only it needs M nudged off b2.
        M = _guarded(1.0, b1, b2) if name == "antisymmetric" else 1.0
        # L/R -> 0 is a trivial zero of both brackets (no arc); a straight rod with
        # kappa_n = 0 is stable, so the scan starts at L/R = 1e-3.
        def bracket(L: float, M: float = M, fn: Callable[..., float] = fn) -> float:
            return fn(M, L, b1, b2)

        found = find_roots(bracket, 1e-3, L_over_R_cap, n_scan=800)
        if found.roots:
            r = found.roots[0]
            if best is None or r.x < best[0]:
                best = (r.x, name, r.residual)
    if best is None:
        return MaxArcLength(b1, b2, math.inf, "none", 0.0, "no root below the cap")
    return MaxArcLength(b1, b2, best[0], best[1], best[2],
                        "eqs (3.13)/(3.14) and (3.8) at M = 1, scan + Brent")


def straight_clamped_critical(b1: float, b2: float) -> float:
    """Critical ``L kappa_n = 2 pi sqrt(b1 b2)`` of the straightened clamped rod, eq (3.9)."""
    return 2.0 * math.pi * math.sqrt(require_positive("b1", b1) * require_positive("b2", b2))


def straight_clamped_mode(b1: float, b2: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mode (3.10) at the critical load, ``s = L (x - 1/2)``: ``(u3/L, omega)`` with ``c = 1``."""
    s = np.asarray(x) - 0.5
    u = 1.0 + np.cos(2 * np.pi * s)
    return u, -2 * np.pi * math.sqrt(b1 / b2) * u


def energy_ratio_column_to_straightened(
    *, b1: float, b2: float, area: float, I_min: float, I3: float, L: float
) -> float:
    """``SE_Euler column / SE_straightened rod`` at their critical states, generalising (3.15).

    Clamped-clamped Euler column at ``P = 4 pi^2 E I_min / L^2`` stores ``P^2 L / (2 E A)``; the
    straightened clamped rod at (3.9) stores ``B3 (L kappa_n)^2 / (2 L)``. Their ratio is
    ``4 pi^2 I_min^2 / (A L^2 I3 b1 b2)``; for a circle of radius ``r`` it is
    ``(1 + nu) pi^2 (r/L)^2``, eq (3.15). Lengths in any one unit.
    """
    for name, v in (("area", area), ("I_min", I_min), ("I3", I3), ("L", L)):
        require_positive(name, v)
    return 4 * math.pi**2 * I_min**2 / (area * L**2 * I3 * b1 * b2)
