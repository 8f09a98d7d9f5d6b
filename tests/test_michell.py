"""Validation of ``rodstab.analytic.michell`` against paper Section 3.3 (Michell's problem).

Oracles: the paper's numbers (b2 omega0' = sqrt 3, j = 2, r = -sqrt(3)/2 for one loop; N = 3
unstable at every twist via j = 1, 2); the paper's integral identity; and an independent second
method: the integrand of (3.21) evaluated on a fine periodic grid for the trial displacement
fields (3.22), following the paper's route (phi_r, phi_3 from the displacements,
beta = sqrt(phi_r^2 + phi_3^2), gamma = atan2(-phi_3, phi_r), derivatives taken numerically),
minimised over the amplitude ratio r; the smallest twist where min P2 = 0 is located by Brent.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar

from rodstab.analytic.michell import (
    michell_mode_pencil,
    michell_p2_closed_form,
    michell_stability,
)
from rodstab.errors import RodstabInputError

#: Grid points per loop for the periodic quadrature (trapezoid + FFT derivatives: spectrally
#: accurate for these analytic periodic integrands).
N_GRID = 512


def _spectral_derivative(f: np.ndarray, period: float) -> np.ndarray:
    """d f / d theta of a smooth periodic sample f on a uniform grid over one period."""
    n = f.size
    k = np.fft.fftfreq(n, d=period / n) * 2 * np.pi
    if n % 2 == 0:
        k[n // 2] = 0.0
    return np.real(np.fft.ifft(1j * k * np.fft.fft(f)))


def p2_quadrature(t: float, j: int, r: float, loops: int = 1, b: float = 1.0) -> float:
    """P2 of (3.21) (R = 1, B3 = 1) by periodic trapezoid quadrature for the fields (3.22) with
    j theta -> j theta / N: u_r = a k cos(k theta), u_theta = -a sin(k theta),
    u3 = b sin(k theta), k = j/N, a = r b k / (k^2 - 1); t = b2 omega0'."""
    k = j / loops
    a = r * b * k / (k * k - 1)
    period = 2 * np.pi * loops
    th = np.arange(N_GRID * loops) * period / (N_GRID * loops)
    u_r, u_t, u3 = a * k * np.cos(k * th), -a * np.sin(k * th), b * np.sin(k * th)
    phi_r = _spectral_derivative(u3, period)                        # (3.18) R^-1 u3'
    phi_3 = -(_spectral_derivative(u_r, period) - u_t)              # (3.18) -R^-1 (u_r' - u_th)
    beta = np.hypot(phi_r, phi_3)                                    # (3.17)-(3.18)
    gamma = np.unwrap(np.arctan2(-phi_3, phi_r))                     # beta cos g = phi_r, ...
    winding = round((gamma[-1] + (gamma[1] - gamma[0]) - gamma[0]) / (2 * np.pi))
    slope = 2 * np.pi * winding / period
    dgamma = _spectral_derivative(gamma - slope * th, period) + slope
    dbeta = _spectral_derivative(beta, period)
    integrand = (-t * beta**2 * dgamma + dbeta**2 + beta**2 * dgamma**2
                 - beta**2 * np.cos(gamma) ** 2)
    return 0.5 * float(np.sum(integrand)) * period / th.size


def _min_over_r(t: float, j: int, loops: int = 1) -> tuple[float, float]:
    """min over r of P2 / ((pi/2)(b k)^2) by bounded scalar minimisation (r of the sign of -t)."""
    k = j / loops
    scale = 0.5 * np.pi * k * k
    bounds = (-6.0, -0.05) if t >= 0 else (0.05, 6.0)
    res = minimize_scalar(lambda r: p2_quadrature(t, j, r, loops) / scale, bounds=bounds,
                          method="bounded", options={"xatol": 1e-10})
    return float(res.fun), float(res.x)


# ------------------------------------------------------------------------ paper's numbers


def test_sec_3_3_michell_one_loop_sqrt3():
    """Paper: 'The lowest non-trivial eigenvalue is associated with j = 2 and given by
    b2 omega0' = sqrt 3 with r = -sqrt(3)/2', in agreement with Michell (1889)."""
    for b2 in (0.75, 0.6, 1.0):
        r = michell_stability(b2, 1)
        assert r.b2_omega0_critical == pytest.approx(math.sqrt(3), rel=1e-14)
        assert r.omega0_critical == pytest.approx(math.sqrt(3) / b2, rel=1e-14)
        assert r.mode_j == 2
        assert r.r_critical == pytest.approx(-math.sqrt(3) / 2, rel=1e-14)
        assert r.stable_at_zero_twist and r.unstable_modes == ()
        assert r.residual < 1e-12


def test_sec_3_3_three_loops_unstable_at_every_twist():
    """Paper, end of 3.3: with N = 3, 'P2 can be negative for any value of omega0' when j = 1
    or 2' -- the 3-loop ring is unstable for any twist (as without twist, Sec. 3.1)."""
    r = michell_stability(0.75, 3)
    assert not r.stable_at_zero_twist
    assert r.unstable_modes == (1, 2)
    assert math.isnan(r.b2_omega0_critical) and math.isnan(r.omega0_critical)


@pytest.mark.parametrize("b1", [2.0, 0.5, 1.0 + 1e-6])
def test_sec_3_3_requires_isotropic_bending(b1):
    """(3.16) assumes B1 = B3 (b1 = 1); any other b1 is rejected, naming b1."""
    with pytest.raises(ValueError, match="b1"):
        michell_stability(0.75, 1, b1=b1)


