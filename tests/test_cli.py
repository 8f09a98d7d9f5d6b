"""Tests of the ``rodstab`` command line (``rodstab.cli``).

Every run goes through the real entry point, ``rodstab.cli.main``, with the ``run_cli``
fixture (``tests/conftest.py``): every analysis subcommand's ``--json`` prints exactly one JSON
object with the documented keys, and the values are the paper's closed forms (so the CLI is
also an end-to-end check). Exit status: every invalid invocation exits with status 2 and prints
exactly one line on stderr, without a traceback, naming the offending option or value; a solver
that does not converge gives status 3; any other exception is a bug and propagates.
"""

from __future__ import annotations

import io
import json
import math
import re

import pytest


def _reject_nan(token: str) -> None:
    raise AssertionError(f"JSON contains {token}, which is not valid JSON")


@pytest.fixture
def cli_json(run_cli):
    """``cli_json(args)``: run the CLI and return its one JSON object (:func:`_json`)."""
    return lambda args: _json(run_cli(args))


def _json(result) -> dict:
    """Assert exit 0 and exactly one JSON object on one stdout line; return it."""
    assert result.exit_code == 0, (result.stdout, result.stderr)
    lines = result.stdout.splitlines()
    assert len(lines) == 1, result.stdout
    payload = json.loads(lines[0], parse_constant=_reject_nan)
    assert isinstance(payload, dict)
    return payload


# ------------------------------------------------------------------------------ --json output


def test_cli_section_json_keys_and_circle_values(cli_json):
    """section --json: b1, b2, sqrt_b1b2; circle nu = 1/3: b1 = 1, b2 = 3/4 (Sec. 3.1)."""
    p = cli_json(["section", "--json"])
    assert {"b1", "b2", "sqrt_b1b2"} <= p.keys()
    assert p["b1"] == 1.0 and p["b2"] == pytest.approx(0.75, rel=1e-15)
    assert p["sqrt_b1b2"] == pytest.approx(math.sqrt(0.75), rel=1e-15)


def test_cli_section_json_rectangle_and_ratios(cli_json):
    """Rectangle h/t = 2: b1 = (h/t)^2 = 4; --b1/--b2 given directly are echoed."""
    assert cli_json(["section", "--shape", "rectangle", "--aspect", "2", "--json"])["b1"] == 4.0
    p = cli_json(["section", "--b1", "2.5", "--b2", "0.4", "--json"])
    assert (p["b1"], p["b2"], p["sqrt_b1b2"]) == (2.5, 0.4, pytest.approx(1.0, rel=1e-15))


#: A section's ratios (what the closed-form commands use), without the geometry of its size.
_RATIO_KEYS = ("shape", "b1", "b2", "nu", "torsion", "aspect", "sqrt_b1b2")


def _ratios(payload: dict) -> dict:
    return {k: payload[k] for k in _RATIO_KEYS}


def test_cli_section_by_dimensions_rectangle_h_over_t_is_the_aspect(cli_json):
    """Issue 13: --height 5 mm --thickness 0.5 mm is h/t = 10: b1 = (h/t)^2 = 100 exactly
    (both in mm: the ratio is taken in one unit), b2 the same as --aspect 10."""
    p = cli_json(["section", "--shape", "rectangle", "--height", "5 mm", "--thickness",
                  "0.5 mm", "--json"])
    assert p["b1"] == 100.0 and p["aspect"] == 10.0
    assert _ratios(p) == _ratios(cli_json(["section", "--shape", "rectangle", "--aspect", "10",
                                           "--json"]))
    assert p["dimensions"]["height"] == {"text": "5 mm", "value": pytest.approx(5e-3, rel=1e-15),
                                         "unit": "m"}
    # h t = 2.5 mm^2; I3 = h t^3/12 (in the plane), I1 = t h^3/12 (out of it)
    assert p["geometry"]["area"]["value"] == pytest.approx(2.5e-6, rel=1e-14)
    assert p["geometry"]["I3"]["value"] == pytest.approx(5e-3 * 5e-4**3 / 12, rel=1e-14)
    assert p["geometry"]["I1"]["value"] == pytest.approx(5e-4 * 5e-3**3 / 12, rel=1e-14)


@pytest.mark.parametrize("height, thickness, aspect", [
    ("0.2 in", "1 mm", 5.08),  # 1 in = 25.4 mm exactly
    ("5", "0.5", 10.0),  # plain numbers: their ratio only
    ("2 mm", "4 mm", 0.5)])
