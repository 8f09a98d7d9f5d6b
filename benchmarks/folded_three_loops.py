"""The 3-loop ring as a flat stack whose layers swap twice: which swaps fold from one loop.

A prototype construction (not in the package), run on demand: ``python
benchmarks/folded_three_loops.py [--cone SECTION ELEMENTS]``. Three strands stacked along z,
``s`` apart; over one turn the top two swap (turning about their midpoint by pi, clear of the
third by ``s`` throughout), then the bottom two. Each swap turns one way or the other
(``senses``). The strip is kept flat (push-off along z). Prints the ribbon's linking number by
Gauss's integral and by signed crossings (rodstab.multistable.linking): swaps of one sense give
+-2 (the wound ring, like the torus curve that stacking.stack_loops builds: -2), of opposite
senses 0, the number of the untwisted one-loop ring, so only that stacking is the ring folded
from it (docs/theory/contact.md, "Ribbon self-linking").

``--cone circle|rect2 N``: the limits with contact at zero gap (the FE cone,
:func:`rodstab.multistable.cone_limit.cone_limits`, out of plane, ``N`` elements per loop) of
the 3-loop ring stacked flat with its two swaps ``delta`` apart (a fraction of a turn), beside
the torus curve's. At zero gap the layers' normals are vertical away from the swaps, so the
cone cannot tell the swaps' senses apart: the wound and the folded flat stackings share these
numbers, which depend on where the layers swap.

``--hold``: the package's construction (:func:`rodstab.multistable.folding.fold_loops`, swap
windows of half a turn) and the wound ring (the torus curve), relaxed with contact at load 1
(circle, ``h/L = 0.01``, ``dhat = 0.1 h``, 16 and 32 el. per loop): convergence, the verdict,
the energy above the coincident ring, the ribbon's linking and where the layers swap
(:func:`rodstab.multistable.folding.layer_swaps`).

``--snake [h/L] [elements] [dhat/h] [steps] [factor]`` (default 0.01 16 0.1 40 30): the folded
ring held at load 1 (as ``--hold``) followed both ways (to loads 2 and 0.3) by the
pseudo-arclength continuation with Hessian eigenvalue monitoring
(:func:`rodstab.nonlinear.continuation.run.continuation`, ``steps`` steps over the range, at most
``factor`` times that), not stopped at the first special point. Prints the first special point
each way with the cosine of the lowest eigenmode there with the ring's sliding field
(:func:`rodstab.multistable.stacked.ring_sliding_field`; near 1: the pinned swap pattern hops
along the mesh), the range of loads the path reaches, and its lowest and highest folds.
Loads as ``(L/2pi) kappa_n = 3 mu``. The second method beside ``stacked_limits`` (natural
parameter, slides taken as the same state): docs/theory/contact.md, "Followed by arclength".

``--gauge [h/L] [elements] [dhat/h] [steps] [k]`` (default 0.01 16 0.1 40 1): the same, with
a phase condition that removes the sliding symmetry (a prototype, not in the package): the
penalty ``(K / 2) (a . (x - x_held))^2`` on the node positions, ``a`` the held state's unit
sliding field (nodes), ``K = k`` times the median node stiffness times the node unknowns, so the
constraint holds to round-off and its force ``K a . (x - x_held)``, the pinning force the
mesh exerts on the swap pattern, does not depend on ``k``. The path then follows one branch
instead of snaking through the pinned copies: 2 and 5 times ``steps`` up and down.

``--near circle|rect2 ELEMENTS LOAD [up|down] [h/L] [dhat/h]``: the held ring (default h/L
0.01, dhat 0.1 h)
stepped in the natural parameter to LOAD (Newton with contact, steps of 0.009), then the
arclength continuation over 0.3 beyond it: started near an end, the path reaches it instead
of wandering through the pinned copies (docs/theory/contact.md, "Started near the ends").

``--regauge [h/L] [elements] [dhat/h] [piece]`` (default 0.01 16 0.1 4): upward only, the
phase condition set anew (from the state reached) every ``piece`` steps of 0.025 in the load
factor, so it fixes the swap pattern relative to the last state rather than the held one; stops
at the first fold or failed piece. Prints every special point and each piece's end.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from rodstab.multistable.linking import crossing_linking, gauss_linking


def _smooth(t: np.ndarray) -> np.ndarray:
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def _turn(theta: np.ndarray, window: tuple[float, float]) -> np.ndarray:
    return np.pi * _smooth((theta - window[0]) / (window[1] - window[0]))


def strand(start: int, theta: np.ndarray, senses: tuple[int, int], s: float,
           first: tuple[float, float] = (0.8, 1.4), second: tuple[float, float] = (3.6, 4.2)
           ) -> np.ndarray:
    """Return the ``(r, z)`` offsets of the strand starting in slot ``start`` (2 top, 0 bottom)."""
    phi1, phi2 = _turn(theta, first), _turn(theta, second)
    r, z = np.zeros_like(theta), np.full_like(theta, s * (start - 1))
    slot = np.full(theta.shape, start)
    if start in (1, 2):  # the first swap: top and middle turn about z = s / 2
        sign = 1.0 if start == 2 else -1.0
        r = senses[0] * sign * 0.5 * s * np.sin(phi1)
        z = 0.5 * s + sign * 0.5 * s * np.cos(phi1)
        slot = np.where(phi1 >= np.pi, 3 - start, start)
    after = (theta >= second[0]) & (slot <= 1)  # the second: middle and bottom about -s / 2
    sign = np.where(slot == 1, 1.0, -1.0)
    r = np.where(after, senses[1] * sign * 0.5 * s * np.sin(phi2), r)
    z = np.where(after, -0.5 * s + sign * 0.5 * s * np.cos(phi2), z)
    return np.c_[r, z]


def ring(senses: tuple[int, int], s: float = 0.05, n: int = 1200) -> np.ndarray:
    """Return the closed centreline: loops starting top, bottom, middle (each ends at the next)."""
    theta = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    loops = []
    for start in (2, 0, 1):
        rz = strand(start, theta, senses, s)
        loops.append(np.c_[(1.0 + rz[:, 0]) * np.cos(theta), (1.0 + rz[:, 0]) * np.sin(theta),
                           rz[:, 1]])
    return np.vstack(loops)


def closest_strands(C: np.ndarray, s: float) -> float:
    """Closest distance between points more than ``4 s`` apart along the closed curve."""
    n = len(C)
    step = float(np.linalg.norm(C[1] - C[0]))
    best = np.inf
    for i, j in cKDTree(C).query_pairs(1.5 * s, output_type="ndarray"):
        along = min(abs(i - j), n - abs(i - j)) * step
        if along > 4.0 * s:
            best = min(best, float(np.linalg.norm(C[i] - C[j])))
    return best


def main() -> None:
    s = 0.05
    print(f"3 strands {s} apart, strip flat (push-off 0.1 s along z)")
    print("senses   strands apart/s   Lk (Gauss)   Lk (crossings, 2 projections)")
    for senses in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
        C = ring(senses, s)
        P = C + np.array([0.0, 0.0, 0.1 * s])
        print(f"{senses!s:8} {closest_strands(C, s) / s:15.3f} {gauss_linking(C, P):12.6f}   "
              f"{crossing_linking(C, P, 1)}, {crossing_linking(C, P, 2)}")


def flat_pairs(a: object, n: int, delta: float) -> list:
    """Touching pairs of ``ring.build(loops=3)`` stacked flat, swaps at 0 and ``delta`` (rad).

    On ``(0, delta)`` loop 0 is on top, 2 in the middle, 1 at the bottom; on ``(delta, 2 pi)``
    2, 0, 1 (the top two swapped); at ``2 pi`` each loop runs into the next with the bottom
    two swapped. ``n_z = +1`` where the pair's first loop lies on the second, -1 the other
    way, 0 where they do not touch (rows dropped).
    """
    import math

    from rodstab.multistable.cone import SAMPLES_PER_ELEMENT

    loop = a.segments[0].length  # type: ignore[attr-defined]
    s = np.linspace(0.0, loop, SAMPLES_PER_ELEMENT * n + 1)
    theta = 2.0 * math.pi * s / loop
    nz = {(0, 1): np.zeros_like(theta), (0, 2): np.zeros_like(theta),
          (1, 2): np.zeros_like(theta)}
    first = (theta > 1e-9) & (theta < delta - 1e-9)
    second = (theta > delta + 1e-9) & (theta < 2.0 * math.pi - 1e-9)
    for upper, lower, where in ((0, 2, first), (2, 1, first), (2, 0, second), (0, 1, second)):
        key = (min(upper, lower), max(upper, lower))
        nz[key][where] = 1.0 if upper == key[0] else -1.0
    return [(ia, ib, s, s.copy(), z) for (ia, ib), z in nz.items()]


def cone_table(section: str, n: int) -> None:
    """Print the flat stackings' limits with contact against the torus curve's."""
    import math
    import time

    from rodstab.multistable.cone_limit import cone_limits
    from rodstab.problems import ring as rings
    from rodstab.sections import circle, rectangle

    sec = {"circle": circle(), "rect2": rectangle(aspect=2.0)}[section]
    a = rings.build(rings.Params(section=sec, loops=3))

    def row(label: str, **kw: object) -> None:
        t = time.perf_counter()
        out = []
        for held in (False, True):
            r = cone_limits(a, "torus", n, held_closed=held, **kw)  # type: ignore[arg-type]
            out += [3.0 * side.load_factor if side is not None else float("nan")
                    for side in (r.lower, r.upper)]
        print(f"{label:24} {out[0]:10.5f} {out[1]:10.5f}   {out[2]:10.5f} {out[3]:10.5f}   "
              f"({time.perf_counter() - t:.1f} s)")

    print(f"3-loop ring, {section}, {n} el./loop, zero gap, out of plane: (L/2pi) kappa_n")
    print(f"{'stacking':24} {'cone: lower':>10} {'upper':>10}   {'held closed: lower':>10} "
          f"{'upper':>10}")
    row("torus curve")
    for frac in (0.5, 1 / 3, 0.25, 1 / 6, 1 / 12):
        row(f"flat, swaps {frac:.4f} turn", pairs=flat_pairs(a, n, 2.0 * math.pi * frac))


def hold_table() -> None:
    """Print the folded and the wound 3-loop ring relaxed with contact at load 1."""
    import math
    import time

    from rodstab.multistable.folding import layer_swaps
    from rodstab.multistable.linking import self_linking
    from rodstab.multistable.stacked import describe, relax, stacked_ring
    from rodstab.problems import ring as rings
    from rodstab.sections import circle

    a = rings.build(rings.Params(section=circle(), loops=3))
    print("3-loop ring, circle, h/L 0.01, dhat 0.1 h, load factor 1 ((L/2pi) kappa_n = 3)")
    print("stacking  el.  converged  stable  lowest eig.   E - E_coincident  Lk  swaps (deg)")
    for n in (16, 32):
        for how in ("folded", "wound"):
            t = time.perf_counter()
            rod, st = stacked_ring(a, thickness_ratio=0.01, elements_per_loop=n,
                                   dhat_fraction=0.1, stacking=how)
            d = describe(rod, st.rod, *relax(rod, 1.0))
            swaps = ", ".join(f"{math.degrees(v):.1f}" for v in layer_swaps(rod))
            print(f"{how:8} {n:4d}  {d.converged!s:9}  {d.stable!s:6}  "
                  f"{d.lowest_eigenvalue:11.3e}  {d.energy - d.energy_coincident:16.6f}  "
                  f"{self_linking(rod).value:+d}  {swaps}  ({time.perf_counter() - t:.1f} s)")


def slide_cosine(rod: object) -> tuple[float, float]:
    """Lowest eigenvalue of the Jacobi-scaled Hessian and its mode's |cosine| with sliding."""
    from rodstab.multistable.stacked import ring_sliding_field
    from rodstab.nonlinear.stability import jacobi_scaling, lowest_eigenpairs

    free = rod.free_dofs()  # type: ignore[attr-defined]
    H = rod.energy_terms()[2][free][:, free].tocsc()  # type: ignore[attr-defined]
    d = jacobi_scaling(0.5 * (H + H.T))
    vals, V = lowest_eigenpairs((H.multiply(d[:, None]).multiply(d[None, :])).tocsc(), 4)
    s = ring_sliding_field(rod)  # type: ignore[arg-type]
    if s is None:
        return float(vals[0]), float("nan")
    m = d * V[:, 0]
    return float(vals[0]), float(abs(m @ s) / (np.linalg.norm(m) * np.linalg.norm(s)))


