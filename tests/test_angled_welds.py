"""Welds of any angle (issue 19 item 1): the end term of the exact second variation.

P2's integrand (2.12) differs from the exact second variation about a held state of uniform
moment ``m`` by ``-1/2 m (beta omega)'``; the term telescopes across smooth welds and cusps but
not across a weld of any other angle (:func:`rodstab.linear.assembly.end_term_matrices`). The
references here are independent of the FE engine: the curvature of an exactly rotated frame
(sympy), the closed form of a straight clamped rod (Timoshenko's ``2 pi sqrt(B1 B2) / l``), the
exact general solutions of the transfer method, the Bloch method on one arc, and the nonlinear
rod (a discrete geometrically exact model, Richardson-extrapolated in ``h^2``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from rodstab.linear.assembly import end_term_matrices
from rodstab.linear.solve import linear_stability
from rodstab.model import Assembly, Segment
from rodstab.multistable import atlas
from rodstab.multistable.states import uniform_ring
from rodstab.nonlinear.solve import critical_load_factor
from rodstab.sections import circle
from rodstab.transfer import full_system_critical

CIRCLE = circle()


def _hat(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def test_second_order_curvature_of_an_exactly_rotated_frame():
    """``kappa_3`` of ``exp(eps Theta) R0(s)`` to ``O(eps^2)``: (2.10) minus ``1/2 (beta omega)'``.

    ``R0`` is the circle's frame ``(i_r, i_theta, e3)``, ``Theta = beta i_r + omega i_theta``
    in the lab frame (continuous at a weld, zero at a clamp: the rotation whose second
    variation has no boundary terms of its own). ``R^T R'`` is formed exactly (the Frechet
    derivative of ``expm``) at random cubic ``beta``, ``omega``; the ``eps^2`` coefficient by
    the symmetric difference in ``eps`` (error ``O(eps^2)``).
    """
    rng = np.random.default_rng(19)
    R, eps = 0.7, 1e-3
    pb, pw = (np.polynomial.Polynomial(rng.normal(size=4)) for _ in range(2))
    worst = 0.0
    for s in np.linspace(0.0, 2.0, 7):
        th = s / R
        d1 = np.array([math.cos(th), math.sin(th), 0.0])
        d2 = np.array([-math.sin(th), math.cos(th), 0.0])
        R0 = np.column_stack([d1, d2, [0.0, 0.0, 1.0]])
        dR0 = np.column_stack([d2 / R, -d1 / R, [0.0, 0.0, 0.0]])
        b, db, w, dw = pb(s), pb.deriv()(s), pw(s), pw.deriv()(s)
        v = b * d1 + w * d2
        dv = db * d1 + b * d2 / R + dw * d2 - w * d1 / R

        def kappa3(e: float, v=v, dv=dv, R0=R0, dR0=dR0) -> float:
            Q, dQ = scipy.linalg.expm_frechet(_hat(e * v), _hat(e * dv))
            W = (Q @ R0).T @ (dQ @ R0 + Q @ dR0)
            return float(W[1, 0])

        k0, kp, km = kappa3(0.0), kappa3(eps), kappa3(-eps)
        assert k0 == pytest.approx(1 / R, rel=1e-14)
        second = (kp + km - 2 * k0) / (2 * eps * eps)
        paper = -(b * b + w * w) / (2 * R) - b * dw  # (2.10) without (alpha beta)'
        exact = paper + 0.5 * (db * w + b * dw)  # paper - 1/2 (beta omega)'
        worst = max(worst, abs(second - exact) / (1 + abs(exact)))
        assert abs(second - paper) > 1e-3 or abs(db * w + b * dw) < 1e-3
    assert worst < 1e-5


@pytest.mark.parametrize("deg", [0.0, 180.0, 37.0, 90.0, -120.0])
def test_end_terms_cancel_exactly_at_smooth_welds_and_cusps_only(deg):
    t = np.array([math.cos(0.3), math.sin(0.3)])
    a = math.radians(deg)
    t2 = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]) @ t
    E_end, _ = end_term_matrices(t, 1.0, 1.0, 0.0, 1.0)
    E_start, _ = end_term_matrices(t2, -1.0, 1.0, 0.0, 1.0)
    total = np.abs(E_end + E_start).max()
    if deg in (0.0, 180.0):
        assert total < 1e-15
    else:
        assert total > 0.1 * abs(math.sin(a))


def two_rods(deg: float) -> Assembly:
    """Two straight unit rods welded at ``deg``, far ends clamped, natural curvature 1."""
    a = Segment(name="a", length=1.0, curvature=0.0, natural_curvature=1.0, B1=CIRCLE.b1,
                B2=CIRCLE.b2, B3=1.0)
    b = Segment(name="b", length=1.0, curvature=0.0, natural_curvature=1.0, B1=CIRCLE.b1,
                B2=CIRCLE.b2, B3=1.0, start=(1.0, 0.0),
                angle=math.radians(deg))
    return Assembly(segments=(a, b), welds=((("a", "end"), ("b", "start")),),
                    supports=(("a", "start", "clamped"), ("b", "end", "clamped")))


def square() -> Assembly:
    """Four straight unit rods welded at 90 degrees into a square (the issue's ring)."""
    corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    segs = tuple(Segment(name=f"s{i}", length=1.0, curvature=0.0, natural_curvature=1.0,
                         B1=CIRCLE.b1, B2=CIRCLE.b2, B3=1.0, start=corners[i],
                         angle=i * math.pi / 2) for i in range(4))
    return Assembly(segments=segs,
                    welds=tuple(((f"s{i}", "end"), (f"s{(i + 1) % 4}", "start"))
                                for i in range(4)))


def nonlinear_limit(a: Assembly, side: float) -> float:
    """Nonlinear rod's first critical load on one side of 0, extrapolated in h^2 (8, 16 el.)."""
    c8, c16 = (critical_load_factor(a, 0.0, 4.0 * side, elements_per_segment=n)
               .load_factor_critical for n in (8, 16))
    return c16 + (c16 - c8) / 3.0


def test_two_rods_at_a_kink_against_closed_form_and_nonlinear_rod():
    """Issue 19 reproducer: FE gave (-4.0721, 1.3693) at 90 degrees; exact is +-pi sqrt(b1 b2).

    At 0 degrees the pair is one clamped straight rod of length 2 under a uniform moment:
    ``m_c = 2 pi sqrt(B1 B2) / 2``. The limit does not depend on the weld angle (found, then
    checked by the nonlinear rod at 90 degrees and the exact general solutions at each angle).
    """
    exact = math.pi * math.sqrt(CIRCLE.b1 * CIRCLE.b2)  # 2.7207
    for deg in (0.0, 45.0, 90.0, 135.0):
        a = two_rods(deg)
        fe = linear_stability(a, 32)
        lo, hi = fe.load_factor_interval
        assert hi == pytest.approx(exact, rel=1e-6)
        assert lo == pytest.approx(-exact, rel=1e-6)
        if deg in (45.0, 90.0):
            tr = full_system_critical(a, 1.0, 0, 3.5)
            assert tr.lambda_c == pytest.approx(exact, rel=1e-8)
    a = two_rods(90.0)
    assert nonlinear_limit(a, 1.0) == pytest.approx(exact, rel=5e-4)
    assert nonlinear_limit(a, -1.0) == pytest.approx(-exact, rel=5e-4)


def test_square_ring_fe_equals_nonlinear_rod_and_bloch():
    """Issue 19: ``atlas --method fe`` gave the square an upper limit 0.663; the rod gives 1.236."""
    a = square()
    lo, hi = linear_stability(a, 32).load_factor_interval
    assert hi == pytest.approx(nonlinear_limit(a, 1.0), rel=5e-4)
    assert lo == pytest.approx(nonlinear_limit(a, -1.0), rel=5e-4)
    ring = uniform_ring(4, weld=math.pi / 2, natural_curvature=1.0, B1=CIRCLE.b1, B2=CIRCLE.b2)
    b = atlas.bloch_interval(ring, 0.0)
    assert (b.lo, b.hi) == pytest.approx((lo, hi), rel=1e-7)


@pytest.mark.parametrize("n, turn_deg, b1, b2", [
    (4, 134.21, 0.388, 15.8),
    (5, -56.06, 1.41, 9.05),
    (4, 14.78, 0.227, 6.43),
    (3, -13.85, 0.371, 1.28),
])
def test_bloch_and_fe_agree_on_rings_welded_at_any_angle(n, turn_deg, b1, b2):
    ring = uniform_ring(n, weld=math.radians(turn_deg), natural_curvature=1.0, B1=b1, B2=b2)
    states = [s for s in ring.states(max_turns=1.0).states if abs(s.theta) < 2.5][:2]
    assert states
    for st in states:
        t = atlas.transfer_interval(ring, st)
        f = atlas.fe_interval(ring, st)
        for lt, lf in ((t.lower, f.lower), (t.upper, f.upper)):
            assert lt.load_factor == pytest.approx(lf.load_factor, rel=1e-6, abs=1e-6)