def test_cli_section_by_dimensions_in_other_units_or_plain(cli_json, height, thickness, aspect):
    """Mixed units are converted before the ratio; plain numbers give h/t as written."""
    p = cli_json(["section", "--shape", "ellipse", "--height", height, "--thickness",
                  thickness, "--json"])
    assert p["aspect"] == pytest.approx(aspect, rel=1e-14)
    assert p["b1"] == pytest.approx(aspect**2, rel=1e-14)  # ellipse b1 = (h/t)^2 (eq. 3.11)


def test_cli_section_by_dimensions_tube_is_inner_over_outer(cli_json):
    """--outer-diameter 10 mm --inner-diameter 8 mm is the tube of --aspect 0.8."""
    p = cli_json(["section", "--shape", "tube", "--outer-diameter", "10 mm",
                  "--inner-diameter", "8 mm", "--json"])
    assert _ratios(p) == _ratios(cli_json(["section", "--shape", "tube", "--aspect", "0.8",
                                           "--json"]))
    # J = 2 I = pi (Do^4 - Di^4)/32
    assert p["geometry"]["J"]["value"] == pytest.approx(math.pi * (1e-2**4 - 8e-3**4) / 32,
                                                        rel=1e-14)


def test_cli_section_dimensions_and_E_give_B1_B2_B3(cli_json):
    """--E with dimensions: B3 = E t^3 h/12, B1 = E h^3 t/12 (rectangle); a circle's
    B3 = E pi D^4/64 and B2 = G J = E/(2 (1 + nu)) pi D^4/32."""
    E = 200e9
    p = cli_json(["section", "--shape", "rectangle", "--height", "5 mm", "--thickness",
                  "0.5 mm", "--E", "200 GPa", "--json"])
    B = {k: v["value"] for k, v in p["stiffness"].items()}
    assert B["B3"] == pytest.approx(E * 5e-3 * 5e-4**3 / 12, rel=1e-13)
    assert B["B1"] == pytest.approx(E * 5e-4 * 5e-3**3 / 12, rel=1e-13)
    assert B["B2"] == pytest.approx(p["b2"] * B["B3"], rel=1e-15)
    assert p["stiffness"]["B1"]["unit"] == "N*m^2"
    c = cli_json(["section", "--diameter", "3 mm", "--nu", "0.3", "--E", "200 GPa", "--json"])
    I = math.pi * 3e-3**4 / 64
    assert c["stiffness"]["B3"]["value"] == pytest.approx(E * I, rel=1e-13)
    assert c["stiffness"]["B2"]["value"] == pytest.approx(E / 2.6 * 2 * I, rel=1e-13)


def test_cli_section_dimensions_in_the_table(run_cli):
    """The table shows the dimensions as written, their ratio and, with --E, B1 B2 B3."""
    out = run_cli(["section", "--shape", "rectangle", "--height", "5 mm", "--thickness",
                   "0.5 mm", "--E", "200 GPa"])
    assert out.exit_code == 0, out.stderr
    assert "height 5 mm, thickness 0.5 mm (h/t = 10)" in out.stdout
    assert "B3 = 0.0104167 N*m^2" in out.stdout  # 200e9 x 5e-3 x 1.25e-10 / 12


def test_cli_ring_by_dimensions_equals_ring_by_aspect(cli_json):
    """Every command with the section options reads the dimensions as their aspect."""
    a = cli_json(["ring", "--loops", "2", "--shape", "rectangle", "--height", "3 mm",
                  "--thickness", "1 mm", "--json"])
    b = cli_json(["ring", "--loops", "2", "--shape", "rectangle", "--aspect", "3", "--json"])
    assert a == b


def test_cli_ratios_override_shape_note_goes_to_stderr_not_stdout(run_cli):
    """--b1/--b2 with an explicit --shape: the documented note is on stderr; stdout stays one
    JSON object with the given ratios (shape 'ratios')."""
    result = run_cli(["section", "--shape", "rectangle", "--b1", "1", "--b2", "1", "--json"])
    assert result.exit_code == 0
    assert "override" in result.stderr
    p = json.loads(result.stdout)
    assert (p["shape"], p["b1"], p["b2"]) == ("ratios", 1.0, 1.0)


