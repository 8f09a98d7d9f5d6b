"""rodstab.multistable.states: the closed held states of a ring of welded rods against closed forms.

Closed forms (derived in the module docstring): a state turns each rod by ``theta`` with
``n psi = 0 (mod 2 pi)``, ``psi = theta + pi`` (cusps) or ``theta`` (smooth), and closes in
position when ``exp(i psi) != 1`` or ``theta = 2 pi m != 0``. Its weld points are the distinct
vertices of the chord polygon: ``n / order(exp(i psi))`` rods lie on each oriented rod, and the
welds of a full-circle state (``theta = 2 pi m``) all lie at one point.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rodstab.cli import main
from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design, parse_design
from rodstab.model import Assembly
from rodstab.multistable.states import closed_states, ring_assembly, ring_of, uniform_ring


def _order(psi: float, n: int) -> int:
    """Smallest p >= 1 with p psi = 0 (mod 2 pi) (psi a multiple of 2 pi / n)."""
    return next(p for p in range(1, n + 1)
                if abs(math.remainder(p * psi, 2 * math.pi)) < 1e-9)


def _closed_form(n: int, weld: str | float, max_turns: float = 1.0
                 ) -> list[tuple[float, int, int]]:
    """(theta, distinct weld points, covering) of every closed state, by the closure rules."""
    out = []
    offset = {"cusp": math.pi, "smooth": 0.0}.get(weld, weld)  # type: ignore[arg-type]
    for j in range(-4 * n, 4 * n + 1):
        theta = 2 * math.pi * j / n - offset
        if abs(theta) > 2 * math.pi * max_turns + 1e-9:
            continue
        psi = theta + offset
        full_circle = abs(math.remainder(theta, 2 * math.pi)) < 1e-9 and abs(theta) > 1e-9
        if abs(math.remainder(psi, 2 * math.pi)) < 1e-9 and not full_circle:
            continue  # chords all parallel and non-zero: the chain does not close
        p = _order(psi, n)
        welds = 1 if full_circle else p
        out.append((theta, welds, n // p))
    return sorted(out)


@pytest.mark.parametrize("n,weld", [(4, "cusp"), (6, "cusp"), (8, "cusp"), (3, "cusp"),
                                    (2, "cusp"), (4, "smooth"), (6, "smooth"), (1, "smooth")])
def test_enumerated_states_are_the_closed_form_ones(n, weld):
    """Thetas, distinct weld points and covering equal the closure rules' (module docstring)."""
    r = closed_states(n, weld=weld)
    got = [(s.theta, s.distinct_weld_points, s.covering) for s in r.states]
    want = _closed_form(n, weld)
    assert len(got) == len(want), (got, want)
    for (t1, w1, c1), (t2, w2, c2) in zip(got, want, strict=True):
        assert t1 == pytest.approx(t2, abs=1e-12) and (w1, c1) == (w2, c2)
    for s in r.states:
        assert s.closure_gap < 1e-12
        assert s.turning_number == pytest.approx(n * s.theta / (2 * math.pi))


def test_hexagram_has_the_four_named_states_and_their_mirrors():
    """Six cusp-welded rods: line 0, star 120, daisy 240, eight 360 deg; star and daisy have
    six weld points, the line two, the eight one; 60 and 300 deg cover a 3-rod ring twice."""
    by_label = {s.label: s for s in closed_states(6, weld="cusp").states}
    expect = {"line": (0, 2, 3), "star": (120, 6, 1), "daisy": (240, 6, 1), "eight": (360, 1, 3),
              "theta=60deg": (60, 3, 2), "theta=300deg": (300, 3, 2)}
    for label, (deg, welds, cover) in expect.items():
        s = by_label[label]
        assert math.degrees(s.theta) == pytest.approx(deg)
        assert (s.distinct_weld_points, s.covering) == (welds, cover)
        assert s.mirror in by_label and by_label[s.mirror].theta == pytest.approx(-s.theta)
    assert len(by_label) == 11  # 5 mirror pairs and the line; 180 deg does not close


