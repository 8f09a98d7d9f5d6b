"""Tests of rodstab.sections against closed forms, a textbook table and the paper's statements."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.sections import (
    SHAPES,
    TORSION_OPTIONS,
    Section,
    circle,
    ellipse,
    from_ratios,
    make_section,
    rectangle,
    rectangle_b2_paper,
    rectangle_torsion_constant,
    sized_section,
    thin_tube,
    tube,
)

NUS = (-0.5, 0.0, 0.25, 1 / 3, 0.5)


@functools.cache
def reference_k(ratio: float, n_max: int = 20001) -> float:
    """k = J/(a b^3) of a rectangle with a/b = ratio >= 1, by a plain float loop.

    Independent of rodstab: Saint-Venant's series summed smallest term first up to n_max
    (neglected tail < 1/(8 n_max^4) ~ 8e-19).
    """
    s = 0.0
    for n in range(n_max, 0, -2):
        s += math.tanh(n * math.pi * ratio / 2) / n**5
    return (1.0 - 192.0 / math.pi**5 / ratio * s) / 3.0


# --- paper Section 3.1: circular sections, solid or annular ----------------------------------


@pytest.mark.parametrize("shape, sizes, aspect, I3", [
    ("rectangle", {"height": 5e-3, "thickness": 5e-4}, 10.0, 5e-3 * 5e-4**3 / 12),
    ("ellipse", {"height": 2e-3, "thickness": 4e-3}, 0.5, math.pi * 2e-3 * 4e-3**3 / 64),
    ("tube", {"outer_diameter": 10.0, "inner_diameter": 8.0}, 0.8,
     math.pi * (10.0**4 - 8.0**4) / 64),
    ("circle", {"diameter": 3.0}, None, math.pi * 3.0**4 / 64)])
def test_sized_section_has_the_ratios_of_its_aspect_and_the_I3_of_its_size(shape, sizes,
                                                                             aspect, I3):
    """Issue 13 (CLI --height/--thickness ...): a section built from its dimensions has the b1,
    b2 of make_section at its aspect, and I3 = h t^3/12, pi h t^3/64, pi (Do^4 - Di^4)/64."""
    s = sized_section(shape, sizes, nu=0.3)
    ref = make_section(shape, aspect=aspect, nu=0.3)
    assert (s.b1, s.b2) == pytest.approx((ref.b1, ref.b2), rel=1e-13)
    assert s.I3 == pytest.approx(I3, rel=1e-14)


def test_sized_section_rejects_a_shape_without_dimensions():
    with pytest.raises(RodstabInputError, match="'ratios'"):
        sized_section("ratios", {}, nu=0.3)


@pytest.mark.parametrize("nu", NUS)
@pytest.mark.parametrize(
    "section",
    [
        lambda nu: circle(nu=nu),
        lambda nu: circle(radius=0.37, nu=nu),
        lambda nu: tube(outer_radius=2.0, inner_radius=1.3, nu=nu),
        lambda nu: tube(outer_radius=1.0, inner_radius=0.0, nu=nu),
        lambda nu: thin_tube(radius=5.0, wall=0.1, nu=nu),
    ],
    ids=["circle", "circle_r", "tube", "tube_solid", "thin_tube"],
)
def test_sec_3_1_circular_sections_have_b1_1_and_b2_1_over_1_plus_nu(section, nu):
    """Paper Sec. 3.1: circular sections, solid or annular, have b1 = 1 and b2 = 1/(1+nu).

    Holds exactly: I1 = I3 and J = 2 I for every axisymmetric section.
    """
    s = section(nu)
    assert s.b1 == 1.0
    assert s.b2 == 1.0 / (1.0 + nu)
    assert s.sqrt_b1b2 == pytest.approx(1.0 / math.sqrt(1.0 + nu), rel=1e-15)
    assert s.nu == nu and s.torsion == "exact"


def test_circle_and_tube_geometry_closed_forms():
    """A = pi r^2, I = pi r^4/4, J = pi r^4/2; annulus pi(ro^4 - ri^4)/4; thin tube pi r^3 w."""
    c = circle(radius=2.0)
    assert (c.area, c.I1, c.I3, c.J) == pytest.approx((4 * math.pi, 4 * math.pi, 4 * math.pi,
                                                        8 * math.pi))
    t = tube(outer_radius=2.0, inner_radius=1.0)
    assert t.aspect == 0.5
    assert (t.area, t.I3, t.J) == pytest.approx((3 * math.pi, 15 * math.pi / 4,
                                                 15 * math.pi / 2))
    th = thin_tube(radius=2.0, wall=0.01)
    assert (th.area, th.I1, th.J) == pytest.approx((0.04 * math.pi, 0.08 * math.pi,
                                                    0.16 * math.pi))
    assert c.shape == "circle" and t.shape == "tube" and th.shape == "thin-tube"


# --- eq. (3.11): ellipse ------------------------------------------------------------------------


@pytest.mark.parametrize("nu", NUS)
@pytest.mark.parametrize("aspect", [0.2, 0.75, 1.0, 2.0, 4.0, 17.0])
@pytest.mark.parametrize("torsion", TORSION_OPTIONS)
def test_eq_3_11_ellipse_sqrt_b1b2(aspect, nu, torsion):
    """Eq. (3.11): sqrt(B1 B2)/B3 = (h/t) sqrt(2/((1+nu)(1+(t/h)^2))); and b1 = (h/t)^2.

    The code builds b2 from J = pi a^3 b^3/(a^2+b^2) and I3 = pi a b^3/4; (3.11) is exact, so
    both torsion options agree.
    """
    s = ellipse(aspect=aspect, nu=nu, torsion=torsion, thickness=0.3)
    expected = aspect * math.sqrt(2.0 / ((1.0 + nu) * (1.0 + aspect**-2)))
    assert s.sqrt_b1b2 == pytest.approx(expected, rel=1e-13)
    assert s.b1 == aspect**2
    assert s.torsion == torsion and s.aspect == aspect
    h, t = 0.3 * aspect, 0.3
    assert s.area == pytest.approx(math.pi * h * t / 4, rel=1e-14)
    assert s.I1 == pytest.approx(math.pi * t * h**3 / 64, rel=1e-14)


def test_ellipse_circle_limit():
    """Aspect 1: the ellipse is a circle, so b1 = 1 and b2 = 1/(1+nu) (paper Sec. 3.1)."""
    s = ellipse(aspect=1.0, nu=0.3)
    assert s.b1 == 1.0
    assert s.b2 == pytest.approx(1 / 1.3, rel=1e-15)


# --- rectangle: Saint-Venant torsion constant --------------------------------------------------

# Timoshenko & Goodier, Theory of Elasticity (3rd ed.), Sec. 109, table for torsion of
# rectangular bars: k1 = J / (a b^3) with a >= b the long and short sides (4 significant digits).
TIMOSHENKO_K = [
    (1.0, 0.1406),
    (1.5, 0.1958),
    (2.0, 0.2287),
    (3.0, 0.2633),
    (4.0, 0.2808),
    (5.0, 0.2913),
    (10.0, 0.3123),
]


@pytest.mark.parametrize(("ratio", "k_table"), TIMOSHENKO_K)
def test_timoshenko_goodier_table_rectangle_torsion_coefficient(ratio, k_table):
    """Saint-Venant's J/(a b^3) matches Timoshenko & Goodier's table to its last digit."""
    J = rectangle_torsion_constant(width=ratio * 0.7, height=0.7)
    assert J / (ratio * 0.7 * 0.7**3) == pytest.approx(k_table, abs=5e-5)


def test_timoshenko_goodier_thin_strip_limit_one_third():
    """a/b -> inf: J -> a b^3/3 (table's last entry), with 1/3 - k ~ 0.21 b/a."""
    for ratio in (1e3, 1e6, 1e9):
        k = rectangle_torsion_constant(width=ratio, height=1.0) / ratio
        assert 1 / 3 - k == pytest.approx(0.21 / ratio, rel=0.01)


@pytest.mark.parametrize("ratio", [1.0, 1.5, 2.0, 10.0])
def test_rectangle_torsion_constant_matches_independent_series(ratio):
    """Full-precision value vs the test's own plain float loop of Saint-Venant's series."""
    J = rectangle_torsion_constant(width=ratio, height=1.0)
    assert J / ratio == pytest.approx(reference_k(ratio), rel=1e-14)


@pytest.mark.parametrize(("w", "h"), [(1.0, 2.5), (0.3, 0.1), (7.0, 7.0), (1e-3, 4.0)])
def test_rectangle_torsion_constant_symmetric_in_width_height(w, h):
    """J of a w x h bar equals J of an h x w bar (same cross-section, rotated)."""
    assert rectangle_torsion_constant(width=w, height=h) == rectangle_torsion_constant(
        width=h, height=w
    )


def test_rectangle_torsion_series_converges_at_expected_rate():
    """Truncation error of Saint-Venant's series for the square, vs rtol.

    Error <= rtol at each level, strictly decreasing, and log(error) vs log(rtol) has slope
    ~1 (series cut where the tail bound 1/(4 N^4) meets rtol); asserted >= 1 - 0.2.
    """
    expected_order = 1.0
    rtols = np.array([1e-3, 1e-5, 1e-7, 1e-9, 1e-11])
    ref = reference_k(1.0)
    errors = np.array(
        [abs(rectangle_torsion_constant(width=1.0, height=1.0, rtol=r) / ref - 1) for r in rtols]
    )
    assert np.all(errors <= rtols)
    assert np.all(np.diff(errors) < 0)
    assert np.all(errors > 1e3 * np.finfo(float).eps)  # fit stays above round-off
    slope = np.polyfit(np.log(rtols), np.log(errors), 1)[0]
    assert slope >= expected_order - 0.2


@pytest.mark.parametrize("aspect", [0.1, 0.75, 1.0, 2.5, 8.0])
def test_rectangle_b1_and_geometry(aspect):
    """Paper before eq. (3.12): b1 = (h/t)^2; I1 = t h^3/12, I3 = h t^3/12, A = h t."""
    s = rectangle(aspect=aspect, thickness=2.0)
    h = 2.0 * aspect
    assert s.b1 == aspect**2
    assert (s.area, s.I1, s.I3) == pytest.approx((2 * h, 2 * h**3 / 12, h * 8 / 12), rel=1e-14)


@pytest.mark.parametrize("nu", NUS)
def test_sec_3_2_square_b1_1_and_b2_slightly_below_circle(nu):
    """Paper Sec. 3.2: the square has b1 = 1 and b2 "slightly smaller" than 1/(1+nu).

    Exact: b2 = 6 k1/(1+nu) = 0.84346/(1+nu) with k1 = 0.140577 (independent loop).
    """
    s = rectangle(aspect=1.0, nu=nu)
    assert s.b1 == 1.0
    assert s.b2 == pytest.approx(6 * reference_k(1.0) / (1 + nu), rel=1e-13)
    assert 0.8 / (1 + nu) < s.b2 < 1 / (1 + nu)


@pytest.mark.parametrize("nu", NUS)
@pytest.mark.parametrize("aspect", [0.5, 1.0, 4.0])
def test_rectangle_exact_b2_is_J_over_2_1_plus_nu_I3(aspect, nu):
    """b2 = J/(2(1+nu) I3), J from the independent loop with the long side first."""
    s = rectangle(aspect=aspect, nu=nu)
    long_, short = max(aspect, 1.0), min(aspect, 1.0)
    J = reference_k(long_ / short) * long_ * short**3
    assert s.J == pytest.approx(J, rel=1e-14)
    assert s.b2 == pytest.approx(J / (2 * (1 + nu) * aspect / 12), rel=1e-14)


# --- eq. (3.12) as printed ----------------------------------------------------------------------


@pytest.mark.parametrize("nu", NUS)
@pytest.mark.parametrize("aspect", [0.05, 0.75, 1.0, 2.0, 4.0, 30.0])
def test_eq_3_12_paper_torsion_as_printed(aspect, nu):
    """Eq. (3.12): b2 = 2/(1+nu) (1 - 195/pi^5 (t/h) tanh(pi h/(2t))), constant 195 as printed."""
    expected = 2 / (1 + nu) * (1 - 195 / math.pi**5 / aspect * math.tanh(math.pi * aspect / 2))
    assert rectangle_b2_paper(aspect=aspect, nu=nu) == pytest.approx(expected, rel=1e-14)
    s = rectangle(aspect=aspect, nu=nu, torsion="paper")
    assert s.b2 == pytest.approx(expected, rel=1e-14)
    assert s.b1 == aspect**2 and s.torsion == "paper"
    assert s.J == pytest.approx(2 * (1 + nu) * s.b2 * s.I3, rel=1e-14)


@pytest.mark.parametrize("aspect", [1.0, 1.1, 1.5, 2.0, 4.0, 10.0, 100.0])
def test_eq_3_12_within_2_percent_of_exact_for_h_over_t_at_least_1(aspect):
    """(3.12) vs exact b2 for h/t >= 1: at most 1.46 % low, worst at h/t = 1.

    Measured with an independent float loop (n <= 20001): b2_paper/b2_exact - 1 = -1.459 % at
    h/t = 1, -0.771 % at 1.5, -0.505 % at 2, -0.207 % at 4, -0.074 % at 10, -0.007 % at 100.
    The gap comes from 195 vs 192 sum_{n odd} tanh(n pi h/2t)/n^5 (= 176.9 at h/t = 1).
    """
    nu = 1 / 3
    paper = rectangle(aspect=aspect, nu=nu, torsion="paper").b2
    exact = rectangle(aspect=aspect, nu=nu, torsion="exact").b2
    independent = 6 * reference_k(aspect) / (1 + nu)
    assert exact == pytest.approx(independent, rel=1e-13)
    gap = paper / exact - 1
    assert -0.02 < gap < 0.0
    square = rectangle(aspect=1.0, nu=nu)
    worst = rectangle_b2_paper(aspect=1.0, nu=nu) / square.b2 - 1
    # (3.12) as printed at h/t = 1 over the independent series: -1.459 %
    printed = 2 / (1 + nu) * (1 - 195 / math.pi**5 * math.tanh(math.pi / 2))
    assert worst == pytest.approx(printed / (6 * reference_k(1.0) / (1 + nu)) - 1, rel=1e-12)
    assert worst == pytest.approx(-0.01459, abs=1e-5)  # the docstring's number
    assert abs(gap) <= abs(worst) + 1e-15


def test_eq_3_12_paper_b2_nonpositive_is_rejected():
    """(3.12) as printed turns negative below h/t ~ 0.0334 (195/(2 pi^4) > 1); exact stays > 0."""
    assert rectangle_b2_paper(aspect=0.02, nu=0.3) < 0
    with pytest.raises(RodstabInputError, match="aspect=0.02"):
        rectangle(aspect=0.02, torsion="paper")
    assert rectangle(aspect=0.02).b2 > 0


# --- from_ratios, Section, make_section ---------------------------------------------------------


def test_from_ratios_and_to_dict():
    """Given ratios pass through unchanged; geometry is None; sqrt_b1b2 = sqrt(b1 b2)."""
    s = from_ratios(b1=4.0, b2=0.25)
    assert (s.shape, s.b1, s.b2, s.nu, s.torsion, s.aspect, s.J) == (
        "ratios", 4.0, 0.25, None, "given", None, None
    )
    assert s.sqrt_b1b2 == 1.0
    d = s.to_dict()
    assert d["b1"] == 4.0 and d["area"] is None and set(d) >= {"shape", "b2", "I1", "I3"}


def test_section_is_frozen_and_validated():
    """Result objects are immutable, and hand-built ones are checked like the constructors'."""
    s = circle()
    with pytest.raises(AttributeError):
        s.b1 = 2.0  # type: ignore[misc]
    with pytest.raises(RodstabInputError, match="b2"):
        Section("circle", 1.0, -1.0, 0.3, "exact", None, None, None, None, None)
    with pytest.raises(RodstabInputError, match="'hexagon'"):
        Section("hexagon", 1.0, 1.0, 0.3, "exact", None, None, None, None, None)


def test_make_section_shapes_and_defaults():
    """make_section dispatches to the constructors with documented defaults."""
    assert make_section() == circle()
    assert make_section("circle", nu=0.2) == circle(nu=0.2)
    assert make_section("ellipse") == ellipse(aspect=1.0)
    assert make_section("rectangle", aspect=3.0, torsion="paper") == rectangle(
        aspect=3.0, torsion="paper"
    )
    assert make_section("tube") == tube(outer_radius=1.0, inner_radius=0.5)
    assert make_section("tube", aspect=0.0).aspect == 0.0
    assert {make_section(shape).shape for shape in SHAPES} == set(SHAPES)


def test_make_section_b1_b2_override_shape():
    """Both b1 and b2 given: they override the shape (and nu) and give a 'ratios' section."""
    assert make_section("rectangle", b1=2.0, b2=0.5) == from_ratios(b1=2.0, b2=0.5)
    assert make_section(None, b1=2.0, b2=0.5, nu=0.1) == from_ratios(b1=2.0, b2=0.5)


@pytest.mark.parametrize(
    ("kwargs", "fragments"),
    [
        ({"shape": "circle", "b1": 2.0}, ["b1", "2.0", "b2"]),
        ({"shape": "circle", "b2": 0.7}, ["b2", "0.7", "b1"]),
        ({"shape": "circle", "aspect": 2.0}, ["aspect", "2.0", "circle"]),
        ({"shape": "square"}, ["shape", "'square'", "circle", "rectangle", "tube"]),
        ({"shape": None}, ["shape", "None"]),
        ({"shape": "ellipse", "torsion": "approx"}, ["torsion", "'approx'", "exact", "paper"]),
        ({"shape": "circle", "torsion": "Exact"}, ["torsion", "'Exact'"]),
        ({"b1": 2.0, "b2": 0.5, "aspect": 3.0}, ["aspect", "3.0", "b1"]),
        ({"b1": 2.0, "b2": 0.5, "torsion": "paper"}, ["torsion", "'paper'"]),
        ({"shape": "tube", "aspect": 1.0}, ["aspect", "1.0", "[0, 1)"]),
        ({"shape": "tube", "aspect": -0.1}, ["aspect", "-0.1"]),
        ({"shape": "tube", "aspect": math.nan}, ["aspect", "nan"]),
        ({"shape": "rectangle", "aspect": 0.0}, ["aspect", "0.0"]),
        ({"shape": "ellipse", "aspect": -2.0}, ["aspect", "-2.0"]),
        ({"shape": "rectangle", "nu": 0.6}, ["nu", "0.6"]),
        ({"b1": 2.0, "b2": -0.5}, ["b2", "-0.5"]),
    ],
)
def test_make_section_errors(kwargs, fragments):
    """Bad CLI combinations raise RodstabInputError naming the option, its value, valid ones."""
    kwargs = dict(kwargs)
    shape = kwargs.pop("shape", "circle")
    with pytest.raises(RodstabInputError) as info:
        make_section(shape, **kwargs)
    for fragment in fragments:
        assert fragment in str(info.value)


# --- bad input table ----------------------------------------------------------------------------

BAD_INPUTS = [
    (circle, {"radius": 0.0}, "radius", 0.0),
    (circle, {"radius": -1.0}, "radius", -1.0),
    (circle, {"radius": math.inf}, "radius", math.inf),
    (circle, {"nu": 0.51}, "nu", 0.51),
    (circle, {"nu": -1.0}, "nu", -1.0),
    (ellipse, {"aspect": math.nan}, "aspect", math.nan),
    (ellipse, {"aspect": 2.0, "thickness": 0.0}, "thickness", 0.0),
    (ellipse, {"aspect": 2.0, "torsion": "sokolnikoff"}, "torsion", "sokolnikoff"),
    (rectangle, {"aspect": -3.0}, "aspect", -3.0),
    (rectangle, {"aspect": math.inf}, "aspect", math.inf),
    (rectangle, {"aspect": 2.0, "thickness": -1.0}, "thickness", -1.0),
    (rectangle, {"aspect": 2.0, "torsion": "192"}, "torsion", "192"),
    (rectangle, {"aspect": 2.0, "nu": math.nan}, "nu", math.nan),
    (tube, {"outer_radius": 1.0, "inner_radius": 1.0}, "inner_radius", 1.0),
    (tube, {"outer_radius": 1.0, "inner_radius": 2.0}, "inner_radius", 2.0),
    (tube, {"outer_radius": 1.0, "inner_radius": -0.5}, "inner_radius", -0.5),
    (tube, {"outer_radius": 0.0, "inner_radius": 0.0}, "outer_radius", 0.0),
    (thin_tube, {"radius": 1.0, "wall": 0.0}, "wall", 0.0),
    (thin_tube, {"radius": 1.0, "wall": 1.0}, "wall", 1.0),
    (thin_tube, {"radius": -1.0, "wall": 0.1}, "radius", -1.0),
    (from_ratios, {"b1": 0.0, "b2": 1.0}, "b1", 0.0),
    (from_ratios, {"b1": 1.0, "b2": -math.inf}, "b2", -math.inf),
    (from_ratios, {"b1": 1.0, "b2": True}, "b2", True),
    (rectangle_torsion_constant, {"width": 0.0, "height": 1.0}, "width", 0.0),
    (rectangle_torsion_constant, {"width": 1.0, "height": math.nan}, "height", math.nan),
    (rectangle_torsion_constant, {"width": 1.0, "height": 1.0, "rtol": 0.0}, "rtol", 0.0),
    (rectangle_torsion_constant, {"width": 1.0, "height": 1.0, "rtol": 1e-20}, "rtol", 1e-20),
    (rectangle_torsion_constant, {"width": 1.0, "height": 1.0, "rtol": 1.0}, "rtol", 1.0),
    (rectangle_b2_paper, {"aspect": 0.0, "nu": 0.3}, "aspect", 0.0),
    (rectangle_b2_paper, {"aspect": 1.0, "nu": 0.7}, "nu", 0.7),
]


@pytest.mark.parametrize(
    ("func", "kwargs", "name", "value"),
    BAD_INPUTS,
    ids=[f"{f.__name__}-{n}={v!r}" for f, _, n, v in BAD_INPUTS],
)
def test_bad_input_names_parameter_and_value(func, kwargs, name, value):
    """Every invalid input raises RodstabInputError (a ValueError) naming parameter and value."""
    with pytest.raises(RodstabInputError) as info:
        func(**kwargs)
    assert isinstance(info.value, ValueError)
    message = str(info.value)
    assert name in message
    assert repr(value) in message


@pytest.mark.parametrize("build, word", [
    (lambda: rectangle(aspect=1e308), "aspect"),
    (lambda: rectangle(aspect=1e-300), "aspect"),
    (lambda: ellipse(aspect=2e4), "aspect"),
    (lambda: rectangle(aspect=1e4, thickness=1e100), "thickness"),
    (lambda: rectangle(aspect=1.0, thickness=1e-120), "thickness"),
    (lambda: from_ratios(b1=1e308, b2=1e308), "b1"),
    (lambda: from_ratios(b1=1.0, b2=1e-12), "b2"),
], ids=["rect 1e308", "rect 1e-300", "ellipse 2e4", "I1 overflow", "I3 underflow",
        "ratios 1e308", "b2 1e-12"])
def test_out_of_range_sections_are_refused_naming_the_input(build, word):
    """Hostile sizes never overflow into a traceback or a null sqrt(b1 b2) (issue 10)."""
    with pytest.raises(RodstabInputError, match=word):
        build()


@pytest.mark.parametrize("aspect", [1e-4, 1e4])
def test_the_ends_of_the_aspect_range_give_finite_ratios(aspect):
    """b1 = (h/t)^2 exactly at both ends, and sqrt(b1 b2) finite and positive."""
    for s in (rectangle(aspect=aspect), ellipse(aspect=aspect)):
        assert s.b1 == pytest.approx(aspect**2, rel=1e-15)
        assert 0 < s.sqrt_b1b2 < math.inf
