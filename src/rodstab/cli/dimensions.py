"""The section's dimensions on the command line: ``--height "5 mm" --thickness "0.5 mm"`` ...

Parsing only: each option is read as a length (:func:`rodstab.units.parse_quantity`) or a
plain number and checked against ``--shape``; the section they give is built by
:func:`rodstab.sections.sized_section`, its stiffnesses by :meth:`Section.stiffnesses`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from ..errors import RodstabInputError
from ..limits import LENGTH_RANGE
from ..sections import ASPECT_RANGE, SECTION_DIMENSIONS, Section, sized_section
from ..units import Quantity, parse_quantity, split_quantity
from .output import fmt

#: Section dimensions (the design keys of :data:`~rodstab.sections.SECTION_DIMENSIONS`), as the
#: parameter names of their options ``--height``, ``--thickness``, ``--diameter``,
#: ``--outer-diameter``, ``--inner-diameter``.
DIMENSION_OPTIONS = ("height", "thickness", "diameter", "outer_diameter", "inner_diameter")
#: Options of ``_section_options`` that fix a closed-form section, so conflict with --polygon.
CLOSED_FORM_OPTIONS = ("shape", "aspect", "torsion", "b1", "b2", *DIMENSION_OPTIONS)


def opt(key: str) -> str:
    """Return the option of a dimension key (``outer_diameter`` -> ``--outer-diameter``)."""
    return "--" + key.replace("_", "-")


@dataclasses.dataclass(frozen=True)
class SectionDimensions:
    """The section's dimensions given on the command line (``--height "5 mm"`` ...).

    Attributes
    ----------
    shape : str
        The ``--shape`` they describe.
    text : dict of str to str
        Each given dimension key (``height``, ``thickness``, ``diameter``, ``outer_diameter``,
        ``inner_diameter``) -> its text as written.
    si : dict of str to float or None
        Each key -> its length in metres; None when the dimensions are plain numbers (they then
        fix the section's ratio only).
    aspect : float or None
        The ratio they fix: h/t (rectangle, ellipse), inner/outer diameter (tube); None for a
        circle (scale-free: every circle has the same b1, b2).
    """

    shape: str
    text: dict[str, str]
    si: dict[str, float] | None
    aspect: float | None

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON form: ``{key: {"text", "value", "unit"}}`` (value in m, or plain)."""
        return {k: {"text": t, "value": None if self.si is None else self.si[k],
                    "unit": None if self.si is None else "m"} for k, t in self.text.items()}


def _read_size(key: str, text: str) -> tuple[float, Quantity | None]:
    """Read one dimension option: a length quantity (``"5 mm"``) or a plain number.

    Returns ``(number, quantity or None)``: the number as written and, for a quantity, its
    parse by :func:`rodstab.units.parse_quantity` (which imports pint: plain numbers do not).
    """
    option = opt(key)
    inner = key == "inner_diameter"  # 0: a solid tube, as the design key
    if split_quantity(text) is not None:
        q = parse_quantity(text, option, "length")
        value, si = q.magnitude, q.si
    else:
        q = None
        try:
            value = si = float(text)
        except ValueError:
            raise RodstabInputError(f"{option} {text!r} is neither a length (e.g. '5 mm') nor "
                                    "a plain number") from None
    positive = si >= 0.0 if inner else si > 0.0
    if not (math.isfinite(si) and positive):
        raise RodstabInputError(f"{option} {text!r} must be a finite size "
                                f"{'>= 0' if inner else '> 0'}")
    if q is not None and si != 0.0 and not LENGTH_RANGE[0] <= si <= LENGTH_RANGE[1]:
        raise RodstabInputError(f"{option} {text!r} is outside [{LENGTH_RANGE[0]:g}, "
                                f"{LENGTH_RANGE[1]:g}] m (a dimension of the cross-section)")
    return value, q


def _ratio(num: tuple[float, Quantity | None], den: tuple[float, Quantity | None]) -> float:
    """Return num/den in a common unit (the numerator's): exact when both share a unit."""
    (a, qa), (b, qb) = num, den
    if qa is None or qb is None:
        return a / b
    return a / (b * (qb.si_per_unit / qa.si_per_unit))


def dimensions(shape: str, given: dict[str, str], aspect: float | None,
                b1: float | None, b2: float | None) -> SectionDimensions:
    """Check the dimension options against ``--shape``, ``--aspect``, ``--b1``/``--b2``.

    Raises
    ------
    RodstabInputError
        Naming the option and its value: given with ``--aspect`` or ``--b1``/``--b2``, not a
        dimension of ``shape``, one of a pair missing, a plain number mixed with a quantity,
        a wrong unit, a size <= 0, inner diameter >= outer, h/t out of range.
    """
    key, text = next(iter(given.items()))
    if aspect is not None:
        raise RodstabInputError(f"{opt(key)} {text!r} and --aspect {aspect!r} both fix the "
                                "section's ratio: give the dimensions or --aspect, not both")
    for name, value in (("--b1", b1), ("--b2", b2)):
        if value is not None:
            raise RodstabInputError(f"{opt(key)} {text!r} cannot be used with {name} "
                                    f"{value!r}, which fixes the section's ratios")
    need = SECTION_DIMENSIONS[shape]
    for k, t in given.items():
        if k not in need:
            raise RodstabInputError(f"{opt(k)} {t!r} has no meaning for --shape {shape} (its "
                                    f"dimensions: {' and '.join(map(opt, need))})")
    missing = [k for k in need if k not in given]
    if missing:
        raise RodstabInputError(f"{opt(key)} {text!r} needs {' and '.join(map(opt, missing))}"
                                f" (--shape {shape} is given by {' and '.join(map(opt, need))})")
    sizes = {k: _read_size(k, given[k]) for k in need}
    kinds = {k: q is not None for k, (_, q) in sizes.items()}
    if len(set(kinds.values())) > 1:
        plain = next(k for k in need if not kinds[k])
        unit = next(k for k in need if kinds[k])
        raise RodstabInputError(f"{opt(plain)} {given[plain]!r} is a plain number but "
                                f"{opt(unit)} {given[unit]!r} has a unit: give both with "
                                "units, or both as plain numbers (then only their ratio counts)")
    si = None
    if all(kinds.values()):
        si = {k: q.si for k, (_, q) in sizes.items() if q is not None}
    ratio = None
    if shape == "tube":
        ratio = _ratio(sizes["inner_diameter"], sizes["outer_diameter"])
        if not ratio < 1.0:
            raise RodstabInputError(f"--inner-diameter {given['inner_diameter']!r} must be "
                                    f"smaller than --outer-diameter {given['outer_diameter']!r}")
    elif shape != "circle":
        ratio = _ratio(sizes["height"], sizes["thickness"])
        if not ASPECT_RANGE[0] <= ratio <= ASPECT_RANGE[1]:
            raise RodstabInputError(
                f"--height {given['height']!r} over --thickness {given['thickness']!r} is h/t = "
                f"{ratio:.6g}, outside [{ASPECT_RANGE[0]:g}, {ASPECT_RANGE[1]:g}] (the h/t of "
                "a rod's cross-section)")
    return SectionDimensions(shape=shape, text=dict(given), si=si, aspect=ratio)


def dimension_lines(section: Section, dims: SectionDimensions, young: str | None,
                     payload: dict[str, Any]) -> list[str]:
    """Add the dimensions (and with ``--E`` the stiffnesses in N m^2) to ``payload``; lines."""
    given = ", ".join(f"{k.replace('_', ' ')} {t}" for k, t in dims.text.items())
    ratio = {"tube": "inner/outer", "circle": None}.get(dims.shape, "h/t")
    lines = [f"dimensions   {given}" + ("" if ratio is None or dims.aspect is None else
                                        f" ({ratio} = {fmt(dims.aspect)})")
             + (" (plain numbers: only their ratio counts)" if dims.si is None else "")]
    payload["dimensions"] = dims.to_dict()
    if dims.si is None:
        if young is not None:
            raise RodstabInputError(f"--E {young!r} needs the section's dimensions with units "
                                    f"(e.g. --{next(iter(dims.text)).replace('_', '-')} "
                                    "'5 mm'), not plain numbers")
        return lines
    sized = sized_section(dims.shape, dims.si, nu=section.nu if section.nu is not None
                          else 1 / 3, torsion=section.torsion)
    assert sized.area is not None and sized.I1 is not None and sized.I3 is not None
    assert sized.J is not None  # closed-form shapes have their geometry
    payload["geometry"] = {"area": {"value": sized.area, "unit": "m^2"},
                           **{k: {"value": v, "unit": "m^4"} for k, v in
                              (("I1", sized.I1), ("I3", sized.I3), ("J", sized.J))}}
    lines.append(f"geometry     area {sized.area:.6g} m^2, I1 {sized.I1:.6g} m^4, "
                 f"I3 {sized.I3:.6g} m^4, J {sized.J:.6g} m^4")
    if young is not None:
        E = parse_quantity(young, "--E", "modulus").si
        if not E > 0.0:
            raise RodstabInputError(f"--E {young!r} must be a positive modulus (e.g. "
                                    "'200 GPa')")
        # the ratios b1, b2 of the table above, I3 of these dimensions
        B = dict(zip(("B1", "B2", "B3"), section.stiffnesses(E, sized.I3), strict=True))
        B3 = B["B3"]
        payload["stiffness"] = {k: {"value": v, "unit": "N*m^2"} for k, v in B.items()}
        payload["E"] = {"value": E, "unit": "Pa", "text": young}
        lines.append(f"stiffness    B1 = {B['B1']:.6g}, B2 = {B['B2']:.6g}, B3 = {B3:.6g} "
                     f"N*m^2 (E {young}, nu {fmt(section.nu or 0.0)})")
    return lines

