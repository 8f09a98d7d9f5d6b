"""Beyond the onset: post-buckled branches from a bifurcation, and imperfection sensitivity.

Branch from the bifurcation (amplitude control): at the critical load ``mu_c`` of the held
state, the critical mode's largest out-of-plane nodal displacement ``z_k`` is prescribed,
``z_k = a``, and the load ``mu`` is solved for with the equilibrium equations by a bordered
Newton method::

    [ H(q, mu)   dg/dmu ] [dq ]     [ g(q, mu)  ]
    [ e_k^T      0      ] [dmu] = - [ z_k - a   ]

(``g`` is affine in ``mu``, so ``dg/dmu = g(q, mu + 1) - g(q, mu)`` exactly). Amplitude control
passes through the bifurcation and through limit points of ``mu`` alike. The initial
post-buckling is read from ``mu(a) = mu_c + c1 a + c2 a^2``: ``c1 != 0`` asymmetric,
``c2 > 0`` stable symmetric (supercritical), ``c2 < 0`` unstable symmetric (subcritical).

Imperfection sensitivity: the natural shape carries an imperfection shaped like the critical
mode (the joints' natural curvatures are changed by the curvature change of ``eps`` times the
mode), the load is raised from the held state by natural continuation, and the limit load
``mu_max(eps)`` is where the Hessian's lowest eigenvalue reaches zero.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..model import Assembly
from ..numerics import find_roots
from ..results import Result
from .discrete import PENALTY, DiscreteRod, discretise
from .solve import critical_load_factor, lowest_modes, newton


@dataclasses.dataclass(frozen=True)
class Branch(Result):
    """A traced post-buckled branch: amplitude, load, energy, lowest eigenvalue at fixed load."""

    load_factor_critical: float
    amplitude: tuple[float, ...]
    load_factor: tuple[float, ...]
    energy: tuple[float, ...]
    lowest_eigenvalue: tuple[float, ...]
    c1: float
    c2: float
    verdict: str
    converged: bool
    method: str
    shapes: tuple = ()  # node positions (n, 3) along the positive-amplitude side


def _mode_node(rod: DiscreteRod, vec: np.ndarray) -> tuple[int, float]:
    """The free z-unknown where the mode's out-of-plane displacement is largest."""
    free = rod.free_dofs()
    z_free = [i for i, dof in enumerate(free) if dof < 3 * len(rod.x) and dof % 3 == 2]
    k = max(z_free, key=lambda i: abs(vec[i]))
    return k, float(vec[k])


def _dg_dmu(rod: DiscreteRod) -> np.ndarray:
    mu = rod.load_factor
    g0 = rod.energy_terms()[1]
    rod.load_factor = mu + 1.0
    g1 = rod.energy_terms()[1]
    rod.load_factor = mu
    return g1 - g0


def _bordered_newton(rod: DiscreteRod, k: int, a: float, *, max_iter: int = 40) -> bool:
    """Solve g = 0 with the free unknown ``k`` held at ``a`` and ``mu`` free (in place)."""
    free = rod.free_dofs()
    scale = float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))
    n = len(free)
    for _ in range(max_iter):
        _, g, H = rod.energy_terms()
        gf = g[free]
        dof = free[k]
        val = rod.x.reshape(-1)[dof]
        if np.max(np.abs(gf)) <= 1e-9 * scale and abs(val - a) <= 1e-12 * max(1.0, abs(a)):
            return True
        Hf = H[free][:, free].tocsc()
        gm = _dg_dmu(rod)[free]
        ek = sp.csr_matrix(([1.0], ([0], [k])), shape=(1, n))
        M = sp.bmat([[Hf, sp.csr_matrix(gm[:, None])], [ek, None]], format="csc")
        rhs = -np.concatenate([gf, [val - a]])
        with np.errstate(all="ignore"):
            import warnings

            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                sol = spla.spsolve(M, rhs)
        if not np.all(np.isfinite(sol)):
            # Singular bordered matrix: a second critical mode (a double eigenvalue, as in
            # the symmetric folded ring). The minimum-norm step keeps that mode's amplitude.
            sol = np.linalg.lstsq(M.toarray(), rhs, rcond=1e-12)[0]
        dq = np.zeros(rod.n_dof)
        dq[free] = sol[:n]
        rod.apply(dq)
        rod.load_factor += float(sol[n])
    return False


