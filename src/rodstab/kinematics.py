"""Kinematics of an inextensible Kirchhoff rod about a circular or straight reference state.

Implements Section 2 of the paper (eqs. 2.1-2.12) and its straight-state special case (4.1):

* (2.1)        embedded frame ``(e1, e2, e3)`` from the Euler angles ``(alpha, beta, gamma)``;
* (2.4), (2.5) centreline stretch and rotations read off the tangent ``e2``;
* (2.8)        exact curvatures ``(kappa1, kappa2, kappa3)``; ``R = inf`` gives (4.1);
* (2.10)       their quadratic (moderate-rotation) expansion, ``omega = alpha + gamma``;
* (2.9)        strain energy density; (2.12) its quadratic part ``P2``;
* numerical measurement of the truncation orders claimed below (2.10) and (2.12).

Frames. The reference basis ``(i_r, i_theta, i_3)`` is right-handed, ``i_r`` points outward from
the reference circle of radius ``R``, ``i_theta`` is its tangent in the direction of increasing
``theta = s / R`` and ``i_3`` is normal to its plane, so that ``d i_r/ds = i_theta / R`` and
``d i_theta/ds = -i_r / R``. Components "on (i_r, i_theta, i_3)" are called *reference*
components; curvatures are components on the embedded frame ``(e1, e2, e3)`` (``Omega = kappa_i
e_i``, below (2.8)). For a straight reference state (``R = inf``) the reference basis is constant.

Findings about the paper's Section 2 (derived in ``tests/test_kinematics.py`` with sympy and by
an independent finite-difference evaluation of (2.7)):

* (2.1), (2.4), (2.5), (2.8), (2.9), (2.10), (4.1) agree. The truncation claims of (2.10) are true:
  ``kappa1``, ``kappa2`` are odd and ``kappa3`` is even in ``(alpha, beta, gamma)``, so the first
  two have no quadratic and the third no cubic terms; the cubic terms of ``kappa1``, ``kappa2`` are
  non-zero, so the errors are exactly ``O(eps^3)``, ``O(eps^3)``, ``O(eps^4)``.
* (2.12): the integrand of ``P2`` agrees, but the boundary term is ``B3 M alpha beta / R |_0^L``,
  not ``2 B3 M alpha beta / R |_0^L`` as printed (it stands outside the factor 1/2). It vanishes for
  rings and clamped arcs (``alpha beta |_0^L = 0``), the cases Section 2.2 names. ``SE`` has no
  cubic term (the energy density is even in the angles), so ``SE0 + P2`` is accurate to
  ``O(eps^4)``, also for non-symmetric perturbations.
* (2.11): the middle member of ``phi_3 = (du_r/ds - u_theta/R) = -beta gamma`` lacks the minus
  sign of its definition in (2.5); ``du_r/ds - u_theta/R = +sin(beta) sin(gamma)``.

Only numpy is needed at run time.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import RodstabInputError, require_finite, require_positive

__all__ = [
    "axis_strains",
    "curvatures",
    "curvatures_second_order",
    "energy_remainder_order",
    "frame",
    "p2_boundary_term",
    "p2_density",
    "reference_basis",
    "remainder_orders",
    "strain_energy_density",
]

#: Largest and smallest perturbation amplitude ``eps`` of the order measurements: the largest
#: keeps higher-order terms from bending the log-log line, the smallest keeps the remainders
#: (>= ~1e-12) four decades above double-precision round-off (~1e-16 relative).
EPS_MAX = 1e-1
EPS_MIN = 1e-3
#: Number of geometrically spaced amplitudes in an order measurement.
N_EPS = 9
#: Gauss-Legendre nodes for the energy integrals; the integrands are entire functions of ``s`` and
#: are integrated to round-off.
N_QUADRATURE = 64

FloatArray = NDArray[np.float64]


def _inverse_radius(R: float) -> float:
    """Return ``1/R`` for a reference radius ``R > 0``; ``R = inf`` (straight state) gives 0."""
    if isinstance(R, (int, float, np.floating, np.integer)) and not isinstance(R, bool):
        if math.isinf(R) and R > 0:
            return 0.0
    return 1.0 / require_positive("R", R)


def _prestress_curvature(R: float, M: float | None, kappa_n: float | None) -> float:
    """Return ``1/R - kappa_n`` (= ``M / R``), from either ``M`` or ``kappa_n`` (exactly one)."""
    inv_r = _inverse_radius(R)
    if M is not None and kappa_n is not None:
        raise RodstabInputError(f"give only one of M and kappa_n, got M={M!r}, kappa_n={kappa_n!r}")
    if M is not None:
        if inv_r == 0.0:
            raise RodstabInputError(
                f"M = 1 - R kappa_n is undefined for a straight reference state (R={R!r}); "
                f"give kappa_n instead of M={M!r}"
            )
        return require_finite("M", M) * inv_r
    if kappa_n is None:
        raise RodstabInputError("give one of M and kappa_n, got M=None, kappa_n=None")
    return inv_r - require_finite("kappa_n", kappa_n)


def reference_basis(theta: ArrayLike) -> FloatArray:
    """Return the reference basis ``(i_r, i_theta, i_3)`` in lab Cartesian components (Fig. 2a).

    Parameters
    ----------
    theta : array_like, shape (...)
        Circumferential angle ``theta = s / R``.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Row ``i`` holds the lab components ``(x, y, z)`` of ``i_r``, ``i_theta``, ``i_3``:
        ``i_r = (cos, sin, 0)``, ``i_theta = (-sin, cos, 0)``, ``i_3 = (0, 0, 1)``.
    """
    th = np.asarray(theta, dtype=float)
    c, s = np.cos(th), np.sin(th)
    zero, one = np.zeros_like(th), np.ones_like(th)
    return np.stack(
        [np.stack([c, s, zero], -1), np.stack([-s, c, zero], -1), np.stack([zero, zero, one], -1)],
        -2,
    )


def frame(alpha: ArrayLike, beta: ArrayLike, gamma: ArrayLike) -> FloatArray:
    """Embedded unit vectors ``(e1, e2, e3)`` from the Euler angles, eq. (2.1).

    Parameters
    ----------
    alpha, beta, gamma : array_like, broadcastable, shape (...)
        Euler angles (radians): ``beta``, ``gamma`` set the tangent ``e2`` (Fig. 2b), ``alpha`` is
        the further rotation of the cross-section about ``e2`` (Fig. 2c).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``F[..., i, j] = e_i . i_j`` with ``(i_1, i_2, i_3) = (i_r, i_theta, i_3)``: row ``i`` is
        ``e_i`` in reference components. ``F`` is the transpose of the paper's direction-cosine
        matrix ``l_ij = i_i . e_j``; it is a proper rotation and the identity at zero angles.
    """
    a, b, g = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (alpha, beta, gamma)))
    ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    cw, sw = np.cos(a + g), np.sin(a + g)
    vb = 1.0 - cb  # (1 - cos beta), written as in (2.1)
    e1 = np.stack([cw + vb * sa * sg, sa * sb, -sw + vb * sa * cg], -1)
    e2 = np.stack([sb * sg, cb, sb * cg], -1)
    e3 = np.stack([sw - vb * ca * sg, -ca * sb, cw - vb * ca * cg], -1)
    return np.stack([e1, e2, e3], -2)


def axis_strains(beta: ArrayLike, gamma: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Centreline stretch and rotations of an inextensible rod, eqs. (2.4)-(2.5).

    Parameters
    ----------
    beta, gamma : array_like, broadcastable, shape (...)
        Euler angles of the tangent (radians).

    Returns
    -------
    eps_theta, phi_r, phi_3 : ndarray, shape (...)
        ``eps_theta = du_theta/ds + u_r/R = cos(beta) - 1`` (2.4),
        ``phi_r = du_3/ds = sin(beta) cos(gamma)`` and
        ``phi_3 = -(du_r/ds - u_theta/R) = -sin(beta) sin(gamma)`` (2.5), so that the unit tangent
        is ``e2 = -phi_3 i_r + (1 + eps_theta) i_theta + phi_r i_3``.
    """
    b, g = np.broadcast_arrays(np.asarray(beta, dtype=float), np.asarray(gamma, dtype=float))
    return np.cos(b) - 1.0, np.sin(b) * np.cos(g), -np.sin(b) * np.sin(g)