def test_energy_is_half_b3_k_minus_kappa_squared_per_rod():
    """E = n B3 (k - kappa_n)^2 L / 2: zero for the star at kappa_n = 2 pi / (3 L)."""
    L = 2.0
    kn = 2 * math.pi / (3 * L)
    r = closed_states(6, length=L, natural_curvature=kn, B3=3.0)
    for s in r.states:
        assert s.energy == pytest.approx(0.5 * 6 * 3.0 * (s.theta / L - kn) ** 2 * L)
    assert {s.label: s.energy for s in r.states}["star"] == pytest.approx(0.0, abs=1e-12)


def test_every_state_builds_a_valid_assembly_and_an_open_chain_is_refused():
    """model.validate accepts each state's welds; 180-degree cusp arcs do not close."""
    for s in closed_states(8, weld="cusp").states:
        a = ring_assembly(8, s.theta)
        assert len(a.welds) == 8
    with pytest.raises(RodstabInputError, match="do not meet"):
        ring_assembly(6, math.pi)


@pytest.mark.parametrize("kwargs,name", [
    ({"segments": 1, "weld": "cusp"}, "segments 1"), ({"segments": 0}, "segments"),
    ({"segments": 6, "weld": "glued"}, "glued"), ({"segments": 6, "max_turns": 0.0}, "max_turns"),
    ({"segments": 6, "max_turns": math.nan}, "max_turns"),
])
def test_bad_rings_are_refused_naming_the_value(kwargs, name):
    n = kwargs.pop("segments")
    with pytest.raises(RodstabInputError, match=name):
        closed_states(n, **kwargs)


def test_ring_state_names_the_missing_state():
    assert uniform_ring(6).state("daisy").theta == pytest.approx(4 * math.pi / 3)
    with pytest.raises(RodstabInputError, match="'tulip'"):
        uniform_ring(6).state("tulip")


def test_cli_states_json_and_plot(capsys, tmp_path):
    png = tmp_path / "states.png"
    main(["states", "--segments", "4", "--json", "--plot", str(png)])
    out = json.loads(capsys.readouterr().out)
    labels = [s["label"] for s in out["states"]]
    assert {"line", "star", "daisy", "eight"} <= set(labels)
    for row in out["states"]:
        assert set(row) >= {"label", "held_curvature", "turning_number", "distinct_weld_points",
                            "energy"}
    assert png.stat().st_size > 0


@pytest.mark.parametrize("argv,name", [
    (["--segments", "1"], "segments 1"), (["--segments", "0"], "segments"),
    (["--segments", "-2", "--smooth"], "segments"), (["--max-turns", "-1"], "max_turns"),
    (["--length", "0"], "length"),
])
def test_cli_states_bad_input_exits_2_naming_the_value(capsys, argv, name):
    with pytest.raises(SystemExit) as exc:
        main(["states", *argv, "--json"])
    assert exc.value.code == 2
    err = capsys.readouterr()
    assert err.out == "" and name in err.err and len(err.err.strip().splitlines()) == 1


def test_chain_positions_match_the_chord_sum():
    """The assembly's weld points are the partial sums of chords rotated by psi (daisy)."""
    theta = 4 * math.pi / 3
    a = ring_assembly(6, theta)
    chord = np.sinc(0.5 * theta / math.pi)
    psi = theta + math.pi
    pts = np.cumsum([chord * np.exp(1j * (i * psi + 0.5 * theta)) for i in range(6)])
    got = np.array([complex(*a.segment(str(i + 1)).end_point("end")) for i in range(6)])
    assert np.allclose(got, pts, atol=1e-12)


@pytest.mark.parametrize("n,alpha", [(3, math.pi / 3), (5, -1.0), (4, 2.5)])
def test_welds_at_any_angle_follow_the_closure_rules(n, alpha):
    """A weld turning the tangent by alpha: theta = 2 pi j / n - alpha, the same rules."""
    r = uniform_ring(n, weld=alpha).states()
    got = [(s.theta, s.distinct_weld_points, s.covering) for s in r.states]
    want = _closed_form(n, alpha)
    assert len(got) == len(want) > 0
    for (t1, w1, c1), (t2, w2, c2) in zip(got, want, strict=True):
        assert t1 == pytest.approx(t2, abs=1e-12) and (w1, c1) == (w2, c2)
    assert r.weld == f"{math.degrees(alpha):.6g}deg"