def gauged(rod: object, k: float) -> object:
    """``rod`` with the phase condition of ``--gauge`` (module doc): a :class:`DiscreteRod`
    subclass whose energy adds the penalty (``_evaluate``; copies keep it)."""
    import dataclasses

    import scipy.sparse as sp

    from rodstab.multistable.stacked import ring_sliding_field
    from rodstab.nonlinear.discrete import DiscreteRod

    @dataclasses.dataclass
    class GaugedRod(DiscreteRod):
        gauge: tuple | None = None

        def _evaluate(self, order, links, stretch=True, with_contact=True):  # noqa: ANN001, ANN202
            E, g, H = super()._evaluate(order, links, stretch, with_contact)
            if self.gauge is None:
                return E, g, H
            a, x0, K = self.gauge
            c = float(np.sum(a * (self.x - x0)))
            av = a.ravel()
            if g is not None:
                g[:av.size] += K * c * av
            if H is not None:
                i = np.arange(av.size)
                H = (H + sp.csr_matrix((K * np.outer(av, av).ravel(),
                                        (np.repeat(i, av.size), np.tile(i, av.size))),
                                       shape=H.shape)).tocsr()
            return E + 0.5 * K * c * c, g, H

    kw = {f.name: getattr(rod, f.name) for f in dataclasses.fields(rod) if f.init}  # type: ignore[arg-type]
    out = GaugedRod(**kw)
    full = np.zeros(out.n_dof)
    full[out.free_dofs()] = ring_sliding_field(out)
    a = np.array([full[out.node_dofs(i)] for i in range(len(out.x))])
    nd = a.size
    K = k * float(np.median(np.abs(out.energy_terms()[2].diagonal()[:nd]))) * nd
    out.gauge = (a / np.linalg.norm(a), out.x.copy(), K)
    return out