def curvatures(
    alpha: ArrayLike,
    beta: ArrayLike,
    gamma: ArrayLike,
    dalpha: ArrayLike,
    dbeta: ArrayLike,
    dgamma: ArrayLike,
    R: float,
) -> FloatArray:
    """Exact curvatures ``(kappa1, kappa2, kappa3)`` on the embedded frame, eq. (2.8).

    Parameters
    ----------
    alpha, beta, gamma : array_like, broadcastable, shape (...)
        Euler angles (radians) at the stations ``s``.
    dalpha, dbeta, dgamma : array_like, broadcastable, shape (...)
        Their derivatives with respect to arc length ``s`` (1/length).
    R : float
        Radius of the circular reference state, ``> 0``; ``math.inf`` for a straight reference
        state, where the ``R^-1`` terms vanish and (2.8) reduces to (4.1).

    Returns
    -------
    ndarray, shape (..., 3)
        ``(kappa1, kappa2, kappa3)``, components of ``Omega = kappa_i e_i`` on the embedded
        frame (1/length); the reference state has ``(0, 0, 1/R)``. Equal to (2.7) evaluated
        with the frame (2.1) and the rotating reference basis.
    """
    inv_r = _inverse_radius(R)
    a, b, g, da, db, dg = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (alpha, beta, gamma, dalpha, dbeta, dgamma))
    )
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    p = db - inv_r * np.sin(g)  # (dbeta/ds - R^-1 sin gamma)
    q = -sb * dg + inv_r * cb * np.cos(g)  # (-sin beta dgamma/ds + R^-1 cos beta cos gamma)
    k1 = ca * p - sa * q
    k2 = da + cb * dg + inv_r * sb * np.cos(g)
    k3 = ca * q + sa * p
    return np.stack([k1, k2, k3], -1)