def _design_geometry(a: Assembly) -> list[tuple]:
    """Each segment's name, end points, end tangents and natural curvature."""
    out = []
    for s in a.segments:
        out.append((s.name, *s.end_point("start"), *s.end_point("end"), *s.tangent(0.0),
                    *s.tangent(s.length), s.natural_curvature))
    return out


def test_the_folded_six_ring_design_is_a_ring_of_identical_cusp_welded_rods():
    """examples/folded_six_ring.toml: alternately oriented rods with natural curvature -1/+1
    are, along the ring, six identical rods of natural curvature +1 (the ring runs backwards
    through the rods the file curves negatively) at cusps; held straight (theta = 0) the ring
    rebuilt from its topology is the design's own geometry, rod by rod."""
    a = load_design("examples/folded_six_ring.toml").assembly
    ring = ring_of(a)
    assert (ring.segments, ring.weld, ring.natural_curvature) == (6, "cusp", 1.0)
    assert dict(ring.order) == {"s1": -1, "s2": 1, "s3": -1, "s4": 1, "s5": -1, "s6": 1}
    rebuilt = ring.held(0.0)
    # the same geometry modulo a rigid motion: turn and shift rod s1 onto the design's
    mine, theirs = rebuilt.segment("s1"), a.segment("s1")
    turn = math.atan2(*theirs.tangent(0.0)[::-1]) - math.atan2(*mine.tangent(0.0)[::-1])
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    p0, q0 = mine.end_point("start"), theirs.end_point("start")
    for m in rebuilt.segments:
        t = a.segment(m.name)
        assert m.natural_curvature == t.natural_curvature and m.curvature == t.curvature
        for end, s in (("start", 0.0), ("end", m.length)):
            np.testing.assert_allclose(rot @ (m.end_point(end) - p0) + q0, t.end_point(end),
                                       atol=1e-12)
            np.testing.assert_allclose(rot @ m.tangent(s), t.tangent(s), atol=1e-12)
    # the one-loop state (Fig. 10): the star, stress-free at kappa_n L = 2 pi / 3
    star = ring.state("star")
    assert ring.stress_free_load(star.theta) == pytest.approx(2 * math.pi / 3)


def test_a_hexagram_read_back_is_its_own_ring():
    a = ring_assembly(6, 2 * math.pi / 3, natural_curvature=0.5, B1=2.0, B2=0.7)
    ring = ring_of(a)
    assert ring == uniform_ring(6, weld="cusp", natural_curvature=0.5, B1=2.0, B2=0.7)
    assert _design_geometry(ring.held(2 * math.pi / 3)) == _design_geometry(a)


def _ring_design(theta: float = 2 * math.pi / 3) -> dict:
    """A design dict of the hexagram held at ``theta`` (rods 1..6 welded end to start, cusps)."""
    a = ring_assembly(6, theta, natural_curvature=1.0)
    segs = []
    for s in a.segments:
        segs.append({"name": s.name, "length": s.length, "curvature": s.curvature,
                     "natural_curvature": s.natural_curvature, "start": list(s.start),
                     "angle_deg": math.degrees(s.angle)})
    welds = [{"ends": [f"{w[0][0]}.{w[0][1]}", f"{w[1][0]}.{w[1][1]}"]} for w in a.welds]
    return {"section": {"shape": "circle"}, "segment": segs, "weld": welds}


def test_a_star_design_dict_reads_as_the_hexagram():
    ring = ring_of(parse_design(_ring_design()).assembly)
    assert (ring.segments, ring.weld, ring.natural_curvature) == (6, "cusp", 1.0)


@pytest.mark.parametrize("edit,name", [
    (lambda d: [d["weld"].pop()] + [g.update(natural_curvature=0.0) for g in d["segment"]],
     "is not welded"),
    (lambda d: d.update(support=[{"end": "1.start"}]), "no supports"),
])
def test_designs_that_are_not_rings_are_refused_naming_the_value(edit, name):
    d = _ring_design(0.0)  # the line: no held moment, so an open chain is a valid design
    edit(d)
    with pytest.raises(RodstabInputError, match=name):
        ring_of(parse_design(d).assembly)


