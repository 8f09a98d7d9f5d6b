"""Design a folding ring.

The six-sided ring of Section 5 (six 120-degree arcs welded at cusps) folds into three straight
loops. Made of rods of natural curvature 1/R0, its one-loop state is stress-free; the folded
state stores energy and must not buckle when the ring is packed. Which rectangular sections
(nu = 1/3) keep the folded ring stable at kappa_n R0 = 1, and with what margin?

The FE engine gives the folded state's critical kappa_n R0 for each candidate h/t, the package's
root finder the smallest h/t at which it reaches 1 and at which it reaches the target 1.5 (a 50 %
margin), and the engine again the stable interval of the one-loop state of the chosen design.
"""

from matplotlib.figure import Figure

from rodstab.numerics import refine_root
from rodstab.problems import folded_ring, unfolded_ring
from rodstab.sections import rectangle

TARGET = 1.5  # required folded-state limit, in units of the stress-free kappa_n R0 = 1


def folded_limit(aspect: float) -> float:
    """Critical kappa_n R0 of the folded state for a rectangle of aspect h/t (FE engine)."""
    params = folded_ring.Params(section=rectangle(aspect=aspect), arc_angle_deg=120.0)
    mu = folded_ring.engine_stability(params, elements=12).load_factor_critical
    return folded_ring.to_paper(mu, params)["kappa_R0"]


aspects = [1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]
limits = [folded_limit(a) for a in aspects]
print(f"{'h/t':>5}  folded limit kappa_n R0")
for a, k in zip(aspects, limits, strict=True):
    print(f"{a:5.2f}  {k:.4f}  {'stable' if k > 1 else 'buckles'} when folded at kappa_n R0 = 1")

first = refine_root(lambda a: folded_limit(a) - 1.0, 1.0, 4.0, rel_xtol=1e-6)
chosen = refine_root(lambda a: folded_limit(a) - TARGET, 1.0, 4.0, rel_xtol=1e-6)
print(f"folded state stable at kappa_n R0 = 1 for h/t > {first:.4f}")
print(f"folded limit {TARGET} (design target) at h/t = {chosen:.4f}")

design = unfolded_ring.Params(section=rectangle(aspect=chosen))
lo, hi = unfolded_ring.engine_stability(design).load_factor_interval
print(f"one-loop state of that ring: stable for {lo:.4f} < kappa_n R0 < {hi:.4f}")
print(f"both states stable at kappa_n R0 = 1: {lo < 1.0 < hi and folded_limit(chosen) > 1.0}")

fig = Figure(figsize=(5.6, 3.6))
ax = fig.subplots()
ax.plot(aspects, limits, "o-", label="folded state: critical kappa_n R0")
ax.axhline(1.0, color="k", lw=0.8, ls=":", label="stress-free one-loop ring")
ax.axhline(TARGET, color="tab:red", lw=0.8, ls="--", label=f"design target {TARGET}")
ax.axvline(chosen, color="tab:red", lw=0.8)
ax.set_xlabel("h / t")
ax.set_ylabel("kappa_n R0")
ax.set_title("Six-sided ring of 120-degree arcs, rectangle, nu = 1/3")
ax.legend(fontsize=8)
ax.grid(alpha=0.3)
fig.savefig("folded_limit.png", dpi=110, bbox_inches="tight")