@pytest.mark.parametrize("loops, lo, hi, modes", [
    (1, 7 / 8 - math.sqrt(1 / 64 + 3), 1.0, [2, 0]),
    (3, 7 / 8 - math.sqrt(1 / 64 + 4 / 3), 7 / 8 - math.sqrt(1 / 64 + 1 / 3), [4, 2]),
])
def test_cli_ring_json(cli_json, loops, lo, hi, modes):
    """ring --loops N --json: loops, M_interval, kappa_L_over_2pi_interval, bounding_modes;
    values from (3.3) for b1 = 1, b2 = 3/4 (M^- = 7/8 - sqrt(1/64 + 3 k^2/4))."""
    p = cli_json(["ring", "--loops", str(loops), "--json"])
    assert {"loops", "M_interval", "kappa_L_over_2pi_interval", "bounding_modes"} <= p.keys()
    assert p["loops"] == loops
    assert p["M_interval"] == pytest.approx([lo, hi], rel=1e-12)
    assert p["kappa_L_over_2pi_interval"] == pytest.approx(
        [loops * (1 - hi), loops * (1 - lo)], rel=1e-12, abs=1e-14)
    assert p["bounding_modes"] == modes


@pytest.mark.parametrize("extra, g", [([], math.sqrt(0.75)),
                                      (["--b1", "4", "--b2", "0.25"], 1.0)])
def test_cli_arc_json_straight_limit(cli_json, extra, g):
    """arc --L-over-R 0 --json: L_over_R, L_kappa_interval = +-2 pi sqrt(b1 b2) (3.9),
    critical_mode 'symmetric'."""
    p = cli_json(["arc", "--L-over-R", "0", *extra, "--json"])
    assert {"L_over_R", "L_kappa_interval", "critical_mode"} <= p.keys()
    assert p["L_over_R"] == 0.0
    assert p["L_kappa_interval"] == pytest.approx([-2 * math.pi * g, 2 * math.pi * g], rel=1e-12)
    assert p["critical_mode"] == "symmetric"


def test_cli_arc_json_curved(cli_json):
    """arc --L-over-R 3 --json: the interval contains the stress-free state L kappa_n = L/R."""
    p = cli_json(["arc", "--L-over-R", "3", "--json"])
    lo, hi = p["L_kappa_interval"]
    assert p["L_over_R"] == 3.0 and lo < 3.0 < hi and p["critical_mode"] == "symmetric"


def test_cli_arc_max_length_json(cli_json):
    """arc-max-length --json: L_over_R_max = 2 pi for b1 = 1 (paper, after (3.14))."""
    p = cli_json(["arc-max-length", "--json"])
    assert {"L_over_R_max", "critical_mode"} <= p.keys()
    assert p["L_over_R_max"] == pytest.approx(2 * math.pi, rel=1e-12)
    assert p["critical_mode"] == "symmetric"


def test_cli_michell_json(cli_json):
    """michell --loops 1 --json: b2_omega0_critical = sqrt 3, mode_j = 2 (Sec. 3.3); --loops 3:
    unstable at every twist, the critical twist is null (JSON has no NaN) and mode_j = 1."""
    p = cli_json(["michell", "--loops", "1", "--json"])
    assert {"b2_omega0_critical", "mode_j"} <= p.keys()
    assert p["b2_omega0_critical"] == pytest.approx(math.sqrt(3), rel=1e-14)
    assert p["mode_j"] == 2
    p = cli_json(["michell", "--loops", "3", "--json"])
    assert p["b2_omega0_critical"] is None and p["mode_j"] == 1


@pytest.mark.parametrize("args", [["section"], ["ring", "--loops", "3"], ["arc", "--L-over-R", "1"],
                                  ["arc-max-length"], ["michell"]])
def test_cli_table_output_is_not_json(run_cli, args):
    """Without --json each subcommand prints a readable table (several lines, not JSON)."""
    result = run_cli(args)
    assert result.exit_code == 0, result.stderr
    assert result.stdout.startswith("section ")
    with pytest.raises(json.JSONDecodeError):
        json.loads(result.stdout)


def test_cli_main_valid_invocation_exit_0_and_silent_stderr(run_cli):
    """The real entry point (a fresh interpreter): valid input exits 0 with one JSON line and
    nothing on stderr."""
    proc = run_cli(["ring", "--loops", "3", "--json"], fresh_process=True)
    assert proc.exit_code == 0 and proc.stderr == ""
    assert json.loads(proc.stdout)["bounding_modes"] == [4, 2]


