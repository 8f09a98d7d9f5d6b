"""Cross-sections: stiffness ratios b1 = B1/B3 and b2 = B2/B3 of a rod.

References
----------
* S. Leanza, R. R. Zhao, J. W. Hutchinson, "On the elastic stability of folded rings in
  circular and straight states" (the paper): Section 3.1 (circular sections, solid or annular,
  have b1 = 1, b2 = 1/(1+nu)), eq. (3.11) (ellipse), eq. (3.12) (rectangle, Sokolnikoff's
  approximation, printed with the constant 195/pi^5).
* S. P. Timoshenko, J. N. Goodier, *Theory of Elasticity*, 3rd ed., Sec. 109: Saint-Venant's
  series for the torsion constant of a rectangle and the ellipse's J = pi a^3 b^3/(a^2 + b^2).
* I. S. Sokolnikoff, *Mathematical Theory of Elasticity*, 2nd ed. (1956), Sec. 37.
* R. van Leeuwen, *sectionproperties* (https://github.com/robbievanleeuwen/section-properties):
  any polygon with holes, meshed by Shewchuk's Triangle into six-node (quadratic) triangles;
  second moments by exact integration, Saint-Venant's torsion constant by FE of the warping
  function (:func:`polygon_section`).

Conventions
-----------
B1 = E I1 bends the rod out of the plane of the ring (about e1, I1 = int x3^2 dA), B3 = E I3 bends
it in that plane (about e3, I3 = int x1^2 dA) and B2 = G J twists it, G = E / (2 (1 + nu)), so
``b1 = I1 / I3`` and ``b2 = J / (2 (1 + nu) I3)``. A section has height h along e3 and thickness t
along e1; its aspect is h / t.

A polygon (:func:`polygon_section`) is given in its own (x, y) coordinates with **y along e3,
out of the plane of the ring** (as h of the rectangle) and x along e1, in the plane: a
t x h rectangle is ``[[0, 0], [t, 0], [t, h], [0, h]]``. The theory (paper, Section 2) assumes
that the principal axes of the section are e1 and e3; a polygon whose principal axes are not x
and y is refused unless ``orientation_deg`` names the principal axis that is the ring's normal.
:func:`composite_section` takes several such polygons of different E and nu, bonded.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping, Sequence
from numbers import Real
from typing import Any

import numpy as np

from .errors import (
    RodstabInputError,
    require_finite,
    require_in_range,
    require_poisson,
    require_positive,
)
from .results import Result

#: Torsion-constant options of the non-circular shapes: the exact Saint-Venant value, or the
#: paper's closed form (eq. 3.12 as printed; identical to the exact value for the ellipse).
TORSION_OPTIONS = ("exact", "paper")
#: Shapes that :func:`make_section` (the CLI's entry point) builds.
SHAPES = ("circle", "ellipse", "rectangle", "tube")
#: Section dimensions of a design with units, by shape: lengths, ``height`` (h) along e3 out
#: of the ring's plane, ``thickness`` (t) along e1 in it.
SECTION_DIMENSIONS = {"circle": ("diameter",), "tube": ("outer_diameter", "inner_diameter"),
                      "rectangle": ("height", "thickness"), "ellipse": ("height", "thickness")}
#: :attr:`Section.shape` of :func:`polygon_section` (and the design files' shape key for it).
POLYGON = "polygon"
#: :attr:`Section.shape` of :func:`composite_section` (several materials).
COMPOSITE = "composite"
#: Every value of :attr:`Section.shape` (``make_section`` reaches "thin-tube" and "ratios" only
#: through :func:`thin_tube` and the b1/b2 override; "polygon" is :func:`polygon_section`).
_ALL_SHAPES = (*SHAPES, "thin-tube", "ratios", POLYGON, COMPOSITE)
#: Torsion constant of a polygon: Saint-Venant's, by FE of the warping function.
FE_TORSION = "fe-warping"
#: Every value of :attr:`Section.torsion`; "given" marks ratios supplied directly.
_ALL_TORSION = (*TORSION_OPTIONS, "given", FE_TORSION)

#: Default relative truncation error of :func:`rectangle_torsion_constant`.
SERIES_RTOL = 1e-15
#: Smallest accepted ``rtol``: below double precision the tail bound only buys more terms.
SERIES_RTOL_MIN = 1e-16
#: Default inner/outer radius ratio of the tube that :func:`make_section` builds.
TUBE_DEFAULT_ASPECT = 0.5

#: Accepted h/t of ellipses and rectangles: a rod's cross-section (beyond, a plate or a sheet
#: of wires; b1 = (h/t)^2 would reach 1e8).
ASPECT_RANGE = (1e-4, 1e4)
#: Accepted stiffness ratios b1 = B1/B3 and b2 = B2/B3: every section in ASPECT_RANGE lies
#: inside (b1 = (h/t)^2 in [1e-8, 1e8]); beyond, sqrt(b1 b2) and the critical loads overflow.
RATIO_RANGE = (1e-9, 1e9)
_ASPECT_WHY = "the h/t of a rod's cross-section"
_RATIO_WHY = "the stiffness ratio of a rod's cross-section; h/t in [1e-4, 1e4] gives at most 1e8"

# Saint-Venant's constant 192/pi^5 and the paper's printed 195/pi^5 (eq. 3.12).
_SV_CONSTANT = 192.0 / math.pi**5
_PAPER_CONSTANT = 195.0 / math.pi**5


@dataclasses.dataclass(frozen=True)
class Section(Result):
    """Stiffness ratios of a rod cross-section, with the geometry they came from.

    Attributes
    ----------
    shape : str
        "circle", "ellipse", "rectangle", "tube", "thin-tube", "ratios", "polygon" or
        "composite".
    b1 : float
        B1/B3, out-of-plane over in-plane bending stiffness (= I1/I3).
    b2 : float
        B2/B3, torsional over in-plane bending stiffness (= J / (2 (1 + nu) I3)).
    nu : float or None
        Poisson's ratio; None when b1, b2 were given directly.
    torsion : str
        "exact", "paper" (eq. 3.11/3.12 as printed), "given" (ratios supplied directly) or
        "fe-warping" (a polygon's Saint-Venant J by the finite element method).
    aspect : float or None
        h/t for ellipse and rectangle, inner/outer radius ratio for tube, None otherwise.
    area, I1, I3, J : float or None
        Area, second moments and torsion constant of the geometry documented by the
        constructor (unit thickness or the given radii); None for "ratios".
    """

    shape: str
    b1: float
    b2: float
    nu: float | None
    torsion: str
    aspect: float | None
    area: float | None
    I1: float | None
    I3: float | None
    J: float | None

    def __post_init__(self) -> None:
        # A Section built by hand must be as valid as one from the constructors.
        if self.shape not in _ALL_SHAPES:
            raise RodstabInputError(f"shape must be one of {_ALL_SHAPES}, got {self.shape!r}")
        if self.torsion not in _ALL_TORSION:
            raise RodstabInputError(
                f"torsion must be one of {_ALL_TORSION}, got {self.torsion!r}"
            )
        require_in_range("b1", self.b1, *RATIO_RANGE, _RATIO_WHY)
        require_in_range("b2", self.b2, *RATIO_RANGE, _RATIO_WHY)

    @property
    def sqrt_b1b2(self) -> float:
        """sqrt(b1 b2) = sqrt(B1 B2)/B3, the stiffness combination of eq. (3.9) and Fig. 4."""
        return math.sqrt(self.b1 * self.b2)


def _check_torsion(torsion: str) -> str:
    if not isinstance(torsion, str) or torsion not in TORSION_OPTIONS:
        raise RodstabInputError(f"torsion must be one of {TORSION_OPTIONS}, got {torsion!r}")
    return torsion


def _b2(J: float, I3: float, nu: float) -> float:
    """b2 = G J / (E I3) with G = E / (2 (1 + nu))."""
    # Divide J by 2 I3 first: for round sections J = 2 I3 exactly (a power-of-two scaling), so
    # the ratio is exactly 1.0 and b2 is exactly 1/(1 + nu), as stated in Section 3.1.
    return (J / (2.0 * I3)) / (1.0 + nu)


def _round_section(shape: str, nu: float, aspect: float | None, area: float, I: float) -> Section:
    """Section with I1 = I3 = I and J = 2 I (any axisymmetric section)."""
    J = 2.0 * I
    return Section(
        shape=shape,
        b1=1.0,
        b2=_b2(J, I, nu),
        nu=nu,
        torsion="exact",
        aspect=aspect,
        area=area,
        I1=I,
        I3=I,
        J=J,
    )


def circle(*, radius: float = 1.0, nu: float = 1 / 3) -> Section:
    """Solid circular section: b1 = 1, b2 = 1/(1 + nu) (paper, Section 3.1).

    Parameters
    ----------
    radius : float
        Radius r > 0; ``area`` = pi r^2, ``I1`` = ``I3`` = pi r^4/4, ``J`` = pi r^4/2.
    nu : float
        Poisson's ratio in (-1, 0.5].

    Returns
    -------
    Section
        With ``shape="circle"``, ``torsion="exact"``, ``aspect=None``.
    """
    r = require_positive("radius", radius)
    nu = require_poisson(nu)
    return _round_section("circle", nu, None, math.pi * r**2, math.pi * r**4 / 4.0)


def tube(*, outer_radius: float, inner_radius: float, nu: float = 1 / 3) -> Section:
    """Thick annular section: b1 = 1, b2 = 1/(1 + nu) (paper, Section 3.1, "annular").

    Parameters
    ----------
    outer_radius : float
        Outer radius ro > 0.
    inner_radius : float
        Inner radius ri with 0 <= ri < ro (ri = 0 is the solid circle).
    nu : float
        Poisson's ratio in (-1, 0.5].

    Returns
    -------
    Section
        With ``shape="tube"``, ``aspect`` = ri/ro, ``area`` = pi (ro^2 - ri^2),
        ``I1`` = ``I3`` = pi (ro^4 - ri^4)/4 and ``J`` = pi (ro^4 - ri^4)/2.
    """
    ro = require_positive("outer_radius", outer_radius)
    ri = require_finite("inner_radius", inner_radius)
    if ri < 0.0:
        raise RodstabInputError(f"inner_radius must be >= 0, got {inner_radius!r}")
    if ri >= ro:
        raise RodstabInputError(
            f"inner_radius must be smaller than outer_radius={outer_radius!r}, "
            f"got {inner_radius!r}"
        )
    nu = require_poisson(nu)
    area = math.pi * (ro**2 - ri**2)
    return _round_section("tube", nu, ri / ro, area, math.pi * (ro**4 - ri**4) / 4.0)


def thin_tube(*, radius: float, wall: float, nu: float = 1 / 3) -> Section:
    """Thin-walled circular tube (wall << radius): b1 = 1, b2 = 1/(1 + nu).

    Uses the thin-wall forms I1 = I3 = pi r^3 w and J = 2 pi r^3 w (Bredt), which keep
    J = 2 I exactly, so the ratios equal those of the thick tube (paper, Section 3.1).

    Parameters
    ----------
    radius : float
        Mid-wall radius r > 0.
    wall : float
        Wall thickness w with 0 < w < r; ``area`` = 2 pi r w.
    nu : float
        Poisson's ratio in (-1, 0.5].

    Returns
    -------
    Section
        With ``shape="thin-tube"``, ``aspect=None``.
    """
    r = require_positive("radius", radius)
    w = require_positive("wall", wall)
    if w >= r:
        raise RodstabInputError(
            f"wall must be smaller than radius={radius!r} for a thin tube, got {wall!r}"
        )
    nu = require_poisson(nu)
    return _round_section("thin-tube", nu, None, 2.0 * math.pi * r * w, math.pi * r**3 * w)


def ellipse(
    *, aspect: float, nu: float = 1 / 3, torsion: str = "exact", thickness: float = 1.0
) -> Section:
    """Solid elliptical section with semi-axes h/2 along e3 and t/2 along e1.

    b1 = (h/t)^2 and, from the exact J = pi a^3 b^3/(a^2 + b^2) (a = h/2, b = t/2),
    b2 = 2 / ((1 + nu) (1 + (t/h)^2)), so sqrt(b1 b2) is eq. (3.11). Eq. (3.11) is exact, hence
    ``torsion="paper"`` gives the same numbers; it is accepted (and recorded) so that one torsion
    option applies to every shape.

    Parameters
    ----------
    aspect : float
        h/t > 0.
    nu : float
        Poisson's ratio in (-1, 0.5].
    torsion : {"exact", "paper"}
        Recorded in the result; both give the exact value.
    thickness : float
        t > 0; the geometry fields are for h = aspect * t.

    Returns
    -------
    Section
        With ``shape="ellipse"``, ``area`` = pi h t/4, ``I1`` = pi t h^3/64,
        ``I3`` = pi h t^3/64.
    """
    x = require_in_range("aspect", aspect, *ASPECT_RANGE, _ASPECT_WHY)
    t = require_positive("thickness", thickness)
    nu = require_poisson(nu)
    torsion = _check_torsion(torsion)
    h = x * t
    a, b = h / 2.0, t / 2.0
    I1 = math.pi * b * a**3 / 4.0
    I3 = math.pi * a * b**3 / 4.0
    J = math.pi * a**3 * b**3 / (a**2 + b**2)
    # b1 from the closed form, not I1/I3, so that b1 == aspect**2 without round-off.
    return Section(
        shape="ellipse",
        b1=x**2,
        b2=_b2(J, I3, nu),
        nu=nu,
        torsion=torsion,
        aspect=x,
        area=math.pi * a * b,
        I1=I1,
        I3=I3,
        J=J,
    )


def _series_terms(rtol: float) -> int:
    """Largest odd n kept so that the neglected tail changes J by at most ``rtol`` (relative)."""
    # Tail: sum_{m odd >= N+2} tanh(.)/m^5 <= int_N^inf dx/(2 x^5) = 1/(8 N^4). Its weight in J
    # relative to J is (192/pi^5)(b/a) / (1 - (192/pi^5)(b/a) S) <= 0.6274/0.3698 < 2 for
    # b <= a (S <= sum 1/n^5 over odd n = 1.00452), so N >= (4 rtol)^(-1/4) suffices.
    n = math.ceil((4.0 * rtol) ** -0.25)
    return n if n % 2 == 1 else n + 1


def rectangle_torsion_constant(
    *, width: float, height: float, rtol: float = SERIES_RTOL
) -> float:
    """Exact (Saint-Venant) torsion constant J of a solid width x height rectangle.

    With a >= b the long and short sides,
    J = a b^3/3 (1 - (192/pi^5)(b/a) sum_{n odd} tanh(n pi a/(2 b))/n^5)
    (Timoshenko & Goodier, Sec. 109). The formula is exact for either orientation, but only with
    a >= b does the bracket avoid cancellation, so the sides are sorted first; J is therefore
    symmetric in ``width`` and ``height``.

    Parameters
    ----------
    width, height : float
        Side lengths, > 0.
    rtol : float
        Bound on the relative truncation error of J, in [1e-16, 1). The series is cut where a
        rigorous bound on the neglected tail meets it (about ``(4 rtol)**-0.25 / 2`` terms), not
        where a single term first drops below ``rtol``, which would leave a tail ~n/8 times
        larger.

    Returns
    -------
    float
        J, in units of length^4.
    """
    w = require_positive("width", width)
    h = require_positive("height", height)
    tol = require_positive("rtol", rtol)
    if not (SERIES_RTOL_MIN <= tol < 1.0):
        raise RodstabInputError(f"rtol must lie in [{SERIES_RTOL_MIN}, 1), got {rtol!r}")
    a, b = max(w, h), min(w, h)
    n = np.arange(1, _series_terms(tol) + 1, 2, dtype=float)
    # fsum: the bracket 1 - 0.63 S is computed from a sum dominated by its first term.
    s = math.fsum((np.tanh(n * math.pi * a / (2.0 * b)) / n**5).tolist())
    return a * b**3 / 3.0 * (1.0 - _SV_CONSTANT * (b / a) * s)


def rectangle_b2_paper(*, aspect: float, nu: float) -> float:
    """b2 of a solid rectangle from eq. (3.12), exactly as printed.

    b2 = 2/(1 + nu) (1 - (195/pi^5)(t/h) tanh(pi h/(2 t))), h/t = ``aspect``.

    Sokolnikoff's one-term approximation with the paper's constant 195; the exact series has
    192/pi^5 times sum_{n odd} tanh(n pi h/(2 t))/n^5 (-> 192.87/pi^5 for h >> t). For h/t >= 1
    it is 1.46 % below the exact b2 at h/t = 1 and closer above; for h/t < 1 (where t, not h, is
    the long side) the error grows (2.3 % at 0.75, 23 % at 0.1) and the value turns negative
    below h/t ~ 0.0334. Evaluated for any positive aspect; :func:`rectangle` rejects b2 <= 0.

    Parameters
    ----------
    aspect : float
        h/t > 0.
    nu : float
        Poisson's ratio in (-1, 0.5].

    Returns
    -------
    float
        The printed eq. (3.12); may be <= 0 for very small aspect.
    """
    x = require_positive("aspect", aspect)
    nu = require_poisson(nu)
    return 2.0 / (1.0 + nu) * (1.0 - _PAPER_CONSTANT / x * math.tanh(math.pi * x / 2.0))


def rectangle(
    *, aspect: float, nu: float = 1 / 3, torsion: str = "exact", thickness: float = 1.0
) -> Section:
    """Solid rectangular section, height h along e3 and thickness t along e1.

    b1 = (h/t)^2 (paper, before eq. 3.12); b2 = J/(2 (1 + nu) I3) with the exact Saint-Venant J
    (:func:`rectangle_torsion_constant`) for ``torsion="exact"``, or eq. (3.12) as printed
    (:func:`rectangle_b2_paper`) for ``torsion="paper"``.

    Parameters
    ----------
    aspect : float
        h/t > 0.
    nu : float
        Poisson's ratio in (-1, 0.5].
    torsion : {"exact", "paper"}
        Torsion constant to use.
    thickness : float
        t > 0; the geometry fields are for h = aspect * t.

    Returns
    -------
    Section
        With ``shape="rectangle"``, ``area`` = h t, ``I1`` = t h^3/12, ``I3`` = h t^3/12 and
        ``J`` consistent with the returned b2 (J = 2 (1 + nu) b2 I3 for ``torsion="paper"``).

    Raises
    ------
    RodstabInputError
        If ``torsion="paper"`` and eq. (3.12) gives b2 <= 0 (aspect below about 0.0334).
    """
    x = require_in_range("aspect", aspect, *ASPECT_RANGE, _ASPECT_WHY)
    t = require_positive("thickness", thickness)
    nu = require_poisson(nu)
    torsion = _check_torsion(torsion)
    h = x * t
    # Products, not powers: a float power raises OverflowError where a product gives inf.
    I1 = t * h * h * h / 12.0
    I3 = h * t * t * t / 12.0
    require_finite("thickness (I1 = t h^3 / 12 overflows)", I1)
    require_positive("thickness (I3 = h t^3 / 12 underflows)", I3)
    if torsion == "exact":
        J = rectangle_torsion_constant(width=t, height=h)
        b2 = _b2(J, I3, nu)
    else:
        b2 = rectangle_b2_paper(aspect=x, nu=nu)
        if b2 <= 0.0:
            raise RodstabInputError(
                f"aspect={aspect!r} is too small for torsion='paper': eq. (3.12) gives "
                f"b2={b2!r} <= 0; use torsion='exact'"
            )
        # Report the J implied by (3.12), so that the fields stay consistent with b2.
        J = 2.0 * (1.0 + nu) * b2 * I3
    return Section(
        shape="rectangle",
        b1=x**2,
        b2=b2,
        nu=nu,
        torsion=torsion,
        aspect=x,
        area=h * t,
        I1=I1,
        I3=I3,
        J=J,
    )


def from_ratios(*, b1: float, b2: float) -> Section:
    """Section given directly by its stiffness ratios b1 = B1/B3 and b2 = B2/B3 (both > 0).

    Returns
    -------
    Section
        With ``shape="ratios"``, ``torsion="given"`` and every geometry field None.
    """
    return Section(
        shape="ratios",
        b1=require_in_range("b1", b1, *RATIO_RANGE, _RATIO_WHY),
        b2=require_in_range("b2", b2, *RATIO_RANGE, _RATIO_WHY),
        nu=None,
        torsion="given",
        aspect=None,
        area=None,
        I1=None,
        I3=None,
        J=None,
    )


def make_section(
    shape: str | None = "circle",
    *,
    aspect: float | None = None,
    nu: float = 1 / 3,
    torsion: str = "exact",
    b1: float | None = None,
    b2: float | None = None,
) -> Section:
    """Build a section from CLI-style options.

    * ``b1`` and ``b2`` both given: :func:`from_ratios`, overriding ``shape`` (and ``nu``, which
      ratios do not need). Giving only one of them, or also an ``aspect`` or ``torsion="paper"``
      (which would be silently unused), raises.
    * "circle": :func:`circle` of unit radius; ``aspect`` must be None.
    * "ellipse", "rectangle": ``aspect`` = h/t (1.0 if None), unit thickness.
    * "tube": ``aspect`` = inner/outer radius ratio in [0, 1) (0.5 if None), unit outer radius.

    ``torsion`` is validated for every shape; circles and tubes have no approximate formula, so
    both options give their exact b2 = 1/(1 + nu) and the result records "exact".

    Raises
    ------
    RodstabInputError
        For an unknown ``shape`` or ``torsion`` (the message lists the valid ones), an
        inconsistent combination of options, or any invalid value.
    """
    torsion = _check_torsion(torsion)
    # nu is checked even when b1/b2 make it unused: an invalid value is never silently ignored.
    require_poisson(nu)
    if (b1 is None) != (b2 is None):
        given, missing = ("b1", "b2") if b2 is None else ("b2", "b1")
        value = b1 if b2 is None else b2
        raise RodstabInputError(
            f"{given}={value!r} was given without {missing}: give both b1 and b2, or neither"
        )
    if b1 is not None and b2 is not None:
        if aspect is not None:
            raise RodstabInputError(
                f"aspect={aspect!r} cannot be used with b1 and b2, which fix the section"
            )
        if torsion != "exact":
            raise RodstabInputError(
                f"torsion={torsion!r} cannot be used with b1 and b2, which fix the section"
            )
        return from_ratios(b1=b1, b2=b2)
    if not isinstance(shape, str) or shape not in SHAPES:
        raise RodstabInputError(
            f"shape must be one of {SHAPES} (or give b1 and b2), got {shape!r}"
        )
    if shape == "circle":
        if aspect is not None:
            raise RodstabInputError(
                f"aspect={aspect!r} has no meaning for shape 'circle'; omit it"
            )
        return circle(nu=nu)
    if shape == "tube":
        ratio = TUBE_DEFAULT_ASPECT if aspect is None else require_finite("aspect", aspect)
        if not (0.0 <= ratio < 1.0):
            raise RodstabInputError(
                f"aspect (inner/outer radius ratio of a tube) must lie in [0, 1), got {aspect!r}"
            )
        return tube(outer_radius=1.0, inner_radius=ratio, nu=nu)
    x = 1.0 if aspect is None else aspect
    if shape == "ellipse":
        return ellipse(aspect=x, nu=nu, torsion=torsion)
    return rectangle(aspect=x, nu=nu, torsion=torsion)


def sized_section(shape: str, sizes: Mapping[str, float], *, nu: float = 1 / 3,
                  torsion: str = "exact") -> Section:
    """Build a closed-form section of the given dimensions (its area, I1, I3, J in their unit).

    ``sizes`` holds the dimensions of ``shape`` (the keys of a design's section:
    ``diameter``; ``outer_diameter``, ``inner_diameter``; ``height`` h along e3 and
    ``thickness`` t along e1), all in one length unit. Same b1, b2 as :func:`make_section`
    with the aspect h/t or inner/outer; ``area``, ``I1``, ``I3``, ``J`` are those of these
    dimensions (E I3 is then B3).
    """
    torsion = _check_torsion(torsion)
    if shape == "circle":
        return circle(radius=sizes["diameter"] / 2, nu=nu)
    if shape == "tube":
        return tube(outer_radius=sizes["outer_diameter"] / 2,
                    inner_radius=sizes["inner_diameter"] / 2, nu=nu)
    build = {"rectangle": rectangle, "ellipse": ellipse}.get(shape)
    if build is None:
        raise RodstabInputError(f"shape must be one of {SHAPES} to be built from dimensions, "
                                f"got {shape!r}")
    return build(aspect=sizes["height"] / sizes["thickness"], thickness=sizes["thickness"],
                 nu=nu, torsion=torsion)


# --------------------------------------------------------------------------- any polygon
# Issue 13: a section given as a polygon with holes. The mesh and the finite elements are
# sectionproperties' (an optional dependency, imported only here); rodstab checks the polygon,
# normalises it, chooses the axes and turns second moments and J into b1 and b2.

#: Default ``mesh_size`` of :func:`polygon_section`: the largest triangle's area as a fraction
#: of the section's area. About 1600 six-node triangles; the 2:1 rectangle's J is then within
#: 3e-6 of Saint-Venant's series (tests/test_polygon_sections.py), in about 1 s.
POLYGON_MESH_SIZE = 1e-3
#: Accepted ``mesh_size``. Below 1e-4 a mesh has ~16000 triangles, which sectionproperties
#: analyses in tens of seconds for J errors ~1e-8; above 0.25 the companion mesh (4 x coarser,
#: for :attr:`PolygonSection.J_mesh_change`) would exceed one triangle per section.
MESH_SIZE_RANGE = (1e-4, 0.25)
#: Most triangles of a mesh. Triangle's 30-degree quality bound puts triangles no larger than
#: the local wall thickness, so a slender section needs many whatever ``mesh_size`` says;
#: past this the analysis (~1 ms per triangle) is refused rather than left to run for minutes.
MAX_MESH_ELEMENTS = 20_000
#: Most vertices of the polygon and its holes together.
MAX_POLYGON_VERTICES = 5_000
#: Largest |coordinate| of a polygon point, in its own length unit.
MAX_POLYGON_COORDINATE = 1e12
#: Accepted size (largest extent) of a polygon, in its own length unit (as design lengths).
POLYGON_SIZE_RANGE = (1e-9, 1e9)
#: Largest perimeter^2 / area (holes' perimeters included): 4e4 is a 1e4:1 strip, the limit of
#: ASPECT_RANGE; beyond it the quality mesh alone would have hundreds of thousands of triangles.
MAX_SLENDERNESS = 1e5
#: An area below this fraction of size^2 is zero (collinear points).
_ZERO_AREA = 1e-12
#: Largest |I13| / sqrt(I1 I3) accepted in the frame (e1, e3): the in-plane/out-of-plane
#: coupling of bending that the theory neglects. Exact for the polygon (the second moments of
#: a polygon are integrated exactly), and at 1e-6 of the order of the FE error of b2 at the
#: default mesh: below what the section analysis resolves.
COUPLING_TOL = 1e-6
#: How far (degrees) ``orientation_deg`` may be from the principal axis it names.
ORIENTATION_TOL_DEG = 1.0
#: Principal moments closer than this (relative) make every axis principal (a square, a
#: regular polygon): any ``orientation_deg`` is then a principal axis.
_ISOTROPIC = 1e-9
_SECTIONS_EXTRA = 'polygon sections need sectionproperties: pip install "rodstab[sections]"'


#: A closed ring of points (x, y), the closing point not repeated.
Ring = tuple[tuple[float, float], ...]


@dataclasses.dataclass(frozen=True)
class SectionPart(Result):
    """One material region of a polygon section: an outline with holes, E and nu.

    Attributes
    ----------
    outer : tuple of (x, y)
        The outline as given (a repeated closing point and repeated consecutive points
        removed; same geometry).
    holes : tuple of tuples of (x, y)
        The holes, likewise (a hole may be filled by another part).
    E : float
        Young's modulus, any unit (only ratios between parts matter).
    nu : float
        Poisson's ratio; G = E / (2 (1 + nu)).
    """

    outer: Ring
    holes: tuple[Ring, ...]
    E: float
    nu: float


@dataclasses.dataclass(frozen=True)
class PolygonSection(Section):
    """A :class:`Section` from polygons with holes (polygon_section, composite_section).

    ``area`` is the geometric area; ``I1``, ``I3`` are about the (modulus-weighted) centroid,
    ``I1`` about e1, the in-plane principal axis, ``I3`` about e3; for a composite they are
    modulus-weighted and divided by ``parts[0].E``, and ``J`` is the shear-modulus-weighted
    torsion constant divided by ``parts[0]``'s G, so that ``b1 = I1/I3`` and
    ``b2 = J/(2 (1 + parts[0].nu) I3)`` hold for every polygon section. Lengths are in the
    polygon's unit. ``aspect`` is None; ``nu`` is None when the parts' differ.

    Attributes
    ----------
    parts : tuple of SectionPart
        The material regions (one for :func:`polygon_section`, with E = 1).
    mesh_size : float
        Largest triangle area over the section's area.
    n_elements, n_nodes : int
        Six-node triangles and nodes of the mesh.
    centroid : (float, float)
        Centroid (modulus-weighted), polygon coordinates.
    principal_deg : (float, float)
        Directions of the principal axes, degrees from +x in [0, 180): of the larger second
        moment int E d^2 dA (d the coordinate along the axis) first.
    normal_deg : float
        Direction of e3 (the ring's normal) used, degrees from +x: 90 (polygon y) unless
        ``orientation_deg`` was given, then the principal direction it named.
    orientation_deg : float or None
        As given.
    coupling : float
        |I13| / sqrt(I1 I3) in the frame used (<= :data:`COUPLING_TOL`).
    J_mesh_change : float
        |J - J4| / J, J4 from a mesh 4 times coarser (in area, 2 times in size): an error
        indicator. J converges as (size)^p, so the error here is about J_mesh_change /
        (2^p - 1): p = 4 for convex polygons (measured, tests/test_polygon_sections.py), so
        1/15 of it; re-entrant corners (a T, an L) lower p towards 4/3, and then the error
        here is about as large as J_mesh_change. It under-reports when the polygon's edges
        are shorter than the elements (a curve drawn with many points): one quadratic
        element per edge does not resolve the warping between vertices (a regular 48-gon at
        mesh_size 0.01 gets a zero warping function and J = Ix + Iy at both meshes); tie
        mesh_size to the edge length, as tests/test_polygon_sections.py does.
    """

    parts: tuple[SectionPart, ...]
    mesh_size: float
    n_elements: int
    n_nodes: int
    centroid: tuple[float, float]
    principal_deg: tuple[float, float]
    normal_deg: float
    orientation_deg: float | None
    coupling: float
    J_mesh_change: float

    @property
    def outer(self) -> Ring:
        """The outline of the first part (the only one of :func:`polygon_section`)."""
        return self.parts[0].outer

    @property
    def holes(self) -> tuple[Ring, ...]:
        """The holes of the first part (the only one of :func:`polygon_section`)."""
        return self.parts[0].holes


@dataclasses.dataclass(frozen=True)
class _Moments:
    """Weighted centroidal second moments and J of one mesh of normalised parts.

    Every integral carries the parts' weights w (E, or G for ``J``, over part 0's).
    """

    area: float  # geometric
    cx: float
    cy: float
    ixx: float  # int w y^2 dA
    iyy: float  # int w x^2 dA
    ixy: float  # int w x y dA
    J: float  # torsion constant weighted by the shear moduli
    n_elements: int
    n_nodes: int


#: Largest ratio of two parts' moduli E (or G): beyond, the softer part is a hole in all but
#: name and the weighted FE system loses its digits.
MODULUS_RATIO_MAX = 1e6
#: A normalised part: outline, holes, E and G relative to part 0's.
_Key = tuple[tuple[Ring, tuple[Ring, ...], float, float], ...]


def _short(value: Any) -> str:
    """``repr`` of a value cut to 80 characters, for messages."""
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _ring(name: str, points: Any) -> Ring:
    """Check one closed ring of points ``[[x, y], ...]``; drop repeats (same geometry).

    Raises naming ``name[i]`` for a point that is not a pair of finite numbers, and ``name``
    for fewer than 3 distinct points.
    """
    if isinstance(points, (str, bytes)) or not isinstance(points, Sequence | np.ndarray):
        raise RodstabInputError(f"{name} must be a list of points [[x, y], ...], "
                                f"got {_short(points)}")
    if len(points) > MAX_POLYGON_VERTICES:
        raise RodstabInputError(f"{name} has {len(points)} points; at most "
                                f"{MAX_POLYGON_VERTICES} are accepted")
    out: list[tuple[float, float]] = []
    for i, p in enumerate(points):
        ok = (isinstance(p, Sequence | np.ndarray) and not isinstance(p, (str, bytes))
              and len(p) == 2 and all(isinstance(v, Real | np.floating | np.integer)
                                       and not isinstance(v, (bool, np.bool_)) for v in p))
        if not ok:
            raise RodstabInputError(f"{name}[{i}] must be a point [x, y] of two numbers, "
                                    f"got {_short(p)}")
        x, y = float(p[0]), float(p[1])
        if not (math.isfinite(x) and math.isfinite(y)):
            raise RodstabInputError(f"{name}[{i}] = {_short(p)} is not finite")
        if max(abs(x), abs(y)) > MAX_POLYGON_COORDINATE:
            raise RodstabInputError(f"{name}[{i}] = {_short(p)} lies beyond "
                                    f"{MAX_POLYGON_COORDINATE:g} (a coordinate in the "
                                    "polygon's length unit)")
        # A repeated point (a closing point, a CAD export's duplicate) adds no geometry.
        if not out or (x, y) != out[-1]:
            out.append((x, y))
    if len(out) > 1 and out[0] == out[-1]:
        out.pop()
    if len(out) < 3:
        raise RodstabInputError(f"{name} needs at least 3 distinct points, got {len(out)}: "
                                f"{_short(points)}")
    return tuple(out)


def _shapely() -> Any:
    """Import shapely (a dependency of sectionproperties) or say how to install it."""
    try:
        import shapely
        import shapely.validation
    except ImportError:  # pragma: no cover - the test extras install it
        raise RodstabInputError(_SECTIONS_EXTRA) from None
    return shapely


def _check_simple(name: str, ring: Ring, size: float) -> Any:
    """Shapely polygon of one ring; raise naming ``name`` if it is flat or crosses itself."""
    shapely = _shapely()
    pts = np.array(ring)
    # Collinear points first: shapely calls them a self-intersection, which hides the cause.
    if np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)[-1] <= _ZERO_AREA * size:
        raise RodstabInputError(f"{name} has zero area (its points are collinear): "
                                f"{_short([list(p) for p in ring])}")
    poly = shapely.Polygon(ring)
    if not poly.is_valid:
        why = shapely.validation.explain_validity(poly)
        raise RodstabInputError(f"{name} is not a simple polygon ({why}); its edges must not "
                                "cross or touch")
    return poly


def _check_parts(parts: tuple[SectionPart, ...]) -> float:
    """Check that the parts form one connected, non-overlapping region; return its size."""
    outers = np.array([p for part in parts for p in part.outer])
    size = float(np.ptp(outers, axis=0).max())
    if not (POLYGON_SIZE_RANGE[0] <= size <= POLYGON_SIZE_RANGE[1]):
        raise RodstabInputError(f"the polygon's size (largest extent) must lie in "
                                f"[{POLYGON_SIZE_RANGE[0]:g}, {POLYGON_SIZE_RANGE[1]:g}] (a "
                                f"section in its length unit), got {size!r}")
    count = sum(len(r) for part in parts for r in (part.outer, *part.holes))
    if count > MAX_POLYGON_VERTICES:
        raise RodstabInputError(f"the polygons and their holes have {count} points; at most "
                                f"{MAX_POLYGON_VERTICES} are accepted")
    shapely = _shapely()
    regions: list[Any] = []
    for i, part in enumerate(parts):
        # One part: the names of polygon_section ("polygon", "holes[k]"); several: prefixed.
        pre = f"parts[{i}]." if len(parts) > 1 else ""
        shell = _check_simple(f"{pre}polygon", part.outer, size)
        inner = [_check_simple(f"{pre}holes[{k}]", h, size) for k, h in enumerate(part.holes)]
        for k, h in enumerate(inner):
            if not shell.contains_properly(h):
                raise RodstabInputError(
                    f"{pre}holes[{k}] = {_short([list(p) for p in part.holes[k]])} is not "
                    "inside the polygon (a hole may not touch the outline)")
            for m in range(k):
                if h.intersects(inner[m]):
                    raise RodstabInputError(f"{pre}holes[{k}] and {pre}holes[{m}] overlap or "
                                            "touch")
        region = shapely.Polygon(part.outer, part.holes)
        if not region.is_valid:  # e.g. a hole touching the outline along an edge
            why = shapely.validation.explain_validity(region)
            raise RodstabInputError(f"{pre}polygon with its holes is not one valid region "
                                    f"({why})")
        for j, other in enumerate(regions):
            if region.intersection(other).area > _ZERO_AREA * size * size:
                raise RodstabInputError(f"parts[{i}] and parts[{j}] overlap (each point of a "
                                        "section has one material)")
        regions.append(region)
    union = shapely.unary_union(regions)
    if union.geom_type != "Polygon":
        raise RodstabInputError(f"the parts do not form one connected section ({len(parts)} "
                                "parts, touching along edges are one piece; a point contact "
                                "or a gap is not)")
    perimeter = union.exterior.length + sum(r.length for r in union.interiors)
    slender = perimeter**2 / union.area
    if slender > MAX_SLENDERNESS:
        raise RodstabInputError(f"the polygon is too slender for a section analysis: "
                                f"perimeter^2/area = {slender:.3g} > {MAX_SLENDERNESS:g} (a "
                                "strip longer than 1e4 times its thickness)")
    return size


def _normalised(parts: tuple[SectionPart, ...]) -> tuple[np.ndarray, float, _Key]:
    """Centre of the bounding box, size (largest extent), and the parts moved there, scaled 1.

    The analysis runs on the normalised parts: its mesh and results do not depend on the
    length unit, and sectionproperties' rounding of vertices to 12 decimals is relative.
    Moduli are divided by part 0's.
    """
    pts = np.array([p for part in parts for p in part.outer])
    span = np.ptp(pts, axis=0)
    size, centre = float(span.max()), pts.min(axis=0) + 0.5 * span

    def unit(r: Ring) -> Ring:
        return tuple((float((x - centre[0]) / size), float((y - centre[1]) / size))
                     for x, y in r)

    E0, G0 = parts[0].E, parts[0].E / (2.0 * (1.0 + parts[0].nu))
    key = tuple((unit(p.outer), tuple(unit(h) for h in p.holes), p.E / E0,
                 p.E / (2.0 * (1.0 + p.nu)) / G0) for p in parts)
    return centre, size, key


def _meshed(key: _Key, mesh_size: float, shear: bool) -> Any:
    """Mesh normalised parts: a sectionproperties geometry, triangles <= ``mesh_size`` x area.

    Its materials' moduli are the parts' E (``shear`` False) or G (True).
    """
    try:
        from sectionproperties.pre.geometry import CompoundGeometry, Geometry
        from sectionproperties.pre.pre import Material
    except ImportError:
        raise RodstabInputError(_SECTIONS_EXTRA) from None
    shapely = _shapely()
    geoms = []
    for i, (outer, holes, E, G) in enumerate(key):
        # sectionproperties weights every integral, the warping problem included, by its
        # material's elastic_modulus: G for the torsion constant of mixed Poisson's ratios.
        mat = Material(name=f"part{i}", elastic_modulus=G if shear else E, poissons_ratio=0.0,
                       yield_strength=1.0, density=1.0, color="grey")
        geoms.append(Geometry(geom=shapely.Polygon(outer, holes), material=mat))
    geom = geoms[0] if len(geoms) == 1 else CompoundGeometry(geoms)
    area = sum(shapely.Polygon(o, h).area for o, h, _, _ in key)
    geom.create_mesh(mesh_sizes=[mesh_size * area])
    return geom


def _analyse(key: _Key, mesh_size: float, shear: bool) -> Any:
    """Geometric and warping analysis of the mesh of :func:`_meshed` (sectionproperties)."""
    from sectionproperties.analysis.section import Section as SpSection

    geom = _meshed(key, mesh_size, shear)
    n_elements = len(geom.mesh["triangles"])
    if n_elements > MAX_MESH_ELEMENTS:
        raise RodstabInputError(f"the polygon's mesh has {n_elements} triangles at mesh_size="
                                f"{mesh_size!r}, more than {MAX_MESH_ELEMENTS}: the section has "
                                "walls too thin for its size (a coarser mesh_size cannot help "
                                "when the mesh quality bound sets the count)")
    sec = SpSection(geom)
    sec.calculate_geometric_properties()
    sec.calculate_warping_properties()
    return sec


@functools.lru_cache(maxsize=32)
def _moments(key: _Key, mesh_size: float) -> _Moments:
    """FE section analysis of checked, normalised parts (size 1): sectionproperties.

    Cached: b2 depends on nu only through G, so a sweep over nu (or one design file with the
    same polygon in every segment) meshes and solves once per distinct set of G ratios.
    """
    sec = _analyse(key, mesh_size, shear=False)
    ixx, iyy, ixy = sec.get_eic()
    cx, cy = sec.get_c()
    if all(abs(G / E - 1.0) <= 1e-14 for _, _, E, G in key):
        # One Poisson's ratio: G / G0 = E / E0, the E-weighted J is the G-weighted one.
        J = float(sec.get_ej())
    else:
        J = float(_analyse(key, mesh_size, shear=True).get_ej())
    return _Moments(area=float(sec.get_area()), cx=float(cx), cy=float(cy), ixx=float(ixx),
                    iyy=float(iyy), ixy=float(ixy), J=J,
                    n_elements=int(len(sec.elements)), n_nodes=int(sec.num_nodes))


def _frame_moments(m: _Moments, normal_deg: float) -> tuple[float, float, float]:
    """(I1, I3, I13) with e3 along ``normal_deg`` and e1 = e3 turned by -90 degrees.

    The coordinate along e3 is x3 = x cos(a) + y sin(a), along e1 x1 = x sin(a) - y cos(a)
    (a = normal_deg; a = 90 gives x3 = y, x1 = x). I1 = int x3^2 dA, I3 = int x1^2 dA.
    """
    a = math.radians(normal_deg)
    c, s = math.cos(a), math.sin(a)
    I1 = m.iyy * c * c + m.ixx * s * s + 2.0 * m.ixy * s * c
    I3 = m.iyy * s * s + m.ixx * c * c - 2.0 * m.ixy * s * c
    I13 = (m.iyy - m.ixx) * s * c - m.ixy * (c * c - s * s)
    return I1, I3, I13


def _principal(m: _Moments) -> tuple[float, float, bool]:
    """Principal directions (degrees in [0, 180), larger moment first) and isotropy.

    The second moment about the coordinate along direction a, int (x cos a + y sin a)^2 dA,
    is stationary where tan 2a = 2 Ixy / (Iyy - Ixx).
    """
    # Rounded to 1e-9 degree: a symmetric section's axes print as 90 and 0, not 2.8e-14.
    a = round(0.5 * math.degrees(math.atan2(2.0 * m.ixy, m.iyy - m.ixx)), 9) % 180.0
    spread = math.hypot(m.iyy - m.ixx, 2.0 * m.ixy)  # = I_max - I_min
    return a, (a + 90.0) % 180.0, spread <= _ISOTROPIC * (m.ixx + m.iyy)


def _normal_direction(m: _Moments, orientation_deg: float | None) -> float:
    """Direction of e3 (degrees): y, or the principal axis that ``orientation_deg`` names."""
    first, second, isotropic = _principal(m)
    axes = f"{first:.6g} and {second:.6g} degrees from the x axis"
    if orientation_deg is None:
        I1, I3, I13 = _frame_moments(m, 90.0)
        coupling = abs(I13) / math.sqrt(I1 * I3)
        if coupling > COUPLING_TOL:
            raise RodstabInputError(
                f"the polygon's principal axes lie at {axes}, not along x and y "
                f"(Ixy / sqrt(Ixx Iyy) = {coupling:.3g} > {COUPLING_TOL:g}): the theory "
                "assumes a principal axis normal to the plane of the ring; rotate the polygon, "
                "or give orientation_deg = the direction of the ring's normal, one of those "
                "two angles")
        return 90.0
    if isotropic:
        return orientation_deg  # every axis is principal
    # Directions are axes: compare modulo 180 degrees.
    gaps = [abs((orientation_deg - a + 90.0) % 180.0 - 90.0) for a in (first, second)]
    k = int(np.argmin(gaps))
    if gaps[k] > ORIENTATION_TOL_DEG:
        raise RodstabInputError(
            f"orientation_deg={orientation_deg!r} is not a principal axis of the polygon: "
            f"they lie at {axes} (within {ORIENTATION_TOL_DEG:g} degree needed)")
    return (first, second)[k]


def _part(name: str, outer: Any, holes: Any, E: float, nu: float) -> SectionPart:
    """Check the points of one part (geometry is checked with all parts together)."""
    ring = _ring(f"{name}polygon", outer)
    if isinstance(holes, (str, bytes)) or not isinstance(holes, Sequence | np.ndarray):
        raise RodstabInputError(f"{name}holes must be a list of polygons, got {_short(holes)}")
    inner = tuple(_ring(f"{name}holes[{k}]", h) for k, h in enumerate(holes))
    return SectionPart(outer=ring, holes=inner, E=require_positive(f"{name}E", E),
                       nu=require_poisson(nu))


def _polygon_result(shape: str, parts: tuple[SectionPart, ...], mesh_size: float | None,
                    orientation_deg: float | None) -> PolygonSection:
    """Analyse checked parts (:func:`polygon_section`, :func:`composite_section`)."""
    frac = POLYGON_MESH_SIZE if mesh_size is None else require_in_range(
        "mesh_size", mesh_size, *MESH_SIZE_RANGE,
        "the largest triangle's area over the section's area")
    if orientation_deg is not None:
        orientation_deg = require_in_range("orientation_deg", orientation_deg, -360.0, 360.0,
                                           "a direction in degrees")
    _check_parts(parts)
    centre, size, key = _normalised(parts)
    m = _moments(key, frac)
    coarse = _moments(key, 4.0 * frac)
    normal = _normal_direction(m, orientation_deg)
    I1n, I3n, I13n = _frame_moments(m, normal)
    first, second, _ = _principal(m)
    s2, s4 = size * size, size**4
    I1, I3, J = I1n * s4, I3n * s4, m.J * s4
    require_finite("the polygon's I1 (size^4 overflows)", I1)
    require_positive("the polygon's I3 (size^4 underflows)", I3)
    nus = {p.nu for p in parts}
    return PolygonSection(
        shape=shape,
        b1=I1n / I3n,
        # m.J is weighted by G / G0 and I3 by E / E0: b2 = G0 J / (E0 I3).
        b2=_b2(m.J, I3n, parts[0].nu),
        nu=parts[0].nu if len(nus) == 1 else None,
        torsion=FE_TORSION,
        aspect=None,
        area=m.area * s2,
        I1=I1,
        I3=I3,
        J=J,
        parts=parts,
        mesh_size=frac,
        n_elements=m.n_elements,
        n_nodes=m.n_nodes,
        centroid=(float(centre[0] + m.cx * size), float(centre[1] + m.cy * size)),
        principal_deg=(first, second),
        normal_deg=normal,
        orientation_deg=orientation_deg,
        coupling=abs(I13n) / math.sqrt(I1n * I3n),
        J_mesh_change=abs(m.J - coarse.J) / m.J,
    )


def polygon_section(
    outer: Sequence[Sequence[float]],
    holes: Sequence[Sequence[Sequence[float]]] = (),
    *,
    nu: float = 1 / 3,
    mesh_size: float | None = None,
    orientation_deg: float | None = None,
) -> PolygonSection:
    """Section of any polygon with holes: b1 = I1/I3, b2 = J/(2 (1 + nu) I3), J by FE.

    Polygon y is out of the plane of the ring (e3, like h of :func:`rectangle`), x in it
    (e1). Second moments about the centroid are integrated exactly (straight-sided six-node
    triangles); J is Saint-Venant's, from the FE warping function (sectionproperties), with
    error ~ (element size)^4 for convex polygons. The polygon is translated and scaled to
    size 1 for the analysis, so that the results and the mesh do not depend on the length
    unit.

    Parameters
    ----------
    outer : sequence of [x, y]
        The outline, in any length unit, either orientation; a closing point equal to the
        first is allowed. At least 3 distinct points; no self-intersection.
    holes : sequence of sequences of [x, y]
        Holes, each a simple polygon strictly inside ``outer``, not touching one another.
    nu : float
        Poisson's ratio in (-1, 0.5].
    mesh_size : float, optional
        Largest triangle area over the section's area, in :data:`MESH_SIZE_RANGE`; default
        :data:`POLYGON_MESH_SIZE`.
    orientation_deg : float, optional
        Direction of the ring's normal e3 in polygon coordinates, degrees from +x in
        [-360, 360]. Needed when the principal axes are not x and y: it names the principal
        axis (within :data:`ORIENTATION_TOL_DEG`) that is e3, and that exact axis is used
        (:attr:`PolygonSection.normal_deg`).

    Returns
    -------
    PolygonSection
        ``shape="polygon"``, ``torsion="fe-warping"``, one part with E = 1.

    Raises
    ------
    RodstabInputError
        Naming the offending value: a point that is not two finite numbers, fewer than 3
        points, a self-intersecting or zero-area polygon, a hole outside it or overlapping
        another, a section too slender to mesh, principal axes not along x and y without
        ``orientation_deg``, an ``orientation_deg`` that is not a principal axis, ``nu`` or
        ``mesh_size`` out of range; or sectionproperties not installed.
    """
    nu = require_poisson(nu)
    part = _part("", outer, holes, 1.0, nu)
    return _polygon_result(POLYGON, (part,), mesh_size, orientation_deg)


def composite_section(
    parts: Sequence[Mapping[str, Any]],
    *,
    mesh_size: float | None = None,
    orientation_deg: float | None = None,
) -> PolygonSection:
    """Section of several materials, each a polygon with holes, bonded along shared edges.

    B1 = sum E I1 and B3 = sum E I3 about the modulus-weighted centroid (principal axes of
    the modulus-weighted moments), B2 = the torsional rigidity of the warping problem with
    each part's own G = E/(2 (1 + nu)) (sectionproperties weights its warping analysis by its
    materials' moduli: it is run with G when the parts' nu differ); b1 = B1/B3, b2 = B2/B3.
    Axes and orientation as :func:`polygon_section`.

    Parameters
    ----------
    parts : sequence of mappings
        Each ``{"polygon": [[x, y], ...], "holes": [...] (optional), "E": E > 0, "nu": nu}``;
        parts may share edges (vertices need not match), may fill one another's holes, may
        not overlap, and together form one connected region. Moduli in any one unit, at most
        :data:`MODULUS_RATIO_MAX` apart.
    mesh_size : float, optional
        As :func:`polygon_section` (of the whole section's area).
    orientation_deg : float, optional
        As :func:`polygon_section`.

    Returns
    -------
    PolygonSection
        ``shape="composite"``, ``nu`` None unless all parts have the same.

    Raises
    ------
    RodstabInputError
        As :func:`polygon_section`, naming ``parts[i].polygon`` etc.; also for overlapping or
        disconnected parts, an unknown or missing key of a part, moduli too far apart.
    """
    if isinstance(parts, (str, bytes, Mapping)) or not isinstance(parts, Sequence):
        raise RodstabInputError(f"parts must be a list of parts {{polygon, holes, E, nu}}, got "
                                f"{_short(parts)}")
    if not parts:
        raise RodstabInputError("parts is empty: give at least one part {polygon, E, nu}")
    checked = []
    for i, p in enumerate(parts):
        if not isinstance(p, Mapping):
            raise RodstabInputError(f"parts[{i}] must be a mapping {{polygon, holes, E, nu}}, "
                                    f"got {_short(p)}")
        unknown = sorted(str(k) for k in set(p) - {"polygon", "holes", "E", "nu"})
        missing = [k for k in ("polygon", "E", "nu") if k not in p]
        if unknown or missing:
            raise RodstabInputError(f"parts[{i}] has unknown key(s) {unknown} or misses "
                                    f"{missing}; a part has polygon, holes (optional), E, nu")
        checked.append(_part(f"parts[{i}].", p["polygon"], p.get("holes", ()), p["E"],
                             p["nu"]))
    G = [c.E / (2.0 * (1.0 + c.nu)) for c in checked]
    for name, vals in (("E", [c.E for c in checked]), ("G", G)):
        if max(vals) > MODULUS_RATIO_MAX * min(vals):
            raise RodstabInputError(f"the parts' {name} range from {min(vals):g} to "
                                    f"{max(vals):g}, more than {MODULUS_RATIO_MAX:g} apart")
    return _polygon_result(COMPOSITE, tuple(checked), mesh_size, orientation_deg)


def polygon_mesh(section: PolygonSection) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the mesh a :class:`PolygonSection` was analysed on, in polygon coordinates.

    Meshed again (Triangle is deterministic and fast; the FE is not repeated).

    Returns
    -------
    nodes : ndarray, shape (n_nodes, 2)
        Node coordinates (x, y), the polygon's length unit.
    triangles : ndarray, shape (n_elements, 3)
        Corner node indices of each six-node triangle (mid-side nodes omitted).
    part : ndarray, shape (n_elements,)
        Index of the part (material) of each triangle.
    """
    centre, size, key = _normalised(section.parts)
    geom = _meshed(key, section.mesh_size, shear=False)
    nodes = np.asarray(geom.mesh["vertices"], dtype=float) * size + centre
    tri = np.asarray(geom.mesh["triangles"], dtype=int)[:, :3]
    part = np.asarray(geom.mesh["triangle_attributes"], dtype=float).reshape(len(tri), -1)
    return nodes, tri, part[:, 0].astype(int)
