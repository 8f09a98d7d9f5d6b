"""Benchmark: the hexagram's star -> daisy barrier with contact, with cusp welds of width.

At a point cusp weld two rods of thickness h leave one point along one line, so their end
elements overlap under the contact model, and more so as the mesh refines (the star is outside
the model from 16 el. on; docs/theory/contact.md, "Cusp welds of finite width"). Welds of width
``w = h + 1.5 dhat`` (:func:`rodstab.multistable.discover.common_rod`'s ``cusp_width``) hold
the two ends apart. Printed per mesh (rectangle h/t = 4, kappa_n R0 = 1.5, h = 0.02 L,
dhat = 0.1 h, 17 images unless ``--images``): the string method's barriers star -> daisy and back

* without contact, point welds;
* without contact, wide welds;
* with contact, wide welds: the string brought inside the model by the soft stages
  (``soft`` = (iterations per stage, most stages), default 60 and 14), then relaxed with the
  barrier; the stages used, the closest pair after them, whether two neighbouring images
  of that path (the start of the saddle search) have rods passed through each other between
  them (None: no), and the reported path (the saddle and its two descents with contact,
  every step filtered) judged on every pair the contact model sees.

Run: ``OMP_NUM_THREADS=1 python benchmarks/wide_cusp_barrier.py [elements ...] [--soft IT
STAGES] [--images N] [--dhat D] [--no-contact]`` (default 6 8, 17 images, D = 0.1 h).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from rodstab.errors import NotConverged, RodstabInputError
from rodstab.multistable.discover import common_rod
from rodstab.multistable.string_method import string_barrier
from rodstab.multistable.transitions import ContactTracker, judged_pairs
from rodstab.nonlinear.contact import Interpenetration
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H, DHAT, LOAD = 0.02, 0.1, 1.5


def _judged(xs: list[np.ndarray], rod, model) -> str:  # noqa: ANN001
    """The reported path judged as a transition's stretch, on every pair the model sees."""
    tracker = ContactTracker(rod, H, xs[0], pairs=judged_pairs(rod, model))
    rep = tracker.stretch("path", [(float(k), x) for k, x in enumerate(xs)])
    return (f"reported path ({rep.samples} points, {len(tracker.pairs)} pairs): closest "
            f"{rep.min_distance:.4f} h, "
            + ("RODS PASS THROUGH" if rep.pass_through else "no pass-through"))


def _row(label: str, star, daisy, **kw) -> None:  # noqa: ANN001, ANN003
    t = time.perf_counter()
    try:
        b, snaps = string_barrier(star, daisy, LOAD, **kw)
    except (NotConverged, RodstabInputError, Interpenetration) as exc:
        print(f"  {label:28s} {type(exc).__name__}: {str(exc)[:160]} "
              f"({time.perf_counter() - t:.0f} s)", flush=True)
        return
    extra = ""
    stages = getattr(b.string_run, "contact_stages", None)
    if stages is not None:
        rod = common_rod(star, kw["elements_per_segment"], LOAD, cusp_width=kw["cusp_width"])
        extra = (f"; {len(stages.stiffnesses)} soft stages, closest pair after them "
                 f"{stages.distances[-1] / H:.4f} h, rods pass between images of the stages' "
                 f"path {stages.start_crossing}; "
                 + _judged([s.x for s in snaps], rod, kw["contact"]))
    print(f"  {label:28s} forward {b.barrier_forward:.7f}  backward {b.barrier_backward:.7f}"
          f"  converged {b.converged}{extra} ({time.perf_counter() - t:.0f} s)", flush=True)


def main(meshes: list[int], soft: tuple[int, int], contact: bool, images: int = 17,
         dhat: float = DHAT) -> None:
    """Print the module doc's rows for each mesh (``dhat`` in units of h)."""
    sec = rectangle(aspect=4.0)
    star = state_assembly("hexagram", sec, "star")
    daisy = state_assembly("hexagram", sec, "daisy")
    model = rod_contact_model(star, H, dhat)
    w = H + 1.5 * model.dhat
    for n in meshes:
        print(f"{n} el. per rod (dhat {dhat:g} h, cusp width {w:g}):", flush=True)
        kw = dict(elements_per_segment=n, images=images, name_a="star", name_b="daisy")
        _row("no contact, point welds", star, daisy, **kw)
        _row("no contact, wide welds", star, daisy, cusp_width=w, **kw)
        if contact:
            _row("contact, wide welds", star, daisy, cusp_width=w, contact=model, soft=soft,
                 **kw)


if __name__ == "__main__":
    args = sys.argv[1:]
    soft = (60, 14)
    if "--soft" in args:
        i = args.index("--soft")
        soft = (int(args[i + 1]), int(args[i + 2]))
        del args[i:i + 3]
    images = 17
    if "--images" in args:
        i = args.index("--images")
        images = int(args[i + 1])
        del args[i:i + 2]
    dhat = DHAT
    if "--dhat" in args:
        i = args.index("--dhat")
        dhat = float(args[i + 1])
        del args[i:i + 2]
    contact = "--no-contact" not in args
    args = [a for a in args if a != "--no-contact"]
    main([int(a) for a in args] or [6, 8], soft, contact, images, dhat)