# --------------------------------------------------------------------------- invalid input

L_NAME = ("L-over-R", "L_over_R")

#: (arguments, tokens that must appear in the stderr line; a tuple token = any of its items)
BAD_INPUTS = [
    (["section", "--nu", "0.6"], ["nu", "0.6"]),
    (["section", "--nu", "-1"], ["nu", "-1.0"]),
    (["section", "--nu", "nan"], ["nu", "nan"]),
    (["section", "--nu", "abc"], ["--nu", "abc"]),
    (["arc-max-length", "--nu", "0.7"], ["nu", "0.7"]),
    (["section", "--shape", "rectangle", "--aspect", "0"], ["aspect", "0.0"]),
    (["section", "--shape", "rectangle", "--aspect", "-2"], ["aspect", "-2"]),
    (["section", "--shape", "ellipse", "--aspect", "nan"], ["aspect", "nan"]),
    (["section", "--shape", "rectangle", "--aspect", "inf"], ["aspect", "inf"]),
    (["section", "--shape", "tube", "--aspect", "1.0"], ["aspect", "1.0"]),
    (["section", "--shape", "tube", "--aspect", "-0.1"], ["aspect", "-0.1"]),
    (["section", "--aspect", "2"], ["aspect", "2", "circle"]),
    (["section", "--shape", "rectangle", "--aspect", "0.01", "--torsion", "paper"],
     ["aspect", "0.01"]),
    (["ring", "--loops", "0"], ["loops", "0"]),
    (["ring", "--loops", "-1"], ["loops", "-1"]),
    (["ring", "--loops", "1.5"], ["--loops", "1.5"]),
    (["ring", "--loops", "abc"], ["--loops", "abc"]),
    (["michell", "--loops", "0"], ["loops", "0"]),
    (["section", "--shape", "hexagon"], ["--shape", "hexagon"]),
    (["section", "--torsion", "approximate"], ["--torsion", "approximate"]),
    (["section", "--b1", "2"], ["b1", "2", "b2"]),
    (["section", "--b2", "0.5"], ["b2", "0.5", "b1"]),
    (["section", "--b1", "-1", "--b2", "1"], ["b1", "-1"]),
    (["section", "--b1", "nan", "--b2", "1"], ["b1", "nan"]),
    (["ring", "--b1", "1", "--b2", "0"], ["b2", "0"]),
    (["section", "--b1", "1", "--b2", "1", "--aspect", "2"], ["aspect", "2"]),
    (["section", "--b1", "1", "--b2", "1", "--torsion", "paper"], ["torsion", "paper"]),
    (["arc", "--L-over-R", "-1"], [L_NAME, "-1"]),
    (["arc", "--L-over-R", "nan"], [L_NAME, "nan"]),
    (["arc", "--L-over-R", "inf"], [L_NAME, "inf"]),
    (["arc", "--L-over-R", "x"], [L_NAME, "x"]),
    (["arc"], ["--L-over-R"]),
    (["michell", "--shape", "rectangle", "--aspect", "2"], ["b1", "4.0"]),
    (["michell", "--b1", "2", "--b2", "1"], ["b1", "2.0"]),
    (["frobnicate"], ["frobnicate"]),
    (["section", "--bogus"], ["--bogus"]),
    pytest.param(["section", "--shape", "rectangle", "--b1", "-1", "--b2", "1"], ["b1", "-1"]),
    # section by its dimensions (issue 13)
    (["section", "--shape", "rectangle", "--height", "5 mm", "--thickness", "1 mm",
      "--aspect", "5"], ["--height", "5 mm", "--aspect", "5"]),
    (["section", "--shape", "rectangle", "--diameter", "3 mm"], ["--diameter", "3 mm",
                                                                 "rectangle"]),
    (["section", "--height", "5 mm", "--thickness", "1 mm"], ["--height", "5 mm", "circle"]),
    (["section", "--shape", "tube", "--height", "5", "--outer-diameter", "1",
      "--inner-diameter", "0.5"], ["--height", "5", "tube"]),
    (["section", "--shape", "rectangle", "--height", "5 kg", "--thickness", "1 mm"],
     ["--height", "5 kg", "length"]),
    (["section", "--shape", "rectangle", "--height", "5 mm", "--thickness", "1 furlongz"],
     ["--thickness", "1 furlongz"]),
    (["section", "--shape", "rectangle", "--height", "-5 mm", "--thickness", "1 mm"],
     ["--height", "-5 mm"]),
    (["section", "--shape", "rectangle", "--height", "5", "--thickness", "0"],
     ["--thickness", "0"]),
    (["section", "--diameter", "0 mm"], ["--diameter", "0 mm"]),
    (["section", "--shape", "rectangle", "--height", "5", "--thickness", "0.5 mm"],
     ["--height", "5", "--thickness", "0.5 mm"]),
    (["section", "--shape", "rectangle", "--height", "5 mm"], ["--height", "--thickness"]),
    (["section", "--shape", "rectangle", "--height", "abc", "--thickness", "1"],
     ["--height", "abc"]),
    (["section", "--shape", "rectangle", "--height", "nan", "--thickness", "1"],
     ["--height", "nan"]),
    (["section", "--shape", "rectangle", "--height", "1 km", "--thickness", "1 um"],
     ["--height", "1 km", "--thickness", "1 um"]),
    (["section", "--shape", "tube", "--outer-diameter", "8 mm", "--inner-diameter", "1 cm"],
     ["--inner-diameter", "1 cm", "--outer-diameter", "8 mm"]),
    (["section", "--shape", "rectangle", "--height", "5", "--thickness", "1", "--b1", "1",
      "--b2", "1"], ["--height", "5", "--b1"]),
    (["section", "--E", "200 GPa"], ["--E", "200 GPa"]),
    (["section", "--diameter", "3", "--E", "200 GPa"], ["--E", "200 GPa"]),
    (["section", "--diameter", "3 mm", "--E", "3 m"], ["--E", "3 m"]),
    (["section", "--diameter", "3 mm", "--E", "-2 GPa"], ["--E", "-2 GPa"]),
    (["section", "--polygon", "x.json", "--height", "5 mm"], ["--height", "--polygon"]),
    (["hexagram", "--threshold", "--shape", "rectangle", "--height", "2", "--thickness", "1"],
     ["--threshold", "--height", "2"]),
    pytest.param(["ring", "--shape", "ellipse", "--b1", "1", "--b2", "1", "--aspect", "3"],
                 ["aspect", "3"]),
]


