"""The command lines whose ``--json`` output must not change across refactorings.

Shared by ``tests/test_cli_outputs.py`` (which compares the current output with the recorded
one) and ``tests/data/record_cli_outputs.py`` (which records them from a given checkout).
Both recordings are **regression checks against earlier commits of this project**, not
independent references: they catch a refactoring that changes a number, not a number that was
wrong when recorded (each command's correctness is tested against closed forms, limits and
other methods in its own test module). ``CASES`` were recorded at 07ed206, ``LATER_CASES``
(the multistable commands and the examples 07ed206 could not read) at e0b77e8, the last
commit before the issue-20 split of the command line.
Every subcommand except ``reproduce`` (its numbers are the report's, compared row by row by
``tests/test_checks.py``) appears, and the design-file commands run on every example.
Output paths (``--out``) are written under a temporary directory named by ``{tmp}``.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: Examples added after the recording (07ed206 cannot read them), each with its own tests:
#: hexagram.toml in tests/test_atlas.py, polygon_section.toml in tests/test_polygon_sections.py,
#: the examples in physical units in tests/test_units.py (and every example in
#: tests/test_design.py).
NEW_EXAMPLES = {"examples/hexagram.toml": "tests/test_atlas.py",
                "examples/polygon_section.toml": "tests/test_polygon_sections.py",
                "examples/steel_birod_fig7a.toml": "tests/test_units.py",
                "examples/steel_birod_fig7b.toml": "tests/test_units.py",
                "examples/steel_strip_six_ring.toml": "tests/test_units.py",
                "examples/hexagram_strip.toml": "tests/test_units.py"}
#: Examples added after e0b77e8 too: in no recording; each with its own tests (and in
#: tests/test_design.py and the docs' gallery like every example).
UNRECORDED_EXAMPLES = {"examples/hexagram_eight.toml": "tests/test_braid.py",
                       "examples/hexagram_unequal.toml": "tests/test_atlas.py"}
EXAMPLES = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "examples").glob("*.toml")
                  if p.relative_to(ROOT).as_posix() not in NEW_EXAMPLES | UNRECORDED_EXAMPLES)

_SECTIONS = [[], ["--shape", "rectangle", "--aspect", "4"], ["--shape", "ellipse", "--aspect",
             "2"], ["--shape", "tube", "--aspect", "0.5"], ["--shape", "rectangle", "--aspect",
             "4", "--torsion", "paper"], ["--b1", "4", "--b2", "0.9"]]

CASES: list[list[str]] = (
    [["section", *s] for s in _SECTIONS]
    + [["ring", "--loops", str(n), *s] for n in (1, 2, 3) for s in _SECTIONS[:2]]
    + [["arc", "--L-over-R", x, *s] for x in ("0", "0.5", "2", "4") for s in _SECTIONS[:2]]
    + [["arc-max-length", *s] for s in _SECTIONS[:3]]
    + [["michell", "--loops", str(n), *s] for n in (1, 2, 3) for s in _SECTIONS[:2]]
    + [["birod", *s] for s in (_SECTIONS[0], _SECTIONS[1], _SECTIONS[5])]
    + [["folded-ring", *s] for s in ([], ["--segments", "8"], ["--arc-angle", "90"],
                                      _SECTIONS[1])]
    + [["analyze", e] for e in EXAMPLES]
    + [["analyze", e, "--elements", "8"] for e in EXAMPLES]
    + [["equilibrium", e] for e in EXAMPLES]
    + [["equilibrium", "examples/birod.toml", "--load-factor", "0.5"],
       ["equilibrium", "examples/straight_clamped_rod.toml", "--load-factor", "6",
        "--perturb", "0.01"]]
    + [["sweep", "examples/clamped_arc.toml", "--vary", "section.aspect=1:3:3",
        "--elements", "16", "--no-progress", "--out", "{tmp}/sweep"],
       ["continue", "examples/straight_clamped_rod.toml", "--vary", "load_factor=4:7:6",
        "--elements", "12", "--branch-steps", "4", "--no-progress"],
       ["continue", "examples/twisted_rod.toml", "--vary",
        "support.1.rotation.tangent=0:14:7", "--elements", "8", "--branch-steps", "0",
        "--no-progress"]]
)


#: Recorded at e0b77e8 (``tests/data/cli_outputs_e0b77e8.json``): the multistable commands
#: and the examples added after 07ed206. Sections where the states are stable at the default
#: loads (the circle's hexagram line is not stable at kappa_n R0 = 2).
_RECT4 = ["--shape", "rectangle", "--aspect", "4"]
LATER_CASES: list[list[str]] = (
    [["states"], ["states", "--segments", "4", "--smooth", "--max-turns", "2"],
     ["states", "examples/hexagram.toml"], ["states", "examples/hexagram.toml",
                                            "--load-factor", "2"],
     ["states", "examples/unfolded_six_ring.toml"],
     ["hexagram"], ["hexagram", *_RECT4], ["hexagram", "--method", "fe", *_RECT4],
     ["hexagram", "--threshold", "--shape", "rectangle"],
     ["atlas", "examples/hexagram.toml", "--vary", "section.aspect=2:4:2", "--workers", "0",
      "--no-progress", "--out", "{tmp}/atlas"],
     ["transitions", "--elements", "6", *_RECT4, "--out", "{tmp}/transitions"],
     # --load-factor 1: e0b77e8's default (now the middle of the states' common interval)
     ["barrier", "--elements", "6", "--images", "7", *_RECT4, "--load-factor", "1"],
     ["barrier", "--method", "continuation", "--elements", "6", *_RECT4, "--load-factor",
      "1"],
     ["barrier", "examples/hexagram.toml", "--from", "star", "--to", "daisy", "--elements",
      "6"],
     ["discover", "--starts", "2", "--elements", "8"],
     ["discover", "examples/hexagram.toml", "--starts", "2", "--elements", "8",
      "--no-seed-states"]]
    + [["analyze", e] for e in sorted(NEW_EXAMPLES)]
    + [["equilibrium", e] for e in sorted(NEW_EXAMPLES)]
)


#: Commands added after e0b77e8, each recorded at the commit that added it (``meta`` of
#: ``tests/data/cli_outputs_new.json`` names it).
NEW_CASES: list[list[str]] = [
    ["diagram", "--elements", "6", "--shape", "rectangle", "--aspect", "4", "--vary",
     "load_factor=0.9:1.1:2", "--starts", "0", "--no-progress", "--out", "{tmp}/diagram"],
]


def case_id(args: list[str]) -> str:
    """A readable, unique test id of a command line."""
    return " ".join(a for a in args if not a.startswith("{tmp}"))
