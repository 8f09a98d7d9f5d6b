"""Design files: examples run, strict validation, CLI contract of analyze/birod/folded-ring."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from rodstab.analytic.ring import ring_stability
from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design, parse_design
from rodstab.io.vary import parse_vary
from rodstab.linear.solve import linear_stability

EXAMPLES = sorted(Path(__file__).resolve().parent.parent.joinpath("examples").glob("*.toml"))
ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_every_example_runs_from_the_cli(run_cli, path):
    r = run_cli(["analyze", str(path), "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    for key in ("load_factor_critical", "multiplicity", "load_factor_interval",
                "stable_at_design", "mode_family", "residual", "n_dof"):
        assert key in p
    assert p["converged"]


def test_example_straight_rod_is_eq_3_9():
    """Closed form (3.9): 2 pi sqrt(b1 b2) for kappa_n L at load factor 1, L = 1."""
    d = load_design(ROOT / "examples" / "straight_clamped_rod.toml")
    r = linear_stability(d.assembly, 48)
    assert r.load_factor_critical == pytest.approx(2 * math.pi * math.sqrt(0.75), rel=1e-6)


def test_example_three_loop_ring_is_section_3_1():
    d = load_design(ROOT / "examples" / "ring_3_loops.toml")
    lo, hi = linear_stability(d.assembly, d.elements).load_factor_interval
    M_lo, M_hi = ring_stability(1.0, 0.75, 3).M_interval
    assert (1 - hi, 1 - lo) == pytest.approx((M_lo, M_hi), rel=1e-5)


def _base():
    return {"segment": [{"name": "a", "length": 1.0, "natural_curvature": 1.0}],
            "support": [{"end": "a.start", "type": "clamped"}, {"end": "a.end",
                                                                 "type": "clamped"}]}


@pytest.mark.parametrize("mutate, needle", [
    (lambda d: d.update(bogus=1), "bogus"),
    (lambda d: d["segment"][0].update(lenght=2), "lenght"),
    (lambda d: d["segment"][0].update(length=-1.0), "length"),
    (lambda d: d.update(section={"shape": "circle", "nu": 0.7}), "0.7"),
    (lambda d: d.update(section={"b1": -1.0, "b2": 1.0}), "b1"),
    (lambda d: d.update(section={"shape": "hexagon"}), "hexagon"),
    (lambda d: d.update(weld=[{"ends": ["a.end", "b.start"]}]), "'b'"),
    (lambda d: d["segment"].append({"name": "b", "length": 1.0, "start": [5.0, 0.0]})
     or d.update(weld=[{"ends": ["a.end", "b.start"]}]), "do not meet"),
    (lambda d: d.update(support=[]), "moment equilibrium"),
    (lambda d: d["support"][0].update(type="welded"), "welded"),
    (lambda d: d["support"][0].update(end="a-start"), "a-start"),
    (lambda d: d.update(analysis={"elements": 0}), "elements"),
    (lambda d: d.update(analysis={"load_factor_segment": "zz"}), "zz"),
    (lambda d: d.update(segment=[]), "segment"),
    (lambda d: d["segment"].append({"name": "a", "length": 1.0}), "duplicate"),
])
def test_bad_design_raises_naming_key_or_value(mutate, needle):
    d = _base()
    mutate(d)
    with pytest.raises(RodstabInputError, match=needle):
        parse_design(d)


def test_cli_analyze_bad_file_one_line_exit_2(run_cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[segment]]\nname = "a"\nlength = 1.0\ncolour = "red"\n')
    r = run_cli(["analyze", str(bad)])
    assert r.exit_code == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "colour" in r.stderr


def test_cli_birod_json_contract(run_cli):
    p = json.loads(run_cli(["birod", "--json"]).stdout)
    assert p["lambda_c"] == pytest.approx(math.pi, rel=1e-6)
    assert p["lambda_c_full_system"] == pytest.approx(math.pi, rel=1e-9)
    assert p["psi_c"] == pytest.approx(math.pi / 2 * math.sqrt(0.75), rel=1e-6)
    assert "mode_family" in p


def test_cli_folded_ring_json_contract_240_variant(run_cli):
    """lam_c = pi/3 for six segments; kappa_n R0 = lam sqrt(b1 b2) / theta, theta = 4 pi/3."""
    p = json.loads(run_cli(["folded-ring", "--segments", "6", "--arc-angle", "240",
                            "--json"]).stdout)
    assert p["lambda_c"] == pytest.approx(math.pi / 3, rel=1e-6)
    assert p["multiplicity"] == 2
    assert p["kappa_R0_c"] == pytest.approx(math.pi / 3 * math.sqrt(0.75) / (4 * math.pi / 3),
                                            rel=1e-6)


@pytest.mark.parametrize("n", [4, 8])
def test_folded_2n_rings_critical_is_2pi_over_2n(run_cli, n):
    """Beyond the paper: 2n straight segments folded into n loops: lam_c = 2 pi / (2n)
    (engine and full system), i.e. kappa_n times the total length 2nL is 2 pi sqrt(B1B2)/B3."""
    p = json.loads(run_cli(["folded-ring", "--segments", str(n), "--json"]).stdout)
    assert p["lambda_c"] == pytest.approx(2 * math.pi / n, rel=1e-6)
    assert p["lambda_c_full_system"] == pytest.approx(2 * math.pi / n, rel=1e-9)


def test_cli_sweep_writes_csv_and_matches_single_runs(run_cli, tmp_path):
    """Each sweep row equals an independent `analyze` of the design with that value."""
    r = run_cli(["sweep", "examples/clamped_arc.toml", "--vary", "segment.arc.length=1:2:2",
                 "--out", str(tmp_path), "--no-progress", "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    assert (tmp_path / "sweep.csv").exists() and (tmp_path / "sweep.png").exists()
    # length 2 is the file's value; both refine the mesh alike (no [analysis] elements)
    single = json.loads(run_cli(["analyze", "examples/clamped_arc.toml", "--json"]).stdout)
    assert p["rows"][1]["load_factor_critical"] == pytest.approx(
        single["load_factor_critical"], rel=1e-10)


@pytest.mark.parametrize("vary, needle", [("segment.zz.length=1:2:3", "zz"),
                                          ("section.colour=1:2:3", "colour"),
                                          ("section.aspect=1", "KEY=START:STOP[:N]"),
                                          ("section.aspect=1:2:0", "0")])
def test_cli_sweep_bad_vary_one_line(run_cli, vary, needle):
    r = run_cli(["sweep", "examples/clamped_arc.toml", "--vary", vary])
    assert r.exit_code == 2
    assert len(r.stderr.strip().splitlines()) == 1 and needle in r.stderr


# ----------------------------------------------------------------------- --vary grammar


@pytest.mark.parametrize("spec, expected", [
    ("section.aspect=1:4:13", ("section.aspect", 1.0, 4.0, 13)),
    ("load_factor=1:2", ("load_factor", 1.0, 2.0, 7)),
    (" segment.a.length = 0.5 : -2e-1 : 3 ", ("segment.a.length", 0.5, -0.2, 3)),
])
def test_parse_vary_accepts_key_start_stop_and_optional_n(spec, expected):
    v = parse_vary(spec, default_n=7)
    assert (v.key, v.start, v.stop, v.n) == expected


@pytest.mark.parametrize("spec, needles", [
    ("section.aspect", ["KEY=START:STOP[:N]", "'section.aspect'"]),
    ("section.aspect=1", ["KEY=START:STOP[:N]", "'section.aspect=1'"]),
    ("section.aspect=1:2:3:4", ["KEY=START:STOP[:N]", "1:2:3:4"]),
    ("=1:2", ["KEY", "''"]),
    ("  =1:2", ["KEY", "''"]),
    ("section.aspect=abc:2", ["START", "'abc'", "not a number"]),
    ("section.aspect=1:", ["STOP", "''", "not a number"]),
    ("section.aspect=nan:2", ["START", "'nan'", "finite"]),
    ("section.aspect=1:-inf", ["STOP", "'-inf'", "finite"]),
    ("section.aspect=1:2:0", ["N", "'0'", "positive integer"]),
    ("section.aspect=1:2:-3", ["N", "'-3'", "positive integer"]),
    ("section.aspect=1:2:2.5", ["N", "'2.5'", "positive integer"]),
    ("section.aspect=1:2:x", ["N", "'x'", "positive integer"]),
])
def test_parse_vary_errors_name_the_wrong_part(spec, needles):
    with pytest.raises(RodstabInputError) as info:
        parse_vary(spec, default_n=9)
    for needle in needles:
        assert needle in str(info.value), (needle, str(info.value))