def _args_of(case):
    return case.values[0] if hasattr(case, "values") else case[0]


@pytest.mark.parametrize("args, tokens", BAD_INPUTS,
                         ids=[" ".join(_args_of(c)) for c in BAD_INPUTS])
def test_cli_bad_input_exit_2_one_stderr_line_naming_it(run_cli, args, tokens):
    """Module contract: invalid input exits with status 2 and one line on stderr naming the
    offending option and value; never a traceback; nothing on stdout."""
    assert len(BAD_INPUTS) >= 20
    proc = run_cli(args)
    assert proc.exit_code == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    for token in tokens:
        alternatives = token if isinstance(token, tuple) else (token,)
        assert any(t in lines[0] for t in alternatives), (token, lines[0])
    assert proc.stdout == ""


def test_cli_large_L_over_R_gives_no_traceback(run_cli):
    """A large but finite L/R is either solved (exit 0) or rejected (exit 2, one line)."""
    proc = run_cli(["arc", "--L-over-R", "10000", "--json"])
    assert "Traceback" not in proc.stderr
    assert proc.exit_code in (0, 2)


# ----------------------------------------------------------------------- usage and help


def test_cli_without_arguments_prints_the_multi_line_help(run_cli):
    """``rodstab`` alone shows click's usage and the command list on several lines (exit
    status as click's default: 0 or 2), not one squeezed 'error:' line."""
    r = run_cli([])
    assert r.exit_code in (0, 2)
    text = r.stdout + r.stderr
    assert "error:" not in text
    assert text.lstrip().startswith("Usage: rodstab")
    assert "Commands:" in text and "Exit status" in text
    for command in ("analyze", "continue", "equilibrium", "sweep", "reproduce"):
        assert f"\n  {command} " in text
    assert len(text.splitlines()) > 15


# ----------------------------------------------------------------- --vary (sweep, continue)

STRAIGHT_TOML = """
[[segment]]
name = "rod"
length = 1.0
natural_curvature = 1.0
[[support]]
end = "rod.start"
type = "clamped"
[[support]]
end = "rod.end"
type = "sliding-clamp"
"""

