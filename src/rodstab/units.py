"""Physical units: quantities such as ``"235.6 mm"`` in design files, and results in SI.

A design file that gives its dimensional values as quantity strings (``length = "235.6 mm"``,
``[material] E = "200 GPa"``) is a *design with units* (:mod:`rodstab.io.design`). Its values are
read here, checked for their dimension and converted to SI; the design is then handed to the
solvers in rodstab's usual non-dimensional form, and every result is converted back.

Conversion (one rule, used by every command)
--------------------------------------------
The model is invariant under a change of the length and stiffness units, so a design with
units is solved in the units of its load-factor segment (``[analysis] load_factor_segment``,
default the first segment):

* reference length ``Lc`` = that segment's length (m), reference stiffness ``Bc`` = its
  in-plane bending stiffness ``B3 = E I3`` (N m^2);
* model length = length / ``Lc``; model curvature = curvature x ``Lc``; model stiffness
  (``B1``, ``B2``, ``B3``) = stiffness / ``Bc``; load factors, angles and rotations unchanged;
* back to SI (:meth:`Units.si`): length x ``Lc`` (m), curvature / ``Lc`` (1/m), stiffness x
  ``Bc`` (N m^2), energy and moment x ``Bc / Lc`` (J, N m), force x ``Bc / Lc^2`` (N);
* a load factor ``mu`` (natural curvatures = ``mu`` x the design's) as the reference segment's
  natural curvature ``mu |kappa_n|`` (1/m), positive in the sense the design gives it
  (:func:`load_factor_curvatures`; a stable interval also as radii: :func:`curvature_interval`).

Why scale rather than feed SI numbers to the solvers: the model then reads exactly as the
non-dimensional examples (that segment has L = 1, B3 = 1), on which the solvers' absolute
tolerances (e.g. the continuation corrector's last Newton update, 1e-11 length units) were
set; a steel wire in SI has B3 ~ 1e-2 N m^2 and would meet them at another relative level.

Quantity strings are parsed by pint (https://pint.readthedocs.io), imported only when a
design has units: ``rodstab --help``, the closed-form commands and non-dimensional designs
never import it. The number is read by this module (a decimal number, optional exponent),
only the unit text by pint, so nothing in a design file is evaluated as an expression.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from .errors import RodstabInputError
from .results import Result

if TYPE_CHECKING:
    from .model import Assembly

#: Physical kinds of a design value or result: the SI unit each is reported in.
SI_UNITS = {
    "length": "m",
    "curvature": "1/m",
    "modulus": "Pa",
    "stiffness": "N*m^2",
    "energy": "J",
    "moment": "N*m",
    "force": "N",
    "angle": "rad",
}
#: An example of each kind, for messages.
EXAMPLES = {
    "length": "235.6 mm",
    "curvature": "13.3 1/m",
    "modulus": "200 GPa",
    "stiffness": "0.06 N*m^2",
    "energy": "1.2 J",
    "moment": "0.8 N*m",
    "force": "2 N",
    "angle": "30 deg",
}
#: A quantity string: a decimal number (sign, digits, optional fraction and exponent), then
#: the unit text (possibly empty). ASCII digits only: what float() reads, nothing else.
_QUANTITY = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*",
                       re.DOTALL)
#: Longest quantity string read (a quantity is a few characters).
MAX_QUANTITY_CHARS = 100


@functools.lru_cache(maxsize=1)
def _registry() -> Any:
    """Return pint's unit registry (built once, at the first quantity: ~0.6 s with pint)."""
    import pint

    return pint.UnitRegistry()


def _a(kind: str) -> str:
    """Return ``kind`` with its indefinite article ("a length", "an angle")."""
    return f"{'an' if kind[0] in 'aeiou' else 'a'} {kind}"


def _short(text: str) -> str:
    return repr(text if len(text) <= 60 else text[:57] + "...")


@dataclasses.dataclass(frozen=True)
class Quantity:
    """A parsed quantity string.

    Attributes
    ----------
    si : float
        The value in the SI unit of its kind (:data:`SI_UNITS`).
    magnitude : float
        The number as written.
    unit : str
        The unit as written (stripped), e.g. ``"mm"``.
    si_per_unit : float
        SI units per ``unit`` (0.001 for ``mm`` as a length).
    """

    si: float
    magnitude: float
    unit: str
    si_per_unit: float


