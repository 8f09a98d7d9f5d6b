"""The row of the reproduction report, and what every check function receives.

A check function (one per paper section, listed in :data:`rodstab.checks.REGISTRY`) yields
:class:`Claim` rows. Each row carries the paper's value, rodstab's value, a second method's value
and a status computed by a named rule of :mod:`rodstab.checks.rules`; the paper's value is the
printed text, rodstab's value is computed, and the second method shares no algebra with the first.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from ..results import Result


@dataclasses.dataclass(frozen=True)
class Claim(Result):
    """One checked statement of the paper (one row of the report)."""

    id: str
    section: str
    equation: str
    statement: str
    paper: str
    rodstab: str
    second: str
    second_method: str
    status: str
    note: str = ""


def _no_progress() -> None:
    """Default progress callback: do nothing."""


@dataclasses.dataclass
class Run:
    """Shared by the check functions of one evaluation of the registry.

    ``progress`` is called after each expensive step (a progress bar's tick). ``figures`` collects
    figure data that checks compute anyway (``"fig3"``; ``"beyond"``: branches, imperfections,
    paths), so that the report draws the figures without computing them again.
    ``cpu_seconds``: check function name -> CPU seconds it took (filled by ``evaluate``).
    """

    progress: Callable[[], None] = _no_progress
    figures: dict = dataclasses.field(default_factory=dict)
    cpu_seconds: dict[str, float] = dataclasses.field(default_factory=dict)

    def beyond(self) -> dict:
        """Return the ``"beyond"`` figure data, created empty on first use."""
        return self.figures.setdefault("beyond", {})


def fmt(x: float, n: int = 6) -> str:
    """``x`` to ``n`` significant digits (``%g``): how the report prints computed numbers."""
    return f"{x:.{n}g}"