def _advance(rod: DiscreteRod, k: int, target: float, direction: np.ndarray,
             depth: int = 0) -> bool:
    """Move the branch to amplitude ``target`` (predictor along ``direction``, bordered Newton
    corrector); on failure restore the state and take two half steps (at most 5 halvings)."""
    free = rod.free_dofs()
    saved = (rod.x.copy(), rod.R_edge.copy(), rod.R_joint.copy(), rod.load_factor)
    cur = rod.x.reshape(-1)[free[k]]
    dq = np.zeros(rod.n_dof)
    dq[free] = direction * (target - cur)
    rod.apply(dq)
    if _bordered_newton(rod, k, target):
        return True
    rod.x, rod.R_edge, rod.R_joint, rod.load_factor = saved
    if depth >= 5:
        return False
    mid = 0.5 * (cur + target)
    return (_advance(rod, k, mid, direction, depth + 1)
            and _advance(rod, k, target, direction, depth + 1))


def post_buckling_branch(a: Assembly, lo: float, hi: float, *, elements_per_segment: int = 24,
                         amplitudes: np.ndarray | None = None) -> Branch:
    """Trace the post-buckled branch from the first bifurcation of the held state in (lo, hi].

    ``amplitudes`` are the prescribed largest out-of-plane displacements (in the length unit;
    default: 12 values up to 2 % of the assembly's total length, both signs are not needed for
    the verdict but ``-a`` is traced too to detect asymmetry).
    """
    crit = critical_load_factor(a, lo, hi, elements_per_segment=elements_per_segment)
    mu_c = crit.load_factor_critical
    rod0 = discretise(a, elements_per_segment, mu_c)
    _, vecs = lowest_modes(rod0, 1)
    k, amp = _mode_node(rod0, vecs[:, 0])
    if amplitudes is None:
        amplitudes = np.linspace(0.0, 0.02 * a.total_length, 13)[1:]
    rows = []
    shapes = [rod0.x.copy()]
    ok_all = True
    for sign in (1.0, -1.0):
        rod = rod0.copy()
        free = rod.free_dofs()
        base = rod.x.reshape(-1)[free[k]]
        for s_amp in amplitudes:
            target = base + sign * s_amp
            ok = _advance(rod, k, target, vecs[:, 0] / amp)
            ok_all &= ok
            if not ok:
                break
            mu_fixed = rod.load_factor
            if sign > 0:
                shapes.append(rod.x.copy())
            ev = float(lowest_modes(rod, 1)[0][0])
            rows.append((sign * s_amp, mu_fixed, rod.energy(), ev))
    rows.sort()
    A = np.array([r[0] for r in rows])
    M = np.array([r[1] for r in rows])
    small = np.abs(A) <= 0.5 * np.max(np.abs(A))
    c = np.polyfit(A[small], M[small] - mu_c, 2) if small.sum() >= 3 else [math.nan] * 3
    c2, c1 = float(c[0]), float(c[1])
    tol = 1e-3 * abs(c2) * np.max(np.abs(A))
    if abs(c1) > tol:
        verdict = "asymmetric (unstable on one side)"
    elif c2 > 0:
        verdict = "stable symmetric (supercritical): the load rises after buckling"
    else:
        verdict = "unstable symmetric (subcritical): the load falls after buckling"
    return Branch(mu_c, tuple(A), tuple(M), tuple(r[2] for r in rows), tuple(r[3] for r in rows),
                  c1, c2, verdict, bool(ok_all),
                  "amplitude-controlled bordered Newton from the critical mode", tuple(shapes))


@dataclasses.dataclass(frozen=True)
class ImperfectionSensitivity(Result):
    """Limit loads of imperfect structures (imperfection ``eps`` times the critical mode)."""

    load_factor_critical: float
    epsilon: tuple[float, ...]
    limit_load: tuple[float, ...]
    paths: tuple[tuple[tuple[float, float], ...], ...]  # per eps: (mu, max |z|) along the path
    exponent: float
    verdict: str
    method: str


