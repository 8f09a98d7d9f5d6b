"""Check a hexagram.

A curved-sided hexagram is six identical rods welded end to start at cusps. Built from rods of
natural curvature 1/R0 (R0 = 3L/2pi, the radius of the star's arcs) it can rest in four states:
the line (the folded state of Section 5), the star, the daisy and the eight. Each is stable in an
interval of the load kappa_n R0; a hexagram is *tetrastable* where the four intervals overlap.

This script checks a rectangular section of aspect h/t = 4 (nu = 1/3): the stable interval of
each state by the exact P2 on one arc with a Bloch phase per harmonic (the default method of
`rodstab hexagram`) and by the FE engine on the whole ring, the interval where all four are
stable together, and which two limits bind it. It draws the four bands.
"""

from matplotlib.figure import Figure

from rodstab.problems import hexagram
from rodstab.sections import rectangle

section = rectangle(aspect=4.0)  # nu = 1/3, exact Saint-Venant torsion
print(f"rectangle h/t = 4: b1 = {section.b1:.5g}, b2 = {section.b2:.5g}")

bloch = hexagram.atlas(section)  # transfer: one arc, Bloch phase per harmonic
fe = hexagram.atlas(section, method="fe")  # FE on the whole ring, Richardson 32/64 elements
print(f"{'state':>6}  {'lower':>9}  {'upper':>9}   |FE - Bloch|")
for state, (lo, hi) in bloch.states.items():
    flo, fhi = fe.states[state]
    print(f"{state:>6}  {lo:9.5f}  {hi:9.5f}   {max(abs(flo - lo), abs(fhi - hi)):.1e}")

if bloch.all_four is None:
    print("no kappa_n R0 at which all four states are stable")
else:
    lo, hi = bloch.all_four
    low, up = hexagram.binding_limits(bloch)
    print(f"all four stable for {lo:.5f} < kappa_n R0 < {hi:.5f} (bound by {low} and {up})")
    print(f"a hexagram of stress-free star (kappa_n R0 = 1) is tetrastable: {lo < 1 < hi}")

fig = Figure(figsize=(6.0, 2.8))
ax = fig.subplots()
for i, (lo, hi) in enumerate(bloch.states.values()):
    ax.barh(i, hi - lo, left=lo, height=0.5)
if bloch.all_four is not None:
    ax.axvspan(*bloch.all_four, color="k", alpha=0.12, label="all four stable")
    ax.legend(loc="lower right", fontsize=8)
ax.set_yticks(range(len(bloch.states)), list(bloch.states))
ax.set_xlabel("kappa_n R0")
ax.set_title("Hexagram, rectangle h/t = 4: stable interval of each state")
ax.grid(alpha=0.3)
fig.savefig("bands.png", dpi=110, bbox_inches="tight")