def print_specials(p: object) -> None:
    """Print a path's special points with their sliding cosine and phase force."""
    states = dict(p.states)  # type: ignore[attr-defined]
    for q in p.special_points:  # type: ignore[attr-defined]
        st = states.get(q["value"])
        cos = slide_cosine(st)[1] if st is not None else float("nan")
        print(f"  {q['kind']} at {3 * q['value']:.5f}: sliding cosine {cos:.3f}, phase "
              f"force {gauge_force(st):.2e}")


def gauge_force(rod: object) -> float:
    """The phase condition's force ``K a . (x - x_held)`` (0 without one)."""
    gauge = getattr(rod, "gauge", None)
    if gauge is None:
        return 0.0
    a, x0, K = gauge
    return float(K * np.sum(a * (rod.x - x0)))  # type: ignore[attr-defined]


def snake(h: float, n: int, dhat: float, steps: int, factor: int, gauge: float = 0.0
          ) -> None:
    """Print where the arclength continuation of the held folded ring goes, both ways.

    ``gauge`` > 0: with the phase condition of that ``k`` (``--gauge``), ``factor`` 2 up and
    5 down, every special point printed.
    """
    import time

    from rodstab.multistable.stacked import hold_loops
    from rodstab.nonlinear.continuation.run import continuation
    from rodstab.problems import ring as rings
    from rodstab.sections import circle

    a = rings.build(rings.Params(section=circle(), loops=3))
    _, rod, ok, its, _ = hold_loops(a, n, 1.0, h * len(a.segments), dhat, "folded")
    print(f"folded 3-loop ring, circle, h/L {h:g}, {n} el./loop, dhat {dhat:g} h: held at "
          f"load 1 (converged {ok}, {its} iterations); loads (L/2pi) kappa_n"
          + (f"; phase condition k = {gauge:g}" if gauge > 0 else ""))
    start = gauged(rod, gauge) if gauge > 0 else rod
    for end, fac in ((2.0, 2 if gauge > 0 else factor), (0.3, 5 if gauge > 0 else factor)):
        t = time.perf_counter()
        p = continuation(a, "load_factor", 1.0, end, steps, elements_per_segment=n,
                         rod=start.copy(),  # type: ignore[attr-defined]
                         contact=rod.contact.model,  # type: ignore[union-attr]
                         branch_steps=0, max_steps_factor=fac)
        at_fold = {q["value"] for q in p.special_points if q["kind"] == "fold"}
        folds = [(3.0 * v, slide_cosine(s)[1]) for v, s in p.states if v in at_fold]
        first = p.special_points[0] if p.special_points else None
        print(f"towards {3 * end:g}: {len(p.value)} points, loads reached "
              f"[{3 * min(p.value):.4f}, {3 * max(p.value):.4f}], {len(folds)} folds "
              f"({time.perf_counter() - t:.0f} s; {p.method.split('; ')[-1][:50]})")
        if first is not None:
            lam, cos = slide_cosine(p.states[0][1]) if p.states else (float("nan"),) * 2
            print(f"  first: {first['kind']} at {3 * first['value']:.5f}, lowest mode's "
                  f"sliding cosine {cos:.3f} (eigenvalue {lam:.2e})")
        if gauge > 0:
            print_specials(p)
        if folds:
            lo, hi = min(folds), max(folds)
            print(f"  lowest fold {lo[0]:.5f} (sliding cosine {lo[1]:.3f}), highest "
                  f"{hi[0]:.5f} ({hi[1]:.3f}); folds with cosine >= 0.8: "
                  f"{sum(c >= 0.8 for _, c in folds)}")