def curvatures_second_order(
    alpha: ArrayLike,
    beta: ArrayLike,
    gamma: ArrayLike,
    dalpha: ArrayLike,
    dbeta: ArrayLike,
    dgamma: ArrayLike,
    R: float,
) -> FloatArray:
    """Quadratic (moderate-rotation) expansion of the curvatures, eq. (2.10).

    ``kappa1 = beta' - omega/R``, ``kappa2 = omega' + beta/R``,
    ``kappa3 = (1 - omega^2/2 - beta^2/2)/R - beta omega' + (alpha beta)'`` with
    ``omega = alpha + gamma``. Truncation error (measured by :func:`remainder_orders`):
    ``O(eps^3)`` for ``kappa1``, ``kappa2`` and ``O(eps^4)`` for ``kappa3`` when all angles and
    their derivatives are ``O(eps)``.

    Parameters
    ----------
    alpha, beta, gamma, dalpha, dbeta, dgamma, R
        As in :func:`curvatures`.

    Returns
    -------
    ndarray, shape (..., 3)
        Approximate ``(kappa1, kappa2, kappa3)`` on the embedded frame (1/length).
    """
    inv_r = _inverse_radius(R)
    a, b, g, da, db, dg = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (alpha, beta, gamma, dalpha, dbeta, dgamma))
    )
    w, dw = a + g, da + dg
    k1 = db - inv_r * w
    k2 = dw + inv_r * b
    k3 = inv_r * (1.0 - 0.5 * w**2 - 0.5 * b**2) - b * dw + (da * b + a * db)
    return np.stack([k1, k2, k3], -1)


