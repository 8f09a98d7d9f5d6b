"""Benchmark: where the braided eight's branch with contact ends, by two methods side by side.

The braided eight (:func:`rodstab.multistable.braid.hold_braid`: rectangle h/t = 4, relaxed
with contact at kappa_n R0 = 3) followed both ways in the load factor by

* the pseudo-arclength continuation with Hessian eigenvalue monitoring
  (:func:`rodstab.nonlinear.continuation.run.continuation`, ``stop_at_first``): the first
  special point each way (a fold, located where the path turns; a branch point, where the
  lowest eigenvalue changes sign on a smooth path), and
* natural-parameter following (:func:`rodstab.multistable.braid.braid_limits`, the stacked
  ring's :func:`~rodstab.multistable.stacked._side`): a sign change of the verdict eigenvalue
  bracketed and refined, or the branch's end (Newton fails, or the state leaves the branch:
  it lands off the secant through the last two states).

A fold is where the second can only say that the branch ends; the first says that it turns.
Run: ``OMP_NUM_THREADS=1 python benchmarks/eight_braid_fold.py [h/L] [elements] [dhat/h]
[steps]`` (default 0.01 16 0.1 40: continuation steps over 3 -> 7 and 3 -> 0.2).
``--near h/L elements dhat/h LOAD``: Newton steps of 0.01 in the load factor from 3 to LOAD,
then the continuation over 0.5 beyond it (40 steps, at most 160), every special point
printed: started near an end, the path need not cross the rest of the branch first.
``--arc h/L elements dhat/h END STEPS``: the continuation from 3 to END in STEPS steps (at
most three times as many), every special point printed (docs/theory/contact.md, "Finer steps
move the ends").
"""

from __future__ import annotations

import sys
import time

import numpy as np
from eight_braid_hold import NO_CONTACT, START  # this folder, on the path when run as a script

from rodstab.multistable.braid import braid_limits, hold_braid
from rodstab.nonlinear.continuation.run import continuation
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

#: Where the continuation runs to, up and down from :data:`eight_braid_hold.START`.
ENDS = (7.0, 0.2)


def _first(path) -> str:  # noqa: ANN001
    """The continuation's first special point, or how the run ended."""
    if path.special_points:
        p = path.special_points[0]
        return f"{p['kind']} at {p['value']:.5f}"
    return "none (converged)" if path.converged else path.method.split("STOPPED: ")[-1][:60]


def main(h: float, n: int, dhat: float, steps: int) -> None:
    """Print each side's end by both methods."""
    a = state_assembly("hexagram", rectangle(aspect=4.0), "eight")
    t = time.perf_counter()
    _, rod, ok, its, res = hold_braid(a, n, START, h, dhat)
    print(f"h/L {h:g}, {n} el., dhat {dhat:g} h: held at {START} (converged {ok}, {its} "
          f"iterations), energy {rod.energy():.8f}")
    model = rod.contact.model
    runs = {end: continuation(a, "load_factor", START, end, steps, elements_per_segment=n,
                              rod=rod.copy(), contact=model, branch_steps=0,
                              stop_at_first=True) for end in ENDS}
    t_cont = time.perf_counter() - t
    t = time.perf_counter()
    lim = braid_limits(a, NO_CONTACT, thickness_ratio=h, elements_per_segment=n,
                       start_load_factor=START, dhat_fraction=dhat)
    print(f"  start energy by braid_limits {lim.start.energy:.8f} (the same rope if equal)")
    print(f"  upper: continuation {_first(runs[ENDS[0]])}; followed {lim.upper.outcome()}")
    print(f"  lower: continuation {_first(runs[ENDS[1]])}; followed {lim.lower.outcome()}")
    print(f"  ({t_cont:.0f} s and {time.perf_counter() - t:.0f} s)")


def near(h: float, n: int, dhat: float, load: float, steps: int = 40) -> None:
    """Natural steps of 0.01 from the held rope to ``load``, then arclength over 0.5 beyond.

    Steps halved up to four times where Newton fails. ``--near`` (module doc): started near
    an end, the path reaches it instead of failing on
    the way; prints its special points, loads and lowest eigenvalues.
    """
    from rodstab.nonlinear.solve import newton

    a = state_assembly("hexagram", rectangle(aspect=4.0), "eight")
    t = time.perf_counter()
    _, rod, ok, _, _ = hold_braid(a, n, START, h, dhat)
    mu, step = START, 0.01 if load > START else -0.01
    while (mu + step - load) * (1 if step > 0 else -1) <= 1e-12:
        for h_step in step / 2.0 ** np.arange(5):  # halved up to four times on a failure
            trial = rod.copy()
            trial.load_factor = mu + h_step
            if newton(trial)[0]:
                rod, mu = trial, mu + h_step
                break
        else:
            print(f"Newton failed at {mu + step / 16:.5f} (steps halved 4 times)")
            return
    follow(a, rod, mu, mu + (0.5 if step > 0 else -0.5), steps,
           f"h/L {h:g}, {n} el., dhat {dhat:g} h (held at {START}: {ok}): natural steps to "
           f"{mu:.4f}", t)


def follow(a, rod, start: float, end: float, steps: int, label: str, t: float) -> None:  # noqa: ANN001
    """The continuation from ``rod`` at ``start`` to ``end``: special points, loads, eigenvalues."""
    p = continuation(a, "load_factor", start, end, steps, elements_per_segment=len(rod.R_edge)
                     // len(a.segments), rod=rod.copy(),
                     contact=rod.contact.model, branch_steps=0, max_steps_factor=3)
    print(f"{label}, arclength reached [{min(p.value):.5f}, {max(p.value):.5f}] "
          f"({time.perf_counter() - t:.0f} s)")
    for q in p.special_points:
        print(f"  {q['kind']} at {q['value']:.5f}")
    print("  loads", " ".join(f"{v:.4f}" for v in p.value))
    print("  lowest eigenvalues", " ".join(f"{v:.1e}" for v in p.lowest_eigenvalue))


def arc(h: float, n: int, dhat: float, end: float, steps: int) -> None:
    """``--arc``: the continuation from the held rope at 3 to ``end`` in ``steps`` steps."""
    a = state_assembly("hexagram", rectangle(aspect=4.0), "eight")
    t = time.perf_counter()
    _, rod, ok, _, _ = hold_braid(a, n, START, h, dhat)
    follow(a, rod, START, end, steps, f"h/L {h:g}, {n} el., dhat {dhat:g} h (held: {ok})", t)

if __name__ == "__main__":
    args = sys.argv[1:]
    if args[:1] == ["--arc"]:
        arc(float(args[1]), int(args[2]), float(args[3]), float(args[4]), int(args[5]))
        sys.exit(0)
    if args[:1] == ["--near"]:
        near(float(args[1]), int(args[2]), float(args[3]), float(args[4]))
        sys.exit(0)
    main(float(args[0]) if args else 0.01, int(args[1]) if len(args) > 1 else 16,
         float(args[2]) if len(args) > 2 else 0.1, int(args[3]) if len(args) > 3 else 40)
