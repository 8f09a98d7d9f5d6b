"""Section 3.1 of the paper: untwisted N-loop rings, eqs. (3.1)-(3.3)."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from .. import kinematics, transfer
from ..analytic import ring
from ..numerics import SINGULAR_TOL, find_roots
from ..sections import rectangle
from . import variation
from .core import Claim, Run, fmt
from .rules import (
    DIFFERS,
    REPRODUCED,
    ROOT_RTOL,
    VARIATION_RTOL,
    agrees_to_printed,
    every,
    holds,
    methods_agree,
    residual_below,
    typo_shown_by,
)

#: What the project claims for each row of :func:`ring_checks`.
EXPECTED = {
    "3.1": REPRODUCED, "3.3": DIFFERS, "3.1a": REPRODUCED, "3.1b": REPRODUCED,
    "3.1c": REPRODUCED, "3.1d": REPRODUCED, "3.1e": REPRODUCED, "3.1f": REPRODUCED,
    "3.1g": REPRODUCED, "3.1h-exact": REPRODUCED, "3.1h-paper": REPRODUCED, "3.1i": REPRODUCED,
    "3.1j": REPRODUCED,
}

_MONO = "monodromy of (3.1) over 2 pi N (transfer matrix), closure enforced"


def ring_equations_mismatch(b1: float, b2: float, M: float, seed: int = 0) -> float:
    """Relative mismatch between the first variation of P2 (2.12) and the printed ODEs (3.1).

    Ring with ``R = 1`` (``s = theta``), ``B3 = 1``: with ``p1``, ``p2`` the left-hand sides of
    (3.1), ``DI[omega, beta][d_omega, d_beta] = -int (p1 d_omega + p2 d_beta)`` for every test
    field vanishing at the ends (see :mod:`.variation`). ~1e-15 if (3.1) is right.
    """
    om, be = variation.random_fields(seed, 2)
    d_om, d_be = variation.random_fields(seed + 1, 2, vanish=(1, 1))

    def energy(f: list) -> float:
        o, b = f
        return variation.integral(lambda x: kinematics.p2_density(
            b(x), b.deriv()(x), o(x), o.deriv()(x), R=1.0, B1=b1, B2=b2, B3=1.0, M=M))

    c = -M + b1 + b2
    p1 = b2 * om.deriv(2) + (M - b1) * om + c * be.deriv()  # (3.1), first line
    p2 = b1 * be.deriv(2) + (M - b2) * be - c * om.deriv()  # (3.1), second line
    predicted = -variation.integral(lambda x: p1(x) * d_om(x) + p2(x) * d_be(x))
    return variation.relative_mismatch(
        variation.first_variation(energy, [om, be], [d_om, d_be]), predicted)


def ring_checks(run: Run) -> Iterator[Claim]:
    """Rows of Section 3.1: the ODEs (3.1), the roots (3.3) and the printed ring intervals."""
    b1, b2 = 1.0, 0.75  # circle, nu = 1/3
    r1, r3 = ring.ring_stability(b1, b2, 1), ring.ring_stability(b1, b2, 3)
    t1, t3 = transfer.ring_interval_transfer(b1, b2, 1), transfer.ring_interval_transfer(b1, b2, 3)
    run.progress()
    worst = max(ring_equations_mismatch(*p, seed=i) for i, p in
                enumerate(((b1, b2, -0.5), (9.0, 2.3, 1.7), (0.4, 1.9, -3.0))))
    yield Claim("3.1", "3.1", "(3.1)", "ODEs of the ring eigenproblem",
                "(3.1)", "Euler-Lagrange equations of (2.12) agree (sympy, tests)",
                f"first variation of P2 vs (3.1): max rel. mismatch {worst:.1e}",
                "P2 (2.12) varied along random polynomial fields, 3 parameter sets",
                residual_below(worst, VARIATION_RTOL))
    # Eq (3.3): printed vs corrected, on a section with b1 != 1.
    rect = rectangle(aspect=3.0)
    mp, _ = ring.ring_mode_eigenvalues(2, 1, rect.b1, rect.b2, printed=True)
    mc, _ = ring.ring_mode_eigenvalues(2, 1, rect.b1, rect.b2)
    tr = transfer.ring_interval_transfer(rect.b1, rect.b2, 1)[0]
    yield Claim(
        "3.3", "3.1", "(3.3)", "M± = (b1+b2)/2 ± sqrt((b1-b2)^2/4 + b2 (j/N)^2)",
        f"rectangle h/t = 3, j = 2, N = 1: M- = {fmt(mp)} (as printed)",
        f"M- = {fmt(mc)} with b1 b2 (j/N)^2 under the root", f"{fmt(tr)}", _MONO,
        typo_shown_by(abs(mp - tr) / abs(tr), abs(mc - tr) / abs(tr), ROOT_RTOL),
        "Typo: the roots of the printed quadratic M^2 - M(b1+b2) + b1 b2 (1-(j/N)^2) have "
        "b1 b2 (j/N)^2 under the root. Identical for b1 = 1, so the paper's circular-section "
        "numbers are unaffected; rodstab uses the corrected form.")
    lo1, hi1 = r1.M_interval
    yield Claim("3.1a", "3.1", "(3.3), N=1", "1-loop circle: M_C^- = -0.861 (j = 2)", "-0.861",
                f"{fmt(lo1)} (j = {r1.bounding_modes[0]})", fmt(t1[0]), _MONO,
                every(agrees_to_printed(lo1, -0.861, 3), methods_agree(lo1, t1[0], ROOT_RTOL)),
                f"{lo1:.5f} printed truncated as -0.861.")
    yield Claim("3.1b", "3.1", "(3.3), N=1", "1-loop: M_C^+ = 1 (uniform twist)", "1",
                f"{fmt(hi1)} (j = {r1.bounding_modes[1]})", fmt(t1[1]), _MONO,
                every(agrees_to_printed(hi1, 1.0, 3), methods_agree(hi1, t1[1], ROOT_RTOL)))
    k1 = r1.kappa_L_over_2pi_interval
    k1_t = (1 - t1[1], 1 - t1[0])
    yield Claim("3.1c", "3.1", "N=1", "0 < (L/2pi) kappa_n < 1.86", "(0, 1.86)",
                f"({fmt(k1[0])}, {fmt(k1[1])})", f"({fmt(k1_t[0])}, {fmt(k1_t[1])})", _MONO,
                every(agrees_to_printed(k1[0], 0.0, 2), agrees_to_printed(k1[1], 1.86, 2),
                      methods_agree(k1_t, k1, ROOT_RTOL, ROOT_RTOL)))
    lo3, hi3 = r3.M_interval
    jm = next(m for m in r3.modes if m.j == 2)
    yield Claim("3.1d", "3.1", "(3.3), N=3", "3-loop: upper limit M^- = 0.284 (j = 2)", "0.284",
                f"{fmt(hi3)} (j = {r3.bounding_modes[1]}; j=2 bound {fmt(jm.upper)})",
                fmt(t3[1]), _MONO,
                every(agrees_to_printed(hi3, 0.284, 3), methods_agree(hi3, t3[1], ROOT_RTOL)))
    yield Claim("3.1e", "3.1", "(3.3), N=3", "3-loop: M_C^- = -0.286 (j = 4)", "-0.286",
                f"{fmt(lo3)} (j = {r3.bounding_modes[0]})", fmt(t3[0]), _MONO,
                every(agrees_to_printed(lo3, -0.286, 3), methods_agree(lo3, t3[0], ROOT_RTOL)),
                f"The printed -0.286 is {lo3:.5f} truncated; rounded it is {lo3:.3f}.")
    k3 = r3.kappa_L_over_2pi_interval
    k3_t = (3 * (1 - t3[1]), 3 * (1 - t3[0]))
    yield Claim("3.1f", "3.1", "N=3", "2.15 < (L/2pi) kappa_n < 3.86", "(2.15, 3.86)",
                f"({fmt(k3[0])}, {fmt(k3[1])})", f"({fmt(k3_t[0])}, {fmt(k3_t[1])})", _MONO,
                every(agrees_to_printed(k3[0], 2.15, 2), agrees_to_printed(k3[1], 3.86, 2),
                      methods_agree(k3_t, k3, ROOT_RTOL)))
    ov = ring.ring_overlap(b1, b2)
    gap_t = k3_t[0] - k1_t[1]
    yield Claim("3.1g", "3.1", "N=1,3", "1- and 3-loop ranges do not overlap (circle)",
                "no overlap", "no overlap" if ov.overlap is None else f"overlap {ov.overlap}",
                f"gap {fmt(gap_t)} in (L/2pi) kappa_n", _MONO,
                holds(k3[0] - k1[1] > 0 and gap_t > 0))
    yield from _overlap_claims(run)
    yield _spurious_root_claim(b1, b2, t1[2])
    yield _odd_loops_claim()
    run.figures["rings"] = rings_data()  # the report's N-loop figure, computed in parallel


def _overlap_claims(run: Run) -> Iterator[Claim]:
    """3.1h: rectangles with a large enough h/t have overlapping 1- and 3-loop ranges."""
    for torsion in ("exact", "paper"):
        ht = ring_overlap_threshold(torsion)
        sec_hi = rectangle(aspect=ht * 1.01, torsion=torsion)
        sec_lo = rectangle(aspect=ht * 0.99, torsion=torsion)
        gap_t = (3 * (1 - transfer.ring_interval_transfer(sec_hi.b1, sec_hi.b2, 3)[1])
                 - (1 - transfer.ring_interval_transfer(sec_hi.b1, sec_hi.b2, 1)[0]))
        run.progress()
        yield Claim(
            f"3.1h-{torsion}", "3.1", "N=1,3",
            "Large enough out-of-plane stiffness: 1- and 3-loop ranges overlap (rectangle)",
            "qualitative (no threshold given)",
            f"overlap for h/t > {fmt(ht, 5)} (torsion {torsion})",
            f"at 1.01x: 3-loop lower - 1-loop upper = {fmt(gap_t, 3)} (< 0: overlap)", _MONO,
            holds(ring.ring_overlap(sec_hi.b1, sec_hi.b2).overlap is not None
                  and ring.ring_overlap(sec_lo.b1, sec_lo.b2).overlap is None and gap_t < 0),
            "New number: the paper states the effect but not the threshold.")


def _odd_loops_claim() -> Claim:
    """Row 3.1j: an untwisted ring folds without twist into N loops for odd N only."""
    from ..multistable.folding import flat_foldings
    from ..nonlinear.discrete import discretise
    from ..problems import ring as rings

    found = {}
    for N in (2, 3, 4, 5):  # h = 0.004 of a loop's length (2 pi), 16 el. per loop, load 1
        found[N] = flat_foldings(discretise(rings.build(rings.Params(loops=N)), 16, 1.0),
                                 0.008 * math.pi)
    gauss = [found[N][0] for N in found]
    cross = [found[N][1] for N in found]
    twist = max(f[2] for f in found.values())
    expected = [0 if N % 2 else 1 for N in found]
    return Claim(
        "3.1j", "3.1", "Sec. 3.1", "a 1-loop ring deforms into N loops without twist for odd N",
        "N = 3, 5, ... (no twist); even N: not said",
        f"smallest |Lk| of the flat foldings, N = 2..5 (Gauss): {gauss}; largest |Tw| "
        f"{twist:.2g} turns", f"signed crossings: {cross}",
        "ribbon self-linking by crossings of a seeded projection (rodstab.multistable.linking)",
        every(holds(gauss == expected and cross == expected), holds(twist < 0.05)),
        "Rods that cannot cross keep Lk = Tw + Wr, 0 for the untwisted one-loop ring. N flat "
        "layers close with N - 1 swaps of neighbouring layers (any number has that parity), "
        "each adding +-1 to the writhe: Lk = 0 with the strip flat (Tw = 0) needs N odd, with "
        "swaps of alternating sense (rodstab.multistable.folding). Built and measured for N = "
        "2-5 (every sense sequence for even N), circle, 16 el. per loop, h = 0.004 of a loop's "
        "length; the N-loop stacking on the torus curve links -(N - 1) times (the wound ring).")


def _spurious_root_claim(b1: float, b2: float, admissible: list[float]) -> Claim:
    """3.1i: M = b2 gives a periodic solution of (3.1) (beta = const) that violates closure."""
    sv = transfer.ring_periodicity_measure(b2, 1, b1, b2)
    sigma3 = sv[-1 - transfer.RING_RIGID_NULLITY] / sv[0]  # beyond the two rigid rotations
    rejected = all(abs(m - b2) > ROOT_RTOL * b2 for m in admissible)
    return Claim(
        "3.1i", "3.1", "j = 0", "Second uniform-twist root M^- = b2 is spurious",
        "spurious (trivial mode)", "excluded (beta = const violates closure)",
        f"at M = b2: sigma_3/sigma_1 of T - I = {sigma3:.1e} (periodic solution); "
        f"rejected by closure: {rejected}", _MONO,
        holds(sigma3 < SINGULAR_TOL and rejected))


def ring_overlap_threshold(torsion: str = "exact") -> float:
    """Rectangle aspect h/t above which the 1- and 3-loop stable ranges overlap (Section 3.1)."""

    def gap(ht: float) -> float:
        s = rectangle(aspect=ht, torsion=torsion)
        ia = ring.ring_stability(s.b1, s.b2, 1).kappa_L_over_2pi_interval
        ib = ring.ring_stability(s.b1, s.b2, 3).kappa_L_over_2pi_interval
        return ib[0] - ia[1]

    found = find_roots(gap, 1.0, 10.0, n_scan=90)
    return found.roots[0].x if found.roots else math.nan


def rings_data(n: int = 50, loops: tuple[int, ...] = (1, 3, 5)) -> dict:
    """Stable ``(L/2pi) kappa_n`` intervals of N-loop rings vs rectangle ``h/t`` (new figure)."""
    hts = np.geomspace(0.5, 8.0, n)
    out: dict = {"h_over_t": hts.tolist(), "loops": list(loops), "intervals": {}}
    for N in loops:
        ivs = []
        for h in hts:
            s = rectangle(aspect=float(h))
            ivs.append(list(ring.ring_stability(s.b1, s.b2, N).kappa_L_over_2pi_interval))
        out["intervals"][str(N)] = ivs
    out["overlap_threshold_exact"] = ring_overlap_threshold("exact")
    return out
