"""Physical units (issue 13, part 1): quantities in design files, results in SI.

Reference numbers are closed forms: B3 = E I3 of the section (I3 = pi d^4/64 of a circle,
h t^3/12 of a rectangle), the bi-rod's limit lam_c = B3 kappa_n L / sqrt(B1 B2) = pi of this
project (docs/differences.md, "Section 4"; the paper prints 2 pi), i.e.
psi_c = pi sqrt(b1 b2)/2 with sqrt(b1 b2) = 1/sqrt(1 + nu) for a circle, and the folded
six-sided ring's lam_c = pi/3.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design, parse_design
from rodstab.io.vary import axis_label, axis_unit, model_value, parse_vary, vary_in_units
from rodstab.linear.solve import linear_stability
from rodstab.sections import rectangle
from rodstab.units import as_built, parse_quantity

ROOT = Path(__file__).resolve().parent.parent
FIG7A = str(ROOT / "examples" / "steel_birod_fig7a.toml")
FIG7B = str(ROOT / "examples" / "steel_birod_fig7b.toml")
SIX_RING = str(ROOT / "examples" / "steel_strip_six_ring.toml")
HEXAGRAM = str(ROOT / "examples" / "hexagram_strip.toml")
#: FE of the bi-rod at 32 elements per segment: lam_c within 1.3e-7 of pi (measured margin 8x).
FE_RTOL = 1e-6


def _rod(section: str = 'diameter = "2 mm"', material: str = 'E = "200 GPa"\nnu = 0.3',
         segment: str = 'length = "100 mm"\nnatural_curvature = "40 1/m"') -> dict:
    """A clamped straight rod with units, as parsed TOML."""
    import tomllib

    return tomllib.loads(f"[material]\n{material}\n[section]\n{section}\n"
                         f'[[segment]]\nname = "rod"\n{segment}\n'
                         '[[support]]\nend = "rod.start"\ntype = "clamped"\n'
                         '[[support]]\nend = "rod.end"\ntype = "sliding-clamp"\n')


# --------------------------------------------------------------------------- conversions


@pytest.mark.parametrize("text, kind, si", [
    ("235.6 mm", "length", 0.2356), ("1 in", "length", 0.0254), ("2.5e-1m", "length", 0.25),
    ("13.3 1/m", "curvature", 13.3), ("0.5 1/mm", "curvature", 500.0),
    ("200 GPa", "modulus", 200e9), ("1 N/mm^2", "modulus", 1e6),
    ("0.06 N*m^2", "stiffness", 0.06), ("60 N*mm^2", "stiffness", 6e-5),
    ("180 deg", "angle", math.pi), ("0.5", "angle", 0.5)])
def test_quantities_convert_to_si(text, kind, si):
    assert parse_quantity(text, "k", kind).si == pytest.approx(si, rel=1e-12)


def test_circle_b3_is_e_pi_d4_over_64():
    """Circle d = 2 mm, E = 200 GPa: B3 = E pi d^4/64 = 0.157080 N m^2, B1 = B3, B2 = B3/(1+nu)
    (paper, Section 3.1); the model is in units of the segment's L and B3."""
    d = parse_design(_rod())
    B3 = 200e9 * math.pi * 0.002**4 / 64
    assert d.units.stiffness == pytest.approx(B3, rel=1e-12)
    assert d.units.length == pytest.approx(0.1, rel=1e-15)
    s = d.assembly.segments[0]
    assert (s.length, s.B3, s.B1) == (pytest.approx(1.0), pytest.approx(1.0), pytest.approx(1.0))
    assert s.B2 == pytest.approx(1 / 1.3, rel=1e-12)
    assert s.natural_curvature == pytest.approx(40 * 0.1, rel=1e-12)  # kappa_n L


def test_rectangle_tube_and_shear_modulus_give_their_closed_forms():
    """Rectangle h = 5 mm out of the plane, t = 0.5 mm in it: B3 = E h t^3/12, B1/B3 = (h/t)^2
    (not the other way round); tube: B3 = E pi (do^4 - di^4)/64; G = 80 GPa with E = 200 GPa
    is nu = E/(2G) - 1 = 0.25, so a circle's B2/B3 = 1/1.25."""
    d = parse_design(_rod('shape = "rectangle"\nheight = "5 mm"\nthickness = "0.5 mm"'))
    assert d.units.stiffness == pytest.approx(200e9 * 5e-3 * 0.5e-3**3 / 12, rel=1e-12)
    assert d.assembly.segments[0].B1 == pytest.approx(100.0, rel=1e-12)
    d = parse_design(_rod('shape = "tube"\nouter_diameter = "4 mm"\ninner_diameter = "3 mm"'))
    assert d.units.stiffness == pytest.approx(200e9 * math.pi * (0.004**4 - 0.003**4) / 64,
                                              rel=1e-12)
    d = parse_design(_rod(material='E = "200 GPa"\nG = "80 GPa"'))
    assert d.units.nu == pytest.approx(0.25, rel=1e-12)
    assert d.assembly.segments[0].B2 == pytest.approx(0.8, rel=1e-12)


def test_natural_radius_is_one_over_natural_curvature():
    a = parse_design(_rod(segment='length = "100 mm"\nnatural_radius = "-25 mm"')).assembly
    b = parse_design(_rod(segment='length = "100 mm"\nnatural_curvature = "-40 1/m"')).assembly
    assert a.segments[0].natural_curvature == pytest.approx(b.segments[0].natural_curvature,
                                                            rel=1e-15)
    plain = parse_design({"segment": [{"name": "r", "length": 1.0, "natural_radius": 0.5}],
                          "support": [{"end": "r.start"}, {"end": "r.end"}]})
    assert plain.units is None and plain.assembly.segments[0].natural_curvature == 2.0


