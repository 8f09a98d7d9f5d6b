"""Parameter sweeps of the linear engine (``rodstab sweep``).

The critical load factor of a design while one design value varies.

Each value gives an independent design (:func:`rodstab.design.set_design_value`, validated
by :func:`rodstab.design.parse_design`) and one linear stability solve
(:func:`rodstab.linear.solve.linear_stability`); nothing is carried from one value to the next.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable
from typing import Any

from .design import Design, parse_design, set_design_value
from .errors import RodstabInputError, require_finite, require_positive_int
from .limits import DEFAULT as DEFAULT_LIMITS
from .limits import Limits, require_steps
from .linear.solve import linear_stability
from .results import Result

#: The columns of a sweep's table after the varied key (:meth:`SweepRow.record`).
COLUMNS = ("load_factor_critical", "load_factor_lower", "multiplicity",
           "paper_load_factor_critical", "residual")
#: The column of a design with units: |natural curvature| (1/m) of the load-factor segment at
#: the critical load factor.
PHYSICAL_COLUMN = "critical_natural_curvature_per_m"


@dataclasses.dataclass(frozen=True)
class SweepRow(Result):
    """The linear stability of the design at one value of the varied key."""

    value: float
    load_factor_critical: float
    load_factor_lower: float
    multiplicity: int
    paper_load_factor_critical: float
    residual: float
    converged: bool
    #: |natural curvature| (1/m) of the load-factor segment at the critical load factor, for
    #: a design with units (None without units).
    critical_natural_curvature: float | None = None

    def record(self, key: str) -> dict[str, Any]:
        """Return the row as the CLI's CSV/JSON record: ``key`` (the value), then COLUMNS.

        A design with units adds :data:`PHYSICAL_COLUMN` (1/m).
        """
        out = {key: self.value} | {c: getattr(self, c) for c in COLUMNS}
        if self.critical_natural_curvature is not None:
            out[PHYSICAL_COLUMN] = self.critical_natural_curvature
        return out


@dataclasses.dataclass(frozen=True)
class SweepResult(Result):
    """A sweep of ``key``: one :class:`SweepRow` per value, in the order given."""

    key: str
    rows: tuple[SweepRow, ...]
    elements_per_segment: int | None
    method: str

    @property
    def converged(self) -> bool:
        """True when every row's eigen solve converged."""
        return all(r.converged for r in self.rows)

    def table(self) -> list[dict[str, Any]]:
        """Return the rows as the CLI's CSV/JSON records.

        The varied value under the column ``key``, then ``load_factor_critical``,
        ``load_factor_lower``, ``multiplicity``, ``paper_load_factor_critical``, ``residual``.
        """
        return [r.record(self.key) for r in self.rows]


def design_at(design: Design, key: str, value: float, unit: str | None = None) -> Design:
    """Return ``design`` with the design value ``key`` set to ``value``, validated.

    Parameters
    ----------
    design : Design
        The base design (not modified).
    key : str
        A key of :func:`rodstab.design.set_design_value`.
    value : float
        Its new value.
    unit : str, optional
        Its unit (a design with units: :func:`rodstab.design.vary_in_units`).

    Returns
    -------
    Design
        The modified design.

    Raises
    ------
    RodstabInputError
        If ``key`` names no design value, or the design is invalid at ``value``; the message
        names the key and the value (``--vary KEY = VALUE: ...``).
    """
    data = set_design_value(design.raw, key, value, unit)
    try:
        return parse_design(data, design.source)
    except RodstabInputError as exc:
        shown = f"{value:g}" if unit is None else f"{value:g} {unit}"
        raise RodstabInputError(f"--vary {key} = {shown}: {exc}") from None


def sweep(design: Design, key: str, values: Iterable[float], *, elements: int | None = None,
          progress: Callable[[], Any] | None = None,
          on_row: Callable[[SweepRow], Any] | None = None,
          limits: Limits = DEFAULT_LIMITS, unit: str | None = None) -> SweepResult:
    """Linear stability of ``design`` with the design value ``key`` set to each of ``values``.

    Parameters
    ----------
    design : Design
        The base design (its ``raw`` data is copied and modified, never changed in place).
    key : str
        A dotted design key accepted by :func:`rodstab.design.set_design_value`, e.g.
        ``section.aspect`` or ``segment.arc.length``.
    values : iterable of float
        One or more finite values of ``key``, solved in the order given.
    elements : int, optional
        Elements per segment; default: each modified design's ``[analysis] elements``.
    progress : callable, optional
        Called with no argument after each value (e.g. a progress bar's update).
    on_row : callable, optional
        Called with each finished :class:`SweepRow` before the next value is solved (e.g. to
        append it to a file, so that an interrupted sweep keeps its finished rows).
    unit : str, optional
        The unit of ``values`` (a design with units, :func:`rodstab.design.vary_in_units`).

    Returns
    -------
    SweepResult
        One row per value, in the order given.

    Raises
    ------
    RodstabInputError
        If ``key`` names no design value, a value is not a finite number or gives an invalid
        design (the message names it), ``values`` is empty or ``elements`` is not a positive
        integer.
    """
    vals = list(values)
    if not vals:
        raise RodstabInputError(f"sweep needs one or more values of {key!r}, got none")
    vals = [require_finite(f"sweep value of {key!r}", v) for v in vals]
    ne = None if elements is None else require_positive_int("elements", elements)
    require_steps(len(vals), f"{len(vals)} values", "sweep points", limits)
    rows = []
    for v in vals:
        d = design_at(design, key, v, unit)
        r = linear_stability(d.assembly, d.elements if ne is None else ne, limits=limits)
        ref = d.assembly.segment(d.load_factor_segment)
        kc = None if d.units is None else \
            abs(d.units.si(r.load_factor_critical * ref.natural_curvature, "curvature"))
        rows.append(SweepRow(v, r.load_factor_critical, r.load_factor_interval[0],
                             r.multiplicity, d.paper_load_factor(r.load_factor_critical),
                             r.residual, r.converged, kc))
        if on_row is not None:
            on_row(rows[-1])
        if progress is not None:
            progress()
    method = "linear_stability at each value (FE of P2, eq 2.12)"
    return SweepResult(key, tuple(rows), ne, method)
