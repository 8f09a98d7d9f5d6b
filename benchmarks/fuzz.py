"""Long fuzz run of the ``rodstab`` CLI (issue 10), on demand.

    OMP_NUM_THREADS=1 python benchmarks/fuzz.py [--examples 10000] [--seed 0] [--hang 30]

Runs ``--examples`` cases of tests/fuzz_inputs.py (fuzzed design files and numeric options,
each bounded by small meshes, ``--max-dof`` and ``--max-steps``) in-process through the real
entry point, and prints a tally: examples, exit statuses 0/2/3, tracebacks (any other
exception, or another status), hangs (a case still running after ``--hang`` seconds, stopped
by SIGALRM), the slowest case. Each traceback or hang is written to ``--report`` (argv, design
bytes, traceback) to be turned into a table test. Exit status 1 if there was any.
"""

from __future__ import annotations

import argparse
import collections
import json
import signal
import sys
import tempfile
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from conftest import run_cli  # noqa: E402
from fuzz_inputs import Case, argv_of, cli_case  # noqa: E402
from hypothesis import HealthCheck, given, seed, settings  # noqa: E402


class Hang(BaseException):
    """A case ran past its time bound (raised by SIGALRM)."""


def _alarm(signum: int, frame: object) -> None:
    raise Hang()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--hang", type=int, default=30, help="seconds before a case is a hang")
    ap.add_argument("--report", type=Path, default=Path("fuzz-report"))
    args = ap.parse_args()
    tally: collections.Counter[str] = collections.Counter()
    by_command: collections.Counter[str] = collections.Counter()
    failures: list[dict] = []
    slowest = (0.0, "")
    signal.signal(signal.SIGALRM, _alarm)
    t_start = time.perf_counter()

    @seed(args.seed)
    @settings(max_examples=args.examples, deadline=None, database=None,
              suppress_health_check=list(HealthCheck), phases=["generate"])
    @given(case=cli_case())
    def run(case: Case) -> None:
        nonlocal slowest
        with tempfile.TemporaryDirectory() as tmp:
            argv = argv_of(case, Path(tmp))
            t0 = time.perf_counter()
            signal.alarm(args.hang)
            try:
                r = run_cli(argv)
                outcome = str(r.exit_code) if r.exit_code in (0, 2, 3) else "traceback"
                detail = r.stderr[-3000:]
            except Hang:
                outcome, detail = "hang", f"still running after {args.hang} s"
            except Exception:  # a traceback the user would see
                outcome, detail = "traceback", traceback.format_exc()[-4000:]
            finally:
                signal.alarm(0)
            dt = time.perf_counter() - t0
        tally["examples"] += 1
        tally[outcome] += 1
        by_command[f"{case.argv[0]} -> {outcome}"] += 1
        if dt > slowest[0]:
            slowest = (dt, " ".join(argv)[:200])
        if outcome in ("traceback", "hang"):
            failures.append({"outcome": outcome, "argv": list(case.argv),
                             "design": None if case.design is None
                             else case.design.decode("utf-8", "replace"),
                             "detail": detail})
        if tally["examples"] % 1000 == 0:
            print(f"  {tally['examples']} examples, {time.perf_counter() - t_start:.0f} s, "
                  f"{tally['traceback']} tracebacks, {tally['hang']} hangs", flush=True)

    run()
    elapsed = time.perf_counter() - t_start
    print(f"examples     {tally['examples']} in {elapsed:.0f} s (seed {args.seed})")
    print(f"exit 0       {tally['0']}")
    print(f"exit 2       {tally['2']}")
    print(f"exit 3       {tally['3']}")
    print(f"tracebacks   {tally['traceback']}")
    print(f"hangs        {tally['hang']} (bound {args.hang} s)")
    print(f"slowest      {slowest[0]:.2f} s: {slowest[1]}")
    print("by command   " + ", ".join(f"{k}: {v}" for k, v in sorted(by_command.items())))
    if failures:
        args.report.mkdir(parents=True, exist_ok=True)
        out = args.report / f"failures-seed{args.seed}.json"
        out.write_text(json.dumps(failures, indent=1))
        print(f"failures     written to {out}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