def test_a_design_with_units_is_the_equivalent_plain_design():
    """Scale invariance: Fig. 7a in mm and GPa is solved as the plain bi-rod with L = 1,
    natural curvature 2 psi = pi/2, circle nu = 0.3 (segments equal to round-off), and gives
    its critical load factor; a 10x larger bi-rod in cm of another E has the same load factor
    and a 10x smaller critical natural curvature."""
    d = load_design(FIG7A)
    plain = parse_design({
        "section": {"shape": "circle", "nu": 0.3},
        "segment": [{"name": "upper", "length": 1.0, "natural_curvature": math.pi / 2},
                    {"name": "lower", "length": 1.0, "natural_curvature": -math.pi / 2,
                     "start": [0.0, 0.0], "angle_deg": 0.0}],
        "weld": [{"ends": ["upper.start", "lower.start"]}, {"ends": ["upper.end", "lower.end"]}],
        "support": [{"end": "upper.start"}]})
    for s, p in zip(d.assembly.segments, plain.assembly.segments, strict=True):
        for key in ("length", "natural_curvature", "B1", "B2", "B3"):
            assert getattr(s, key) == pytest.approx(getattr(p, key), rel=1e-14, abs=1e-15)
    mu = linear_stability(d.assembly, 16).load_factor_critical
    assert mu == pytest.approx(linear_stability(plain.assembly, 16).load_factor_critical,
                               rel=1e-12)
    text = Path(FIG7A).read_text().replace("117.80972450961724 mm", "117.80972450961724 cm") \
        .replace('"75 mm"', '"75 cm"').replace('"-75 mm"', '"-75 cm"') \
        .replace("200 GPa", "70 GPa")
    import tomllib

    big = parse_design(tomllib.loads(text))
    assert linear_stability(big.assembly, 16).load_factor_critical == pytest.approx(mu,
                                                                                    rel=1e-12)
    assert big.units.length == pytest.approx(10 * d.units.length, rel=1e-14)


# --------------------------------------------------------------------------- verdicts


def test_fig_7a_is_stable_43_percent_below_its_limit(run_cli):
    """Fig. 7a: psi = pi/4 against psi_c = pi/(2 sqrt(1.3)) = 1.3777: stable, the natural
    curvature 1 - sqrt(1.3)/2 = 43.0 % below the critical one (R0_c = 2 sqrt(1.3) R0 / 4...)."""
    r = run_cli(["analyze", FIG7A, "--json"])
    assert r.exit_code == 0, r.stderr
    u = json.loads(r.stdout)["units"]
    psi_c = math.pi / (2 * math.sqrt(1.3))
    assert u["psi"]["value"] == pytest.approx(math.pi / 4, rel=1e-14)
    assert u["critical_psi"] == {"value": pytest.approx(psi_c, rel=FE_RTOL), "unit": "rad"}
    # the paper's limit is twice this (its lam_c = 2 pi): pi / sqrt(1 + nu)
    assert 2 * u["critical_psi"]["value"] == pytest.approx(math.pi / math.sqrt(1.3),
                                                           rel=FE_RTOL)
    assert u["critical_natural_radius"]["value"] == pytest.approx(0.075 * (math.pi / 4) / psi_c,
                                                                  rel=FE_RTOL)
    verdict = u["as_built"]
    assert verdict["stable"] and verdict["limit"] == "upper" and verdict["side"] == "below"
    assert verdict["margin"] == pytest.approx(1 - math.sqrt(1.3) / 2, rel=FE_RTOL)
    text = run_cli(["analyze", FIG7A]).stdout
    assert "as built (load factor 1): STABLE, natural curvature 43.0 % below the critical " \
        "one" in text


