"""States of a ring.

`examples/folded_six_ring.toml` describes the folded state of Section 5: six straight rods,
alternately oriented, of natural curvature -1 and +1 (times the load factor), welded at x = 0 and
x = L. `rodstab.multistable.states.ring_of` reads it as what it is: a ring of six identical rods of
natural curvature +1 along the ring, welded end to start at cusps. Every closed planar state of
uniform moment of that ring follows: its label, held curvature, turning number, weld points,
covering and the load factor at which it is stress-free; the stored energy is given at the load
factor of the experiment of Fig. 10 (the one-loop state stress-free, kappa_n L = 2 pi / 3).

For the states with kL >= 0 the script also gives the stable interval of the load factor (the
Bloch method of `rodstab atlas`), and it draws the states.
"""

import math

import numpy as np
from matplotlib.figure import Figure

from rodstab.io.design import load_design
from rodstab.multistable import atlas
from rodstab.multistable.states import ring_of, state_centrelines

design = load_design("examples/folded_six_ring.toml")
ring = ring_of(design.assembly)
print(f"{ring.segments} rods, {ring.weld} welds, length {ring.length:g}, natural curvature "
      f"{ring.natural_curvature:g} per unit load factor along the ring")

load = 2 * math.pi / 3  # kappa_n L of the experiment: the star (one-loop ring) is stress-free
states = ring.states(load_factor=load).states
print(f"{'label':>14} {'kL deg':>7} {'turning':>7} {'welds at':>8} {'covering':>8} "
      f"{'free at':>8} {'energy':>9}  stable load factors")
for st in states:
    if st.theta >= 0:
        lo, hi = atlas.state_interval(ring, st).interval
        stable = f"({lo:.4f}, {hi:.4f})"
    else:
        stable = "(mirror)"
    print(f"{st.label:>14} {math.degrees(st.theta):7.0f} {st.turning_number:7.0f} "
          f"{st.distinct_weld_points:8d} {st.covering:8d} {ring.stress_free_load(st.theta):8.4f} "
          f"{st.energy:9.4f}  {stable}")

shown = [st for st in states if st.theta >= 0]
fig = Figure(figsize=(2.2 * len(shown), 2.6))
for ax, st in zip(fig.subplots(1, len(shown)), shown, strict=True):
    lines = state_centrelines(ring, st.theta)
    for line in lines:
        ax.plot(line[:, 0], line[:, 1], lw=1.5)
    points = np.concatenate(lines)  # a square window round the state (the line has no height)
    centre, half = points.mean(axis=0), 0.55 * np.ptp(points, axis=0).max()
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_title(st.label, fontsize=9)
    ax.set_aspect("equal")
    ax.axis("off")
fig.savefig("states.png", dpi=110, bbox_inches="tight")