def _unit_factor(unit: str, path: str, text: str, kind: str) -> float:
    """SI units of ``kind`` per ``unit`` (pint); errors name ``path`` and the whole ``text``."""
    ureg = _registry()
    import pint

    example = EXAMPLES[kind]
    try:
        parsed = ureg.parse_units(unit) if unit else ureg.dimensionless
    except pint.errors.UndefinedUnitError:
        raise RodstabInputError(f"{path} = {_short(text)}: unknown unit {_short(unit)} "
                                f"({_a(kind)} is expected, e.g. {example!r})") from None
    except Exception as exc:
        # pint's parser of the unit text raises what its tokenizer meets (AssertionError,
        # tokenize.TokenError, DefinitionSyntaxError, ...) on text it cannot read: the
        # user's text, not a bug of rodstab.
        raise RodstabInputError(f"{path} = {_short(text)}: cannot read the unit "
                                f"{_short(unit)} ({type(exc).__name__}); give a unit such as "
                                f"{example.split(' ', 1)[1]!r}") from None
    try:
        return float(ureg.Quantity(1.0, parsed).to(SI_UNITS[kind].replace("^", "**"))
                     .magnitude)
    except pint.errors.DimensionalityError:
        got = ureg.Quantity(1.0, parsed).dimensionality
        what = "dimensionless" if not got else f"of dimension {got}"
        raise RodstabInputError(f"{path} = {_short(text)} is {what}, not {_a(kind)} (e.g. "
                                f"{example!r})") from None


def parse_quantity(text: Any, path: str, kind: str) -> Quantity:
    """Read ``text`` (``"5 mm"``) as a quantity of ``kind`` and convert it to SI.

    Parameters
    ----------
    text : str
        A number followed by a unit pint knows (``"235.6 mm"``, ``"13.3 1/m"``, ``"200 GPa"``,
        ``"0.06 N*m^2"``, ``"30 deg"``).
    path : str
        The key path or option that holds it, for messages (``segment[0].length``).
    kind : str
        A key of :data:`SI_UNITS`; ``"angle"`` also accepts a bare number (radians).

    Returns
    -------
    Quantity
        The SI value and the unit as written.

    Raises
    ------
    RodstabInputError
        Naming ``path`` and ``text``: not a string, no number, not finite, an unknown unit,
        or a unit of another dimension (``'5 kg'`` for a length).
    """
    if kind not in SI_UNITS:
        raise ValueError(f"unknown kind {kind!r}; one of {list(SI_UNITS)}")
    example = EXAMPLES[kind]
    if not isinstance(text, str):
        raise RodstabInputError(f"{path} must be a quantity with a unit (a string such as "
                                f"{example!r}), got {text!r}")
    if len(text) > MAX_QUANTITY_CHARS:
        raise RodstabInputError(f"{path} = {_short(text)} is longer than "
                                f"{MAX_QUANTITY_CHARS} characters; a quantity is a number and "
                                f"a unit, e.g. {example!r}")
    match = _QUANTITY.fullmatch(text)
    if match is None:
        raise RodstabInputError(f"{path} = {_short(text)} is not a quantity: give a number and "
                                f"a unit, e.g. {example!r}")
    number, unit = match.group(1), match.group(2)
    magnitude = float(number)
    if not math.isfinite(magnitude):
        raise RodstabInputError(f"{path} = {_short(text)} is not a finite number")
    if not unit and kind != "angle":
        raise RodstabInputError(f"{path} = {_short(text)} has no unit: {_a(kind)} needs one, "
                                f"e.g. {example!r}")
    factor = _unit_factor(unit, path, text, kind)
    si = magnitude * factor
    if not math.isfinite(si):
        raise RodstabInputError(f"{path} = {_short(text)} is not finite in SI "
                                f"({SI_UNITS[kind]})")
    return Quantity(si=si, magnitude=magnitude, unit=unit, si_per_unit=factor)