def regauge(h: float, n: int, dhat: float, piece: int, stop: float = 2.0) -> None:
    """Print the phased continuation upward, the phase set anew every ``piece`` steps."""
    import time

    from rodstab.multistable.stacked import hold_loops
    from rodstab.nonlinear.continuation.run import continuation
    from rodstab.problems import ring as rings
    from rodstab.sections import circle

    a = rings.build(rings.Params(section=circle(), loops=3))
    _, rod, ok, its, _ = hold_loops(a, n, 1.0, h * len(a.segments), dhat, "folded")
    print(f"folded 3-loop ring, circle, h/L {h:g}, {n} el./loop, dhat {dhat:g} h, phase set "
          f"anew every {piece} steps of 0.025; loads (L/2pi) kappa_n")
    v, state, step, t = 1.0, rod, 0.025, time.perf_counter()
    while stop - v > 1e-9:
        g = gauged(state, 1.0)
        end = min(v + piece * step, stop)
        p = continuation(a, "load_factor", v, end, max(1, round((end - v) / step)),
                         elements_per_segment=n, rod=g,  # type: ignore[arg-type]
                         contact=rod.contact.model,  # type: ignore[union-attr]
                         branch_steps=0, max_steps_factor=3)
        print_specials(p)
        print(f"piece {3 * v:.4f} -> {3 * p.value[-1]:.4f}: lowest eigenvalue "
              f"{p.lowest_eigenvalue[-1]:.2e} ({time.perf_counter() - t:.0f} s)")
        if not p.converged or any(q["kind"] == "fold" for q in p.special_points):
            print("stopped:", p.method.split("; ")[-1][:70])
            break
        v, state = p.value[-1], g


