"""Deflated continuation (multistable/diagram.py) and `rodstab diagram`.

Oracles: the clamped straightened rod's buckling load (closed form, eq. 3.9: lambda_c = 2 pi),
reached by the diagram's located index change at 8 and 16 elements with order 2, and its
supercritical pitchfork (the buckled branch exists and is stable above it, below the straight
state's energy, and the straight state snaps onto it); the hexagram's daisy lower limit by the
linear engine (Bloch method, `rodstab hexagram`: 0.942867 at h/t = 4) against the diagram's
band end extrapolated from 6 and 12 elements; closed-form functions for the crossing scan.
"""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from rodstab.multistable import diagram as dg
from rodstab.multistable import diagram_check as dgc
from rodstab.multistable import discover as dv
from rodstab.multistable.identify import Snapshot
from rodstab.problems import straightened_rod as sr


def test_nearest_crossing_finds_the_sign_change_nearest_the_coarse_end():
    """Lower end (stable above): f = p - 0.3; upper end (stable below): f = 0.7 - p."""
    assert dgc._nearest_crossing(lambda p: p - 0.3, 0.35, 0.1, +1) == pytest.approx(0.3, abs=1e-9)
    assert dgc._nearest_crossing(lambda p: 0.7 - p, 0.62, 0.1, -1) == pytest.approx(0.7, abs=1e-9)
    # two crossings in the window: the one nearest the coarse end, of the right sense
    # zeros of cos(10 p) at pi/20 + k pi/10; from 0.5 the nearest, 0.471, turns positive
    # upwards, so the upper end (positive below) is the next one, pi/4
    got = dgc._nearest_crossing(lambda p: math.cos(10 * p), 0.5, 0.1, -1)
    assert got == pytest.approx(math.pi / 4, abs=1e-9)
    assert dgc._nearest_crossing(lambda p: 1.0 + p * 0, 0.5, 0.1, +1) is None  # none: None


def _point(value: float, index: int) -> dg.BranchPoint:
    return dg.BranchPoint(value, 0.0, index, False, 0.0, True, 0.0, 0.0, 0)


def test_bands_end_at_the_located_index_changes_and_at_the_range():
    b = dg._Branch("x", "seed", {v: (None, _point(v, i)) for v, i in
                                 ((0.0, 2), (0.1, 0), (0.2, 0), (0.3, 1), (0.4, 0))})
    specials = [dg.SpecialPoint("index change", 0, 0.07, (0.0, 0.1), 2, 0, ()),
                dg.SpecialPoint("index change", 0, 0.26, (0.2, 0.3), 0, 1, ())]
    # the last change is not located: its bracket's midpoint
    assert dg._bands(b, specials, 0) == ((0.07, 0.26), (0.35, 0.4))


@pytest.mark.slow
def test_straightened_rod_buckling_load_and_its_pitchfork():
    """The diagram of the clamped straightened rod in mu = kappa_n L / ...: lambda_c = 2 pi."""
    p = sr.Params()
    mu_c = 2 * math.pi / sr.to_paper(1.0, p)["lambda"]  # eq. (3.9)
    located = []
    for n in (8, 16):
        rod = dv.common_rod(sr.build(p), n, 0.8 * mu_c)
        d = dg.deflated_diagram(rod, [("straight", Snapshot.of(rod))], [],
                                list(np.linspace(0.8 * mu_c, 1.2 * mu_c, 5)), starts=0)
        straight = d.branches[0]
        assert [q.index for q in straight.points] == [0, 0, 0, 1, 1]
        (sp,) = [s for s in d.special_points if s.branch == 0]
        located.append(sp.value)
        # the switch search found the buckled branch beyond mu_c: stable, below the straight
        assert sp.branches, "no branch found at the straight rod's branch point"
        buckled = d.branches[sp.branches[0]]
        assert all(q.index == 0 and q.value > mu_c for q in buckled.points)
        top = buckled.points[-1]
        assert top.value == pytest.approx(1.2 * mu_c)
        assert top.energy < straight.points[-1].energy
        assert buckled.begins.startswith("ends between")  # it joins the straight branch
        # past mu_c the straight rod snaps, pushed either way, onto the buckled branch (its
        # mirror is the same state), releasing the energy between the two there
        (snap,) = d.snaps
        assert snap.lands_on == (buckled.id, buckled.id)
        past = [q for q in straight.points if q.value == snap.from_value][0]
        low = [q for q in buckled.points if q.value == snap.from_value][0]
        assert snap.energy_drop == pytest.approx((past.energy - low.energy,) * 2, rel=1e-6)
    e8, e16 = (x - mu_c for x in located)
    assert 3.5 < e8 / e16 < 4.5  # order 2
    assert located[1] + (located[1] - located[0]) / 3 == pytest.approx(mu_c, rel=1e-3)