def split_quantity(value: Any) -> tuple[float, str] | None:
    """Return ``(number, unit text)`` of a string shaped as a quantity (``"5 mm"``), else None.

    A string, a number, then non-empty unit text. What makes a design one with units
    (:mod:`rodstab.io.design`); whether the unit exists and has the right dimension is checked
    where the value is read (:func:`parse_quantity`).
    """
    if not isinstance(value, str) or len(value) > MAX_QUANTITY_CHARS:
        return None
    match = _QUANTITY.fullmatch(value)
    if match is None or not match.group(2):
        return None
    return float(match.group(1)), match.group(2)


def looks_like_quantity(value: Any) -> bool:
    """Whether ``value`` is shaped as a quantity (:func:`split_quantity`)."""
    return split_quantity(value) is not None


def convert(value: float, unit: str, to_unit: str, what: str) -> float:
    """Return ``value`` in ``unit`` expressed in ``to_unit`` (``2 m`` -> 2000 for ``mm``).

    Raises
    ------
    RodstabInputError
        Naming ``what`` if either unit is unknown or their dimensions differ.
    """
    ureg = _registry()
    import pint

    try:
        return float(ureg.Quantity(value, ureg.parse_units(unit)).to(ureg.parse_units(to_unit))
                     .magnitude)
    except pint.errors.DimensionalityError:
        raise RodstabInputError(f"{what}: {unit!r} and {to_unit!r} are not units of the same "
                                "quantity") from None
    except Exception as exc:  # pint's parser on user text (see _unit_factor)
        raise RodstabInputError(f"{what}: cannot read the units {unit!r}, {to_unit!r} "
                                f"({type(exc).__name__}: {exc})") from None


def parse_unit(text: Any, path: str, kind: str) -> float:
    """Read a bare unit (``"mm"``) of ``kind``; return SI units per unit (0.001 for mm).

    Raises
    ------
    RodstabInputError
        Naming ``path`` and ``text`` if it is not a string, or not a unit of ``kind``.
    """
    if not isinstance(text, str) or not text.strip():
        raise RodstabInputError(f"{path} must be a unit such as "
                                f"{EXAMPLES[kind].split(' ', 1)[1]!r}, got {text!r}")
    return _unit_factor(text.strip(), path, text, kind)


#: Factor of each kind from model units to SI, as powers of (Lc, Bc): kind -> (p, q) with
#: SI = model x Lc^p x Bc^q (module docstring).
_POWERS = {
    "length": (1, 0),
    "curvature": (-1, 0),
    "stiffness": (0, 1),
    "energy": (-1, 1),
    "moment": (-1, 1),
    "force": (-2, 1),
    "angle": (0, 0),
}


