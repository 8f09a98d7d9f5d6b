"""Bi-rod of Section 4: two rods of natural curvature +kappa0 and -kappa0 welded at both ends.

Strain energy (4.3); the paper's load ``lambda = B3 kappa0 L / sqrt(B1 B2)`` (as (5.7)) and the
end rotation ``psi = kappa0 L / 2`` of Section 4 (``psi_c = pi sqrt(b1 b2)`` claimed, i.e.
``lambda_c = 2 pi``, the straightened rod (3.9)). Units: ``B3 = 1``; the load factor ``mu`` is
``kappa0`` (natural curvature ``+-1`` per unit ``mu``).
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import RodstabInputError, require_positive
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits
from ..linear.solve import LinearStability
from ..model import Assembly
from ..sections import Section, circle
from ..transfer import ASSEMBLY_RIGID_NULLITY, FullSystemCritical, full_system_critical
from ._common import Method, engine, nonlinear_critical, segment

#: Elements per segment of the linear engine used by ``rodstab birod``.
DEFAULT_ELEMENTS = 48
#: Elements per segment of the nonlinear rod in :data:`METHODS` (report row NL-bi-rod).
NONLINEAR_ELEMENTS = 24
#: The paper's critical load (Section 4): ``lambda_c = 2 pi`` (this project finds ``pi``).
PAPER_LAMBDA_C = 2 * math.pi
_CLAMPS = ("start", "both", None)


@dataclasses.dataclass(frozen=True, kw_only=True)
class Params:
    """Parameters of the bi-rod: ``section``, rod ``length`` L and ``clamp``.

    ``clamp``: ``"start"`` (the paper: one end clamped), ``"both"``, or ``None`` (free; the
    three rigid motions are gauged out).
    """

    section: Section = dataclasses.field(default_factory=circle)
    length: float = 1.0
    clamp: str | None = "start"

    def __post_init__(self) -> None:
        """Validate: positive length, a known clamp."""
        require_positive("length", self.length)
        if self.clamp not in _CLAMPS:
            raise RodstabInputError(f"clamp must be 'start', 'both' or None, got {self.clamp!r}")


def build(params: Params) -> Assembly:
    """Return the bi-rod: ``upper`` (kappa_n = +1) and ``lower`` (-1) welded at both ends."""
    L = float(params.length)
    section = params.section
    segs = (segment("upper", section, L, 0.0, 1.0), segment("lower", section, L, 0.0, -1.0))
    welds = ((("upper", "start"), ("lower", "start")), (("upper", "end"), ("lower", "end")))
    sup: tuple[tuple[str, str, str], ...] = (
        () if params.clamp is None else (("upper", "start", "clamped"),))
    if params.clamp == "both":
        sup += (("upper", "end", "clamped"),)
    return Assembly(segments=segs, welds=welds, supports=sup, reference_load=0.0)


def to_paper(mu: float, params: Params) -> dict[str, float]:
    """Return the paper's units of load factor ``mu``: ``lambda`` (5.7) and ``psi`` (Section 4).

    ``lambda = B3 kappa0 L / sqrt(B1 B2) = mu L / sqrt(b1 b2)``,
    ``psi = kappa0 L / 2 = lambda sqrt(b1 b2) / 2`` (radians).
    """
    lam = mu * params.length / params.section.sqrt_b1b2
    return {"lambda": lam, "psi": 0.5 * lam * params.section.sqrt_b1b2}


def paper_critical(params: Params) -> dict[str, float]:
    """Return the paper's claimed ``lambda_c = 2 pi`` and ``psi_c = pi sqrt(b1 b2)``."""
    return {"lambda": PAPER_LAMBDA_C, "psi": math.pi * params.section.sqrt_b1b2}


def full_system(params: Params) -> FullSystemCritical:
    """``lambda_c`` by the exact general solutions joined by all joint conditions (second method).

    :func:`rodstab.transfer.full_system_critical`; no rigid motions when clamped. The paper's
    derivation after (4.6) imposes the natural conditions (4.6) at the clamp too, which confines
    it to the opening mode ``u(1) = -u(2)`` (``lambda = 2 pi``); the full system also has
    ``u(1) = u(2)``, ``alpha(1) = -alpha(2)`` with ``sin(lambda) = 0``: ``lambda = pi``.
    """
    nullity = ASSEMBLY_RIGID_NULLITY if params.clamp is None else 0
    return full_system_critical(build(params), params.section.sqrt_b1b2 / params.length,
                                nullity, 7.0)


def engine_stability(params: Params, elements: int = DEFAULT_ELEMENTS,
                     limits: Limits = DEFAULT_LIMITS) -> LinearStability:
    """Critical load factor ``mu = kappa0`` by the linear FE engine."""
    return engine(build(params), elements, limits)


def _lam(mu: float, params: Params) -> dict[str, float]:
    return {"lambda": to_paper(mu, params)["lambda"]}


def _transfer(params: Params) -> dict[str, float]:
    return {"lambda": full_system(params).lambda_c}


def _fe(params: Params) -> dict[str, float]:
    return _lam(engine_stability(params).load_factor_critical, params)


def _nonlinear(params: Params) -> dict[str, float]:
    # Scan lambda in (0.5, 1.25 x 2 pi): clamped at both ends each rod is the straightened rod
    # of (3.9), lambda_c = 2 pi; every other clamp holds a subset of those constraints, so its
    # lambda_c is at most 2 pi (a Rayleigh quotient over more admissible fields). A fixed
    # (0.5, 4.5) missed the both-clamped limit (nan).
    # The discrete rod's error goes as (lambda_c l_e)^2: twice the elements for the 2 pi mode
    # keep it at the pi mode's (AGREE_RTOL's 5e-3; at NONLINEAR_ELEMENTS it was 5.6e-3).
    mu_per_lam = params.section.sqrt_b1b2 / params.length
    elements = NONLINEAR_ELEMENTS * (2 if params.clamp == "both" else 1)
    return _lam(nonlinear_critical(build(params), 0.5 * mu_per_lam,
                                   1.25 * 2 * math.pi * mu_per_lam, elements), params)


#: Methods that solve the bi-rod, each returning the critical ``lambda``. None is the paper's
#: derivation: its ``2 pi`` (:func:`paper_critical`) is not expected to agree (Section 4 row 4.8).
METHODS: dict[str, Method] = {"transfer": _transfer, "fe": _fe, "nonlinear": _nonlinear}
#: How closely each pair must agree (relative), and why.
AGREE_RTOL: dict[tuple[str, str], float] = {
    # FE mesh error at DEFAULT_ELEMENTS vs the exact full system (report row 4.8).
    ("transfer", "fe"): 1e-6,
    # Discrete rod at NONLINEAR_ELEMENTS: second-order mesh error (report row NL-bi-rod).
    ("transfer", "nonlinear"): 5e-3,
}
