"""The library sweep (:func:`rodstab.sweep.sweep`): each row is an independent linear
stability solve of the design with the varied value set (oracle: single
:func:`rodstab.linear.solve.linear_stability` runs on designs built by hand)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from rodstab.analytic.arc import clamped_arc_stability
from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design, parse_design
from rodstab.io.vary import set_design_value
from rodstab.linear.solve import converged_stability, linear_stability
from rodstab.sections import rectangle
from rodstab.sweep import SweepResult, columns, sweep

ROOT = Path(__file__).resolve().parent.parent
ARC = ROOT / "examples" / "clamped_arc.toml"


def test_sweep_rows_match_single_linear_stability_runs():
    """Every row equals linear_stability of the design with that value (same elements)."""
    d = load_design(ARC)
    values = [1.0, 1.5, 2.0]
    calls = []
    r = sweep(d, "segment.arc.length", values, elements=16, progress=lambda: calls.append(1))
    assert isinstance(r, SweepResult) and r.key == "segment.arc.length"
    assert len(calls) == len(values) and r.converged
    assert r.executor.startswith("serial (default: ")  # 3 cheap points: no cluster started
    assert [row.index for row in r.rows] == [0, 1, 2] and r.resumed == 0
    for row, v in zip(r.rows, values, strict=True):
        single = parse_design(set_design_value(d.raw, "segment.arc.length", v))
        ls = linear_stability(single.assembly, 16)
        assert row.value == v
        assert row.load_factor_critical == pytest.approx(ls.load_factor_critical, rel=1e-12)
        assert row.load_factor_lower == pytest.approx(ls.load_factor_interval[0], rel=1e-12)
        assert row.multiplicity == ls.multiplicity
        assert row.paper_load_factor_critical == pytest.approx(
            single.paper_load_factor(ls.load_factor_critical), rel=1e-12)


def test_sweep_default_mesh_is_analyzes_and_table_keys_are_the_clis():
    d = load_design(ARC)
    r = sweep(d, "section.aspect", np.linspace(1.0, 2.0, 2))
    assert r.elements_per_segment is None
    # no [analysis] elements: refined from the design's start as `analyze` does (aspect 2 is
    # the file's value), which meets the closed form (3.7)/(3.8) of L/R = 2
    single = converged_stability(d.assembly, d.elements)
    assert single.elements > d.elements
    assert r.rows[1].load_factor_critical == pytest.approx(single.load_factor_critical,
                                                           rel=1e-12)
    sec = rectangle(aspect=2.0)
    hi = clamped_arc_stability(sec.b1, sec.b2, 2.0).L_kappa_interval[1] / 2.0
    assert r.rows[1].load_factor_critical == pytest.approx(hi, rel=1e-6)
    table = r.table()
    assert list(table[0]) == list(columns("section.aspect")) == [
        "index", "section.aspect", "status", "load_factor_critical", "load_factor_lower",
        "multiplicity", "paper_load_factor_critical", "residual", "seconds", "error"]
    assert table[0]["status"] == "ok" and table[0]["error"] == ""
    assert r.to_dict()["rows"][0]["value"] == 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.key = "other"  # type: ignore[misc]


@pytest.mark.parametrize("key, values, kwargs, needle", [
    ("segment.zz.length", [1.0], {}, "zz"),
    ("section.aspect", [], {}, "none"),
    ("section.aspect", [1.0, float("nan")], {}, "nan"),
    ("section.aspect", ["2"], {}, "'2'"),
    ("section.aspect", [1.0], {"elements": 0}, "elements"),
    ("analysis.elements", [8.5, 9.5], {}, "takes integer values, got 8.5"),  # no value fits
    ("section.aspect", [1.0], {"workers": -1}, "--workers must be an integer from 0"),
    ("section.aspect", [1.0], {"workers": 2.5}, "2.5"),
    ("section.aspect", [1.0], {"workers": 2, "scheduler": "tcp://h:8786"},
     "--workers and --scheduler both"),
    ("section.aspect", [1.0], {"scheduler": " "}, "--scheduler must be an address"),
    ("section.aspect", [1.0], {"points_per_task": 0}, "--points-per-task must be a positive"),
])
def test_sweep_bad_input_raises_naming_it(key, values, kwargs, needle):
    with pytest.raises(RodstabInputError, match=None) as info:
        sweep(load_design(ARC), key, values, **kwargs)
    assert needle in str(info.value)
