"""rodstab.problems: every registered structure builds with its defaults; paper units; every
declared method solves it and the methods agree within the declared tolerances."""

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


METHOD_NAMES = {"analytic", "transfer", "fe", "nonlinear"}


@pytest.mark.parametrize("name", sorted(problems.REGISTRY))
def test_every_problem_declares_methods_and_pairwise_tolerances(name):
    """METHODS names come from the four families; every method is in some declared pair."""
    problem = problems.REGISTRY[name]
    assert set(problem.METHODS) <= METHOD_NAMES and len(problem.METHODS) >= 2
    paired = {m for pair in problem.AGREE_RTOL for m in pair}
    assert paired == set(problem.METHODS)
    assert all(0 < rtol < 0.05 for rtol in problem.AGREE_RTOL.values())


@pytest.fixture(scope="module")
def solved():
    """name -> {method: its critical values} for the default parameters (each solved once)."""
    return {name: {m: f(problem.Params()) for m, f in problem.METHODS.items()}
            for name, problem in problems.REGISTRY.items()}


@pytest.mark.parametrize("name", sorted(problems.REGISTRY))
def test_declared_methods_agree_within_the_declared_tolerance(solved, name):
    """Each declared pair agrees on every quantity both report (the paper's value is no method:
    bi-rod and folded ring keep their paper_critical 2 pi apart)."""
    problem = problems.REGISTRY[name]
    values = solved[name]
    for (a, b), rtol in problem.AGREE_RTOL.items():
        common = set(values[a]) & set(values[b])
        assert common, (name, a, b)
        for key in sorted(common):
            va, vb = float(values[a][key]), float(values[b][key])
            assert math.isfinite(va) and math.isfinite(vb), (name, a, b, key, va, vb)
            assert problems.agree(va, vb, rtol), (name, key, a, va, b, vb, rtol)


@pytest.mark.parametrize("name", ["bi-rod", "folded-ring"])
def test_paper_critical_stays_apart_from_the_methods(solved, name):
    """The paper's 2 pi (Sections 4-5) is not what the methods find (pi, pi/3): a finding."""
    problem = problems.REGISTRY[name]
    claimed = problem.paper_critical(problem.Params())["lambda"]
    for values in solved[name].values():
        assert not problems.agree(values["lambda"], claimed, 0.1)


def test_agree_is_relative_above_one_and_absolute_below():
    assert problems.agree(100.0, 100.4, 5e-3) and not problems.agree(100.0, 101.0, 5e-3)
    assert problems.agree(0.0, 4e-9, 1e-8) and not problems.agree(0.0, 2e-8, 1e-8)
    assert problems.agree(-math.inf, -math.inf, 1e-8)
    assert not problems.agree(math.nan, math.nan, 1e-8)


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
    ("ring", {"loops": 0}, "loops"),
    ("clamped-arc", {"L_over_R": -1.0}, "L_over_R"),
    ("clamped-arc", {"L_over_R": math.nan}, "L_over_R"),
    ("michell", {"loops": 1.5}, "loops"),
    ("twisted-rod", {"length": 0.0}, "length"),
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


def test_ring_to_paper_M_and_kappa_L_over_2pi():
    """mu = R kappa_n: M = 1 - mu (3.3), (L/2pi) kappa_n = N mu (L = 2 pi N R)."""
    params = problems.ring.Params(loops=3)
    assert problems.ring.to_paper(0.5, params) == {"M": 0.5, "kappa_L_over_2pi": 1.5}


@pytest.mark.parametrize("L_over_R", [0.0, 2.0])
def test_clamped_arc_stress_free_load_is_L_over_R(L_over_R):
    """The stress-free arc has kappa_n = 1/R: L kappa_n = L/R (straight rod: mu = L kappa_n)."""
    params = problems.clamped_arc.Params(L_over_R=L_over_R)
    mu = 1.0 if L_over_R > 0 else 0.0
    assert problems.clamped_arc.to_paper(mu, params)["L_kappa_n"] == L_over_R


def test_michell_and_twisted_rod_are_refused_by_the_linear_engine():
    """Natural twist / end rotation: only the nonlinear model solves these assemblies."""
    from rodstab.linear.solve import linear_stability

    with pytest.raises(RodstabInputError):
        linear_stability(problems.michell.build(problems.michell.Params()), 8)


def test_michell_three_loops_has_no_critical_twist():
    """End of Section 3.3: N = 3 is unstable already untwisted -- no critical twist (NaN)."""
    params = problems.michell.Params(loops=3)
    assert math.isnan(problems.michell.METHODS["analytic"](params)["b2_omega0"])