def strain_energy_density(
    kappa: ArrayLike, kappa_n: float, B1: float, B2: float, B3: float
) -> FloatArray:
    """Strain energy per unit length, the integrand of eq. (2.9) including its factor 1/2.

    ``0.5 * (B1 kappa1^2 + B2 kappa2^2 + B3 (kappa3 - kappa_n)^2)``, so that
    ``SE = integral_0^L strain_energy_density ds``.

    Parameters
    ----------
    kappa : array_like, shape (..., 3)
        Curvatures ``(kappa1, kappa2, kappa3)`` on the embedded frame, e.g. from
        :func:`curvatures`.
    kappa_n : float
        Natural curvature about the 3-axis.
    B1, B2, B3 : float
        Bending stiffness about ``e1``, torsional stiffness, bending stiffness about ``e3`` (> 0).

    Returns
    -------
    ndarray, shape (...)
        Energy per unit length.
    """
    kn = require_finite("kappa_n", kappa_n)
    b1, b2, b3 = (require_positive(n, v) for n, v in (("B1", B1), ("B2", B2), ("B3", B3)))
    k = np.asarray(kappa, dtype=float)
    if k.ndim == 0 or k.shape[-1] != 3:
        raise RodstabInputError(f"kappa must have shape (..., 3), got shape {k.shape}")
    return 0.5 * (b1 * k[..., 0] ** 2 + b2 * k[..., 1] ** 2 + b3 * (k[..., 2] - kn) ** 2)


def p2_density(
    beta: ArrayLike,
    dbeta: ArrayLike,
    omega: ArrayLike,
    domega: ArrayLike,
    *,
    R: float,
    B1: float,
    B2: float,
    B3: float,
    M: float | None = None,
    kappa_n: float | None = None,
) -> FloatArray:
    """Quadratic energy per unit length about the reference state, integrand of ``P2`` in (2.12).

    Convention: the factor 1/2 of (2.12) is *included*, as in :func:`strain_energy_density`:
    ``p2_density = 0.5 * {B1 (beta' - omega/R)^2 + B2 (omega' + beta/R)^2
    - B3 M ((beta/R)^2 + (omega/R)^2 + 2 (beta/R) omega')}``, and

    ``P2 = integral_0^L p2_density ds + [p2_boundary_term]_0^L``.

    The paper's "integrand of P2" (end of Section 2.2) is the braces ``{...}``, i.e.
    ``2 * p2_density``; for uniform twist it is ``(b1 - M) omega^2 B3 / R^2``.

    Parameters
    ----------
    beta, dbeta, omega, domega : array_like, broadcastable, shape (...)
        ``beta``, ``omega = alpha + gamma`` (radians) and their ``s``-derivatives.
    R : float
        Reference radius ``> 0``, or ``math.inf`` for a straight reference state.
    B1, B2, B3 : float
        Stiffnesses as in :func:`strain_energy_density`.
    M, kappa_n : float, optional
        Exactly one: ``M = 1 - R kappa_n`` (circular state) or the natural curvature
        ``kappa_n`` (required when ``R = inf``, where ``M / R`` is replaced by ``-kappa_n``).

    Returns
    -------
    ndarray, shape (...)
        Quadratic energy per unit length.
    """
    inv_r = _inverse_radius(R)
    m_over_r = _prestress_curvature(R, M, kappa_n)  # = 1/R - kappa_n = M/R
    b1, b2, b3 = (require_positive(n, v) for n, v in (("B1", B1), ("B2", B2), ("B3", B3)))
    b, db, w, dw = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (beta, dbeta, omega, domega))
    )
    # eq. (2.12), with B3 M (.)/R^2 written as B3 (M/R) (.)/R so that R = inf is regular
    braces = (
        b1 * (db - inv_r * w) ** 2
        + b2 * (dw + inv_r * b) ** 2
        - b3 * m_over_r * (inv_r * (b**2 + w**2) + 2.0 * b * dw)
    )
    return 0.5 * braces