@pytest.mark.slow
def test_cli_writes_the_diagram_and_its_daisy_band_agrees_with_the_atlas(run_cli, tmp_path):
    r = run_cli(["diagram", "--shape", "rectangle", "--aspect", "4", "--vary",
                 "load_factor=0.9:1.1:2", "--elements", "6", "--starts", "0", "--out",
                 tmp_path / "d", "--no-progress", "--json"])
    assert r.exit_code == 0, r.stderr
    out = json.loads(r.stdout)
    labels = {b["label"] for b in out["branches"]}
    assert {"line", "star", "daisy", "eight"} <= labels
    (daisy,) = [e for e in out["band_ends"] if e["state"] == "daisy"]
    assert daisy["atlas"] == pytest.approx(0.942867, abs=1e-6)  # rodstab hexagram
    assert daisy["agrees"] is True
    assert abs(daisy["extrapolated"] - daisy["atlas"]) < 0.1 * daisy["mesh_error"]
    with (tmp_path / "d" / "branches.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == sum(len(b["points"]) for b in out["branches"])
    assert (tmp_path / "d" / "diagram.png").stat().st_size > 10_000


@pytest.mark.parametrize("args, words", [
    (["--vary", "segment.a.natural_curvature=0:1"], ["segment.a.natural_curvature",
                                                      "load_factor or segment.<name>.length"]),
    (["--vary", "load_factor=0:1:4", "--load-factor", "2"], ["--load-factor 2.0",
                                                              "segment.NAME.length"]),
    (["--vary", "segment.9.length=1:1.1:2"], ["segment '9' is not in the design"]),
    (["--vary", "load_factor=0:1:4", "--saddles-at", "0.3"], ["--saddles-at", "0.3",
                                                              "not a value"]),
    (["--vary", "load_factor=0:1:4", "--saddles-at", "x"], ["--saddles-at", "'x'"]),
    (["--vary", "load_factor=0:1:4", "--saddle-modes", "0"], ["--saddle-modes", "0"]),
    (["--vary", "load_factor=0:1:4", "--max-barrier", "-1"], ["--max-barrier", "-1"]),
    (["--vary", "load_factor=0:1:4", "--starts", "-2"], ["--starts", "-2"]),
    (["--vary", "load_factor=1:1:4"], ["load_factor=1:1:4", "must differ"]),
])
def test_bad_input_exits_2_naming_it(run_cli, tmp_path, args, words):
    r = run_cli(["diagram", *args, "--out", tmp_path / "d"])
    assert r.exit_code == 2, r.stdout + r.stderr
    for w in words:
        assert w in r.stderr


@pytest.mark.slow
def test_hexagram_line_star_saddle_is_traced_as_a_branch():
    """The saddle search at kappa_n R0 = 1 finds the line-star saddle (14.2795 B3/L at 8 el.,
    the string method's: `rodstab barrier --from line --to star --load-factor 1 --elements 8`)
    and the diagram traces it over the grid (stepping stones and the tangent predictor: a
    plain Newton step from it fails at 1.01)."""
    from rodstab.multistable.discover import ring_seeds
    from rodstab.problems import hexagram
    from rodstab.sections import rectangle

    ring = hexagram.ring(rectangle(aspect=4))
    rod, seeds, known = ring_seeds(ring, "star", 8, 0.8, True)
    d = dg.deflated_diagram(rod, seeds, known, [0.8, 0.9, 1.0, 1.1, 1.2], starts=0,
                            directions=tuple(x for _, x in ring.order), saddles_at=[1.0],
                            saddle_modes=3, max_rise=3.0)
    (search,) = d.saddle_searches
    (saddle,) = [s for s in search["saddles"] if abs(s["energy"] - 14.2795) < 5e-5]
    b = d.branches[saddle["branch"] - 1]
    assert [q.value for q in b.points] == pytest.approx([0.8, 0.9, 1.0, 1.1, 1.2])
    assert all(q.index == 1 and not q.planar for q in b.points)
    assert b.begins == b.ends == "range"


@pytest.mark.slow
def test_birod_diagram_band_agrees_with_analyze_and_the_buckled_branch_is_found(run_cli,
                                                                                tmp_path):
    """examples/birod.toml (Section 4: natural curvatures +-1, held straight, welded at both
    ends, one end clamped) is no ring: its held state is the one seed. The held branch's
    upper band end at 8 / 16 el., extrapolated, agrees with the linear engine on the design
    (`rodstab analyze examples/birod.toml`: 2.7207, lam = pi); past it the held state snaps
    onto a non-planar branch below it, which the diagram then follows (deflated Newton with
    the retraction, tests/test_discover.py)."""
    r = run_cli(["diagram", "examples/birod.toml", "--vary", "load_factor=2.6:3.0:4",
                 "--elements", "8", "--starts", "0", "--out", tmp_path / "d", "--no-progress",
                 "--json"])
    assert r.exit_code == 0, r.stderr
    out = json.loads(r.stdout)
    (end,) = [e for e in out["band_ends"] if e["state"] == "held"]
    assert end["side"] == "upper" and end["atlas"] == pytest.approx(2.7207, abs=1e-4)
    assert end["agrees"] is True
    held = next(b for b in out["branches"] if b["label"] == "held")
    buckled = [b for b in out["branches"] if b["label"] == "unnamed"
               and all(not p["planar"] and p["index"] == 0 for p in b["points"])]
    assert buckled and len(buckled[0]["points"]) >= 2  # followed, not one point
    at = {p["value"]: p["energy"] for p in held["points"]}
    assert all(p["energy"] < at[p["value"]] for p in buckled[0]["points"])
    (snap,) = out["snaps"]
    assert snap["lands_on"][0] == buckled[0]["id"]


@pytest.mark.slow
def test_the_diagrams_snap_is_the_transition_and_both_converge_to_the_atlas(run_cli, tmp_path):
    """Issue 22, section 3: where the star's stable branch ends, the diagram snaps onto the
    daisy, as `rodstab transitions` does; the two discrete models differ (the transition's is
    built from the held geometry), so their thresholds differ by the mesh error (1.9e-3 at 8 el.,
    4.6e-4 at 16), and both, extrapolated in h^2 from 8 and 16 el., reach the Bloch/FE atlas's
    upper end of the star, 2.357247 (rectangle h/t = 4, docs/guide/multistable.md)."""
    ends: dict[str, list[float]] = {"diagram": [], "transitions": []}
    for n in (8, 16):
        r = run_cli(["diagram", "examples/hexagram.toml", "--vary", "load_factor=2.3:2.4:3",
                     "--elements", str(n), "--starts", "0", "--out", tmp_path / f"d{n}",
                     "--no-progress", "--json"])
        assert r.exit_code == 0, r.stderr
        d = json.loads(r.stdout)
        label = {b["id"]: b["label"] for b in d["branches"]}
        (snap,) = [s for s in d["snaps"] if label[s["branch"]] == "star"]
        assert {label[b] for b in snap["lands_on"]} == {"daisy"}
        ends["diagram"].append(snap["value"])
        t = run_cli(["transitions", "examples/hexagram.toml", "--elements", str(n), "--state",
                     "star", "--json"])
        assert t.exit_code == 0, t.stderr
        (edge,) = [e for e in json.loads(t.stdout)["edges"]
                   if e["from"] == "star" and e["stimulus"] == "load_factor"]
        assert edge["to"] == "daisy"
        ends["transitions"].append(edge["threshold"])
    for coarse, fine in ends.values():
        assert abs(fine - 2.357247) < abs(coarse - 2.357247)  # converging
        assert fine + (fine - coarse) / 3 == pytest.approx(2.357247, abs=1e-4)