def test_a_rod_of_another_section_is_read_and_the_bloch_method_refuses_it_naming_it():
    d = _ring_design(0.0)
    d["segment"][2].update(section={"shape": "circle", "nu": 0.2})
    ring = ring_of(parse_design(d).assembly)
    assert not ring.identical and "segment '3' has B2" in ring.difference()
    from rodstab.multistable.atlas import bloch_interval

    with pytest.raises(RodstabInputError, match="Bloch method .* identical rods.*segment '3'"):
        bloch_interval(ring, 0.0)


def test_rods_of_other_lengths_and_welds_of_other_angles_are_read_as_rings():
    """A right triangle's rods differ in length; a rhombus of straight rods turns its tangent
    by 60 and 120 degrees at alternate welds: both are rings whose rods or welds differ, and
    each holds its own straight state (mean turning 0: the rotation closure n theta + sum of
    the weld turns = 2 pi j holds with j = 1, the chords are the polygon's sides)."""
    segs = [{"name": "a", "length": 1.0, "curvature": 0.0, "start": [0.0, 0.0], "angle_deg": 0},
            {"name": "b", "length": 1.0, "curvature": 0.0, "start": [1.0, 0.0], "angle_deg": 90},
            {"name": "c", "length": math.sqrt(2.0), "curvature": 0.0, "start": [1.0, 1.0],
             "angle_deg": 225}]
    welds = [{"ends": ["a.end", "b.start"]}, {"ends": ["b.end", "c.start"]},
             {"ends": ["c.end", "a.start"]}]
    a = parse_design({"section": {"shape": "circle"}, "segment": segs, "weld": welds}).assembly
    ring = ring_of(a)
    assert "length" in ring.difference()
    assert [round(math.degrees(t), 9) for t in ring.turns] == [90.0, 135.0, 135.0]
    straight = [st for st in ring.states().states if st.theta == 0.0]
    assert len(straight) == 1 and straight[0].distinct_weld_points == 3
    segs = [{"name": "a", "length": 1.0, "curvature": 0.0, "start": [0.0, 0.0], "angle_deg": 0},
            {"name": "b", "length": 1.0, "curvature": 0.0, "start": [1.0, 0.0], "angle_deg": 60},
            {"name": "c", "length": 1.0, "curvature": 0.0, "start": [1.5, math.sqrt(3) / 2],
             "angle_deg": 180},
            {"name": "d", "length": 1.0, "curvature": 0.0, "start": [0.5, math.sqrt(3) / 2],
             "angle_deg": 240}]
    welds = [{"ends": [f"{p}.end", f"{q}.start"]} for p, q in ("ab", "bc", "cd", "da")]
    a = parse_design({"section": {"shape": "circle"}, "segment": segs, "weld": welds}).assembly
    ring = ring_of(a)
    assert "turns the tangent by 120 deg, weld 1 by 60 deg" in ring.difference()
    assert ring.weld_label == "mixed (60, 120, 60, 120 deg)"
    assert [st.label for st in ring.states().states if st.theta == 0.0] == ["theta=0deg"]


def test_cli_states_from_a_design_file(capsys):
    """The folded six-ring: its one-loop state is the star, free at kappa_n L = 2 pi / 3; the
    energy at the design's load 1 of the line is 6 x (0 - 1)^2 / 2 = 3."""
    main(["states", "examples/folded_six_ring.toml", "--json"])
    out = json.loads(capsys.readouterr().out)
    rows = {r["label"]: r for r in out["states"]}
    assert rows["line"]["energy"] == pytest.approx(3.0)
    assert rows["star"]["stress_free_load"] == pytest.approx(2 * math.pi / 3)
    assert out["weld"] == "cusp" and out["segments"] == 6


@pytest.mark.parametrize("argv,name", [
    (["examples/folded_six_ring.toml", "--segments", "4"], "--segments"),
    (["--load-factor", "2"], "--load-factor 2.0"),
    (["examples/birod.toml"], "support"),
])
def test_cli_states_design_misuse_exits_2(capsys, argv, name):
    with pytest.raises(SystemExit) as exc:
        main(["states", *argv, "--json"])
    assert exc.value.code == 2
    assert name in capsys.readouterr().err


def test_ring_of_takes_a_loaded_design_and_names_what_it_needs():
    """``ring_of(load_design(...))`` reads the design's assembly (it raised a bare
    AttributeError); anything else is an input error naming what it needs (issue 20)."""
    from pathlib import Path

    from rodstab.io.design import load_design
    from rodstab.multistable.states import ring_of as read

    d = load_design(Path(__file__).resolve().parent.parent / "examples" / "hexagram.toml")
    assert read(d) == read(d.assembly)
    with pytest.raises(RodstabInputError, match="needs an Assembly or a design"):
        read("examples/hexagram.toml")