def near_end(shape: str, n: int, near: float, up: bool, h: float = 0.01, dhat: float = 0.1
             ) -> None:
    """Print the arclength continuation of the held ring started near one end (``--near``).

    The held ring (``shape`` circle or rect2) stepped in the natural parameter by 0.009 in
    ``(L/2pi) kappa_n`` (Newton with contact) to ``near``, then followed by the
    pseudo-arclength continuation over 0.3 beyond it (40 steps, at most 160): its special
    points with their sliding cosines, the loads and lowest eigenvalues along it.
    """
    import time

    from rodstab.multistable.stacked import hold_loops
    from rodstab.nonlinear.continuation.run import continuation
    from rodstab.nonlinear.solve import newton
    from rodstab.problems import ring as rings
    from rodstab.sections import circle, rectangle

    section = rectangle(aspect=2.0) if shape == "rect2" else circle()
    a = rings.build(rings.Params(section=section, loops=3))
    _, rod, _, _, _ = hold_loops(a, n, 1.0, h * len(a.segments), dhat, "folded")
    t = time.perf_counter()
    mu, step = 1.0, 0.003 if up else -0.003
    while (mu + step - near / 3) * (1 if up else -1) <= 1e-12:
        rod.load_factor = mu + step
        if not newton(rod)[0]:
            print(f"Newton failed at {3 * (mu + step):.4f}")
            return
        mu += step
    end = (near + (0.3 if up else -0.3)) / 3
    p = continuation(a, "load_factor", mu, end, 40, elements_per_segment=n, rod=rod.copy(),
                     contact=rod.contact.model,  # type: ignore[union-attr]
                     branch_steps=0, max_steps_factor=4)
    print(f"{shape}, {n} el./loop, h/L {h:g}, dhat {dhat:g} h: natural steps to {3 * mu:.4f}, "
          f"arclength reached [{3 * min(p.value):.5f}, {3 * max(p.value):.5f}] "
          f"({time.perf_counter() - t:.0f} s)")
    print_specials(p)
    print("  loads", " ".join(f"{3 * v:.4f}" for v in p.value))
    print("  lowest eigenvalues", " ".join(f"{v:.1e}" for v in p.lowest_eigenvalue))