def test_fig_7b_is_unstable_128_percent_above_this_projects_limit(run_cli):
    """Fig. 7b: psi = pi, 2 sqrt(1.3) - 1 = 128 % above psi_c = pi/(2 sqrt(1.3)). The paper
    says "about 15 %": its psi_c = pi/sqrt(1.3) = 2.755 gives sqrt(1.3) - 1 = 14.0 %."""
    r = run_cli(["analyze", FIG7B, "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    verdict = p["units"]["as_built"]
    assert not p["stable_at_design"] and not verdict["stable"]
    assert verdict["side"] == "above"
    assert verdict["margin"] == pytest.approx(2 * math.sqrt(1.3) - 1, rel=FE_RTOL)
    assert "UNSTABLE, natural curvature 128.0 % above the critical one" in \
        run_cli(["analyze", FIG7B]).stdout


def test_fig_7_energy_and_moment_are_the_held_states():
    """Held straight, each rod stores B3 kappa_0^2 L / 2 and carries M3 = -+B3 kappa_0
    (Section 4), B3 = E pi d^4/64 with d = 1 mm."""
    from rodstab.units import stability_units

    d = load_design(FIG7A)
    u = stability_units(d.units, d.assembly, (-2.0, 2.0))
    B3, k0, L = 200e9 * math.pi * 1e-3**4 / 64, 1 / 0.075, 2 * (math.pi / 4) * 0.075
    assert u["stored_energy"] == {"value": pytest.approx(B3 * k0**2 * L, rel=1e-12),
                                  "unit": "J"}
    assert u["held_moment"]["value"] == {"upper": pytest.approx(-B3 * k0, rel=1e-12),
                                         "lower": pytest.approx(B3 * k0, rel=1e-12)}


def test_steel_strip_six_ring_margin_is_the_folded_rings_closed_form(run_cli):
    """Folded six-sided ring: lam_c = pi/3 (docs/differences.md, "Section 5"), lam = kappa_n L /
    sqrt(b1 b2) with kappa_n L = 2 pi/3: critical load factor sqrt(b1 b2)/2 for the strip
    h/t = 10 (nu = 0.3): stable, 1 - 2/sqrt(b1 b2) below."""
    sec = rectangle(aspect=10.0, nu=0.3)
    r = run_cli(["analyze", SIX_RING, "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    assert p["load_factor_critical"] == pytest.approx(sec.sqrt_b1b2 / 2, rel=1e-5)
    assert p["units"]["as_built"]["stable"]
    assert p["units"]["as_built"]["margin"] == pytest.approx(1 - 2 / sec.sqrt_b1b2, rel=1e-5)


def test_hexagram_strip_interval_is_the_transfer_methods(run_cli):
    """The hexagram of a h/t = 4 strip held as the stress-free star: its stable interval
    (FE of the design) is `rodstab hexagram`'s (exact transfer matrices), in kappa_n R0."""
    exact = json.loads(run_cli(["hexagram", "--shape", "rectangle", "--aspect", "4", "--nu",
                                "0.3", "--json"]).stdout)["states"]["star"]
    p = json.loads(run_cli(["analyze", HEXAGRAM, "--json"]).stdout)
    assert p["load_factor_interval"] == pytest.approx(exact, rel=1e-4)
    u = p["units"]
    assert u["as_built"]["stable"] and u["stored_energy"]["value"] == pytest.approx(0, abs=1e-15)
    assert u["lower_critical_natural_curvature"]["value"] == pytest.approx(exact[0] / 0.08,
                                                                           rel=1e-4)


def test_analyze_states_the_stable_interval_in_natural_curvature_and_radius(run_cli):
    """The stable load factors mu times |kappa_n| = 1/R0 of the reference segment, R0 read
    from the TOML by hand (six-ring: s1's natural_radius = -100 mm; hexagram strip: r1's
    80 mm); the radii are their inverses. Six-ring: symmetric (-mu_c, mu_c) with mu_c =
    sqrt(b1 b2)/2 (the folded ring's lam_c = pi/3), so radius > R0/mu_c in either sense."""
    import tomllib

    for path, name, mu_c in ((SIX_RING, "s1", rectangle(aspect=10.0, nu=0.3).sqrt_b1b2 / 2),
                             (HEXAGRAM, "r1", None)):
        with open(path, "rb") as f:
            seg = next(s for s in tomllib.load(f)["segment"] if s["name"] == name)
        R0 = abs(float(seg["natural_radius"].split()[0])) / 1000  # "-100 mm" -> 0.1 m
        p = json.loads(run_cli(["analyze", path, "--json"]).stdout)
        lo, hi = p["load_factor_interval"]
        u = p["units"]
        assert u["stable_natural_curvature"] == {
            "value": [pytest.approx(lo / R0, rel=1e-12), pytest.approx(hi / R0, rel=1e-12)],
            "unit": "1/m"}
        radii = u["stable_natural_radius"]
        if mu_c is not None:  # the closed form, not the FE's own numbers
            assert u["stable_natural_curvature"]["value"] == [
                pytest.approx(-mu_c / R0, rel=1e-5), pytest.approx(mu_c / R0, rel=1e-5)]
            assert radii["as_given"] == [pytest.approx(R0 / mu_c, rel=1e-5), None]
            # the two limits are solved one per side: equal to round-off, not bit for bit
            # (they differed in the 16th digit with OpenBLAS's SandyBridge kernels)
            assert radii["reversed"] == [pytest.approx(radii["as_given"][0], rel=1e-12), None]
            text = run_cli(["analyze", path]).stdout
            assert f"radius > {1000 * R0 / mu_c:.5g}" in text and "in either sense" in text
        else:  # 0 < lo < hi: radii between R0/hi and R0/lo, none curved the other way
            assert radii == {"as_given": [pytest.approx(R0 / hi, rel=1e-12),
                                          pytest.approx(R0 / lo, rel=1e-12)],
                             "reversed": None, "unit": "m"}
            assert "< natural curvature <" in run_cli(["analyze", path]).stdout


@pytest.mark.parametrize("interval, expected", [
    ((-2.0, 2.0), (True, "upper", 0.5, 0.5)),
    ((0.5, 4.0), (True, "lower", 2.0, 1.0)),  # |log 2| < |log 1/4|: the lower limit is nearer
    ((0.2, 0.5), (False, "upper", 2.0, 1.0)),
    ((2.0, 3.0), (False, "lower", 0.5, 0.5)),
    ((-math.inf, math.inf), None), ((-3.0, -2.0), None)])
def test_as_built_margin(interval, expected):
    v = as_built(interval)
    assert (v if v is None else (v.stable, v.limit, v.ratio, v.margin)) == expected


# --------------------------------------------------------------------------- bad input

_BAD = [
    # (replace in steel_birod_fig7a.toml, words of the one stderr line)
    (('length = "117.80972450961724 mm"', "length = 0.1178"),
     ["segment[0].length = 0.1178", "plain number", "has units"]),
    (('length = "117.80972450961724 mm"', 'length = "5 kg"'),
     ["segment[0].length", "'5 kg'", "[mass]", "not a length"]),
    (('length = "117.80972450961724 mm"', 'length = "5 furlongz"'),
     ["segment[0].length", "'5 furlongz'", "unknown unit 'furlongz'"]),
    (('diameter = "1 mm"', 'diameter = "-1 mm"'), ["section.diameter", "'-1 mm'"]),
    (('shape = "circle"\ndiameter = "1 mm"',
      'shape = "rectangle"\nheight = "2 mm"\nthickness = "-0.5 mm"'),
     ["section.thickness", "'-0.5 mm'"]),
    (('shape = "circle"\ndiameter = "1 mm"', 'shape = "rectangle"\nheight = "2 mm"'),
     ["section", "'rectangle' needs thickness"]),
    (('diameter = "1 mm"', 'diameter = "1 mm"\naspect = 2.0'), ["section.aspect", "2.0"]),
    (('diameter = "1 mm"', 'diameter = "1 mm"\nB3 = "0.01 N*m^2"'),
     ["section.B3", "'0.01 N*m^2'", "section.diameter"]),
    (("\nnu = 0.3\n", '\nG = "50 GPa"\n'), ["material.G", "'50 GPa'", "nu = E/(2G) - 1 = 1"]),
    (("\nnu = 0.3\n", "\n"), ["[material]", "nu", "G"]),
    (('E = "200 GPa"', 'E = "200 m"'), ["material.E", "'200 m'", "not a modulus"]),
    (('natural_radius = "75 mm"', 'natural_radius = "75 mm"\nnatural_curvature = "1 1/m"'),
     ["segment[0]", "natural_curvature or natural_radius"]),
    (('natural_radius = "75 mm"', 'natural_radius = "0 mm"'),
     ["segment[0].natural_radius", "'0 mm'"]),
    (('start = ["0 mm", "0 mm"]', 'start = ["0 mm", 0.0]'), ["segment[1].start[1]", "0.0"]),
]


@pytest.mark.parametrize("change, words", _BAD, ids=[str(i) for i in range(len(_BAD))])
def test_bad_units_exit_2_naming_key_and_value(change, words, run_cli, tmp_path):
    text = Path(FIG7A).read_text()
    assert change[0] in text
    path = tmp_path / "d.toml"
    path.write_text(text.replace(change[0], change[1], 1))
    r = run_cli(["analyze", str(path)])
    assert r.exit_code == 2 and not r.stdout, (r.exit_code, r.stdout)
    (line,) = r.stderr.strip().splitlines()
    for w in [*words, str(path)]:
        assert w in line, (w, line)


def test_a_polygon_with_units_needs_its_coordinate_unit_and_scales_by_it(tmp_path):
    """A t x h = 0.5 mm x 2 mm polygon (y out of the plane) in mm is the rectangle's B3 =
    E h t^3/12; without unit it is refused."""
    pytest.importorskip("sectionproperties")
    poly = [[0, 0], [0.5, 0], [0.5, 2], [0, 2]]
    d = parse_design(_rod(f'polygon = {poly}\nunit = "mm"'))
    assert d.units.stiffness == pytest.approx(200e9 * 2e-3 * 0.5e-3**3 / 12, rel=1e-9)
    with pytest.raises(RodstabInputError, match=r"section\.unit"):
        parse_design(_rod(f"polygon = {poly}"))


#: A steel strip (t = 2 mm) bonded beside an aluminium one (t = 3 mm), both h = 5 mm out of
#: the ring's plane (y): side by side along x, the axis of in-plane bending.
_STEEL = [[0, 0], [2, 0], [2, 5], [0, 5]]
_ALU = [[2, 0], [5, 0], [5, 5], [2, 5]]
_BIMETAL = (f'unit = "mm"\nmesh_size = 0.016\nparts = [{{polygon = {_STEEL}, E = "200 GPa", '
            f'nu = 0.3}}, {{polygon = {_ALU}, E = "70 GPa", G = "26 GPa"}}]')


def _composite(section: str, segment: str = 'length = "235.6 mm"\nnatural_radius = "75 mm"'
               ) -> dict:
    """The clamped/sliding-clamp rod of :func:`_rod` without [material] (parts carry E)."""
    import tomllib

    return tomllib.loads(f'[section]\n{section}\n[[segment]]\nname = "rod"\n{segment}\n'
                         '[[support]]\nend = "rod.start"\ntype = "clamped"\n'
                         '[[support]]\nend = "rod.end"\ntype = "sliding-clamp"\n')


def test_a_bimetal_composite_with_units_is_sum_e_i_about_the_weighted_centroid():
    """Two bonded rectangles side by side along x (steel t1 = 2 mm, E1 = 200 GPa; aluminium
    t2 = 3 mm, E2 = 70 GPa; both h = 5 mm). Closed form (composite beam, transformed
    section): out of the plane both are centred at y = h/2, so B1 = (E1 t1 + E2 t2) h^3/12;
    in the plane about the modulus-weighted centroid x_c = sum E_i A_i x_i / sum E_i A_i,
    B3 = sum E_i (h t_i^3/12 + h t_i (x_i - x_c)^2) (parallel axes). Second moments of
    polygons are exact, so both hold to round-off. B2 (FE) is the library's composite of the
    same parts, G0 J; and the design is the plain one of the same parts with E in GPa, nu2 =
    E2/(2 G2) - 1, L = 1 and L/R0: same b1, b2 and the same critical load factor."""
    pytest.importorskip("sectionproperties")
    from rodstab.sections import composite_section

    d = parse_design(_composite(_BIMETAL))
    s, B = d.assembly.segments[0], d.units.stiffness
    E1, E2, h, t1, t2 = 200e9, 70e9, 5e-3, 2e-3, 3e-3
    x1, x2 = t1 / 2, t1 + t2 / 2
    xc = (E1 * t1 * x1 + E2 * t2 * x2) / (E1 * t1 + E2 * t2)
    B3 = sum(E * (h * t**3 / 12 + h * t * (x - xc) ** 2)
             for E, t, x in ((E1, t1, x1), (E2, t2, x2)))
    assert (d.units.E, d.units.length_unit) == (None, "mm")
    assert s.B3 * B == pytest.approx(B3, rel=1e-12)
    assert s.B1 * B == pytest.approx((E1 * t1 + E2 * t2) * h**3 / 12, rel=1e-12)
    nu2 = 70 / (2 * 26) - 1
    lib = composite_section([{"polygon": _STEEL, "E": 200.0, "nu": 0.3},
                             {"polygon": _ALU, "E": 70.0, "nu": nu2}], mesh_size=0.016)
    assert s.B2 * B == pytest.approx(lib.b2 * B3, rel=1e-12)
    assert s.B2 * B == pytest.approx(E1 / 2.6 * lib.J * 1e-12, rel=1e-12)  # G0 J, mm^4
    plain = parse_design({
        "section": {"parts": [{"polygon": _STEEL, "E": 200.0, "nu": 0.3},
                              {"polygon": _ALU, "E": 70.0, "nu": nu2}], "mesh_size": 0.016},
        "segment": [{"name": "rod", "length": 1.0, "natural_curvature": 235.6 / 75}],
        "support": [{"end": "rod.start", "type": "clamped"},
                    {"end": "rod.end", "type": "sliding-clamp"}]})
    p = plain.assembly.segments[0]
    for key in ("length", "natural_curvature", "B1", "B2", "B3"):
        assert getattr(s, key) == pytest.approx(getattr(p, key), rel=1e-12)
    mu = linear_stability(d.assembly, 16).load_factor_critical
    assert mu == pytest.approx(linear_stability(plain.assembly, 16).load_factor_critical,
                               rel=1e-12)


@pytest.mark.parametrize("section, words", [
    (_BIMETAL.replace('E = "70 GPa"', "E = 70e9"),
     ["section.parts[1].E = 70000000000.0 is a plain number", "has units"]),
    (_BIMETAL.replace('unit = "mm"\n', ""), ["section.unit", "composite"]),
    (_BIMETAL.replace('"70 GPa"', '"70 m"'), ["section.parts[1].E", "'70 m'"]),
    (_BIMETAL.replace('G = "26 GPa"', 'nu = 0.3, G = "26 GPa"'),
     ["section.parts[1] needs exactly one of nu", "G"]),
    (_BIMETAL.replace('G = "26 GPa"', 'G = "20 GPa"'),
     ["section.parts[1].G = '20 GPa'", "nu = E/(2G) - 1 = 0.75"]),
    (_BIMETAL + '\nB3 = "1 N*m^2"', ["section.B3", "section.unit"]),
    (_BIMETAL + '\nheight = "1 mm"', ["section.height", "composite"]),
], ids=["plain-E", "no-unit", "E-not-modulus", "nu-and-G", "G-gives-bad-nu", "B3", "height"])
def test_bad_composites_with_units_name_the_key(section, words):
    pytest.importorskip("sectionproperties")
    with pytest.raises(RodstabInputError) as exc:
        parse_design(_composite(section))
    for w in words:
        assert w in str(exc.value), (w, str(exc.value))


def test_a_quantity_in_a_part_makes_the_design_one_with_units():
    """E = "200 GPa" in a part is a sign of units: a plain length beside it is refused,
    naming it and the part's modulus."""
    pytest.importorskip("sectionproperties")
    with pytest.raises(RodstabInputError, match=r"segment\[0\]\.length = 1\.0 is a plain "
                                                r"number.*section\.parts\[0\]\.E = '200 GPa'"):
        parse_design(_composite(_BIMETAL.replace('unit = "mm"\n', ""),
                                "length = 1.0\nnatural_curvature = 1.0"))


def test_a_plain_design_keeps_its_meaning_and_refuses_quantities_elsewhere():
    """Plain numbers keep today's meaning (no units block); a string that is no quantity is
    the wrong type of a plain design, not a sign of units."""
    assert load_design(ROOT / "examples" / "birod.toml").units is None
    with pytest.raises(RodstabInputError, match=r"segment\[0\]\.length must be a number.*"
                                                r"'abc'.*a string"):
        parse_design({"segment": [{"name": "a", "length": "abc"}]})


# --------------------------------------------------------------------------- --vary


def test_vary_takes_quantities_in_one_unit():
    spec = parse_vary("segment.upper.length=100 mm:0.2 m:5", default_n=9)
    assert (spec.start, spec.stop, spec.n, spec.unit) == (100.0, pytest.approx(200.0), 5, "mm")
    for bad, word in (("segment.a.length=100 mm:0.2:5", "both with a unit"),
                      ("segment.a.length=1 mm:2 kg", "not units of the same")):
        with pytest.raises(RodstabInputError, match=word):
            parse_vary(bad, default_n=9)
    d = load_design(FIG7A)
    with pytest.raises(RodstabInputError, match=r"has units; give START and STOP with a unit"):
        vary_in_units(d, parse_vary("section.diameter=1:2", default_n=3))
    with pytest.raises(RodstabInputError, match=r"has no units"):
        vary_in_units(load_design(ROOT / "examples" / "birod.toml"),
                      parse_vary("segment.upper.length=1 m:2 m", default_n=3))
    with pytest.raises(RodstabInputError, match=r"section.diameter.*\[mass\]"):
        vary_in_units(d, parse_vary("section.diameter=1 kg:2 kg", default_n=3))
    turned = vary_in_units(d, parse_vary("support.0.rotation.tangent=0 deg:90 deg", default_n=3))
    assert (turned.stop, turned.unit) == (pytest.approx(math.pi / 2), None)
    # read into radians: the output says so, on a design with units (plain designs as before)
    assert axis_label(turned.key, axis_unit(d, turned)) == "support.0.rotation.tangent [rad]"
    plain = load_design(ROOT / "examples" / "birod.toml")
    assert axis_unit(plain, parse_vary("support.0.rotation.tangent=0:1", default_n=3)) is None
    # a continuation in the natural curvature: 40 1/m is kappa_n Lc = 40 x 0.1178 in the model
    assert model_value(d, "segment.upper.natural_curvature", 40.0, "1/m") == \
        pytest.approx(40.0 * 2 * (math.pi / 4) * 0.075, rel=1e-12)


def test_sweep_in_a_section_dimension_keeps_the_verdict_of_a_circle(run_cli, tmp_path):
    """Circle: psi_c does not depend on the diameter, so the critical natural curvature
    (1/m) is the same at every d: pi/(2 sqrt 1.3) x 2 / L."""
    r = run_cli(["sweep", FIG7A, "--vary", "section.diameter=1 mm:2 mm:2", "--out",
                 str(tmp_path), "--no-progress", "--elements", "8", "--json"])
    assert r.exit_code == 0, r.stderr
    u = json.loads(r.stdout)["units"]
    assert u["values"] == {"value": [1.0, 2.0], "unit": "mm"}
    assert json.loads(r.stdout)["axis"] == "section.diameter [mm]"
    k = 2 * math.pi / (2 * math.sqrt(1.3)) / (2 * (math.pi / 4) * 0.075)
    assert u["critical_natural_curvature"]["value"] == [pytest.approx(k, rel=1e-4)] * 2
    # the table reads back: a rerun into the same --out resumes every row, equal
    again = run_cli(["sweep", FIG7A, "--vary", "section.diameter=1 mm:2 mm:2", "--out",
                     str(tmp_path), "--no-progress", "--elements", "8", "--json"])
    assert again.exit_code == 0, again.stderr
    resumed = json.loads(again.stdout)
    assert resumed["resumed"] == 2
    assert resumed["units"]["critical_natural_curvature"] == u["critical_natural_curvature"]
    table = run_cli(["sweep", FIG7A, "--vary", "section.diameter=1 mm:2 mm:2", "--out",
                     str(tmp_path), "--no-progress", "--elements", "8"]).stdout
    assert table.split()[:2] == ["section.diameter", "[mm]"]


# --------------------------------------------------------------------------- units blocks


def test_every_design_command_carries_a_units_block(run_cli, tmp_path):
    """equilibrium, continue and states of a design with units give SI next to the model's
    numbers: the held energy (J) is analyze's stored energy; continue's path in load factor
    carries the natural curvature (1/m) and energies (J); states, the energies in J."""
    B3, k0, L = 200e9 * math.pi * 1e-3**4 / 64, 1 / 0.075, 2 * (math.pi / 4) * 0.075
    r = run_cli(["equilibrium", FIG7A, "--json", "--render", str(tmp_path / "eq.png"),
                 "--colour", "twist"])  # the picture's colours in SI (rad/m): a smoke test
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "eq.png").stat().st_size > 0
    u = json.loads(r.stdout)["units"]
    assert u["energy"] == {"value": pytest.approx(B3 * k0**2 * L, rel=1e-9), "unit": "J"}
    assert u["max_internal_moment"]["value"] == pytest.approx(B3 * k0, rel=1e-9)
    r = run_cli(["continue", FIG7A, "--vary", "load_factor=1:1.5:2", "--no-progress",
                 "--no-error-estimate", "--branch-steps", "0", "--elements", "4", "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    assert p["units"]["natural_curvature"]["value"] == [pytest.approx(k0 * v, rel=1e-12)
                                                        for v in p["value"]]
    assert p["units"]["energy"]["unit"] == "J"
    assert p["units"]["energy"]["value"][0] == pytest.approx(B3 * k0**2 * L, rel=1e-6)
    r = run_cli(["states", HEXAGRAM, "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    line = p["states"][[s["label"] for s in p["states"]].index("line")]
    # the line at kappa_n = 1/R0: 6 rods of B3 kappa_n^2 L / 2, B3 = E h t^3 / 12
    B3h, kh, Lh = 200e9 * 2e-3 * 0.5e-3**3 / 12, 1 / 0.08, 2 * math.pi * 0.08 / 3
    i = p["states"].index(line)
    assert p["units"]["energy"]["value"][i] == pytest.approx(3 * B3h * kh**2 * Lh, rel=1e-9)


def test_atlas_of_a_section_dimension_labels_its_axis_and_gives_1_per_m(run_cli, tmp_path):
    """atlas on the hexagram strip (load factor kappa_n R0, R0 = 80 mm read from the TOML)
    over its height: the axis is "section.height [mm]" in the table, the JSON and the figure;
    the star's limits in 1/m are the load factors / R0, and at h = 1.5 mm (h/t = 3) they are
    `rodstab hexagram --aspect 3`'s kappa_n R0 (exact transfer matrices of the star) / R0."""
    r = run_cli(["atlas", HEXAGRAM, "--vary", "section.height=1.5 mm:3 mm:2", "--state", "star",
                 "--out", str(tmp_path), "--no-progress"])
    assert r.exit_code == 0, r.stderr
    assert "section.height [mm]" in r.stdout.splitlines()[3]  # the table's header
    assert "for section.height 1.5..3 mm" in r.stdout
    p = json.loads((tmp_path / "atlas.json").read_text())
    assert p["key"] == "section.height" and p["axis"] == "section.height [mm]"
    u = p["units"]
    assert u["values"] == {"value": [1.5, 3.0], "unit": "mm"}
    R0 = 0.080
    assert u["natural_curvature_per_load_factor"]["value"] == [pytest.approx(1 / R0)] * 2
    star = p["states"]["star"]
    for side in ("lower", "upper"):
        assert u["stable_natural_curvature"]["value"]["star"][side] == [
            pytest.approx(mu / R0, rel=1e-12) for mu in star[side]]
    exact = json.loads(run_cli(["hexagram", "--shape", "rectangle", "--aspect", "3", "--nu",
                                "0.3", "--json"]).stdout)["states"]["star"]
    at_3 = [u["stable_natural_curvature"]["value"]["star"][s][0] for s in ("lower", "upper")]
    assert at_3 == [pytest.approx(k / R0, rel=1e-6) for k in exact]
    # a plain number on a dimensional key is refused, not read in some unit nobody named
    r = run_cli(["atlas", HEXAGRAM, "--vary", "section.height=4:6:3", "--out",
                 str(tmp_path / "plain")])
    assert r.exit_code == 2 and "give START and STOP with a unit" in r.stderr


def test_stable_bands_chart_labels_both_axes():
    """The chart's axes: the varied key with its unit, and the load's second scale."""
    from rodstab.plot.plots import plot_stable_bands

    fig = plot_stable_bands({"value": [1.0, 2.0], "s.lower": [0.5, 0.4], "s.upper": [2.0, 2.5]},
                            ("s",), x_key="value", xlabel="section.height [mm]",
                            ylabel="load factor", second_axis=(12.5, "kappa_n [1/m]"))
    ax = fig.axes[0]
    assert ax.get_xlabel() == "section.height [mm]" and ax.get_ylabel() == "load factor"
    (right,) = ax.child_axes
    assert right.get_ylabel() == "kappa_n [1/m]"
    fig.draw_without_rendering()  # the second axis takes its limits from the first when drawn
    assert right.get_ylim() == pytest.approx(tuple(12.5 * y for y in ax.get_ylim()))
    # the barrier's energy axis: model units by default, as the command names them with units
    from rodstab.plot.plots import plot_barrier_path

    for kwargs, label in (({}, "energy (B3 / L)"), ({"energy_label": "energy [J]"},
                                                     "energy [J]")):
        fig = plot_barrier_path([0.0, 0.5, 1.0], [0.0, 0.02, 0.01], 1, **kwargs)
        assert fig.axes[0].get_ylabel() == label
    # an equilibrium's 3D axes name the file's length unit (model lengths: none)
    import numpy as np

    from rodstab.plot.plots import plot_equilibrium
    from rodstab.plot.ribbons import RodLayout

    layout = RodLayout(np.array([[0, 1]]), np.array([0]), ("a",), np.array([2.0]))
    x, frames = np.array([[0.0, 0, 0], [100.0, 0, 0]]), np.eye(3)[None]
    for unit, label in ((None, "x"), ("mm", "x [mm]")):
        fig = plot_equilibrium(x, frames, layout, length_unit=unit)
        assert fig.axes[0].get_xlabel() == label
    # analyze's mode picture in mm: the drawing and its "largest w" scale by L / 1 mm
    from rodstab.linear.solve import linear_stability
    from rodstab.plot.plots import plot_mode

    d = load_design(SIX_RING)
    r = linear_stability(d.assembly, 4)
    plain, mm = plot_mode(d.assembly, r), plot_mode(d.assembly, r, length_scale=209.44,
                                                    length_unit="mm")
    assert mm.axes[0].get_zlabel() == "z [mm]" and plain.axes[0].get_zlabel() == "z"
    w, w_mm = (t.axes[0].get_title().split("largest w ")[1].split(",")[0] for t in (plain, mm))
    assert w_mm.endswith(" mm")  # 3 digits each: equal to the rounding
    assert float(w_mm[:-3]) == pytest.approx(float(w) * 209.44, rel=5e-3)


def test_states_of_the_steel_six_ring_in_1_per_m_and_joules(run_cli):
    """Each state's held curvature is its turning over the rod length, kL / L (1/m), with
    L = 209.44 mm from the TOML; its energy in J is the model's x B3 / L, with B3 = E h t^3/12
    by hand: the strip stands on edge (h = 5 mm out of the ring's plane, t = 0.5 mm in it), so
    the in-plane bending stiffness takes t^3."""
    r = run_cli(["states", SIX_RING, "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    L, B3 = 0.20943951023931956, 200e9 * 5e-3 * 0.5e-3**3 / 12
    u = p["units"]
    assert u["held_curvature"] == {
        "value": [pytest.approx(math.radians(s["theta_deg"]) / L, rel=1e-12, abs=1e-12)
                  for s in p["states"]], "unit": "1/m"}
    assert u["energy"] == {"value": [pytest.approx(s["energy"] * B3 / L, rel=1e-12, abs=1e-15)
                                     for s in p["states"]], "unit": "J"}
    # the folded (line) state at the design's load: six rods held straight against 1/R0,
    # R0 = 100 mm, each storing B3 L / (2 R0^2)
    line = [s["label"] for s in p["states"]].index("line")
    assert u["energy"]["value"][line] == pytest.approx(6 * B3 * L / (2 * 0.1**2), rel=1e-12)
    header = run_cli(["states", SIX_RING]).stdout.splitlines()[3]
    assert header.split()[-4:] == ["k", "1/m", "energy", "J"]


@pytest.mark.slow
def test_barrier_on_the_hexagram_strip_in_joules(run_cli):
    """The barrier's energies in J are the model's x B3 / L, B3 = E h t^3/12 by hand (h = 2 mm
    out of the plane, t = 0.5 mm in it), L = 167.55 mm; the line it starts from holds six
    straight rods against kappa_n = mu / R0 (R0 = 80 mm): 6 B3 kappa_n^2 L / 2 in closed form."""
    argv = ["barrier", HEXAGRAM, "--from", "line", "--to", "star", "--elements", "4",
            "--images", "5"]
    r = run_cli([*argv, "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    u = p["units"]
    B3, L, R0 = 200e9 * 2e-3 * 0.5e-3**3 / 12, 0.16755160819145564, 0.080
    kappa = p["kappa_R0"] / R0
    assert u["natural_curvature"] == {"value": pytest.approx(kappa, rel=1e-12), "unit": "1/m"}
    assert u["energy_from"]["value"] == pytest.approx(6 * B3 * kappa**2 * L / 2, rel=1e-9)
    for key in ("barrier_forward", "barrier_backward", "energy_saddle", "energy_to"):
        assert u[key] == {"value": pytest.approx(p[key] * B3 / L, rel=1e-12), "unit": "J"}
    text = run_cli(argv).stdout
    assert f"energy {p['energy_saddle']:.6g} ({u['energy_saddle']['value']:.6g} J)" in text
    assert f"natural curvature {kappa:.6g} 1/m of segment 'r1'" in text


def test_transitions_on_the_hexagram_strip_state_load_and_contact_in_si(run_cli):
    """transitions of the hexagram strip: the load factor as the natural curvature mu / R0
    (R0 = 80 mm), the contact thickness h/L x L (L = 167.55 mm), each load-factor threshold
    as the natural curvature there (1/m)."""
    r = run_cli(["transitions", HEXAGRAM, "--state", "star", "--elements", "6",
                 "--contact-thickness", "0.012", "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    u, R0, L = p["units"], 0.080, 0.16755160819145564
    assert u["natural_curvature"] == {"value": pytest.approx(p["load_factor"] / R0, rel=1e-12),
                                      "unit": "1/m"}
    assert u["contact_thickness"] == {"value": pytest.approx(0.012 * L, rel=1e-12), "unit": "m"}
    from rodstab.plot.transition_graph import edge_label

    assert edge_label(p["edges"][0], u["thresholds"][0]) == (
        f"{p['edges'][0]['stimulus']}\n= {p['edges'][0]['threshold']:.4g} "
        f"({p['edges'][0]['threshold'] / R0:.4g} 1/m)")  # the graph's edge, also in 1/m
    assert edge_label(p["edges"][0]).endswith(f"= {p['edges'][0]['threshold']:.4g}")
    assert u["thresholds"] and all(
        q["value"] == pytest.approx(e["threshold"] / R0, rel=1e-12)
        for q, e in zip(u["thresholds"], p["edges"], strict=True)
        if q["quantity"] == "natural_curvature")


@pytest.mark.parametrize("interval, curvature, given, reversed_", [
    # kappa_n = 40 1/m as given: mu x 40 1/m, radii 1/(mu x 40) m of each sense
    ((-2.0, 3.0), [-80.0, 120.0], [1 / 120, math.inf], [1 / 80, math.inf]),
    ((0.5, 2.0), [20.0, 80.0], [1 / 80, 1 / 20], None),
    ((-2.0, -0.5), [-80.0, -20.0], None, [1 / 80, 1 / 20]),
    ((-math.inf, math.inf), [-math.inf, math.inf], [0.0, math.inf], [0.0, math.inf]),
    ((0.0, math.inf), [0.0, math.inf], [0.0, math.inf], None)])
def test_curvature_interval_of_each_sense(interval, curvature, given, reversed_):
    from rodstab.units import curvature_interval

    d = parse_design(_rod())
    out = curvature_interval(d.units, d.assembly, interval)
    assert out["stable_natural_curvature"] == {"value": pytest.approx(curvature, rel=1e-12),
                                               "unit": "1/m"}
    radii = out["stable_natural_radius"]
    for got, want in ((radii["as_given"], given), (radii["reversed"], reversed_)):
        assert got == (None if want is None else pytest.approx(want, rel=1e-12))
    # a naturally straight reference segment: the load factor curves nothing, nothing to state
    straight = parse_design(_rod(segment='length = "100 mm"'))
    assert curvature_interval(straight.units, straight.assembly, interval) == {}


def test_discover_on_the_hexagram_strip_in_si(run_cli):
    """discover's energies in J are the model's x B3 / L (B3 = E h t^3/12, L = 167.55 mm by
    hand); its load as the natural curvature mu / R0 (R0 = 80 mm)."""
    r = run_cli(["discover", HEXAGRAM, "--saddle-modes", "0", "--strings", "0", "--starts", "0",
                 "--no-seed-states", "--elements", "4", "--json"])
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    B3, L = 200e9 * 2e-3 * 0.5e-3**3 / 12, 0.16755160819145564
    u = p["units"]
    assert u["natural_curvature"] == {"value": pytest.approx(2.0 / 0.080, rel=1e-12),
                                      "unit": "1/m"}
    assert u["energy"] == {"value": [pytest.approx(s["energy"] * B3 / L, rel=1e-12)
                                     for s in p["states"]], "unit": "J"}