#: (text after KEY=, tokens the one stderr line names)
BAD_VARY_RANGES = [
    ("", ["KEY=START:STOP[:N]"]),
    ("1", ["KEY=START:STOP[:N]", "=1'"]),
    ("1:2:3:4", ["KEY=START:STOP[:N]", "1:2:3:4"]),
    ("abc:2", ["START", "'abc'", "not a number"]),
    ("1:abc", ["STOP", "'abc'", "not a number"]),
    (":2", ["START", "''"]),
    ("nan:2", ["START", "'nan'", "finite"]),
    ("1:inf", ["STOP", "'inf'", "finite"]),
    ("1:2:0", ["N", "'0'", "positive integer"]),
    ("1:2:-3", ["N", "'-3'", "positive integer"]),
    ("1:2:2.5", ["N", "'2.5'", "positive integer"]),
    ("1:2:x", ["N", "'x'", "positive integer"]),
]


def _vary_args(command: str, vary: str, tmp_path) -> list[str]:
    if command == "sweep":
        return ["sweep", "examples/clamped_arc.toml", "--vary", f"section.aspect{vary}",
                "--out", str(tmp_path), "--no-progress"]
    design = tmp_path / "straight.toml"
    design.write_text(STRAIGHT_TOML)
    return ["continue", str(design), "--vary", f"load_factor{vary}", "--elements", "4",
            "--branch-steps", "0", "--no-progress"]


@pytest.mark.parametrize("command", ["sweep", "continue"])
@pytest.mark.parametrize("rng, tokens", BAD_VARY_RANGES, ids=[r for r, _ in BAD_VARY_RANGES])
def test_cli_bad_vary_part_exit_2_one_line_naming_it(run_cli, tmp_path, command, rng, tokens):
    """Both commands share one --vary grammar: each wrong part is named on one stderr line."""
    r = run_cli(_vary_args(command, f"={rng}" if rng else "", tmp_path))
    assert r.exit_code == 2, (r.exit_code, r.stderr)
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    for token in tokens:
        assert token in lines[0], (token, lines[0])
    assert r.stdout == ""


@pytest.mark.parametrize("command", ["sweep", "continue"])
def test_cli_empty_vary_key_exit_2(run_cli, tmp_path, command):
    args = _vary_args(command, "=1:2", tmp_path)
    args[3] = "=1:2"
    r = run_cli(args)
    assert r.exit_code == 2 and len(r.stderr.splitlines()) == 1
    assert "KEY ''" in r.stderr


def test_cli_sweep_n_is_optional_default_9(run_cli, tmp_path):
    r = run_cli(["sweep", "examples/clamped_arc.toml", "--vary", "section.aspect=1:2",
                 "--elements", "4", "--out", str(tmp_path), "--no-progress", "--json"])
    assert r.exit_code == 0, r.stderr
    assert json.loads(r.stdout)["values"] == pytest.approx([1 + k / 8 for k in range(9)])


# ------------------------------------------------------------------ exit 3: not converged


def test_cli_equilibrium_not_converged_prints_json_then_exit_3(run_cli, monkeypatch):
    """A Newton solve that stops unconverged (a budget of 2 iterations from a start a tenth of
    a length off the held state): the JSON is printed with converged false, then one stderr
    line and exit status 3."""
    import rodstab.nonlinear.newton as S  # where relax() reads it

    monkeypatch.setattr(S, "RELAX_MAX_ITER", 2)
    r = run_cli(["equilibrium", "examples/folded_six_ring.toml", "--perturb", "0.1",
                 "--elements", "8", "--json"])
    assert r.exit_code == 3, (r.exit_code, r.stderr)
    p = json.loads(r.stdout)
    assert p["converged"] is False and p["iterations"] == 2
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("rodstab: not converged:"), r.stderr
    assert "Newton" in lines[0]


def test_cli_equilibrium_not_converged_does_not_judge_stability(run_cli, monkeypatch):
    """The same unconverged solve as text: the stability line says it is not judged (no
    equilibrium to judge), not "NOT stable" -- the eigenvalues of a state that is no
    equilibrium say nothing of stability -- then exit 3."""
    import rodstab.nonlinear.newton as S

    monkeypatch.setattr(S, "RELAX_MAX_ITER", 2)
    r = run_cli(["equilibrium", "examples/folded_six_ring.toml", "--perturb", "0.1",
                 "--elements", "8"])
    assert r.exit_code == 3, (r.exit_code, r.stderr)
    line = next(k for k in r.stdout.splitlines() if k.startswith("stability"))
    assert "not judged (Newton did not converge" in line and "NOT stable" not in line


