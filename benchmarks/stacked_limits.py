"""Benchmark: stability limits of the stacked 3-loop ring with contact (issue 21, part 3).

For each section, thickness ``h / L`` and ``dhat / h``: :func:`rodstab.multistable.stacked.
stacked_limits` (the torus-curve start relaxed with contact at ``mu = 1``, followed in ``mu``
both ways, each first sign change of the verdict eigenvalue bracketed and refined), beside the
no-contact interval of eq. (3.3) and of the same routine with contact off (coincident planar
ring, same mesh). Prints, per run: the limits in ``(L / 2 pi) kappa_n = N mu``, the bracket,
the limiting mode (harmonics of ``u_3`` and ``u_r``, gap change), the state on the stable side
(smallest gap over dhat, mean contact line load, energy above the coincident ring) and the
time.

Measured 2026-12-05, before the follower checked that each state stays on its branch (the
16-el. rows rerun with the check, 2026-12-06, are in docs/theory/contact.md: every lower side
now ends in a jump before these limits) (circle, b1 = 1, b2 = 0.75; limits in
(L / 2 pi) kappa_n; "end": Newton failed 0.003 in mu past the last stable state, no sign
change; "jump": the eigenvalue jumped, no limit reported). No contact: eq. (3.3) 2.1472 ..
3.8593; this routine 2.1419 .. 3.8643 at 16 elements per loop, 2.1457 .. 3.8608 at 32
(modes j = 2 and j = 4, smooth crossings).

===== ==== ====== ===================================== ====================================
el.   h/L  dhat/h lower (mode)                          upper
===== ==== ====== ===================================== ====================================
32    0.01 0.2    1.7085 (u3 j=1, gap change 0.78)      jump at 4.05
32    0.01 0.1    1.5808 (u3 j=2 / ur j=4, 0.48)        end at 4.35
32    0.01 0.05   1.7361 (u3 j=1, 0.63)                 4.0624 (u3 j=5 / ur j=4, 0.43)
32    0.005 0.2   end at 0.99 (no sign change)          4.2568 (ur j=1, in-plane, 1.01)
32    0.005 0.1   end at 0.84 (no sign change)          end at 4.39
32    0.005 0.05  1.6294 (u3 j=1, 0.79)                 4.3303 (ur j=1 / u3 j=4, 1.08)
64    0.01 0.1    end at 0.87 (no sign change)          end at 4.39
16    0.01 0.2    1.5608 (u3 j=1, 0.78)                 end at 4.18
16    0.01 0.1    1.6037 (u3 j=1, 0.57)                 end at 4.24
16    0.01 0.05   end at 1.55                           end at 4.24
16    0.005 0.2   1.3611 (u3 j=2 / ur j=2, 0.22)        end at 4.38
16    0.005 0.1   1.3560 (u3 j=2 / ur j=2, 0.22)        end at 4.44
16    0.005 0.05  start (mu = 1) unstable: eigenvalue -4.4e-6
===== ==== ====== ===================================== ====================================

On the lower side the near-planar stacked ring does not lose stability at 2.147: past it the
ring deflects out of its plane continuously (32 el., h/L 0.01, dhat 0.1 h: largest |z| 1.6 h
at 2.14, 2.9 h at 1.79, 5.6 h at 1.57), the stacking acting as an imperfection of the j = 2
bifurcation, and that buckled branch loses stability where the table says, or ends. Not
converged in dhat, h or the mesh. On the upper side the near-planar ring (largest |z| still
~1.3 h) stays stable past 3.859 to 4.06 .. 4.44 (every run), where it loses stability to a
gap-changing mode or its branch ends. (Before steps were halved where they leave the branch,
a full step at 64 el. landed on another, unstable branch at 2.715 and gave a false limit.)

Rectangle h/t = 2 (16 el., h/L 0.01): no contact 1.4702 .. 4.7202
(eq. 3.3: 1.4834 .. 4.7149); dhat 0.2 h: lower 2.7409 (ur j=1 / u3 j=2, mostly in-plane),
upper end at 5.00; dhat 0.1 h: the start at mu = 1 is unstable (-1.1e-6).

Run: ``OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/stacked_limits.py [elements]
[shape[:h/L,h/L...]] ... [--stacking wound|folded]`` (shape: circle, rect2; default
thicknesses 0.02, 0.01, 0.005; the tables above are of the wound ring, the torus-curve start).
1-5 min per run at 32 elements per loop (steps are halved where they leave the branch).
"""