@dataclasses.dataclass(frozen=True)
class Units(Result):
    """The physical scales of a design with units (module docstring: the conversion).

    Attributes
    ----------
    length : float
        Reference length ``Lc`` (m): the length of the load-factor segment.
    stiffness : float
        Reference stiffness ``Bc`` (N m^2): that segment's ``B3``.
    length_unit : str
        Unit of lengths in tables: the unit of the file's first segment length (e.g. "mm").
    length_unit_m : float
        Metres per ``length_unit``.
    E : float or None
        Young's modulus (Pa) of ``[material]``; None when the design gives ``B3`` instead.
    nu : float or None
        Poisson's ratio of ``[material]`` (given, or from ``E`` and ``G``).
    G : float or None
        Shear modulus (Pa), ``E / (2 (1 + nu))`` when not given.
    segment : str
        The load-factor segment whose length and ``B3`` are the references.
    """

    length: float
    stiffness: float
    length_unit: str
    length_unit_m: float
    E: float | None
    nu: float | None
    G: float | None
    segment: str

    def si(self, value: float, kind: str) -> float:
        """Return the model value ``value`` of ``kind`` in SI (:data:`SI_UNITS`)."""
        p, q = _POWERS[kind]
        return value * self.length**p * self.stiffness**q

    def quantity(self, value: float | None, kind: str) -> dict[str, Any]:
        """Return ``{"value": SI value, "unit": SI unit}`` of a model value (None stays None)."""
        return {"value": None if value is None else self.si(value, kind),
                "unit": SI_UNITS[kind]}

    def quantities(self, values: list[float], kind: str) -> dict[str, Any]:
        """Return ``{"value": [SI values], "unit": SI unit}`` of model values."""
        return {"value": [self.si(v, kind) for v in values], "unit": SI_UNITS[kind]}

    def length_text(self, metres: float) -> str:
        """Return ``metres`` as text in the file's length unit, e.g. ``"174.4 mm"``."""
        return f"{metres / self.length_unit_m:.6g} {self.length_unit}"

    def natural_curvature(self, assembly: Assembly, load_factor: float = 1.0) -> float:
        """Return ``|kappa_n|`` (1/m) of the reference segment of ``assembly`` at ``load_factor``.

        The natural curvatures are the load factor times the design's (``natural_curvature``
        of :attr:`segment`, model units).
        """
        return abs(self.si(load_factor * assembly.segment(self.segment).natural_curvature,
                           "curvature"))

    def block(self, **entries: Any) -> dict[str, Any]:
        """Return a command's ``"units"`` block: :meth:`reference`, then ``entries`` in SI.

        An entry ``(model value, kind)`` becomes :meth:`quantity`, ``(list of model values,
        kind)`` :meth:`quantities`; any other entry (a ``{"value", "unit"}`` already in SI, a
        list of them) is kept as given.
        """
        out = self.reference()
        for key, entry in entries.items():
            if not isinstance(entry, tuple):
                out[key] = entry
            else:
                value, kind = entry
                out[key] = (self.quantities(list(value), kind) if isinstance(value, list | tuple)
                            else self.quantity(value, kind))
        return out

    def reference(self) -> dict[str, Any]:
        """Return the JSON form of the scales: what one model unit is in SI."""
        out: dict[str, Any] = {
            "system": "SI",
            "reference_segment": self.segment,
            "reference_length": {"value": self.length, "unit": "m"},
            "reference_stiffness": {"value": self.stiffness, "unit": SI_UNITS["stiffness"]},
            "conversion": "length x Lc, curvature / Lc, stiffness x Bc, energy and moment x "
                          "Bc/Lc, force x Bc/Lc^2 (Lc, Bc: reference length and stiffness)",
        }
        if self.E is not None:
            out["material"] = {"E": {"value": self.E, "unit": "Pa"}, "nu": self.nu,
                               "G": {"value": self.G, "unit": "Pa"}}
        return out


@dataclasses.dataclass(frozen=True)
class AsBuilt(Result):
    """Whether a design stands as built (load factor 1), and with what margin.

    The load factor multiplies every natural curvature, so at a load factor ``mu`` the
    natural curvature of the reference segment is ``mu kappa_n``: the critical natural
    curvature is ``hi kappa_n`` (``lo kappa_n`` below, when ``lo > 0``).

    Attributes
    ----------
    stable : bool
        ``lo < 1 < hi``.
    limit : str
        "upper" or "lower": the limit the margin is measured to (the one crossed when
        unstable; the upper one, or the nearer in ratio when both are positive, when stable).
    ratio : float
        Built over critical natural curvature, ``1 / limit``: below 1 under an upper limit
        means stable; above 1 over a lower limit means stable.
    margin : float
        ``|ratio - 1|``: the fraction by which the built natural curvature lies below
        (``ratio < 1``) or above (``ratio > 1``) the critical one.
    """

    stable: bool
    limit: str
    ratio: float
    margin: float

    @property
    def side(self) -> str:
        """Return "below" or "above": where the built natural curvature lies."""
        return "below" if self.ratio < 1.0 else "above"


def as_built(interval: tuple[float, float], built: float = 1.0) -> AsBuilt | None:
    """Stability and margin of the built design from its stable load-factor interval.

    Parameters
    ----------
    interval : (float, float)
        ``(lo, hi)``, the stable load-factor interval around the reference load (``lo`` may be
        ``-inf`` or negative, ``hi`` may be ``inf``).
    built : float
        The built load factor (the design's natural curvatures as written: 1).

    Returns
    -------
    AsBuilt or None
        None when no limit lies on the built side of zero (``hi`` infinite and ``lo <= 0``):
        no natural curvature of the built sign makes it unstable, so there is no margin.
    """
    lo, hi = interval
    stable = lo < built < hi
    if not stable:
        # The limit crossed, if it has the built sign (a critical natural curvature of the
        # opposite sign is no margin of this design).
        if built >= hi > 0:
            return AsBuilt(stable=False, limit="upper", ratio=built / hi,
                           margin=built / hi - 1.0)
        if built <= lo and lo > 0:
            return AsBuilt(stable=False, limit="lower", ratio=built / lo,
                           margin=1.0 - built / lo)
        return None
    candidates = []  # (limit, built / critical): the limits with the built sign
    if math.isfinite(hi) and hi > 0:
        candidates.append(("upper", built / hi))
    if math.isfinite(lo) and lo > 0:
        candidates.append(("lower", built / lo))
    if not candidates:
        return None
    # The nearer limit in the ratio of curvatures (|log ratio|): what a change of the natural
    # curvature meets first.
    name, ratio = min(candidates, key=lambda c: abs(math.log(c[1])))
    return AsBuilt(stable=True, limit=name, ratio=ratio, margin=abs(ratio - 1.0))