def _imperfect(rod: DiscreteRod, vec: np.ndarray, eps: float) -> DiscreteRod:
    """The same rod whose natural shape contains ``eps`` times the mode ``vec`` (free part).

    Natural curvatures of every joint change by the curvature change that the displacement
    ``eps * vec`` causes; the held geometry (and hence the supports) stay as they are.
    """
    from .discrete import _held_curvatures

    free = rod.free_dofs()
    moved = rod.copy()
    dq = np.zeros(rod.n_dof)
    dq[free] = eps * vec
    moved.apply(dq)
    kp0, kl0 = _held_curvatures(rod)
    kp1, kl1 = _held_curvatures(moved)
    imp = rod.copy()
    imp.k_held_pairs = rod.k_held_pairs + (kp1 - kp0)
    a, b = rod.k0_links
    imp.k0_links = (a + (kl1 - kl0), b)
    return imp


def imperfection_sensitivity(a: Assembly, lo: float, hi: float, *,
                             epsilons: tuple[float, ...] = (1e-3, 2e-3, 4e-3, 8e-3),
                             elements_per_segment: int = 16,
                             mu_max_factor: float = 1.5,
                             n_steps: int = 21) -> ImperfectionSensitivity:
    """Limit load ``mu_max(eps)`` of the imperfect structure for each amplitude ``eps``.

    The load is raised from ``0.5 mu_c`` in steps (Newton from the previous equilibrium) and
    the first sign change of the lowest Hessian eigenvalue is refined by the root finder. No
    limit point below ``mu_max_factor mu_c`` means imperfection-insensitive at that amplitude
    (reported as NaN). The exponent is the slope of ``log(1 - mu_max/mu_c)`` vs ``log eps``
    (2/3 for an unstable symmetric bifurcation, 1/2 for an asymmetric one).
    """
    crit = critical_load_factor(a, lo, hi, elements_per_segment=elements_per_segment)
    mu_c = crit.load_factor_critical
    rod0 = discretise(a, elements_per_segment, mu_c)
    _, vecs = lowest_modes(rod0, 1)
    v = vecs[:, 0] / np.max(np.abs(vecs[:, 0]))
    limits, paths = [], []
    for eps in epsilons:
        imp = _imperfect(rod0, v, eps * a.total_length)
        state = {"rod": imp.copy()}

        def lam(mu: float, state=state) -> float:
            r = state["rod"]
            r.load_factor = mu
            ok, _, _ = newton(r)
            if not ok:
                return math.nan
            return float(lowest_modes(r, 1)[0][0])

        grid = np.linspace(0.5 * mu_c, mu_max_factor * mu_c, n_steps)
        vals = []
        path = []
        found = math.nan
        for i, mu in enumerate(grid):
            vals.append(lam(mu))
            path.append((float(mu), float(np.max(np.abs(state["rod"].x[:, 2])))))
            if i and vals[-1] < 0 <= vals[-2]:
                saved = state["rod"].copy()
                res = find_roots(lambda m: lam(m), grid[i - 1], mu, n_scan=4)
                state["rod"] = saved
                found = res.roots[0].x if res.roots else float(mu)
                break
        limits.append(found)
        paths.append(tuple(path))
    lim = np.array(limits)
    ok = np.isfinite(lim) & (lim < mu_c)
    if ok.sum() >= 2:
        p = np.polyfit(np.log(np.array(epsilons)[ok]), np.log(1 - lim[ok] / mu_c), 1)
        exponent = float(p[0])
        verdict = f"imperfection-sensitive: 1 - mu_max/mu_c ~ eps^{exponent:.2f}"
    else:
        exponent = math.nan
        verdict = (f"no limit point below {mu_max_factor:g} mu_c for these amplitudes: "
                   "imperfection-insensitive (stable post-buckling)")
    return ImperfectionSensitivity(mu_c, tuple(epsilons), tuple(limits), tuple(paths),
                                   exponent, verdict,
                                   "natural continuation in the load, Hessian eigenvalue scan")


@dataclasses.dataclass(frozen=True)
class Continuation(Result):
    """Primary path in the load factor, detected special points and traced secondary branches."""

    load_factor: tuple[float, ...]
    energy: tuple[float, ...]
    lowest_eigenvalue: tuple[float, ...]
    converged: tuple[bool, ...]
    special_points: tuple[dict, ...]
    branches: tuple[Branch, ...]
    resumed_steps: int


