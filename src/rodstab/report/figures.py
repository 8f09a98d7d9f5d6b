"""Figures of the reproduction report, drawn from the data dicts of :mod:`rodstab.checks`.

No mathematics here: every number plotted comes from the data passed in. Figures are built with
matplotlib's object API (:class:`matplotlib.figure.Figure`), not pyplot: no backend is selected
and no global figure state is touched.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from ..plot.plots import exponents_in_labels, plain_log_ticks


def _save(fig, out: Path, stem: str) -> list[Path]:
    exponents_in_labels(fig)
    paths = []
    for ext in ("png", "svg"):
        p = out / f"{stem}.{ext}"
        fig.savefig(p, dpi=130, bbox_inches="tight")
        paths.append(p)
    return paths


def fig3(data: dict, out: Path) -> list[Path]:
    """Fig. 3: stable range of L kappa_n vs L/R for clamped arcs (upper and lower branch)."""
    fig = Figure(figsize=(6.4, 4.6))
    ax = fig.subplots()
    for cv in data["curves"]:
        style = "--" if cv["label"] == "circle" else "-"
        (line,) = ax.plot(data["L_over_R"], cv["upper"], style, label=cv["label"])
        ax.plot(data["L_over_R"], cv["lower"], style, color=line.get_color(), alpha=0.35)
    ax.plot(data["L_over_R"], data["L_over_R"], ":", color="k", lw=0.8,
            label="stress-free (kappa_n = 1/R)")
    ax.set_xlabel("L / R")
    ax.set_ylabel("L kappa_n")
    ax.set_title("Clamped arc: stable between lower (faint) and upper curves (nu = 1/3)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return _save(fig, out, "fig3_arc_stability")


def fig4(data: dict, out: Path) -> list[Path]:
    """Fig. 4: sqrt(B1 B2)/B3 vs h/t, exact torsion and the paper's (3.12)."""
    fig = Figure(figsize=(6.0, 4.4))
    ax = fig.subplots()
    ax.loglog(data["h_over_t"], data["rectangle_exact"], label="rectangle, exact Saint-Venant")
    ax.loglog(data["h_over_t"], data["rectangle_paper"], "--", label="rectangle, paper (3.12)")
    ax.loglog(data["h_over_t"], data["ellipse"], label="ellipse (3.11) = exact")
    ax.axhline(data["circle"], color="k", lw=0.8, ls=":", label="circle 1/sqrt(1+nu)")
    ax.set_xlabel("h / t")
    ax.set_ylabel("sqrt(B1 B2) / B3")
    ax.set_title("Fig. 4 (nu = 1/3)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return _save(fig, out, "fig4_stiffness_combination")


def fig5(data: dict, out: Path) -> list[Path]:
    """Fig. 5: longest stable clamped arc of a straight rod vs h/t."""
    fig = Figure(figsize=(6.0, 4.4))
    ax = fig.subplots()
    ax.plot(data["h_over_t"], data["exact"], label="exact torsion")
    ax.plot(data["h_over_t"], data["paper"], "--", label="paper (3.12) torsion")
    ax.axhline(2 * math.pi, color="k", lw=0.8, ls=":", label="2 pi (h/t = 1)")
    ax.set_xlabel("h / t")
    ax.set_ylabel("max stable L / R")
    ax.set_title("Fig. 5: straight rod bent into a clamped arc (nu = 1/3)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return _save(fig, out, "fig5_max_arc_length")


def fig_rings(data: dict, out: Path) -> list[Path]:
    """Draw the new figure: stable (L/2pi) kappa_n intervals of N-loop rings vs rectangle h/t."""
    fig = Figure(figsize=(6.4, 4.6))
    ax = fig.subplots()
    for N in data["loops"]:
        ivs = data["intervals"][str(N)]
        lo = [iv[0] for iv in ivs]
        hi = [iv[1] for iv in ivs]
        ax.fill_between(data["h_over_t"], lo, hi, alpha=0.35, label=f"N = {N}")
    thr = data.get("overlap_threshold_exact")
    if thr is not None and math.isfinite(thr):
        ax.axvline(thr, color="k", lw=0.8, ls=":", label=f"1/3-loop overlap from h/t = {thr:.3g}")
    ax.set_xscale("log")
    plain_log_ticks(ax.xaxis)  # the minor ticks' 2x10^0 3x10^0 4x10^0 ran together
    # The 1-loop lower end falls to 1 - b1 = 1 - (h/t)^2 (uniform twist); clip to keep the
    # N-loop bands readable and say so in the label.
    ax.set_ylim(-2.0, max(max(iv[1] for iv in data["intervals"][str(N)]) for N in data["loops"])
                + 0.5)
    ax.set_xlabel("h / t (rectangle, exact torsion, nu = 1/3)")
    ax.set_ylabel("(L / 2 pi) kappa_n  (N = 1 band continues below -2)")
    ax.set_title("Stable natural curvature of untwisted N-loop rings")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return _save(fig, out, "fig_rings_intervals")


def fig9(data: dict, out: Path) -> list[Path]:
    """Fig. 9: modal u3/L and twist around the folded six-sided ring (two modes)."""
    fig = Figure(figsize=(7, 2.6 * len(data)))
    axes = fig.subplots(len(data), 1, sharex=True)
    for ax, (label, d) in zip(axes, data.items(), strict=True):
        ax.plot(d["s_over_L"], d["u3_over_L"], label="u3 / L (max 1)")
        om = d["omega"]
        scale = max(abs(v) for v in om) or 1.0
        ax.plot(d["s_over_L"], [v / scale for v in om], "--", label="omega (scaled to 1)")
        for j in range(7):
            ax.plot([j], [0], "ko", ms=4)
        ax.set_title(f"folded six-sided ring, circle nu = 1/3: {label}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[-1].set_xlabel("s / L around the ring (joints: dots)")
    return _save(fig, out, "fig9_folded_ring_modes")


def sweep_plot(rows: list[dict], key: str, out: Path, xlabel: str | None = None) -> Path:
    """Critical load factor (and the lower end of the interval) against the varied key.

    ``xlabel`` names the axis (default ``key``; with its unit, e.g. "section.height [mm]").
    """
    x = [r[key] for r in rows]
    fig = Figure(figsize=(6, 4))
    ax = fig.subplots()
    ax.plot(x, [r["load_factor_critical"] for r in rows], "o-", label="upper end (critical)")
    ax.plot(x, [r["load_factor_lower"] for r in rows], "s--", label="lower end")
    ax.set_xlabel(key if xlabel is None else xlabel)
    ax.set_ylabel("load factor")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("stable between the two curves")
    p = Path(out) / "sweep.png"
    exponents_in_labels(fig)
    fig.savefig(p, dpi=120, bbox_inches="tight")
    return p


def fig_beyond(data: dict, out: Path) -> list[Path]:
    """Draw the beyond-the-paper figure: post-buckling, imperfections, Koiter, ring energy.

    Post-buckled branches, imperfect paths of the straightened rod, Koiter's law of the twisted rod,
    and the energy along the 1-loop -> 3-loop ring path.
    """
    fig = Figure(figsize=(12, 13))
    axes = fig.subplots(3, 2)
    ax = axes[0, 0]
    for name, br in data["branches"].items():
        ax.plot(br["amplitude"], br["mu_over_mu_c"], "o-", ms=3, label=name)
    ax.set_xlabel("xi: largest out-of-plane displacement / L (free rigid motion removed)")
    ax.set_ylabel("mu / mu_c")
    ax.set_title("post-buckled branches, circular sections (amplitude control)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax = axes[0, 1]
    imp = data["imperfection"]
    for eps, path in zip(imp["epsilon"], imp["paths"], strict=True):
        ax.plot([p[1] for p in path], [p[0] / imp["mu_c"] for p in path],
                label=f"eps = {eps:g} L")
    ax.axhline(1.0, color="k", lw=0.8, ls=":")
    ax.set_xlabel("largest node displacement / L")
    ax.set_ylabel("mu / mu_c")
    ax.set_title("straightened rod with mode-shaped imperfections (no limit point)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax = axes[1, 0]
    tw = data["twisted"]
    eps = np.array(tw["epsilon"])
    knock = 1.0 - np.array(tw["limit"]) / tw["phi_c"]
    ax.loglog(eps, knock, "o", label="twisted rod (end rotation)")
    ax.loglog(eps, knock[0] * (eps / eps[0]) ** (2 / 3), "k--", lw=0.8,
              label="Koiter: slope 2/3")
    if "imperfection_folded" in data:
        fo = data["imperfection_folded"]
        ef = np.array(fo["epsilon"])
        kf = 1.0 - np.array(fo["limit"]) / fo["mu_c"]
        ax.loglog(ef, kf, "s", label="folded six-sided ring (load factor)")
        ax.loglog(ef, kf[0] * (ef / ef[0]) ** (2 / 3), "k:", lw=0.8)
    plain_log_ticks(ax.xaxis)  # the minor ticks' 3x10^-4 4x10^-4 ran together
    plain_log_ticks(ax.yaxis)
    ax.set_xlabel("imperfection amplitude eps (x L)")
    ax.set_ylabel("knock-down 1 - p_max / p_c")
    ax.set_title(f"imperfection sensitivity (twisted rod: exponent {tw['exponent']:.4f})")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    rp = data["ring_path"]
    k = np.linspace(1.5, 2.5, 200)
    ax.plot(k, math.pi * (k - 1) ** 2, "C1", label="1-loop circle pi (k - 1)^2")
    ax.plot(k, math.pi * (3 - k) ** 2, "C2", label="3-loop circle pi (3 - k)^2")
    ax.plot(rp["mu"], rp["energy"], "C0o-", ms=2, label="buckled ring (48 elements)")
    ax.set_xlabel("(L / 2 pi) kappa_n")
    ax.set_ylabel("energy (B3 = 1, L = 2 pi)")
    ax.set_title("1-loop -> 3-loop: one stable state at each kappa_n, no barrier")
    ax.set_ylim(0, 5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    six = data["six_path"]
    th = six["theta"]
    kr = np.array(six["kappa_R0"])
    en = np.array(six["energy"])
    k = np.linspace(0.0, 2.5, 300)
    lo, hi = six["bistable"]
    ax = axes[2, 0]
    ax.plot(k, 3 * (k * th) ** 2, "C1", label="folded (straight segments)")
    ax.plot(k, 3 * (th - k * th) ** 2, "C2", label="one-loop (arcs)")
    ax.plot(kr, en, "C3o-", ms=2, label="saddle branch (12 el./segment)")
    ax.plot([1.0], [3 * th**2 + six["barrier_at_1"]], "k*", ms=8,
            label=f"saddle at kappa_n R0 = 1 (Richardson), barrier {six['barrier_at_1']:.3g}")
    ax.axvspan(lo, hi, color="0.9", label="both stable")
    ax.set_xlabel("kappa_n R0")
    ax.set_ylabel("energy (B3 / L)")
    ax.set_title("six-sided ring (h/t = 4): states and the saddle between them")
    ax.set_ylim(0, 40)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax = axes[2, 1]
    ax.plot(kr, en - 3 * (kr * th) ** 2, "C1", label="unfolding (from folded)")
    ax.plot(kr, en - 3 * (th - kr * th) ** 2, "C2", label="folding (from one-loop)")
    ax.set_xlabel("kappa_n R0")
    ax.set_ylabel("energy barrier (B3 / L)")
    ax.set_title("barriers: each vanishes where its state loses stability")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return _save(fig, out, "fig_beyond_post_buckling")


def fig_hexagram(data: dict, out: Path) -> list[Path]:
    """Stable bands of kappa_n R0 of the hexagram's four states against h/t, with h/t*."""
    from ..plot.plots import plot_stable_bands
    from ..problems.hexagram import STATES

    png = plot_stable_bands(data["bands"], STATES, out / "fig_hexagram.png",
                            threshold=data["threshold"],
                            title="curved-sided hexagram, rectangles, nu = 1/3 (exact arc + "
                                  "Bloch phase)")
    return [png]


def _branch_style(verdict: str) -> str:
    """Return the line style of a branch: dashed when its verdict says it is unstable.

    Stability from the verdict: on a rotationally symmetric structure the lowest eigenvalue
    along a branch is the symmetry's zero mode, whose sign is noise.
    """
    return "--" if verdict.startswith(("unstable", "asymmetric")) else "-"


def continuation_plot(result, out: Path) -> Path:
    """Draw the bifurcation diagram, the branches against their amplitude, the lowest eigenvalue.

    Left: the primary path (solid where stable, dashed where not) and the secondary branches
    (amplitude vs parameter). Middle: each branch's parameter change from its branch point
    against its amplitude xi, with the fitted initial post-buckling curve p/p_c = 1 + a xi +
    b xi^2 (a supercritical pitchfork changes the parameter by ~b xi^2, so little that on the
    left it is a vertical line). Right: the lowest eigenvalue along the primary path.
    """
    fig = Figure(figsize=(15, 4.4), layout="constrained")
    axes = fig.subplots(1, 3)
    val = np.array(result.value)
    ev = np.array(result.lowest_eigenvalue)
    amp = np.array(result.amplitude)
    stable = ev > 0
    for mask, style, label in ((stable, "-", "stable"), (~stable, "--", "unstable")):
        axes[0].plot(np.where(mask, val, np.nan), np.where(mask, amp, np.nan), style,
                     color="C0", label=f"primary ({label})")
    for i, b in enumerate(result.branches):
        style = _branch_style(b.verdict)
        order = np.argsort(b.amplitude)
        xi, value = np.array(b.amplitude)[order], np.array(b.value)[order]
        label = f"branch from {b.value_critical:.5g}: " + b.verdict.split(":")[0]
        axes[0].plot(value, xi, style, color=f"C{i + 1}", label=label)
        axes[1].plot(xi, value - b.value_critical, style, marker="o", ms=3,
                     color=f"C{i + 1}", label=label)
        a2, b2 = getattr(b, "coefficients", (math.nan, math.nan))
        if len(xi) > 1 and math.isfinite(a2) and math.isfinite(b2):
            s = np.linspace(xi.min(), xi.max(), 101)
            axes[1].plot(s, b.value_critical * (a2 * s + b2 * s**2), ":", color="k", lw=1,
                         label=f"p/p_c = 1 + a xi + b xi^2: a = {a2:.3g}, b = {b2:.4g}")
    for p in result.special_points:
        axes[0].axvline(p["value"], color="r", ls=":", lw=0.8)
        axes[2].axvline(p["value"], color="r", ls=":", lw=0.8)
    axes[0].set_xlabel(result.key)
    axes[0].set_ylabel("amplitude (primary: largest node displacement;\n"
                       "branch: xi, out-of-plane / L)")
    axes[0].set_title("bifurcation diagram (dashed: unstable)", fontsize=10)
    axes[0].legend(fontsize=7)
    axes[0].grid(alpha=0.3)
    axes[1].axhline(0.0, color="k", lw=0.6)
    axes[1].xaxis.set_major_locator(MaxNLocator(nbins=5, steps=[1, 2, 5, 10]))  # "-0.015" is wide
    axes[1].set_xlabel("branch amplitude xi (out-of-plane / L)")
    axes[1].set_ylabel(f"{result.key} - its value at the branch point")
    if result.branches:
        axes[1].set_title("branches against their amplitude (dashed: unstable)", fontsize=10)
        axes[1].legend(fontsize=7)
    else:
        axes[1].set_title("no branch was traced", fontsize=10)
    axes[1].grid(alpha=0.3)
    axes[2].plot(val, ev, "o-", ms=3)
    axes[2].axhline(0.0, color="k", lw=0.8)
    axes[2].set_xlabel(result.key)
    axes[2].set_ylabel("lowest scaled Hessian eigenvalue")
    axes[2].set_title("primary path (stable where > 0)", fontsize=10)
    axes[2].grid(alpha=0.3)
    p = Path(out) / "diagram.png"
    exponents_in_labels(fig)
    fig.savefig(p, dpi=120, bbox_inches="tight")
    return p
