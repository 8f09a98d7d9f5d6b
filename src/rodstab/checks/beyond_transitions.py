"""Beyond the paper: transitions between the stable states of a ring, followed by arclength.

The 1-loop -> 3-loop ring (Section 3.1) and the folded <-> one-loop six-sided ring (Section 5).
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ..model import Assembly
from ..nonlinear.discrete import DiscreteRod
from ..numerics import richardson
from ..problems import folded_ring, ring, unfolded_ring
from ..sections import circle, rectangle
from .core import Claim, Run, fmt
from .rules import NONLINEAR_RTOL, REPRODUCED, RICHARDSON_RTOL, every, holds, methods_agree

#: What the project claims for the row of :func:`ring_transition_checks` and of
#: :func:`six_ring_transition_checks` (independent: they run in parallel).
EXPECTED_RING = {"T-ring": REPRODUCED}
EXPECTED_SIX = {"T-six": REPRODUCED}

#: Round-off allowance in "the natural curvature rises monotonically along the path".
MONOTONE_TOL = 1e-9
#: Where the six-sided ring's saddle branch turns on the one-loop state (Richardson of 8 and
#: 12 el./segment) vs the linear engine's one-loop limit; observed 6e-4.
MEETING_RTOL = 5e-3
#: Most arclength steps (ds = 0.25) of the saddle path, which stops at its turning point (8 and
#: 12 el./segment reach it after 40 to 55 steps, depending on where step halvings fall).
SADDLE_STEPS = 80


def ring_transition_checks(run: Run) -> Iterator[Claim]:
    """Row T-ring."""
    yield _ring_transition_claim(run)


def six_ring_transition_checks(run: Run) -> Iterator[Claim]:
    """Row T-six."""
    yield _six_ring_transition_claim(run)


def _ring_transition_claim(run: Run) -> Claim:
    """Follow the 1-loop ring beyond its bifurcation to the 3-loop ring."""
    from ..nonlinear.continuation import SpecialKind, arclength_from_bifurcation

    c = circle()
    ring1 = ring.build(ring.Params(section=c, loops=1))
    ends = []
    turn_kinds = (SpecialKind.BRANCH_TURNED, SpecialKind.FOLD)
    turns = tuple(k.value for k in turn_kinds)
    for n, steps in ((36, 45), (48, 52)):
        # Stops where it turns (26 and 33 steps); the steps are a cap.
        path = arclength_from_bifurcation(ring1, 1.05, 3.0, elements_per_segment=n, ds=0.25,
                                          n_steps=steps, stop_at_special=True,
                                          stop_kinds=turn_kinds)
        rad = np.array(path.radius)
        i = int(np.argmin(rad))
        # The 3-loop ring is where the path turns (into the mirror image): located there, not
        # read off the sampled point nearest to it (which moved the Richardson value by 1e-3).
        located = [sp["value"] for sp in path.special_points if sp["kind"] in turns]
        ends.append(located[0] if located else math.nan)
    run.progress()
    mu = np.array(path.value[: i + 1])
    ev = np.array(path.lowest_eigenvalue[: i + 1])
    en = np.array(path.energy[: i + 1])
    r1 = ring.analytic_stability(ring.Params(section=c, loops=1)).kappa_L_over_2pi_interval[1]
    r3, r3_hi = ring.analytic_stability(ring.Params(section=c, loops=3)).kappa_L_over_2pi_interval
    rich = ends[1] + (ends[1] - ends[0]) * 36**2 / (48**2 - 36**2)
    k_max = float(mu[int(np.argmax(en))])
    run.beyond()["ring_path"] = {"mu": mu.tolist(), "radius": rad[: i + 1].tolist(),
                                 "energy": en.tolist(), "lowest_eigenvalue": ev.tolist()}
    return Claim(
        "T-ring", "beyond", "3.1", "1-loop -> 3-loop ring transition (circle, nu = 1/3)",
        "transition not analysed (paper, Section 3.1)",
        f"one continuous, stable path from the 1-loop bifurcation {fmt(mu[0], 4)} to the 3-loop "
        f"ring at {fmt(ends[1], 4)} (48 el.), Richardson {fmt(rich, 4)}",
        f"analytic: 1-loop stable below {fmt(r1, 4)}, 3-loop above {fmt(r3, 4)}",
        "pseudo-arclength from the bifurcation (discrete rod, sliding phase pinned)",
        every(holds((ev[1:-1] > 0).all() and (np.diff(mu) > -MONOTONE_TOL).all()),
              methods_agree(rich, r3, RICHARDSON_RTOL)),
        f"Stable states: the 1-loop circle for (L/2pi) kappa_n < {fmt(r1, 4)}, a buckled "
        f"non-planar ring for {fmt(r1, 4)}-{fmt(r3, 4)} (natural curvature rising "
        f"monotonically along it, radius shrinking from {fmt(rad[0], 3)} R to "
        f"{fmt(rad[i], 3)} R), the 3-loop circle for {fmt(r3, 4)}-{fmt(r3_hi, 4)}. Exactly one "
        f"stable state at every kappa_n in (0, {fmt(r3_hi, 4)}): the folding is continuous, "
        "with no bistability and no energy barrier (both ends are supercritical; in the gap "
        "both circles are saddles above the buckled ring). Energy along the path "
        f"{fmt(en[0], 4)} -> max {fmt(en.max(), 4)} (at {fmt(k_max, 4)}) -> {fmt(en[-1], 4)} "
        "(B3 = 1, L = 2 pi; circles: pi (kappa - N)^2). Beyond the 3-loop ring the path "
        "continues into the mirror-image branch.")


def _saddle(folded: Assembly, n: int, window: tuple[float, float], n_steps: int, theta: float):
    """Trace the saddle branch of the folded six-ring at ``n`` el./segment.

    The branch leaves the double bifurcation along its most dangerous direction and is traced while
    the load factor stays in ``window``, up to its first turning point; a point is landed on
    ``theta`` (kappa_n R0 = 1) as the branch passes it.
    """
    from ..nonlinear.continuation import SpecialKind, arclength_from_bifurcation

    return arclength_from_bifurcation(folded, 1.0, 8.0, elements_per_segment=n, ds=0.25,
                                      n_steps=n_steps, mu_window=window, stop_at_special=True,
                                      stop_kinds=(SpecialKind.FOLD, SpecialKind.BRANCH_TURNED),
                                      land_at=(theta,))


def _intersecting_pairs(state: DiscreteRod) -> tuple[int, float]:
    """Pairs of elements of non-neighbouring rods that intersect in ``state``, and the closest.

    Intersect: closer than ``1e-6`` times the rod length (a crossing converged by Newton is
    3e-10 apart; the next pair of the line -> star saddle is 0.04 apart at 6 el.,
    tests/test_saddle_search.py), among the judged pairs of
    :func:`rodstab.multistable.transitions.judged_pairs`.
    """
    from ..multistable.transitions import judged_pairs, pair_distances

    pairs = judged_pairs(state)
    dist = pair_distances(state.x, state.edge_nodes, pairs)[0]
    length = state.assembly.total_length / len(state.assembly.segments)
    return int(np.sum(dist < 1e-6 * length)), float(np.min(dist) / length)


def _richardson(coarse: float, fine: float, n0: int, n1: int) -> float:
    """Second-order Richardson extrapolation from meshes of n0 < n1 elements.

    :func:`rodstab.numerics.richardson` with the meshes' ratio ``n1 / n0``.
    """
    return richardson(coarse, fine, n1 / n0, 2)[0]


def _six_ring_transition_claim(run: Run) -> Claim:
    """Follow the six-sided ring (h/t = 4, 120 deg arcs) between its folded and one-loop states.

    One discrete model (the folded design, segment length L = 1, B3 = 1): the saddle branch
    leaving the folded state's double bifurcation along its most dangerous direction is followed
    by arclength until it turns on the one-loop state (the smallest load on it, a fold of the
    discrete path), at 8 and 12 el./segment; the turning point and the energy barrier at
    kappa_n R0 = 1 (a point landed exactly there) are Richardson-extrapolated. Closed-form
    energies of the two uniform states: folded (straight) 6 x 1/2 kappa_n^2 L, one-loop (arcs of
    curvature theta/L) 6 x 1/2 (theta/L - kappa_n)^2 L, theta = 2 pi/3; equal at 1/2.
    """
    from ..nonlinear.continuation import SpecialKind

    r4 = rectangle(aspect=4.0)
    theta = 2 * math.pi / 3
    folded = folded_ring.build(folded_ring.Params(section=r4))
    lin_fold = folded_ring.engine_stability(folded_ring.Params(section=r4), 16).load_factor_critical
    lin_one = unfolded_ring.engine_stability(unfolded_ring.Params(section=r4, radius=1 / theta))
    one_lo, one_hi = lin_one.load_factor_interval  # kappa_n R0 (R0 = 1/theta: mu / theta)
    meshes = (8, 12)
    ends, barriers, paths = [], [], []
    crossings: list[tuple[int, float]] = []
    for n in meshes:
        path = _saddle(folded, n, (0.0, 6.0), SADDLE_STEPS, theta)
        # The turning point on the one-loop state: a fold of the discrete path (its symmetry is
        # not exact) or, were it exact, the branch point the path turns through.
        turns = (SpecialKind.FOLD.value, SpecialKind.BRANCH_TURNED.value)
        folds = [sp["value"] for sp in path.special_points if sp["kind"] in turns]
        ends.append(min(folds) / theta if folds else math.nan)
        paths.append(path)
        # The barrier: the saddle's energy where the branch first passes kappa_n R0 = 1, less
        # the folded state's closed form.
        at1 = [state for value, state in path.landed if value == theta]
        barriers.append(at1[0].energy() - 3 * theta**2 if at1 else math.nan)
        crossings.append(_intersecting_pairs(at1[0]) if at1 else (0, math.nan))
        run.progress()
    end = _richardson(ends[0], ends[1], *meshes)
    barrier = _richardson(barriers[0], barriers[1], *meshes)
    path = paths[-1]
    mu, ev, en = np.array(path.value), np.array(path.lowest_eigenvalue), np.array(path.energy)
    i = int(np.argmin(mu))
    mu, ev, en = mu[: i + 1], ev[: i + 1], en[: i + 1]
    k = mu / theta
    fold_c = lin_fold / theta
    run.beyond()["six_path"] = {"kappa_R0": k.tolist(), "energy": en.tolist(),
                                "radius": list(path.radius[: i + 1]), "theta": theta,
                                "bistable": [float(one_lo), float(fold_c)],
                                "barrier_at_1": float(barrier),
                                "barriers_by_mesh": dict(zip(meshes, barriers, strict=True)),
                                "saddle_intersections": dict(zip(meshes, crossings,
                                                                 strict=True))}
    return Claim(
        "T-six", "beyond", "5", "Six-sided ring (h/t = 4): folded <-> one-loop transition",
        "experiment at kappa_n R0 = 1: both states stable; bending the folded ring's ends makes "
        "it snap 'with vigor' to the unfolded state (Fig. 10c); transition not analysed",
        f"bistable for {fmt(one_lo, 3)} < kappa_n R0 < {fmt(fold_c, 4)}: the saddle branch "
        f"leaves the folded state's bifurcation ({fmt(k[0], 4)}) going down (subcritical) and "
        f"turns on the one-loop state at {fmt(ends[0], 4)}, {fmt(ends[1], 4)} (8, 12 el.), "
        f"Richardson {fmt(end, 4)}; energy barrier to unfold at kappa_n R0 = 1: "
        f"{fmt(barriers[0], 4)}, {fmt(barriers[1], 4)}, Richardson {fmt(barrier, 3)} B3/L",
        f"linear engine: folded stable below {fmt(fold_c, 4)}, one-loop in "
        f"({fmt(one_lo, 4)}, {fmt(one_hi, 4)})",
        "pseudo-arclength from the folded bifurcation (discrete rod, 8 and 12 el./segment)",
        every(holds((ev[1:-1] < 0).all()),
              methods_agree(end, one_lo, MEETING_RTOL),
              methods_agree(mu[0], lin_fold, NONLINEAR_RTOL)),
        "New: the saddle branch that connects the two stable states is unstable all along "
        "(one negative eigenvalue) and spans the whole bistable range; it passes the one-loop "
        "state into its mirror image. At the experiment's kappa_n R0 = 1 the folded ring stores "
        f"{fmt(3 * theta**2, 3)} B3/L but is held by a barrier of only {fmt(barrier, 3)} "
        "through this saddle: a moderate forced bending releases it, and the snap is "
        f"energetic -- consistent with Fig. 10c. But the rods have no thickness here: at the "
        f"saddle {crossings[0][0]} and {crossings[1][0]} pairs of elements of non-neighbouring "
        f"rods intersect (8, 12 el.; at most {fmt(max(c[1] for c in crossings), 2)} L apart), and "
        "along the path they pass through each other there (docs/theory/contact.md), so for "
        "rods that cannot the barrier is above this one; their path (with contact) is not "
        f"found. Past kappa_n R0 = {fmt(fold_c, 3)} the folded "
        f"ring snaps open by itself (the one-loop ring is stable there up to {fmt(one_hi, 4)}); "
        f"below {fmt(one_lo, 3)} the one-loop ring folds itself. The double eigenvalue has two "
        "branch directions, both subcritical for h/t = 4 (PB-folded); the path followed is the "
        "more dangerous one.")