if __name__ == "__main__":
    import sys

    if sys.argv[1:2] == ["--hold"]:
        hold_table()
    elif sys.argv[1:2] == ["--snake"]:
        a = sys.argv[2:]
        snake(float(a[0]) if a else 0.01, int(a[1]) if len(a) > 1 else 16,
              float(a[2]) if len(a) > 2 else 0.1, int(a[3]) if len(a) > 3 else 40,
              int(a[4]) if len(a) > 4 else 30)
    elif sys.argv[1:2] == ["--gauge"]:
        a = sys.argv[2:]
        snake(float(a[0]) if a else 0.01, int(a[1]) if len(a) > 1 else 16,
              float(a[2]) if len(a) > 2 else 0.1, int(a[3]) if len(a) > 3 else 40, 0,
              float(a[4]) if len(a) > 4 else 1.0)
    elif sys.argv[1:2] == ["--regauge"]:
        a = sys.argv[2:]
        regauge(float(a[0]) if a else 0.01, int(a[1]) if len(a) > 1 else 16,
                float(a[2]) if len(a) > 2 else 0.1, int(a[3]) if len(a) > 3 else 4)
    elif sys.argv[1:2] == ["--near"]:
        a = sys.argv[2:]
        way = [w for w in a[3:] if w in ("up", "down")]
        nums = [float(w) for w in a[3:] if w not in ("up", "down")]
        near_end(a[0], int(a[1]), float(a[2]), way != ["down"], *nums)
    elif sys.argv[1:2] == ["--cone"]:
        cone_table(sys.argv[2], int(sys.argv[3]))
    else:
        main()
