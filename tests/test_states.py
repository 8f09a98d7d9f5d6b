"""rodstab.states: the closed held states of a ring of welded rods against closed forms.

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
from rodstab.states import closed_states, ring_assembly, state_turning


def _order(psi: float, n: int) -> int:
    """Smallest p >= 1 with p psi = 0 (mod 2 pi) (psi a multiple of 2 pi / n)."""
    return next(p for p in range(1, n + 1)
                if abs(math.remainder(p * psi, 2 * math.pi)) < 1e-9)


def _closed_form(n: int, weld: str, max_turns: float = 1.0) -> list[tuple[float, int, int]]:
    """(theta, distinct weld points, covering) of every closed state, by the closure rules."""
    out = []
    offset = math.pi if weld == "cusp" else 0.0
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


def test_state_turning_names_the_missing_state():
    assert state_turning(6, "cusp", "daisy") == pytest.approx(4 * math.pi / 3)
    with pytest.raises(RodstabInputError, match="'tulip'"):
        state_turning(6, "cusp", "tulip")


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