def _curvature_entries(units: Units, prefix: str, kappa: float, length: float) -> dict[str, Any]:
    """Return natural curvature (1/m), radius (m) and the paper's psi = L kappa / 2 (rad)."""
    k = abs(units.si(kappa, "curvature"))
    return {f"{prefix}natural_curvature": {"value": k, "unit": SI_UNITS["curvature"]},
            f"{prefix}natural_radius": {"value": 1.0 / k if k > 0 else math.inf, "unit": "m"},
            f"{prefix}psi": {"value": 0.5 * units.si(length, "length") * k, "unit": "rad"}}


def load_factor_curvatures(units: Units, assembly: Assembly,
                           load_factors: Sequence[float]) -> list[float]:
    """Return load factors as the reference segment's natural curvature (1/m), signed.

    The one rule by which every command states a load factor in 1/m.

    Parameters
    ----------
    units : Units
        The design's scales; ``units.segment`` is the reference (load-factor) segment.
    assembly : Assembly
        The design's (non-dimensional) assembly.
    load_factors : sequence of float
        Load factors ``mu`` (non-dimensional; may be infinite).

    Returns
    -------
    list of float
        ``mu |kappa_n|`` (1/m), ``|kappa_n|`` the reference segment's at load factor 1
        (:meth:`Units.natural_curvature`): positive in the sense the design gives it, negative
        curved the other way; infinite load factors stay infinite (all 0 when the segment is
        naturally straight).
    """
    k = units.natural_curvature(assembly, 1.0)
    return [0.0 if k == 0 else mu * k for mu in load_factors]


def _radius_range(k_lo: float, k_hi: float) -> list[float] | None:
    """Radii ``[1/k_hi, 1/k_lo]`` (m) of the curvatures ``k_lo < k < k_hi`` of one sense.

    ``k_lo`` is clipped to 0 (the other sense is the other range); None when no curvature of
    this sense is in the interval (``k_hi <= 0``). ``1/0`` is ``inf``, ``1/inf`` is 0.
    """
    if k_hi <= 0:
        return None
    k_lo = max(k_lo, 0.0)
    return [0.0 if math.isinf(k_hi) else 1.0 / k_hi, math.inf if k_lo == 0 else 1.0 / k_lo]


def curvature_interval(units: Units, assembly: Assembly,
                       interval: tuple[float, float]) -> dict[str, Any]:
    """Return a stable load-factor interval as natural curvatures and radii of the reference.

    The load factor ``mu`` multiplies every natural curvature, so the reference segment's
    natural curvature at ``mu`` is ``mu |kappa_n|`` (1/m), signed: positive in the sense the
    design gives it (``mu > 0``), negative curved the other way
    (:func:`load_factor_curvatures`, which ``atlas``'s bands use too).

    Parameters
    ----------
    units : Units
        The design's scales; ``units.segment`` is the reference (load-factor) segment.
    assembly : Assembly
        The design's (non-dimensional) assembly.
    interval : (float, float)
        The stable load-factor interval ``(lo, hi)`` (``lo`` may be ``-inf``, ``hi`` ``inf``).

    Returns
    -------
    dict
        Empty when the reference segment is naturally straight (the load factor does not
        curve it); else ``stable_natural_curvature``: ``{"value": [lo k, hi k], "unit": "1/m"}``
        with ``k = |kappa_n|`` at load factor 1, and ``stable_natural_radius``: ``{"as_given":
        [r_min, r_max], "reversed": [r_min, r_max], "unit": "m"}``, the radii (m) of the stable
        natural curvatures of each sense (``r_max`` inf: down to straight; a sense without a
        stable curvature is None).
    """
    k = units.natural_curvature(assembly, 1.0)
    if k == 0:
        return {}
    lo, hi = load_factor_curvatures(units, assembly, interval)
    return {"stable_natural_curvature": {"value": [lo, hi], "unit": SI_UNITS["curvature"]},
            "stable_natural_radius": {"as_given": _radius_range(lo, hi),
                                      "reversed": _radius_range(-hi, -lo), "unit": "m"}}


