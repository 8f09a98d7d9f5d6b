"""Tests of the ``rodstab`` command line (``rodstab.cli``).

Output is checked through ``click.testing.CliRunner`` on ``rodstab.cli.cli``: every analysis
subcommand's ``--json`` prints exactly one JSON object with the documented keys, and the values
are the paper's closed forms (so the CLI is also an end-to-end check). Exit status and stderr
are checked on the real entry point, ``python -m rodstab.cli`` (``rodstab.cli.main``), run as a
subprocess: every invalid invocation exits with status 2 and prints exactly one line on stderr,
without a traceback, naming the offending option or value.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from click.testing import CliRunner

from rodstab.cli import cli

SRC = Path(__file__).resolve().parents[1] / "src"


def _env() -> dict[str, str]:
    env = os.environ.copy()
    env["PYTHONPATH"] = str(SRC) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH")
                                    else "")
    return env


def _run(args: list[str]) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rodstab.cli", *args], capture_output=True,
                          text=True, env=_env(), timeout=120)


def _reject_nan(token: str) -> None:
    raise AssertionError(f"JSON contains {token}, which is not valid JSON")


def _json(args: list[str]) -> dict:
    """Invoke the CLI in-process; assert exit 0 and exactly one JSON object on one stdout line."""
    result = CliRunner().invoke(cli, args)
    assert result.exit_code == 0, (result.output, result.exception)
    lines = result.stdout.splitlines()
    assert len(lines) == 1, result.stdout
    payload = json.loads(lines[0], parse_constant=_reject_nan)
    assert isinstance(payload, dict)
    return payload


# ------------------------------------------------------------------------------ --json output


def test_cli_section_json_keys_and_circle_values():
    """section --json: b1, b2, sqrt_b1b2; circle nu = 1/3: b1 = 1, b2 = 3/4 (Sec. 3.1)."""
    p = _json(["section", "--json"])
    assert {"b1", "b2", "sqrt_b1b2"} <= p.keys()
    assert p["b1"] == 1.0 and p["b2"] == pytest.approx(0.75, rel=1e-15)
    assert p["sqrt_b1b2"] == pytest.approx(math.sqrt(0.75), rel=1e-15)


def test_cli_section_json_rectangle_and_ratios():
    """Rectangle h/t = 2: b1 = (h/t)^2 = 4; --b1/--b2 given directly are echoed."""
    assert _json(["section", "--shape", "rectangle", "--aspect", "2", "--json"])["b1"] == 4.0
    p = _json(["section", "--b1", "2.5", "--b2", "0.4", "--json"])
    assert (p["b1"], p["b2"], p["sqrt_b1b2"]) == (2.5, 0.4, pytest.approx(1.0, rel=1e-15))


def test_cli_ratios_override_shape_note_goes_to_stderr_not_stdout():
    """--b1/--b2 with an explicit --shape: the documented note is on stderr; stdout stays one
    JSON object with the given ratios (shape 'ratios')."""
    result = CliRunner().invoke(cli, ["section", "--shape", "rectangle", "--b1", "1", "--b2",
                                      "1", "--json"])
    assert result.exit_code == 0
    assert "override" in result.stderr
    p = json.loads(result.stdout)
    assert (p["shape"], p["b1"], p["b2"]) == ("ratios", 1.0, 1.0)


@pytest.mark.parametrize("loops, lo, hi, modes", [
    (1, 7 / 8 - math.sqrt(1 / 64 + 3), 1.0, [2, 0]),
    (3, 7 / 8 - math.sqrt(1 / 64 + 4 / 3), 7 / 8 - math.sqrt(1 / 64 + 1 / 3), [4, 2]),
])
def test_cli_ring_json(loops, lo, hi, modes):
    """ring --loops N --json: loops, M_interval, kappa_L_over_2pi_interval, bounding_modes;
    values from (3.3) for b1 = 1, b2 = 3/4 (M^- = 7/8 - sqrt(1/64 + 3 k^2/4))."""
    p = _json(["ring", "--loops", str(loops), "--json"])
    assert {"loops", "M_interval", "kappa_L_over_2pi_interval", "bounding_modes"} <= p.keys()
    assert p["loops"] == loops
    assert p["M_interval"] == pytest.approx([lo, hi], rel=1e-12)
    assert p["kappa_L_over_2pi_interval"] == pytest.approx(
        [loops * (1 - hi), loops * (1 - lo)], rel=1e-12, abs=1e-14)
    assert p["bounding_modes"] == modes


@pytest.mark.parametrize("extra, g", [([], math.sqrt(0.75)),
                                      (["--b1", "4", "--b2", "0.25"], 1.0)])
def test_cli_arc_json_straight_limit(extra, g):
    """arc --L-over-R 0 --json: L_over_R, L_kappa_interval = +-2 pi sqrt(b1 b2) (3.9),
    critical_mode 'symmetric'."""
    p = _json(["arc", "--L-over-R", "0", *extra, "--json"])
    assert {"L_over_R", "L_kappa_interval", "critical_mode"} <= p.keys()
    assert p["L_over_R"] == 0.0
    assert p["L_kappa_interval"] == pytest.approx([-2 * math.pi * g, 2 * math.pi * g], rel=1e-12)
    assert p["critical_mode"] == "symmetric"


def test_cli_arc_json_curved():
    """arc --L-over-R 3 --json: the interval contains the stress-free state L kappa_n = L/R."""
    p = _json(["arc", "--L-over-R", "3", "--json"])
    lo, hi = p["L_kappa_interval"]
    assert p["L_over_R"] == 3.0 and lo < 3.0 < hi and p["critical_mode"] == "symmetric"


def test_cli_arc_max_length_json():
    """arc-max-length --json: L_over_R_max = 2 pi for b1 = 1 (paper, after (3.14))."""
    p = _json(["arc-max-length", "--json"])
    assert {"L_over_R_max", "critical_mode"} <= p.keys()
    assert p["L_over_R_max"] == pytest.approx(2 * math.pi, rel=1e-12)
    assert p["critical_mode"] == "symmetric"


def test_cli_michell_json():
    """michell --loops 1 --json: b2_omega0_critical = sqrt 3, mode_j = 2 (Sec. 3.3); --loops 3:
    unstable at every twist, the critical twist is null (JSON has no NaN) and mode_j = 1."""
    p = _json(["michell", "--loops", "1", "--json"])
    assert {"b2_omega0_critical", "mode_j"} <= p.keys()
    assert p["b2_omega0_critical"] == pytest.approx(math.sqrt(3), rel=1e-14)
    assert p["mode_j"] == 2
    p = _json(["michell", "--loops", "3", "--json"])
    assert p["b2_omega0_critical"] is None and p["mode_j"] == 1


@pytest.mark.parametrize("args", [["section"], ["ring", "--loops", "3"], ["arc", "--L-over-R", "1"],
                                  ["arc-max-length"], ["michell"]])
def test_cli_table_output_is_not_json(args):
    """Without --json each subcommand prints a readable table (several lines, not JSON)."""
    result = CliRunner().invoke(cli, args)
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("section ")
    with pytest.raises(json.JSONDecodeError):
        json.loads(result.stdout)


def test_cli_main_valid_invocation_exit_0_and_silent_stderr():
    """The real entry point: valid input exits 0 with one JSON line and nothing on stderr."""
    proc = _run(["ring", "--loops", "3", "--json"])
    assert proc.returncode == 0 and proc.stderr == ""
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
    pytest.param(["ring", "--shape", "ellipse", "--b1", "1", "--b2", "1", "--aspect", "3"],
                 ["aspect", "3"]),
]


def _args_of(case):
    return case.values[0] if hasattr(case, "values") else case[0]


@pytest.fixture(scope="module")
def bad_results():
    """Run every invalid invocation once, two at a time (each is a fresh interpreter)."""
    arg_lists = [_args_of(c) for c in BAD_INPUTS]
    with ThreadPoolExecutor(max_workers=2) as pool:
        procs = list(pool.map(_run, arg_lists))
    return {tuple(a): p for a, p in zip(arg_lists, procs, strict=True)}


@pytest.mark.parametrize("args, tokens", BAD_INPUTS,
                         ids=[" ".join(_args_of(c)) for c in BAD_INPUTS])
def test_cli_bad_input_exit_2_one_stderr_line_naming_it(bad_results, args, tokens):
    """Module contract: invalid input exits with status 2 and one line on stderr naming the
    offending option and value; never a traceback; nothing on stdout."""
    assert len(BAD_INPUTS) >= 20
    proc = bad_results[tuple(args)]
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    for token in tokens:
        alternatives = token if isinstance(token, tuple) else (token,)
        assert any(t in lines[0] for t in alternatives), (token, lines[0])
    assert proc.stdout == ""


def test_cli_large_L_over_R_gives_no_traceback():
    """A large but finite L/R is either solved (exit 0) or rejected (exit 2, one line)."""
    proc = _run(["arc", "--L-over-R", "10000", "--json"])
    assert "Traceback" not in proc.stderr
    assert proc.returncode in (0, 2)