def continue_in_load(a: Assembly, mu_start: float, mu_stop: float, n_steps: int, *,
                     elements_per_segment: int = 16, out_dir=None, progress=None,
                     branch_amplitude: float = 0.04) -> Continuation:
    """Follow the equilibrium from ``mu_start`` to ``mu_stop`` in ``n_steps`` load steps.

    Each step: Newton from the previous equilibrium, lowest Hessian eigenvalues. A sign change
    of the lowest eigenvalue is a special point: it is refined on the held state (bifurcation
    from the primary path) and the secondary branch is traced from it by amplitude control
    (:func:`post_buckling_branch`). With ``out_dir``, every completed step is appended to
    ``primary.csv`` and the state saved to ``state.npz`` first, so an interrupted run continues
    from the last completed step (losing at most the step in progress).
    """
    import csv
    import json
    from pathlib import Path

    grid = np.linspace(mu_start, mu_stop, n_steps + 1)
    rod = discretise(a, elements_per_segment, float(grid[0]))
    rows: list[tuple[float, float, float, bool]] = []
    resumed = 0
    out = Path(out_dir) if out_dir is not None else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        meta = {"mu_start": mu_start, "mu_stop": mu_stop, "n_steps": n_steps,
                "elements_per_segment": elements_per_segment}
        mpath = out / "run.json"
        if mpath.exists() and json.loads(mpath.read_text()) == meta \
                and (out / "primary.csv").exists() and (out / "state.npz").exists():
            with (out / "primary.csv").open() as fh:
                for r in csv.DictReader(fh):
                    rows.append((float(r["load_factor"]), float(r["energy"]),
                                 float(r["lowest_eigenvalue"]), r["converged"] == "True"))
            st = np.load(out / "state.npz")
            rod.x, rod.R_edge, rod.R_joint = st["x"], st["R_edge"], st["R_joint"]
            resumed = len(rows)
        else:
            mpath.write_text(json.dumps(meta))
            with (out / "primary.csv").open("w") as fh:
                fh.write("load_factor,energy,lowest_eigenvalue,converged\n")
    for mu in grid[len(rows):]:
        rod.load_factor = float(mu)
        ok, _, _ = newton(rod)
        ev = float(lowest_modes(rod, 1)[0][0])
        rows.append((float(mu), rod.energy(), ev, bool(ok)))
        if out is not None:
            np.savez(out / "state.tmp.npz", x=rod.x, R_edge=rod.R_edge, R_joint=rod.R_joint)
            (out / "state.tmp.npz").replace(out / "state.npz")
            with (out / "primary.csv").open("a") as fh:
                fh.write(f"{float(mu)!r},{float(rows[-1][1])!r},{float(ev)!r},{ok}\n")
        if progress is not None:
            progress()
    specials, branches = [], []
    for (m0, _, e0, _), (m1, _, e1, _) in zip(rows, rows[1:]):
        if e0 > 0 >= e1 or e0 <= 0 < e1:
            crit = critical_load_factor(a, m0, m1, elements_per_segment=elements_per_segment,
                                        n_scan=4)
            kind = "branch point (stability lost)" if e0 > 0 else "branch point (regained)"
            point = {"load_factor": crit.load_factor_critical, "kind": kind}
            if e0 > 0 and math.isfinite(crit.load_factor_critical):
                b = post_buckling_branch(
                    a, m0, m1, elements_per_segment=elements_per_segment,
                    amplitudes=np.linspace(0.0, branch_amplitude * a.total_length, 5)[1:])
                branches.append(b)
                point["post_buckling"] = b.verdict
            specials.append(point)
    if out is not None:
        (out / "special_points.json").write_text(json.dumps(specials, indent=1))
        if branches and branches[0].shapes:
            from ..plots import animate_shapes

            b = branches[0]
            animate_shapes(list(b.shapes), rod.edge_nodes, out / "branch.gif",
                           labels=[f"load factor {m:.6g}" for m in
                                   [b.load_factor_critical] + [mu for amp, mu in
                                                               zip(b.amplitude, b.load_factor)
                                                               if amp > 0]])
        with (out / "branches.csv").open("w") as fh:
            fh.write("branch,amplitude,load_factor,energy,lowest_eigenvalue\n")
            for i, b in enumerate(branches):
                for row in zip(b.amplitude, b.load_factor, b.energy, b.lowest_eigenvalue):
                    fh.write(f"{i}," + ",".join(repr(float(v)) for v in row) + "\n")
    return Continuation(tuple(r[0] for r in rows), tuple(r[1] for r in rows),
                        tuple(r[2] for r in rows), tuple(r[3] for r in rows), tuple(specials),
                        tuple(branches), resumed)