@pytest.mark.slow
def test_cli_continue_not_converged_prints_table_then_exit_3(run_cli, tmp_path):
    """A straight rod turned in plane 0 -> 12 rad at its sliding clamp: the step budget
    (8 x 6 steps) ends near 3.1 rad, so the path is not complete: table, then exit 3."""
    design = tmp_path / "straight0.toml"
    design.write_text(STRAIGHT_TOML.replace("natural_curvature = 1.0", "natural_curvature = 0.0"))
    r = run_cli(["continue", str(design), "--vary", "support.1.rotation.binormal=0:12:6",
                 "--elements", "6", "--branch-steps", "0", "--no-progress"])
    assert r.exit_code == 3, (r.exit_code, r.stderr)
    assert "path STOPPED" in r.stdout
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("rodstab: not converged:"), r.stderr
    assert "support.1.rotation.binormal" in lines[0]


def test_cli_not_converged_raised_by_a_solver_is_exit_3(run_cli, tmp_path, monkeypatch):
    """NotConverged raised inside a command (e.g. the start of a path cannot be reached)."""
    import rodstab.nonlinear.continuation as paths
    from rodstab.errors import NotConverged

    def fail(*args, **kwargs):
        raise NotConverged("no equilibrium found at load_factor = 1.0")

    monkeypatch.setattr(paths, "continuation", fail)
    r = run_cli(_vary_args("continue", "=1:2:2", tmp_path))
    assert r.exit_code == 3
    assert r.stderr == "rodstab: not converged: no equilibrium found at load_factor = 1.0\n"


# ------------------------------------------------------------- anything else is a bug


def test_cli_internal_value_error_is_not_reported_as_bad_input(run_cli, monkeypatch):
    """A plain ValueError inside a solver (say from NumPy) is a bug: main() does not turn it
    into an exit-2 'bad input' line; the exception propagates (traceback, exit status 1)."""
    import rodstab.linear.solve as solve

    def broken(*args, **kwargs):
        raise ValueError("array must not contain infs or NaNs")

    monkeypatch.setattr(solve, "linear_stability", broken)
    with pytest.raises(ValueError, match="infs or NaNs") as info:
        run_cli(["analyze", "examples/birod.toml", "--json"])
    assert type(info.value) is ValueError


@pytest.mark.parametrize("argv", [["--help"], ["section", "--json"],
                                  ["ring", "--loops", "3", "--json"],
                                  ["michell", "--loops", "2", "--json"]])
@pytest.mark.slow
def test_closed_form_commands_import_no_scipy(argv):
    """Issue 12's start-up target: --help and the closed-form commands (section, ring,
    michell) import no scipy module (scipy.linalg and scipy.sparse cost ~0.3 s to import)."""
    import subprocess
    import sys

    code = ("import sys\nfrom rodstab.cli import main\ntry:\n    main(sys.argv[1:])\n"
            "except SystemExit:\n    pass\n"
            "print('SCIPY', sorted(m for m in sys.modules if m.split('.')[0] == 'scipy'))")
    r = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True,
                       timeout=60)
    line = next(x for x in r.stdout.splitlines() if x.startswith("SCIPY"))
    assert line == "SCIPY []", line


@pytest.mark.parametrize("argv, imports_pint", [
    (["--help"], False), (["section", "--json"], False), (["ring", "--loops", "3"], False),
    (["section", "--shape", "rectangle", "--aspect", "2"], False),
    (["section", "--shape", "rectangle", "--height", "2", "--thickness", "1"], False),
    (["section", "--shape", "rectangle", "--height", "2 mm", "--thickness", "1 mm"], True),
    (["analyze", "examples/birod.toml", "--elements", "4"], False),
    (["analyze", "examples/steel_birod_fig7a.toml", "--elements", "4"], True)])
@pytest.mark.slow
def test_pint_is_imported_only_for_a_design_with_units(argv, imports_pint):
    """Issue 13: pint (~0.6 s with its registry) is imported lazily: --help, the closed-form
    commands and designs of plain numbers never import it; a design with units does."""
    import subprocess
    import sys
    from pathlib import Path

    code = ("import sys\nfrom rodstab.cli import main\ntry:\n    main(sys.argv[1:])\n"
            "except SystemExit:\n    pass\nprint('PINT', 'pint' in sys.modules)")
    r = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True,
                       timeout=60, cwd=Path(__file__).resolve().parent.parent)
    line = next(x for x in r.stdout.splitlines() if x.startswith("PINT"))
    assert line == f"PINT {imports_pint}", r.stdout + r.stderr