def p2_boundary_term(
    alpha: ArrayLike,
    beta: ArrayLike,
    *,
    R: float,
    B3: float,
    M: float | None = None,
    kappa_n: float | None = None,
) -> FloatArray:
    """End term of ``P2`` in (2.12), corrected: ``B3 M alpha beta / R`` (evaluate ``|_0^L``).

    The paper prints ``2 B3 M alpha beta / R |_0^L`` outside the factor 1/2; collecting the exact
    derivative ``B3 (M/R) d(alpha beta)/ds`` of the quadratic part of (2.9) gives coefficient 1
    (see ``tests/test_kinematics.py``). It vanishes for rings and clamped arcs.

    Parameters
    ----------
    alpha, beta : array_like, broadcastable, shape (...)
        Euler angles at an end of the rod (radians).
    R, B3, M, kappa_n
        As in :func:`p2_density`.

    Returns
    -------
    ndarray, shape (...)
        ``B3 (M/R) alpha beta`` (energy); ``P2`` uses its value at ``s = L`` minus ``s = 0``.
    """
    m_over_r = _prestress_curvature(R, M, kappa_n)
    b3 = require_positive("B3", B3)
    a, b = np.broadcast_arrays(np.asarray(alpha, dtype=float), np.asarray(beta, dtype=float))
    return b3 * m_over_r * a * b


def _random_smooth_state(
    rng: np.random.Generator, s: FloatArray, n_modes: int = 3
) -> tuple[FloatArray, ...]:
    """Random trigonometric ``(a, b, g)`` on ``s`` with exact derivatives ``(da, db, dg)``.

    Each is ``c0 + sum_k c_k sin(k s + phi_k)``: non-periodic on the interval, non-symmetric, with
    no vanishing end values, so that every term of the expansions is exercised.
    """
    out_f, out_d = [], []
    k = np.arange(1, n_modes + 1, dtype=float)
    for _ in range(3):
        c0 = rng.uniform(-1.0, 1.0)
        c = rng.uniform(-1.0, 1.0, n_modes)
        phi = rng.uniform(0.0, 2.0 * np.pi, n_modes)
        arg = np.multiply.outer(s, k) + phi
        out_f.append(c0 + np.sin(arg) @ c)
        out_d.append(np.cos(arg) @ (c * k))
    return (*out_f, *out_d)


def _loglog_slope(eps: FloatArray, err: FloatArray) -> float:
    """Least-squares slope of ``log(err)`` against ``log(eps)``."""
    return float(np.polyfit(np.log(eps), np.log(err), 1)[0])


def remainder_orders(seed: int = 0, *, R: float = 1.3) -> dict[str, float]:
    """Measure the truncation order of (2.10) for each curvature.

    Method: a random smooth state ``(a, b, g)(s)`` on ``0 <= s <= 2`` (:func:`_random_smooth_state`,
    seeded) is scaled, ``alpha = eps a``, ``beta = eps b``, ``gamma = eps g`` (derivatives
    likewise), for ``N_EPS`` amplitudes ``eps`` from ``EPS_MAX`` to ``EPS_MIN``. For each ``eps``
    the error is ``max_s |kappa_i(2.8) - kappa_i(2.10)|``; the order is the least-squares slope of
    ``log(error)`` against ``log(eps)``. Expected (sympy, see tests): 3, 3, 4.

    Parameters
    ----------
    seed : int
        Seed of the random state (numpy ``default_rng``).
    R : float
        Reference radius (``math.inf`` for the straight state, where every term is exercised
        except the ``R^-1`` ones).

    Returns
    -------
    dict
        ``{"kappa1": order, "kappa2": order, "kappa3": order}`` (floats).
    """
    rng = np.random.default_rng(seed)
    s = np.linspace(0.0, 2.0, 101)
    state = _random_smooth_state(rng, s)
    eps = np.geomspace(EPS_MAX, EPS_MIN, N_EPS)
    err = np.empty((N_EPS, 3))
    for n, e in enumerate(eps):
        a, b, g, da, db, dg = (e * x for x in state)
        err[n] = np.max(
            np.abs(curvatures(a, b, g, da, db, dg, R=R)
                   - curvatures_second_order(a, b, g, da, db, dg, R=R)), axis=0
        )
    return {f"kappa{i + 1}": _loglog_slope(eps, err[:, i]) for i in range(3)}