from __future__ import annotations

import sys
import time

from rodstab.analytic.ring import ring_stability
from rodstab.multistable.stacked import SideLimit, stacked_limits
from rodstab.problems import ring
from rodstab.sections import circle, rectangle

LOOPS = 3
THICKNESS = (0.02, 0.01, 0.005)
DHAT = tuple(float(v) for v in __import__("os").environ.get("DHAT", "0.2,0.1,0.05").split(","))


def _side(s: SideLimit) -> str:
    lim = f"{LOOPS * s.limit:.4f}" if s.limit == s.limit else "none"
    out = f"{lim:>8} [{LOOPS * s.bracket[0]:.3f}, {LOOPS * s.bracket[1]:.3f}]"
    if s.mode is not None:
        m = s.mode
        out += (f" mode u3 j={m.harmonic_out} ({m.share_out:.2f}) ur j={m.harmonic_in} "
                f"({m.share_in:.2f}) oop {m.out_of_plane:.2f} dgap {m.gap_change:.2f}")
    if s.path:
        z = [p[2] for p in s.path]
        out += (f" | {len(s.path)} states, N mu {LOOPS * s.path[-1][0]:.3f} reached, max|z| "
                f"{z[0]:.3g} -> {z[-1]:.3g}")
    if s.at_limit is not None and s.at_limit.dhat == s.at_limit.dhat:
        st = s.at_limit
        out += (f" | gap/dhat {st.min_gap / st.dhat:.2f} q {st.line_load_mean:.3g} loaded "
                f"{st.loaded_fraction:.2f} dE {st.energy - st.energy_coincident:.3g}")
    out += f" | {s.how}"
    return out


def main() -> None:
    """Print the tables (module doc)."""
    args = sys.argv[1:]
    stacking = "wound"
    if "--stacking" in args:
        i = args.index("--stacking")
        stacking = args[i + 1]
        del args[i:i + 2]
    n = int(args[0]) if args else 32
    shapes = args[1:] or ["circle"]
    for spec in shapes:
        shape, _, hs = spec.partition(":")
        thicknesses = tuple(float(v) for v in hs.split(",")) if hs else THICKNESS
        section = circle() if shape == "circle" else rectangle(aspect=2.0)
        p = ring.Params(loops=LOOPS, section=section)
        M_lo, M_hi = ring_stability(section.b1, section.b2, LOOPS).M_interval
        nc = (1.0 - M_hi, 1.0 - M_lo)
        a = ring.build(p)
        print(f"== {stacking} stacking: {shape} (b1 = {section.b1:.4g}, "
              f"b2 = {section.b2:.4g}), {LOOPS} loops, "
              f"{n} elements per loop; capsules of diameter h, dhat = c h, stiffness by "
              "stiffness_for_line_load(B3 a / R0^4, dhat, 1/2)", flush=True)
        print(f"eq. (3.3), no contact: {LOOPS * nc[0]:.4f} .. {LOOPS * nc[1]:.4f}", flush=True)
        t = time.perf_counter()
        r = stacked_limits(a, nc, elements_per_loop=n, contact=False)
        print(f"nonlinear, no contact, coincident ring: lower {_side(r.lower)}\n"
              f"    upper {_side(r.upper)}  ({time.perf_counter() - t:.1f} s)", flush=True)
        for hL in thicknesses:
            for c in DHAT:
                t = time.perf_counter()
                try:
                    r = stacked_limits(a, nc, thickness_ratio=hL, elements_per_loop=n,
                                       dhat_fraction=c, stacking=stacking)
                except Exception as exc:  # a benchmark reports every run
                    print(f"h/L {hL:g} dhat/h {c:g}: failed: {type(exc).__name__}: {exc}",
                          flush=True)
                    continue
                st = r.start
                print(f"h/L {hL:g} dhat/h {c:g}: start mu=1: gap/dhat "
                      f"{st.min_gap / st.dhat:.2f} q {st.line_load_mean:.3g} loaded "
                      f"{st.loaded_fraction:.2f} dE {st.energy - st.energy_coincident:.3g} "
                      f"max|z|/h {st.max_height / (hL * a.total_length):.2f} "
                      f"({time.perf_counter() - t:.1f} s)\n"
                      f"    lower {_side(r.lower)}\n    upper {_side(r.upper)}", flush=True)


if __name__ == "__main__":
    main()
