"""Every row of the report has the status the project claims for it (issue 9).

The statuses are the ones ``rodstab reproduce`` printed (session fixture ``reproduction``, one
run shared with ``test_report.py``); the claims are the ``expected`` tables of
:data:`rodstab.checks.REGISTRY`.
"""

from __future__ import annotations

import ast
import json
from pathlib import Path

import pytest

from rodstab import checks
from rodstab.checks import rules

EXPECTED = checks.expected_statuses()
RULES = {"agrees_to_printed", "methods_agree", "order_is", "residual_below", "typo_shown_by",
         "holds", "every"}
CHECKS_DIR = Path(checks.__file__).parent


@pytest.fixture(scope="module")
def printed(reproduction):
    """Row id -> row of ``results.json`` as ``rodstab reproduce`` wrote it."""
    out, _ = reproduction
    rows = json.loads((out / "results.json").read_text())["claims"]
    return {row["id"]: row for row in rows}


@pytest.mark.parametrize(("rid", "expected"), EXPECTED.items(), ids=list(EXPECTED))
def test_computed_status_is_the_claimed_one(printed, rid, expected):
    assert printed[rid]["status"] == expected, printed[rid]


#: Rows the project claims do not reproduce (10 of 69): one test item each. The other rows
#: claim ``reproduced``; had they one item each, it would assert nothing (issue 20: 59 of 69).
DIFFERING = [rid for rid, status in EXPECTED.items() if status != rules.REPRODUCED]
#: Shortest note that can say what differs and what follows from it.
NOTE_MIN_CHARS = 20


@pytest.mark.parametrize("rid", DIFFERING)
def test_a_differing_row_has_a_note(printed, rid):
    """A row claimed ``differs`` explains the evidence and the consequence: a note of its own,
    not empty nor a repeat of the statement or of the paper's text."""
    row = printed[rid]
    note = row["note"].strip()
    assert len(note) > NOTE_MIN_CHARS, rid
    assert note not in (row["statement"].strip(), row["paper"].strip()), rid


def test_every_row_computed_not_reproduced_has_a_note(printed):
    """Whatever its claim, a row whose computed status is not ``reproduced`` has a note (one
    check over all rows: a row that unexpectedly differs must also say why)."""
    assert DIFFERING and len(DIFFERING) < len(EXPECTED)
    bare = [rid for rid, row in printed.items()
            if row["status"] != rules.REPRODUCED and len(row["note"].strip()) <= NOTE_MIN_CHARS]
    assert bare == []


def test_registry_declares_exactly_the_printed_rows_in_order(printed, reproduction):
    _, summary = reproduction
    assert list(printed) == list(EXPECTED)
    assert summary["n_claims"] == len(EXPECTED)
    assert all(row["status"] in rules.STATUSES for row in printed.values())


def _status_arguments(tree: ast.AST):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "Claim":
            kw = [k.value for k in node.keywords if k.arg == "status"]
            yield node, (node.args[8] if len(node.args) > 8 else kw[0])


@pytest.mark.parametrize("path", sorted(CHECKS_DIR.glob("*.py")), ids=lambda p: p.name)
def test_every_status_is_computed_by_a_named_rule(path):
    """No row passes a constant status: the status argument of every ``Claim(...)`` is a call
    of a rule of :mod:`rodstab.checks.rules`."""
    for node, status in _status_arguments(ast.parse(path.read_text())):
        name = getattr(status, "func", None)
        assert isinstance(status, ast.Call) and getattr(name, "id", None) in RULES, (
            f"{path.name}:{node.lineno}: status {ast.unparse(status)}")


# ---------------------------------------------------------------------------------- the rules


def test_typo_shown_by_needs_the_correction_to_hold():
    assert rules.typo_shown_by(1.0, 0.0, 0.1) == rules.DIFFERS
    assert rules.typo_shown_by(0.0, 1.0, 0.1) == rules.REPRODUCED
    assert rules.typo_shown_by(1.0, 1.0, 0.1) == rules.UNRESOLVED
    assert rules.typo_shown_by([1.0, 1.0], [0.0, 0.5], 0.1) == rules.UNRESOLVED


def test_methods_agree_elementwise_and_counts_roots():
    assert rules.methods_agree([1.0, 2.0], [1.0, 2.0 + 1e-12], 1e-10) == rules.REPRODUCED
    assert rules.methods_agree([1.0, 2.0], 2.0, 1e-10) == rules.DIFFERS
    assert rules.methods_agree([1.0, 2.0], [1.0, 2.0, 3.0], 1e-10) == rules.DIFFERS
    assert rules.methods_agree(float("nan"), 1.0, 1.0) == rules.DIFFERS


def test_every_and_printed_precision():
    assert rules.every(rules.REPRODUCED, rules.REPRODUCED) == rules.REPRODUCED
    assert rules.every(rules.REPRODUCED, rules.DIFFERS) == rules.DIFFERS
    assert rules.every(rules.DIFFERS, rules.UNRESOLVED) == rules.UNRESOLVED
    assert rules.agrees_to_printed(-0.861555, -0.861, 3) == rules.REPRODUCED
    assert rules.agrees_to_printed(-0.8635, -0.861, 3) == rules.DIFFERS
    assert rules.order_is([3.05, 3.9], [3, 4]) == rules.REPRODUCED
    assert rules.order_is(2.0, 4) == rules.DIFFERS
