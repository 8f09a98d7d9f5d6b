"""Every checked statement of the paper, section by section, and beyond it.

:data:`REGISTRY` lists the check functions in report order. Each takes a :class:`Run` and yields
:class:`Claim` rows whose status is computed by a named rule of :mod:`.rules`; next to it, each
entry declares the status the project claims for every row (``expected``), which the tests
compare with the computed one. ``rodstab reproduce`` (:mod:`rodstab.report.reproduce`) iterates
the registry and prints the computed status.

| module | paper | rows |
|---|---|---|
| :mod:`.sec2` | Section 2, (2.1)-(2.12) | kinematics, quadratic energy |
| :mod:`.sec3_1` | Section 3.1, (3.1)-(3.3) | N-loop rings |
| :mod:`.sec3_2`, :mod:`.sec3_2_stiffness` | Section 3.2, (3.4)-(3.15) | clamped arcs |
| :mod:`.sec3_3` | Section 3.3, (3.21)-(3.26) | Michell's twisted ring |
| :mod:`.engine` | Section 3 | linear FE engine vs the analytic results |
| :mod:`.sec4` | Section 4, (4.4)-(4.8) | bi-rod |
| :mod:`.sec5` | Section 5, (5.4)-(5.14) | folded six-sided ring |
| :mod:`.beyond_critical`, ... | beyond the paper | nonlinear rod: post-buckling, transitions |
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Mapping

from . import (
    beyond_critical,
    beyond_imperfections,
    beyond_postbuckling,
    beyond_transitions,
    beyond_twisted,
    engine,
    sec2,
    sec3_1,
    sec3_2,
    sec3_2_stiffness,
    sec3_3,
    sec4,
    sec5,
)
from .core import Claim, Run
from .rules import DIFFERS, REPRODUCED, STATUSES, UNRESOLVED

__all__ = ["REGISTRY", "Check", "Claim", "DIFFERS", "REPRODUCED", "Run", "STATUSES",
           "UNRESOLVED", "evaluate", "expected_statuses"]


@dataclasses.dataclass(frozen=True)
class Check:
    """One entry of the registry: a check function and the status claimed for each of its rows."""

    produce: Callable[[Run], Iterator[Claim]]
    expected: Mapping[str, str]


#: The check functions in report order, each with the statuses the project claims.
REGISTRY: tuple[Check, ...] = (
    Check(sec2.section2_checks, sec2.EXPECTED),
    Check(sec3_1.ring_checks, sec3_1.EXPECTED),
    Check(sec3_2.arc_checks, sec3_2.EXPECTED),
    Check(sec3_2_stiffness.stiffness_checks, sec3_2_stiffness.EXPECTED),
    Check(sec3_3.michell_checks, sec3_3.EXPECTED),
    Check(engine.engine_checks, engine.EXPECTED),
    Check(sec4.birod_checks, sec4.EXPECTED),
    Check(sec5.folded_ring_checks, sec5.EXPECTED),
    Check(beyond_critical.critical_checks, beyond_critical.EXPECTED),
    Check(beyond_postbuckling.postbuckling_checks, beyond_postbuckling.EXPECTED),
    Check(beyond_imperfections.imperfection_checks, beyond_imperfections.EXPECTED),
    Check(beyond_twisted.twisted_rod_checks, beyond_twisted.EXPECTED),
    Check(beyond_transitions.transition_checks, beyond_transitions.EXPECTED),
)


def evaluate(run: Run | None = None) -> list[Claim]:
    """Run every check of :data:`REGISTRY` in order and return the rows (computed statuses)."""
    run = Run() if run is None else run
    rows: list[Claim] = []
    for check in REGISTRY:
        rows += check.produce(run)
        run.progress()
    return rows


def expected_statuses() -> dict[str, str]:
    """Row id -> the status the project claims for it, in report order."""
    return {rid: status for check in REGISTRY for rid, status in check.expected.items()}
