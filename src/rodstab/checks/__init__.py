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
| :mod:`.beyond_hexagram` | beyond the paper | the curved-sided hexagram (Lu et al.) |
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Mapping

from . import (
    beyond_contact,
    beyond_critical,
    beyond_hexagram,
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
    """One entry of the registry: a check function and the status claimed for each of its rows.

    ``seconds``: its CPU time on one core as measured (``benchmarks/bench_reproduce.py``), which
    only orders the parallel run (longest first).
    """

    produce: Callable[[Run], Iterator[Claim]]
    expected: Mapping[str, str]
    seconds: float


_PB = beyond_postbuckling

#: The check functions in report order, each with the statuses the project claims. A check is
#: one independent computation (the post-buckling and transition rows are split into several),
#: so that the parallel run can balance them.
REGISTRY: tuple[Check, ...] = (
    Check(sec2.section2_checks, sec2.EXPECTED, 0.03),
    Check(sec3_1.ring_checks, sec3_1.EXPECTED, 3.0),
    Check(sec3_2.arc_checks, sec3_2.EXPECTED, 1.7),
    Check(sec3_2_stiffness.stiffness_checks, sec3_2_stiffness.EXPECTED, 0.5),
    Check(sec3_3.michell_checks, sec3_3.EXPECTED, 1.7),
    Check(engine.engine_checks, engine.EXPECTED, 0.06),
    Check(sec4.birod_checks, sec4.EXPECTED, 0.1),
    Check(sec5.folded_ring_checks, sec5.EXPECTED, 0.8),
    Check(beyond_critical.critical_checks, beyond_critical.EXPECTED, 0.1),
    Check(_PB.straightened_postbuckling_checks, _PB.EXPECTED_STRAIGHTENED, 2.4),
    Check(_PB.birod_postbuckling_checks, _PB.EXPECTED_BIROD, 2.3),
    Check(_PB.folded_postbuckling_checks, _PB.EXPECTED_FOLDED, 2.9),
    Check(_PB.folded_threshold_checks, _PB.EXPECTED_FOLDED_THRESHOLD, 6.1),
    Check(beyond_imperfections.imperfection_checks, beyond_imperfections.EXPECTED, 6.0),
    Check(beyond_twisted.twisted_rod_checks, beyond_twisted.EXPECTED, 5.5),
    Check(beyond_transitions.ring_transition_checks, beyond_transitions.EXPECTED_RING, 3.8),
    Check(beyond_transitions.six_ring_transition_checks, beyond_transitions.EXPECTED_SIX, 6.5),
    Check(beyond_hexagram.hexagram_checks, beyond_hexagram.EXPECTED, 5.3),
    Check(beyond_contact.contact_checks, beyond_contact.EXPECTED, 1.9),
    Check(beyond_contact.contact_limit_checks, beyond_contact.EXPECTED_LIMITS, 7.8),
    Check(beyond_contact.folded_ring_limit_checks, beyond_contact.EXPECTED_FOLDED_RING, 9.0),
    Check(beyond_contact.contact_column_checks, beyond_contact.EXPECTED_COLUMNS, 21.0),
)


def _run_check(i: int) -> tuple[list[Claim], dict, float]:
    """Worker: the rows, figure data and CPU seconds of ``REGISTRY[i]`` (a fresh :class:`Run`)."""
    import time

    run = Run()
    t0 = time.process_time()
    rows = list(REGISTRY[i].produce(run))
    return rows, run.figures, time.process_time() - t0


def _merge(into: dict, figures: dict) -> None:
    """Merge a worker's figure data into ``into``, dictionaries key by key at every depth.

    (Several checks fill one dictionary: the post-buckling checks each add their structure to
    ``beyond.branches``.)
    """
    for key, value in figures.items():
        if isinstance(value, dict) and isinstance(into.get(key), dict):
            _merge(into[key], value)
        else:
            into[key] = value


def evaluate(run: Run | None = None, *, workers: int | None = None) -> list[Claim]:
    """Run every check of :data:`REGISTRY`; return the rows (computed statuses) in registry order.

    The checks are independent: with ``workers`` > 1 (default: the number of CPUs, at most the
    number of checks) they run in that many processes, submitted longest first (``seconds``: the
    two workers then finish together); figure data are merged into ``run.figures``;
    ``run.progress`` ticks once per finished check; ``run.cpu_seconds`` records each check's.
    """
    import os
    import time

    run = Run() if run is None else run
    n = min(len(REGISTRY), os.cpu_count() or 1) if workers is None else workers
    if n <= 1:
        rows: list[Claim] = []
        for check in REGISTRY:
            t0 = time.process_time()
            rows += check.produce(run)
            run.cpu_seconds[check.produce.__name__] = time.process_time() - t0
            run.progress()
        return rows
    from ..numerics.threads import process_pool

    order = sorted(range(len(REGISTRY)), key=lambda i: -REGISTRY[i].seconds)
    with process_pool(n) as pool:
        futures = {i: pool.submit(_run_check, i) for i in order}
        results = {}
        for i in order:
            results[i] = futures[i].result()
            run.progress()
    rows = []
    for i in range(len(REGISTRY)):
        rows += results[i][0]
        _merge(run.figures, results[i][1])
        run.cpu_seconds[REGISTRY[i].produce.__name__] = results[i][2]
    return rows


def expected_statuses() -> dict[str, str]:
    """Row id -> the status the project claims for it, in report order."""
    return {rid: status for check in REGISTRY for rid, status in check.expected.items()}