@dataclasses.dataclass(frozen=True)
class ArclengthPath(Result):
    """Points of a pseudo-arclength path: load, energy, lowest eigenvalue, a shape measure."""

    load_factor: tuple[float, ...]
    energy: tuple[float, ...]
    lowest_eigenvalue: tuple[float, ...]
    radius: tuple[float, ...]  # largest distance of a node from the centroid
    shapes: tuple
    converged: bool
    method: str


def _arclength_correct(rod: DiscreteRod, tq: np.ndarray, tmu: float, ds: float,
                       *, max_iter: int = 25) -> bool:
    """Corrector: g = 0 and t . (accumulated increment) = ds (in place)."""
    free = rod.free_dofs()
    n = len(free)
    scale = float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))
    acc_q = tq * ds  # the predictor already moved by ds along t
    acc_mu = tmu * ds
    for _ in range(max_iter):
        _, g, H = rod.energy_terms()
        gf = g[free]
        c = float(tq @ acc_q + tmu * acc_mu - ds)
        if np.max(np.abs(gf)) <= 1e-9 * scale and abs(c) <= 1e-10 * max(abs(ds), 1e-12):
            return True
        gm = _dg_dmu(rod)[free]
        M = sp.bmat([[H[free][:, free].tocsc(), sp.csr_matrix(gm[:, None])],
                     [sp.csr_matrix(tq[None, :]), sp.csr_matrix([[tmu]])]], format="csc")
        rhs = -np.concatenate([gf, [c]])
        sol = spla.spsolve(M, rhs)
        if not np.all(np.isfinite(sol)):
            return False
        dq = np.zeros(rod.n_dof)
        dq[free] = sol[:n]
        rod.apply(dq)
        rod.load_factor += float(sol[n])
        acc_q = acc_q + sol[:n]
        acc_mu += float(sol[n])
    return False


def _tangent(rod: DiscreteRod, tq_prev: np.ndarray, tmu_prev: float) -> tuple[np.ndarray, float]:
    """Unit tangent of the path: ``[H g_mu; t_prev^T] t = [0; 1]``, normalised, oriented."""
    free = rod.free_dofs()
    n = len(free)
    _, _, H = rod.energy_terms()
    gm = _dg_dmu(rod)[free]
    M = sp.bmat([[H[free][:, free].tocsc(), sp.csr_matrix(gm[:, None])],
                 [sp.csr_matrix(tq_prev[None, :]), sp.csr_matrix([[tmu_prev]])]], format="csc")
    rhs = np.zeros(n + 1)
    rhs[-1] = 1.0
    t = spla.spsolve(M, rhs)
    t /= np.linalg.norm(t)
    if t[:n] @ tq_prev + t[n] * tmu_prev < 0:
        t = -t
    return t[:n], float(t[n])