def test_continue_states_its_mesh_error_and_richardson_reaches_the_closed_form(run_cli):
    """Issue 12: a special point of `continue` carries its discretisation error. Straightened
    clamped rod (circle, nu = 1/3), 16 elements: the branch point is ~1.2 % above (3.9)'s
    2 pi sqrt(b1 b2); 32 elements and Richardson (order 2) land within 1e-4 of it, and the
    stated error of the 16-element value is the actual one to 5 %."""
    from rodstab.analytic.arc import straight_clamped_critical
    from rodstab.sections import circle

    r = run_cli(["continue", "examples/straight_clamped_rod.toml", "--vary", "load_factor=4:7:6",
                 "--no-progress", "--json"])
    assert r.exit_code == 0, r.stderr
    (p,) = json.loads(r.stdout)["special_points"]
    c = circle(nu=1 / 3)
    exact = straight_clamped_critical(c.b1, c.b2)
    assert p["elements_fine"] == 32
    assert abs(p["value_extrapolated"] - exact) <= 1e-4 * exact
    actual = abs(p["value"] - exact)
    assert actual > 0.01 * exact  # the 16-element value is visibly off ...
    assert p["error_estimate"] == pytest.approx(actual, rel=0.05)  # ... and says by how much
    assert math.isclose(p["value_fine"], exact, rel_tol=0.01)


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_elapsed_indicator_shows_after_its_delay_on_a_terminal_and_clears_its_line():
    """A command without its own progress bar says it is working once it has run ``after``
    seconds, on a terminal only, and clears the line before any output and at its end."""
    import time

    from rodstab.cli.output import elapsed_indicator
    from rodstab.cli.output import quiet_indicator as _quiet_indicator

    tty = _Tty()
    with elapsed_indicator("rodstab x: working", tty, after=0.05, tick=0.01):
        deadline = time.monotonic() + 10.0  # a loaded machine may start the thread late
        while "working:" not in tty.getvalue() and time.monotonic() < deadline:
            time.sleep(0.01)
        _quiet_indicator()  # what _emit does before the output
        before_output = tty.getvalue()
        time.sleep(0.1)
    out = tty.getvalue()
    drawn = re.findall(r"\rrodstab x: working: \d+ s", before_output)
    assert drawn, before_output
    assert before_output.endswith("\r" + " " * (len(drawn[-1]) - 1) + "\r")
    assert out == before_output  # nothing drawn after the output began
    quiet = _Tty()
    with elapsed_indicator("rodstab y", quiet, after=1.0, tick=0.01):
        time.sleep(0.1)
    assert quiet.getvalue() == ""  # a fast command shows nothing
    pipe = io.StringIO()
    with elapsed_indicator("rodstab z", pipe, after=0.0, tick=0.01):
        time.sleep(0.1)
    assert pipe.getvalue() == ""  # not a terminal: nothing


#: The commands that solve no FE or nonlinear model (closed forms, or a list of held states):
#: they take no size limits. Every other command takes --max-dof, --max-steps, --max-memory.
WITHOUT_LIMITS = {"section", "arc", "arc-max-length", "states", "reproduce"}


def test_every_solving_command_has_the_limit_options():
    """Issue 20: one definition of the limit options (cli.options.limit_options), on every
    command that solves, barrier and transitions included."""
    from rodstab.cli import cli

    for name, command in cli.commands.items():
        options = {o for p in command.params for o in p.opts}
        has = {"--max-dof", "--max-steps", "--max-memory"} <= options
        assert has == (name not in WITHOUT_LIMITS), name


@pytest.mark.parametrize("argv", [
    ["transitions", "--elements", "6", "--shape", "rectangle", "--aspect", "4"],
    ["barrier", "--elements", "6", "--shape", "rectangle", "--aspect", "4", "--load-factor", "1"]])
def test_barrier_and_transitions_are_sized_against_max_dof_before_solving(argv, run_cli):
    r = run_cli([*argv, "--max-dof", "10"])
    assert r.exit_code == 2 and not r.stdout
    assert "unknowns" in r.stderr and "--max-dof" in r.stderr, r.stderr