def stability_units(units: Units, assembly: Assembly, interval: tuple[float, float],
                    built: float = 1.0) -> dict[str, Any]:
    """Return the physical values of a linear stability result (analyze's ``"units"``).

    Parameters
    ----------
    units : Units
        The design's scales; ``units.segment`` is the reference (load-factor) segment.
    assembly : Assembly
        The design's (non-dimensional) assembly.
    interval : (float, float)
        The stable load-factor interval ``(lo, hi)``.
    built : float
        The load factor of the built object (1: the natural curvatures as written).

    Returns
    -------
    dict
        :meth:`Units.reference`, then for the reference segment, as built and at the
        critical load factor(s): ``natural_curvature`` (|kappa_n|, 1/m), ``natural_radius``
        (m), ``psi`` (the paper's half-angle of the natural arc, ``L kappa_n / 2``, rad;
        Section 4); ``critical_*`` at ``hi``, ``lower_critical_*`` at ``lo`` when ``lo > 0``;
        the whole interval as ``stable_natural_curvature`` and ``stable_natural_radius``
        (:func:`curvature_interval`);
        ``stored_energy`` of the held state as built (J), ``held_moment`` of each segment
        (in-plane bending moment ``B3 (k - kappa_n)`` that holds it, N m); ``as_built``
        (:func:`as_built`, or None when no limit has the built sign).
    """
    seg = assembly.segment(units.segment)
    lo, hi = interval
    out = units.reference()
    kappa = seg.natural_curvature
    out |= _curvature_entries(units, "", built * kappa, seg.length)
    out |= curvature_interval(units, assembly, interval)
    if math.isfinite(hi):
        out |= _curvature_entries(units, "critical_", hi * kappa, seg.length)
    if math.isfinite(lo) and lo > 0:
        out |= _curvature_entries(units, "lower_critical_", lo * kappa, seg.length)
    energy = sum(s.held_energy(built) for s in assembly.segments)
    out["stored_energy"] = units.quantity(energy, "energy")
    out["held_moment"] = {"value": {s.name: units.si(s.held_moments(built)[0], "moment")
                                    for s in assembly.segments}, "unit": SI_UNITS["moment"]}
    verdict = as_built(interval, built)
    out["as_built"] = None if verdict is None else verdict.to_dict() | {"side": verdict.side}
    return out


def path_units(units: Units, kind: str | None, values: list[float], energies: list[float],
               special_values: list[float], natural_curvature: float) -> dict[str, Any]:
    """Return the physical values of a continuation path (the ``"units"`` block of continue).

    Parameters
    ----------
    units : Units
        The design's scales.
    kind : str or None
        The kind of the continuation parameter (:func:`rodstab.io.vary.value_kind`); None for
        the load factor.
    values, energies : list of float
        The path's parameter values and energies (model units).
    special_values : list of float
        The parameter values of its special points.
    natural_curvature : float
        The reference segment's natural curvature at load factor 1 (model units): with the
        load factor as parameter, the path's natural curvatures are ``value x`` this.

    Returns
    -------
    dict
        :meth:`Units.reference`, ``value`` and ``special_value`` in SI (``{"value", "unit"}``)
        when the parameter has a kind, else ``natural_curvature`` and
        ``special_natural_curvature`` (|kappa_n| of the reference segment, 1/m) along the
        load factor; ``energy`` (J).
    """
    out = units.reference()
    if kind is not None:
        out["value"] = units.quantities(values, kind)
        out["special_value"] = units.quantities(special_values, kind)
    else:
        out["natural_curvature"] = units.quantities(
            [abs(v * natural_curvature) for v in values], "curvature")
        out["special_natural_curvature"] = units.quantities(
            [abs(v * natural_curvature) for v in special_values], "curvature")
    out["energy"] = units.quantities(energies, "energy")
    return out