def arclength_from_bifurcation(a: Assembly, lo: float, hi: float, *, elements_per_segment: int
                               = 24, ds: float = 0.05, n_steps: int = 60,
                               mu_window: tuple[float, float] | None = None) -> ArclengthPath:
    """Pseudo-arclength continuation (Keller) along the branch leaving the first bifurcation.

    Starts at the critical load of the held state with the tangent along the critical mode
    (a symmetric pitchfork has ``d mu = 0`` there), then predictor along the tangent and a
    bordered Newton corrector on the arclength constraint; the step halves on failure and grows
    after easy steps. Folds in the load are passed without special treatment (the bordered
    matrix stays regular there). Stops after ``n_steps`` or when the load leaves ``mu_window``.
    """
    crit = critical_load_factor(a, lo, hi, elements_per_segment=elements_per_segment)
    rod = discretise(a, elements_per_segment, crit.load_factor_critical)
    _, vecs = lowest_modes(rod, 1)
    free = rod.free_dofs()
    tq = vecs[:, 0] / np.linalg.norm(vecs[:, 0])
    tmu = 0.0
    out = []
    ok_all = True

    def record() -> None:
        c = rod.x.mean(axis=0)
        out.append((rod.load_factor, rod.energy(), float(lowest_modes(rod, 1)[0][0]),
                    float(np.max(np.linalg.norm(rod.x - c, axis=1))), rod.x.copy()))

    record()
    h = ds
    for _ in range(n_steps):
        saved = (rod.x.copy(), rod.R_edge.copy(), rod.R_joint.copy(), rod.load_factor)
        dq = np.zeros(rod.n_dof)
        dq[free] = h * tq
        rod.apply(dq)
        rod.load_factor += h * tmu
        if not _arclength_correct(rod, tq, tmu, h):
            rod.x, rod.R_edge, rod.R_joint, rod.load_factor = saved
            h *= 0.5
            if h < ds * 1e-3:
                ok_all = False
                break
            continue
        tq, tmu = _tangent(rod, tq, tmu)
        record()
        h = min(1.5 * h, 4 * ds)
        if mu_window and not (mu_window[0] <= rod.load_factor <= mu_window[1]):
            break
    return ArclengthPath(tuple(o[0] for o in out), tuple(o[1] for o in out),
                         tuple(o[2] for o in out), tuple(o[3] for o in out),
                         tuple(o[4] for o in out), ok_all,
                         "pseudo-arclength (Keller), bordered Newton corrector")


@dataclasses.dataclass(frozen=True)
class PrimaryCritical(Result):
    """First loss of stability along the primary equilibrium path (found by continuation)."""

    load_factor_critical: float
    bracket: tuple[float, float]
    steps: int
    method: str


def critical_along_primary(a: Assembly, mu_start: float, mu_stop: float, *,
                           elements_per_segment: int = 32, ds: float = 0.05,
                           refinements: int = 3) -> PrimaryCritical:
    """Critical load of a primary path that is NOT the held state (e.g. a twisted ring).

    Newton at ``mu_start`` (must be stable there), then pseudo-arclength continuation with the
    tangent initially along the load; the first sign change of the lowest Hessian eigenvalue is
    bracketed, the bracket re-traced ``refinements`` times with a quarter of the step, and the
    zero located by linear interpolation of the eigenvalue in the load (error well below the
    discretisation error for the final bracket).
    """
    rod = discretise(a, elements_per_segment, mu_start)
    ok, _, _ = newton(rod)
    if not ok or lowest_modes(rod, 1)[0][0] <= 0:
        return PrimaryCritical(math.nan, (math.nan, math.nan), 0,
                               "no stable equilibrium at mu_start")
    n = len(rod.free_dofs())
    tq, tmu = np.zeros(n), 1.0
    h = ds
    steps = 0
    prev_state = None
    for _ in range(refinements + 1):
        prev = (rod.load_factor, float(lowest_modes(rod, 1)[0][0]))
        found = None
        while rod.load_factor < mu_stop and steps < 4000:
            saved = (rod.x.copy(), rod.R_edge.copy(), rod.R_joint.copy(), rod.load_factor,
                     tq.copy(), tmu)
            rod.load_factor += h * tmu
            dq = np.zeros(rod.n_dof)
            dq[rod.free_dofs()] = h * tq
            rod.apply(dq)
            steps += 1
            if not _arclength_correct(rod, tq, tmu, h):
                rod.x, rod.R_edge, rod.R_joint, rod.load_factor, tq, tmu = saved
                h *= 0.5
                if h < ds * 1e-4:
                    break
                continue
            tq, tmu = _tangent(rod, tq, tmu)
            ev = float(lowest_modes(rod, 1)[0][0])
            if prev[1] > 0 >= ev:
                found = (prev, (rod.load_factor, ev))
                prev_state = saved
                break
            prev = (rod.load_factor, ev)
        if found is None:
            return PrimaryCritical(math.nan, (math.nan, math.nan), steps,
                                   "no loss of stability before mu_stop")
        (m0, e0), (m1, e1) = found
        # Re-trace the bracket with smaller steps from its stable end.
        rod.x, rod.R_edge, rod.R_joint, rod.load_factor, tq, tmu = prev_state
        h = 0.25 * h
    mu_c = m0 + (m1 - m0) * e0 / (e0 - e1)
    return PrimaryCritical(float(mu_c), (float(m0), float(m1)), steps,
                           "pseudo-arclength along the primary path, eigenvalue sign change")
