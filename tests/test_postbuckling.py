"""Initial post-buckling mu/mu_c = 1 + a xi + b xi^2 by the two tracers of
rodstab.nonlinear.continuation (amplitude control and pseudo-arclength share only the
corrector): they must agree, and the verdict must not depend on the mesh."""

from __future__ import annotations

import numpy as np
import pytest

from rodstab.model import Assembly, Segment
from rodstab.nonlinear.continuation import (
    arclength_from_bifurcation,
    post_buckling,
    post_buckling_branch,
)


def _straightened(b1: float, b2: float) -> Assembly:
    s = Segment(name="rod", length=1.0, curvature=0.0, natural_curvature=1.0, B1=b1, B2=b2, B3=1.0)
    return Assembly(segments=(s,), supports=(("rod", "start", "clamped"),
                                             ("rod", "end", "sliding-clamp")))


@pytest.mark.parametrize(("b1", "b2", "sign"), [(1.0, 0.75, 1.0), (4.0, 0.9, -1.0)])
@pytest.mark.slow
def test_straightened_rod_coefficient_by_two_tracers_and_mesh_independent_verdict(b1, b2, sign):
    """Circle (b1 = 1, b2 = 0.75): supercritical; b1 = 4, b2 = 0.9: subcritical. b from
    amplitude control and arclength agree within 2 % at 32 and 64 elements, the verdict is the
    same at 16, 32, 64, and b converges (second order: the 32 -> 64 change is at most 0.4 of
    the 16 -> 32 change)."""
    a = _straightened(b1, b2)
    bs, verdicts = [], []
    for n in (16, 32, 64):
        amp = post_buckling_branch(a, 1.0, 40.0, elements_per_segment=n)
        assert amp.converged
        bs.append(amp.coefficients[1])
        verdicts.append(amp.verdict)
        assert abs(amp.coefficients[0]) < 1e-6  # symmetric: no linear term
        if n >= 32:
            arc = arclength_from_bifurcation(a, 1.0, 40.0, elements_per_segment=n, ds=0.002,
                                             n_steps=8, both_sides=True)
            assert arc.coefficients[1] == pytest.approx(amp.coefficients[1], rel=2e-2)
            assert arc.verdict == amp.verdict
    assert len(set(verdicts)) == 1
    assert np.sign(bs[-1]) == sign
    assert abs(bs[2] - bs[1]) <= 0.4 * abs(bs[1] - bs[0])


def test_post_buckling_verdict_from_a_known_parabola():
    """A synthetic branch p/p_c = 1 + 0.5 xi^2 + 3 xi^4 (both signs): the quartic fit returns
    b = 0.5 exactly, a = 0, and the verdict follows the stable side."""
    xi = np.linspace(-0.05, 0.05, 11)
    p = 2.0 * (1 + 0.5 * xi**2 + 3 * xi**4)
    verdict, a, b = post_buckling(xi, p, 2.0, stable_side=-1.0)
    assert b == pytest.approx(0.5, rel=1e-9) and abs(a) < 1e-9
    assert "supercritical" in verdict
    assert "subcritical" in post_buckling(xi, p, 2.0, stable_side=1.0)[0]
    assert "asymmetric" in post_buckling(xi, 2.0 * (1 + 0.3 * xi), 2.0, -1.0)[0]