def energy_remainder_order(
    seed: int = 0,
    *,
    R: float = 1.3,
    M: float = 0.4,
    B1: float = 1.7,
    B2: float = 0.6,
    B3: float = 1.0,
    L: float = 2.0,
) -> dict[str, float]:
    """Measure the truncation order of ``SE = SE0 + P2``, eq. (2.12), for ``M != 0``.

    Method: as in :func:`remainder_orders`, a random, non-symmetric, non-periodic state scaled by
    ``eps``. ``SE`` is (2.9) with the exact curvatures (2.8), ``SE0 = B3 (M/R)^2 L / 2`` and ``P2``
    is :func:`p2_density` integrated plus the end term, all integrals by ``N_QUADRATURE``-point
    Gauss-Legendre (exact to round-off here). The order is the log-log slope of
    ``|SE - SE0 - P2|`` against ``eps``.

    Parameters
    ----------
    seed : int
        Seed of the random state.
    R, M, B1, B2, B3, L : float
        Reference radius (finite), load parameter ``M = 1 - R kappa_n``, stiffnesses, rod length.

    Returns
    -------
    dict
        ``"energy"``: order with the corrected end term ``B3 M alpha beta / R |_0^L`` (expected 4);
        ``"energy_printed_end_term"``: order with the end term as printed in (2.12),
        ``2 B3 M alpha beta / R |_0^L`` (2 whenever ``M alpha beta |_0^L != 0``).
    """
    inv_r = 1.0 / require_positive("R", R)
    m = require_finite("M", M)
    length = require_positive("L", L)
    kappa_n = (1.0 - m) / R
    x, w = np.polynomial.legendre.leggauss(N_QUADRATURE)
    s = 0.5 * length * (x + 1.0)
    w = 0.5 * length * w
    s_all = np.concatenate([s, [0.0, length]])  # quadrature nodes, then the two ends
    state = _random_smooth_state(np.random.default_rng(seed), s_all)
    se0 = 0.5 * B3 * (m * inv_r) ** 2 * length
    eps = np.geomspace(EPS_MAX, EPS_MIN, N_EPS)
    err = np.empty((N_EPS, 2))
    for n, e in enumerate(eps):
        a, b, g, da, db, dg = (e * v for v in state)
        kap = curvatures(a[:-2], b[:-2], g[:-2], da[:-2], db[:-2], dg[:-2], R=R)
        se = w @ strain_energy_density(kap, kappa_n, B1, B2, B3)
        p2_int = w @ p2_density(
            b[:-2], db[:-2], a[:-2] + g[:-2], da[:-2] + dg[:-2], R=R, B1=B1, B2=B2, B3=B3, M=m
        )
        ends = p2_boundary_term(a[-2:], b[-2:], R=R, B3=B3, M=m)
        jump = ends[1] - ends[0]
        err[n] = abs(se - se0 - p2_int - jump), abs(se - se0 - p2_int - 2.0 * jump)
    return {
        "energy": _loglog_slope(eps, err[:, 0]),
        "energy_printed_end_term": _loglog_slope(eps, err[:, 1]),
    }