@pytest.mark.parametrize("kwargs, name", [(dict(b2=0.0), "b2"), (dict(b2=math.nan), "b2"),
                                          (dict(b2=0.75, loops=0), "loops"),
                                          (dict(b2=0.75, loops=2.5), "loops")])
def test_michell_rejects_bad_input(kwargs, name):
    """Bad input raises RodstabInputError naming the parameter."""
    with pytest.raises(RodstabInputError, match=name):
        michell_stability(**kwargs)


# ------------------------------------------------------------ (3.21)-(3.26) independently


@pytest.mark.parametrize("r", [0.1, 0.5, 1.0, 2.0, -math.sqrt(3) / 2, 5.0])
def test_sec_3_3_integral_identity(r):
    """Paper: (1/pi) int_0^{2 pi} sin^2 cos^2 / (cos^2 + r^2 sin^2) dpsi = (1 + |r|)^-2
    (adaptive quadrature)."""
    val, err = quad(lambda p: (np.sin(p) * np.cos(p)) ** 2 / (np.cos(p) ** 2
                                                              + r * r * np.sin(p) ** 2),
                    0.0, 2 * np.pi, epsabs=1e-13, epsrel=1e-13, limit=200)
    assert val / np.pi == pytest.approx((1 + abs(r)) ** -2, rel=1e-10)


@pytest.mark.parametrize("t, j, r, N", [(1.0, 2, -0.8, 1), (1.7320508, 2, -0.866, 1),
                                        (0.0, 3, 0.4, 1), (-2.0, 4, 0.7, 1), (0.5, 2, -0.3, 3),
                                        (3.0, 1, -1.5, 3), (1.2, 5, -0.9, 3)])
def test_eq_3_26_closed_form_matches_quadrature_of_3_21(t, j, r, N):
    """(3.26), N times with j -> j/N: P2 = (pi/2)(b k)^2 N {2 t k r + k^2 (1 + r^2) - 1}, against
    the periodic quadrature of the (3.21) integrand for the fields (3.22)."""
    k = j / N
    expected = 0.5 * np.pi * k * k * michell_p2_closed_form(t, j, r, N)
    assert michell_p2_closed_form(t, j, r, N) == pytest.approx(
        N * (2 * t * k * r + k * k * (1 + r * r) - 1), rel=1e-15)
    assert p2_quadrature(t, j, r, N) == pytest.approx(expected, rel=1e-9, abs=1e-9)


def test_sec_3_3_second_method_critical_twist_is_sqrt3_mode_2():
    """Second method: for each j = 2..5, the twist t_j > 0 at which min_r P2 (quadrature of
    (3.21)) first reaches 0 (Brent on t); the smallest is t_2 = sqrt 3 with minimiser
    r = -sqrt(3)/2 -- reproducing michell_stability."""
    crit = {}
    for j in range(2, 6):
        crit[j] = brentq(lambda t, j=j: _min_over_r(t, j)[0], 0.05, 6.0, xtol=1e-12)
    j_min = min(crit, key=crit.get)
    assert j_min == 2
    assert crit[2] == pytest.approx(math.sqrt(3), rel=1e-7)
    _, r_min = _min_over_r(crit[2], 2)
    assert r_min == pytest.approx(-math.sqrt(3) / 2, rel=1e-5)
    for j in range(3, 6):
        assert crit[j] == pytest.approx(math.sqrt(j * j - 1), rel=1e-7)  # k^2 - 1 - t^2 = 0
    res = michell_stability(0.75, 1)
    assert res.b2_omega0_critical == pytest.approx(crit[2], rel=1e-7)
    assert res.r_critical == pytest.approx(r_min, rel=1e-5)


@pytest.mark.parametrize("t", [0.0, 0.5, 2.0, 10.0, -3.0])
@pytest.mark.parametrize("j", [1, 2])
def test_sec_3_3_three_loops_negative_p2_for_every_twist_quadrature(t, j):
    """Second method for N = 3: for j = 1, 2 (k < 1) a trial field (3.22) with j theta / 3 gives
    P2 < 0 at any twist (quadrature of (3.21)); r = -t/k, or r = 0.3 at t = 0."""
    k = j / 3
    r = -t / k if t != 0 else 0.3
    assert p2_quadrature(t, j, r, 3) < -1e-3


@pytest.mark.parametrize("k", [1.5, 2.0, 3.0, 4 / 3])
def test_michell_mode_pencil_is_the_quadratic_form_of_3_26(k):
    """The pencil acting on (b k, c), c = r b k, reproduces (3.26)/N:
    (b k)^2 [2 t k r + k^2 (1 + r^2) - 1] = x^T (A - t C) x."""
    A, C = michell_mode_pencil(k)
    for t, r in ((0.7, -0.4), (-1.3, 0.9), (2.0, 1.7)):
        x = np.array([1.0, r])  # b k = 1
        assert x @ (A - t * C) @ x == pytest.approx(2 * t * k * r + k * k * (1 + r * r) - 1,
                                                    rel=1e-14)


def test_michell_ring_of_huge_loop_count_is_refused_before_any_work():
    """3N + 4 modes past limits.max_steps, refused naming loops (issue 10: unbounded)."""
    from rodstab.errors import RodstabInputError

    with pytest.raises(RodstabInputError, match=r"loops 1000000000.*--max-steps"):
        michell_stability(0.75, 10**9)
