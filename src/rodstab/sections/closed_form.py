"""Closed-form cross-sections: circle, tube, ellipse, rectangle, or the ratios b1, b2 given.

The references and the conventions (B1, B2, B3; h along e3, t along e1) are in
:mod:`rodstab.sections`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping

import numpy as np

from ..errors import (
    RodstabInputError,
    require_finite,
    require_in_range,
    require_poisson,
    require_positive,
)
from ..results import Result

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

    def stiffnesses(self, E: float, I3: float | None = None) -> tuple[float, float, float]:
        """Return ``(B1, B2, B3)`` of this section in a material of Young's modulus ``E``.

        ``B3 = E I3`` (in-plane bending), ``B1 = b1 B3``, ``B2 = b2 B3``: in N m^2 for ``E``
        in Pa and ``I3`` in m^4. ``I3`` defaults to the section's own (None for ratios).
        """
        I3 = self.I3 if I3 is None else I3
        if I3 is None:
            raise RodstabInputError(f"a {self.shape!r} section has no I3: its stiffnesses need "
                                    "its geometry")
        B3 = E * I3
        return self.b1 * B3, self.b2 * B3, B3


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
