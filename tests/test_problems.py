"""rodstab.problems: every registered structure builds with its defaults; paper units."""

from __future__ import annotations

import math

import pytest

from rodstab import problems
from rodstab.errors import RodstabInputError
from rodstab.model import Assembly
from rodstab.sections import circle, rectangle


@pytest.mark.parametrize("name", sorted(problems.REGISTRY))
def test_every_problem_builds_an_assembly_with_its_defaults(name):
    problem = problems.REGISTRY[name]
    a = problem.build(problem.Params())
    assert isinstance(a, Assembly) and a.segments
    assert isinstance(problem.DEFAULT_ELEMENTS, int) and problem.DEFAULT_ELEMENTS > 0
    assert all(math.isfinite(v) for v in problem.to_paper(1.0, problem.Params()).values())


@pytest.mark.parametrize("section", [circle(), rectangle(aspect=4.0)], ids=["circle", "h/t=4"])
def test_birod_to_paper_lambda_is_mu_over_sqrt_b1b2(section):
    """lambda = B3 kappa0 L / sqrt(B1 B2) (5.7): mu = pi sqrt(b1 b2) is lambda = pi."""
    params = problems.birod.Params(section=section)
    paper = problems.birod.to_paper(math.pi * section.sqrt_b1b2, params)
    assert paper["lambda"] == pytest.approx(math.pi, rel=1e-14)
    assert paper["psi"] == pytest.approx(math.pi * section.sqrt_b1b2 / 2, rel=1e-14)


def test_folded_ring_to_paper_lambda_and_kappa_R0():
    """mu = (pi/3) sqrt(b1 b2) is lambda = pi/3; kappa_n R0 = lambda sqrt(b1 b2) / theta."""
    section = rectangle(aspect=4.0)
    params = problems.folded_ring.Params(section=section, arc_angle_deg=120.0)
    paper = problems.folded_ring.to_paper(math.pi / 3 * section.sqrt_b1b2, params)
    assert paper["lambda"] == pytest.approx(math.pi / 3, rel=1e-14)
    assert paper["kappa_R0"] == pytest.approx(section.sqrt_b1b2 / 2, rel=1e-14)


@pytest.mark.parametrize("name, kwargs, word", [
    ("bi-rod", {"length": -1.0}, "length"),
    ("bi-rod", {"clamp": "end"}, "clamp"),
    ("folded-ring", {"segments": 5}, "segments"),
    ("folded-ring", {"arc_angle_deg": 0.0}, "arc_angle_deg"),
    ("unfolded-ring", {"radius": 0.0}, "radius"),
    ("straightened-rod", {"length": math.inf}, "length"),
])
def test_bad_params_raise_naming_the_value(name, kwargs, word):
    with pytest.raises(RodstabInputError, match=word):
        problems.REGISTRY[name].Params(**kwargs)


def test_params_are_keyword_only_and_frozen():
    with pytest.raises(TypeError):
        problems.birod.Params(circle())  # type: ignore[misc]
    p = problems.birod.Params()
    with pytest.raises(AttributeError):
        p.length = 2.0  # type: ignore[misc]