# ---------------------------------------------------------------------------------------------
# Rings whose rods differ (issue 22, section 4)
def _unequal(lengths, B3=None, kappa_b3=2 * math.pi / 3):
    """The hexagram's ring with rods of ``lengths`` (and ``B3``), ``B3 x kappa_n`` equal."""
    import dataclasses

    base = uniform_ring(len(lengths), natural_curvature=2 * math.pi / 3)
    B3 = [1.0] * len(lengths) if B3 is None else B3
    rods = tuple(dataclasses.replace(r, length=L, B3=b, natural_curvature=kappa_b3 / b)
                 for r, L, b in zip(base.rods, lengths, B3, strict=True))
    return dataclasses.replace(base, rods=rods)


def test_the_alternating_hexagram_closes_where_three_repeats_of_a_pair_close():
    """Rods of 1.45 and 0.55 alternating, one curvature k, cusps: the pair of rods turns the
    tangent by 2 k + 2 pi, so three pairs close in rotation for every k and in position when
    exp(2 i k) is a cube root of unity other than 1 (the three chords then sum to zero):
    2 k = 2 pi j / 3, j not a multiple of 3, i.e. mean turning k = 60 j degrees. At j = 0, 3, 6
    each pair's chord must vanish, and 1.45 - 0.55 != 0 (the line) and the arcs' chords
    (the eight, the 180-degree state) do not: those states are missing."""
    ring = _unequal([1.45, 0.55] * 3)
    got = sorted(round(math.degrees(s.theta), 9) for s in ring.states().states)
    assert got == [60.0 * j for j in range(-6, 7) if j % 3]
    assert {s.label for s in ring.states().states} >= {"star", "daisy", "mirror-star"}


def test_rods_of_other_sections_turn_by_c_over_b3_and_the_energy_is_the_rods_sum():
    """B3_i k_i = c and B3_i kappa_n,i = d in every rod (moment balance at every weld): the
    energy is sum_i B3_i (k_i - mu kappa_n,i)^2 L_i / 2 over the built assembly, zero at the
    stress-free load c / d; the assembly validates (every weld balanced)."""
    # B3 proportional to length keeps every k_i L_i = c L_i / B3_i equal: it closes like the
    # identical ring, its rods alternating in length, stiffness and natural curvature
    ring = _unequal([1.5, 0.5] * 3, B3=[3.0, 1.0] * 3)
    assert not ring.identical
    states = {s.label: s for s in ring.states(load_factor=1.3).states}
    star = states["star"]
    a = ring.held(star.theta)
    turns = [s.curvature * s.length for s in a.segments]
    assert turns == pytest.approx([2 * math.pi / 3] * 6, rel=1e-12)
    energy = sum(0.5 * s.B3 * (s.curvature - 1.3 * s.natural_curvature) ** 2 * s.length
                 for s in a.segments)
    assert star.energy == pytest.approx(energy, rel=1e-12)
    free = ring.stress_free_load(star.theta)
    assert all(s.curvature == pytest.approx(free * s.natural_curvature, rel=1e-12)
               for s in a.segments)


def test_a_ring_with_one_longer_rod_has_no_state_of_uniform_moment_and_says_so():
    """One rod 10 % longer: the rotation closure fixes k, the chords cannot sum to zero."""
    ring = _unequal([1.1, 1.0, 1.0, 1.0, 1.0, 1.0])
    with pytest.raises(RodstabInputError, match="no planar held state of uniform moment.*"
                                                "elasticas, for the nonlinear engine"):
        ring.states()


def test_cli_states_of_the_unequal_hexagram_example(capsys):
    main(["states", "examples/hexagram_unequal.toml", "--json"])
    out = json.loads(capsys.readouterr().out)
    rows = {r["label"]: r for r in out["states"]}
    assert "line" not in rows and "eight" not in rows
    assert rows["star"]["rod_turnings_deg"] == pytest.approx([174.0, 66.0] * 3)
    assert "segment 'r2' has length 0.55" in out["rods_differ"]
