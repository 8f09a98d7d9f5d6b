"""Table: the hexagram's star -> daisy barrier with and without contact (issue 21, part 4).

Runs ``rodstab barrier --structure hexagram --from star --to daisy --shape rectangle --aspect 4
--load-factor 1.5`` (17 images) with and without ``--contact`` at each (elements per rod,
h / L, dhat / h) of ``CASES`` and prints: the forward barrier both ways, the closest approach
of two non-excluded elements over the path's states (over h) both ways, the soft stages the
contact path needed, and the wall time of each run. The table of docs/theory/contact.md
("Barriers with contact") was measured with it (2026-12-05).

Run: ``python benchmarks/string_contact.py [--quick]`` (``--quick``: the first case only).
"""

from __future__ import annotations

import json
import subprocess
import sys
import time

BASE = ["barrier", "--structure", "hexagram", "--from", "star", "--to", "daisy", "--shape",
        "rectangle", "--aspect", "4", "--load-factor", "1.5", "--json"]
CASES = [(6, 0.02, 0.1), (6, 0.02, 0.05), (6, 0.02, 0.025), (6, 0.05, 0.1), (8, 0.02, 0.1),
         (8, 0.02, 0.05), (8, 0.02, 0.025), (10, 0.02, 0.1), (10, 0.02, 0.05),
         (10, 0.02, 0.025)]


def run(args: list[str]) -> tuple[dict, float]:
    t = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "rodstab.cli", *BASE, *args], capture_output=True,
                       text=True)
    dt = time.perf_counter() - t
    if r.returncode != 0:
        return {"error": r.stderr.strip().splitlines()[-1]}, dt
    return json.loads(r.stdout), dt


def main() -> None:
    cases = CASES[:1] if "--quick" in sys.argv else CASES
    print(f"{'el.':>4} {'h/L':>5} {'dhat/h':>6} {'without':>10} {'with':>10} "
          f"{'closest w/o':>11} {'with':>7} {'stages':>6} {'s w/o':>6} {'s with':>6}")
    plain: dict[tuple[int, float], tuple[dict, float]] = {}
    for n, h, c in cases:
        if (n, h) not in plain:
            plain[(n, h)] = run(["--elements", str(n), "--contact-thickness", str(h)])
        p, tp = plain[(n, h)]
        w, tw = run(["--elements", str(n), "--contact", "--contact-thickness", str(h),
                     "--contact-dhat", str(c)])
        if "error" in w or "error" in p:
            print(f"{n:>4} {h:>5} {c:>6}  {w.get('error') or p.get('error')}")
            continue
        print(f"{n:>4} {h:>5} {c:>6} {p['barrier_forward']:>10.6g} {w['barrier_forward']:>10.6g} "
              f"{p['contact']['min_distance']:>11.4g} {w['contact']['min_distance']:>7.4g} "
              f"{len(w['contact']['soft_stages']['stiffnesses']):>6} {tp:>6.1f} {tw:>6.1f}")


if __name__ == "__main__":
    main()
