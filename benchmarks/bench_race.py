"""Verdict race at equal accuracy (issue 12, target 4), run on demand.

The straightened rod (Section 3.2) held straight with both ends clamped: L = 1, circle
(B1 = B3 = 1, B2 = B1 / (1 + nu), nu = 1/3), natural in-plane curvature mu. Exact critical
load mu_c = 2 pi sqrt(B1 B2) / (B3 L) (eq. 3.9,
:func:`rodstab.analytic.arc.straight_clamped_critical`).

1. PyElastica's own threshold against its resolution N. Undamped Cosserat dynamics from rest,
   out-of-plane displacement a0 sin^2(pi s) (the displacement of mode (3.10)); the modal amplitude
   A(t) (least-squares projection of z on that shape) is fitted by A = a C(lam, t) + b S(lam, t),
   C = cos(sqrt(lam) t), S = sin(sqrt(lam) t) / sqrt(lam) -- both entire in lam, i.e. cosh/sinh
   for lam < 0 -- with lam found by variable projection. lam is the mode's squared frequency
   (> 0, stable) or minus its squared growth rate (< 0, unstable); it crosses zero at
   PyElastica's threshold, found by secant iterations in mu. The smallest N of the scan whose
   threshold is within 1 % of mu_c races.
2. rodstab's mesh from a Richardson estimate: thresholds on n0, 2 n0, 4 n0, ... elements;
   observed order p from the last three meshes, error estimate |mu_n/2 - mu_n| / (2^p - 1);
   the first mesh whose estimate is <= 0.1 % races. For the nonlinear model (the held state's
   Hessian pencil, :func:`rodstab.nonlinear.solve.critical_load_factor`, n0 = 16, p ~ 2) and
   for the linear FE engine (P2 of the held state, n0 = 2, p ~ 4).
3. The race at f = 0.9, 0.98, 1.02, 1.1 mu_c. rodstab, each median of 5: "eig", the sign of the
   lowest eigenvalue of the held state's Hessian (cold: discretise + Hessian + eigen solve, every
   verdict from scratch, as the shipped race did); "LDL", the same sign by Sylvester's inertia
   (one sparse LDL^T instead of the eigen solve); "warm", the Hessian pencil (affine in mu)
   assembled once, one LDL^T per verdict; "linear", the linear engine from scratch (assembly
   of P2 + one factorisation whose inertia on the closure constraints is the verdict,
   :func:`rodstab.linear.solve.stable_at`); "lin. warm", P2's pencil assembled once
   (:func:`rodstab.linear.solve.linear_pencil`), one factorisation per verdict. PyElastica,
   one run: the motion above, final time from the measured growth rate
   (:func:`race_final_time`), stopped once |A| > 100 a0; verdict by the fitted lam AND the
   growth of |A| (both must agree, else "undecided").
Run: ``python benchmarks/bench_race.py`` (or ``python benchmarks/bench_nonlinear.py race``).
PyElastica is installed with the benchmark extra: ``pip install ".[bench]"``.
"""

from __future__ import annotations

import math
import statistics
import time
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.optimize import minimize_scalar

from rodstab.analytic.arc import straight_clamped_critical
from rodstab.linear.solve import LinearPencil, linear_pencil, linear_stability, stable_at
from rodstab.model import Assembly, Segment
from rodstab.nonlinear.discrete import DiscreteRod, discretise
from rodstab.nonlinear.solve import critical_load_factor, lowest_eigenvalues
from rodstab.numerics import count_below, jacobi_scaling

NU = 1 / 3
B1, B2, B3 = 1.0, 1.0 / (1 + NU), 1.0  # circle: twist B2 = B1 / (1 + nu)
L = 1.0
MU_C = straight_clamped_critical(B1 / B3, B2 / B3) / L  # eq. (3.9)
RACE_FACTORS = (0.9, 0.98, 1.02, 1.1)
#: Required accuracy of the thresholds (relative to mu_c).
ELASTICA_TOL, RODSTAB_TOL = 1e-2, 1e-3
#: PyElastica resolutions scanned (elements).
ELASTICA_N = (40, 60, 80, 100, 105, 110, 120)
#: Radius of the PyElastica rod (L / r = 50; unit density).
RADIUS = 0.02
#: Time step as a fraction of the axial-wave limit dx / sqrt(E / rho): 0.8 is stable and gives
#: the same lam to 1e-6 as 0.4 (measured at N = 110); 0.95 diverges.
CFL = 0.8
#: ... and at most DT_MAX (s): on coarse meshes the shear-rotation modes limit the step
#: (4.25e-6 s is stable at N = 40 and 60, 7.1e-6 s diverges at N = 40).
DT_MAX = 4e-6
#: Perturbation amplitude (m): small enough that 100x growth stays linear.
A0 = 1e-6
#: Simulated time of each threshold measurement (s): several oscillations / e-foldings at
#: |f - threshold| = 3 %, enough for the fit to resolve |lam| ~ 1e2 s^-2 near the threshold.
MEASURE_TIME = 0.06
#: Record the modal amplitude every this many steps.
SAMPLE = 10
#: Design growth of the slowest unstable race load: T = acosh(GROWTH_DESIGN) / sigma.
GROWTH_DESIGN = 100.0
#: Verdict "unstable" needs max |A| / a0 >= GROWTH_UNSTABLE (reached even if the true growth
#: rate were half the measured one: cosh(acosh(100) / 2) = 7.1), "stable" needs <= GROWTH_STABLE
#: (undamped and stable, |A| stays near its initial value).
GROWTH_UNSTABLE, GROWTH_STABLE = 5.0, 2.0


def straight_rod() -> Assembly:
    s = Segment(name="rod", length=L, curvature=0.0, natural_curvature=1.0, B1=B1, B2=B2, B3=B3)
    return Assembly(segments=(s,), supports=(("rod", "start", "clamped"),
                                             ("rod", "end", "clamped")))


# --- PyElastica ---------------------------------------------------------------------------

def elastica_motion(mu: float, n: int, final_time: float, stop_growth: float = math.inf
                    ) -> tuple[np.ndarray, np.ndarray, float]:
    """Sample times and modal amplitude ``A(t) / a0`` (shapes ``(m,)``) of the perturbed held
    rod, and the wall time of the time integration alone (s). The run stops early once
    ``|A| / a0 > stop_growth`` (a verdict needs no more; the trace stays linear)."""
    import elastica as ea

    class Sim(ea.BaseSystemCollection, ea.Constraints):
        pass

    inertia = math.pi * RADIUS**4 / 4
    E = B1 / inertia
    G = E / (2 * (1 + NU))  # twist G (2 I) = B1 / (1 + nu) = B2
    sim = Sim()
    rod = ea.CosseratRod.straight_rod(n, np.zeros(3), np.array([1.0, 0, 0]),
                                      np.array([0, 0, 1.0]), L, RADIUS, 1.0, youngs_modulus=E,
                                      shear_modulus=G)
    rod.rest_kappa[0, :] = mu  # natural curvature about d1 = e3 (in plane), held straight
    shape = np.sin(np.pi * np.linspace(0, 1, n + 1)) ** 2
    rod.position_collection[2, :] += A0 * shape
    sim.append(rod)
    sim.constrain(rod).using(ea.FixedConstraint, constrained_position_idx=(0, -1),
                             constrained_director_idx=(0, -1))
    sim.finalize()
    dt = min(CFL * (L / n) / math.sqrt(E), DT_MAX)  # unit density
    stepper = ea.PositionVerlet()
    w = shape / (shape @ shape)
    z = rod.position_collection[2]
    n_steps = int(round(final_time / dt))
    ts, amp = np.empty(n_steps // SAMPLE + 1), np.empty(n_steps // SAMPLE + 1)
    t, j = 0.0, 0
    start = time.perf_counter()
    for i in range(n_steps):
        t = stepper.step(sim, t, dt)
        if i % SAMPLE == 0:
            ts[j], amp[j] = t, w @ z / A0
            j += 1
            if abs(amp[j - 1]) > stop_growth:
                break
    return ts[:j], amp[:j], time.perf_counter() - start


def _basis(lam: float, t: np.ndarray) -> np.ndarray:
    if lam >= 0:
        w = math.sqrt(lam)
        return np.stack([np.cos(w * t), t * np.sinc(w * t / np.pi)], axis=1)
    s = math.sqrt(-lam)
    return np.stack([np.cosh(s * t), np.sinh(s * t) / s], axis=1)


def _misfit(lam: float, t: np.ndarray, a: np.ndarray) -> float:
    X = _basis(lam, t)
    c = np.linalg.lstsq(X, a, rcond=None)[0]
    return float(np.sum((X @ c - a) ** 2) / np.sum(a**2))


def mode_eigenvalue(t: np.ndarray, a: np.ndarray, lam_max: float = 1e6) -> tuple[float, float]:
    """Fit ``a(t) = c1 C(lam, t) + c2 S(lam, t)``: return ``lam`` (s^-2) and the relative misfit.

    Scan of ``lam`` in ``[-lam_max, lam_max]`` (c1, c2 by linear least squares at each), then
    bounded Brent refinement around the best grid point.
    """
    grid = np.linspace(-lam_max, lam_max, 801)
    i = int(np.argmin([_misfit(x, t, a) for x in grid]))
    res = minimize_scalar(_misfit, bounds=(grid[max(i - 1, 0)], grid[min(i + 1, 800)]),
                          args=(t, a), method="bounded", options={"xatol": 1e-9 * lam_max})
    return float(res.x), float(res.fun)


def elastica_threshold(n: int) -> tuple[float, float, float]:
    """PyElastica's threshold ``f_c = mu / mu_c`` at ``n`` elements by secant iterations on the
    fitted ``lam(f)``; returns ``(f_c, dlam/df there, wall s)``."""
    start = time.perf_counter()

    def lam(f: float) -> float:
        t, a, _ = elastica_motion(f * MU_C, n, MEASURE_TIME)
        return mode_eigenvalue(t, a)[0]

    f0, f1 = 0.97, 1.03
    l0, l1 = lam(f0), lam(f1)
    for _ in range(4):
        f2 = f1 - l1 * (f1 - f0) / (l1 - l0)
        f0, l0, f1, l1 = f1, l1, f2, lam(f2)
        if abs(f1 - f0) < 1e-4:
            break
    return f1, (l1 - l0) / (f1 - f0), time.perf_counter() - start


def race_final_time(f_c: float, slope: float) -> float:
    """Final time of a PyElastica verdict: ``acosh(GROWTH_DESIGN) / sigma``.

    ``sigma = sqrt(-lam)`` of the slowest-growing unstable race load, ``lam`` from the measured
    line ``lam(f) = slope (f - f_c)`` (slope < 0) at the chosen N.
    """
    lams = [slope * (f - f_c) for f in RACE_FACTORS if slope * (f - f_c) < 0]
    if not lams:
        raise RuntimeError("no race load is unstable for PyElastica at this N")
    return math.acosh(GROWTH_DESIGN) / math.sqrt(-max(lams))


def elastica_verdict(mu: float, n: int, final_time: float) -> tuple[str, float, float, float]:
    """``(verdict, wall s, lam s^-2, max |A| / a0)``; verdict "stable", "unstable" or
    "undecided" (the fitted lam and the growth disagree). Stops at growth GROWTH_DESIGN."""
    t, a, wall = elastica_motion(mu, n, final_time, stop_growth=GROWTH_DESIGN)
    lam = mode_eigenvalue(t, a)[0]
    growth = float(np.max(np.abs(a)))
    if lam < 0 and growth >= GROWTH_UNSTABLE:
        return "unstable", wall, lam, growth
    if lam > 0 and growth <= GROWTH_STABLE:
        return "stable", wall, lam, growth
    return "undecided", wall, lam, growth


# --- rodstab ------------------------------------------------------------------------------

def rodstab_threshold(n: int) -> float:
    """Threshold of the nonlinear model: the held state's Hessian pencil, ``n`` elements."""
    return critical_load_factor(straight_rod(), 1.0, 8.0, elements_per_segment=n
                                ).load_factor_critical


def linear_threshold(n: int) -> float:
    """Threshold of the linear FE engine (P2 of the held state), ``n`` elements."""
    return linear_stability(straight_rod(), n).load_factor_critical


def richardson_mesh(threshold: Any, n0: int, tol: float = RODSTAB_TOL
                    ) -> tuple[int, float, float, float, list]:
    """First mesh ``n0, 2 n0, 4 n0, ...`` whose Richardson error estimate is <= ``tol``.

    Observed order ``p = log2((mu_n/4 - mu_n/2) / (mu_n/2 - mu_n))`` from the last three meshes,
    estimate ``|mu_n/2 - mu_n| / (2^p - 1) / mu_n`` (relative). Returns ``(n, mu_n, p,
    estimate, [(n, mu_n), ...])``.
    """
    rows: list[tuple[int, float]] = []
    n = n0
    while n <= 1024:
        rows.append((n, threshold(n)))
        if len(rows) >= 3:
            (_, m0), (_, m1), (_, m2) = rows[-3:]
            p = math.log2((m0 - m1) / (m1 - m2))
            est = abs(m1 - m2) / (2**p - 1) / m2
            if est <= tol:
                return n, m2, p, est, rows
        n *= 2
    raise RuntimeError("no mesh up to 1024 elements meets the tolerance")


def _free_hessian(rod: DiscreteRod) -> sp.csr_matrix:
    free = rod.free_dofs()
    Hf = rod.energy_terms()[2][free][:, free]
    return 0.5 * (Hf + Hf.T)


def _positive_definite(H: Any) -> bool:
    """Sylvester: no negative pivot of the Jacobi-scaled ``H``'s LDL^T <=> lowest eigenvalue > 0."""
    D = sp.diags(jacobi_scaling(H))
    neg = count_below((D @ H @ D).tocsc(), 0.0)
    if neg is None:  # the symmetric factorisation was not available: eigen solve
        return bool(np.linalg.eigvalsh((D @ H @ D).toarray())[0] > 0)
    return neg == 0


def rodstab_verdict_eig(mu: float, n: int) -> tuple[bool, float]:
    """Cold verdict, as in bench_nonlinear: sign of the lowest Hessian eigenvalue."""
    t = time.perf_counter()
    stable = bool(lowest_eigenvalues(discretise(straight_rod(), n, mu), 1)[0] > 0)
    return stable, time.perf_counter() - t


def rodstab_verdict_inertia(mu: float, n: int) -> tuple[bool, float]:
    """Cold verdict by inertia: discretise, Hessian, one sparse LDL^T."""
    t = time.perf_counter()
    stable = _positive_definite(_free_hessian(discretise(straight_rod(), n, mu)))
    return stable, time.perf_counter() - t


def rodstab_verdict_linear(mu: float, n: int) -> tuple[bool, float]:
    """Cold verdict of the linear engine: assemble P2's pencil, one factorisation with its
    inertia on the closure constraints (:func:`rodstab.linear.solve.stable_at`)."""
    t = time.perf_counter()
    stable = stable_at(straight_rod(), mu, n)
    return stable, time.perf_counter() - t


def rodstab_verdict_linear_warm(mu: float, pencil: LinearPencil) -> tuple[bool, float]:
    """Warm verdict of the linear engine: P2's pencil assembled once, one factorisation."""
    t = time.perf_counter()
    stable = pencil.stable_at(mu)
    return stable, time.perf_counter() - t


def rodstab_pencil(n: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Free Hessians at mu = 0 and 1: the held state's Hessian is ``H0 + mu (H1 - H0)``."""
    rod = discretise(straight_rod(), n, 0.0)
    H0 = _free_hessian(rod)
    rod.load_factor = 1.0
    return H0, _free_hessian(rod) - H0


def rodstab_verdict_warm(mu: float, pencil: tuple[sp.csr_matrix, sp.csr_matrix]
                         ) -> tuple[bool, float]:
    t = time.perf_counter()
    stable = _positive_definite(pencil[0] + mu * pencil[1])
    return stable, time.perf_counter() - t


def cold_profile(mu: float, n: int, repeats: int = 5) -> dict[str, float]:
    """Median wall time (s) of each step of a cold verdict."""
    steps: dict[str, list[float]] = {"discretise": [], "Hessian": [], "LDL^T": [],
                                     "eigen solve": []}
    for _ in range(repeats):
        t0 = time.perf_counter()
        rod = discretise(straight_rod(), n, mu)
        t1 = time.perf_counter()
        H = _free_hessian(rod)
        t2 = time.perf_counter()
        _positive_definite(H)
        t3 = time.perf_counter()
        lowest_eigenvalues(rod, 1)  # forms the Hessian again: subtract that
        t4 = time.perf_counter()
        for k, v in zip(steps, (t1 - t0, t2 - t1, t3 - t2, t4 - t3 - (t2 - t1)), strict=True):
            steps[k].append(v)
    return {k: statistics.median(v) for k, v in steps.items()}


def _median_time(fn: Any, repeats: int = 5) -> tuple[bool, float]:
    out = [fn() for _ in range(repeats)]
    assert len({s for s, _ in out}) == 1
    return out[0][0], statistics.median(t for _, t in out)


def race() -> None:
    try:
        import elastica  # noqa: F401
    except ImportError:
        print("PyElastica not installed (pip install '.[bench]'): race skipped")
        return
    print(f"exact mu_c = 2 pi sqrt(B1 B2) / B3 = {MU_C:.6f} (eq. 3.9)")
    elastica_motion(MU_C, 20, 1e-4)  # compile the numba kernels outside every timing
    print(f"\nPyElastica threshold vs resolution (undamped, dt = {CFL} dx / c, "
          f"dt <= {DT_MAX:g} s, fit of lam(f) over {MEASURE_TIME} s, secant on f):")
    print(f"{'N':>5} {'f_c':>9} {'f_c - 1':>9} {'dlam/df':>10} {'wall s':>7}")
    chosen = None
    for n in ELASTICA_N:
        f_c, slope, wall = elastica_threshold(n)
        print(f"{n:>5} {f_c:>9.5f} {100 * (f_c - 1):>8.3f}% {slope:>10.4g} {wall:>7.1f}",
              flush=True)
        if chosen is None and abs(f_c - 1) <= ELASTICA_TOL:
            chosen = (n, f_c, slope)
    if chosen is None:
        print("no scanned N meets 1 %: race skipped")
        return
    n_e, f_e, slope = chosen
    T = race_final_time(f_e, slope)
    sig = math.acosh(GROWTH_DESIGN) / T
    print(f"PyElastica races at N = {n_e} (threshold {100 * (f_e - 1):+.3f} %); slowest "
          f"unstable race load grows at sigma = {sig:.1f}/s -> final time "
          f"acosh({GROWTH_DESIGN:g}) / sigma = {T:.4f} s")

    meshes = {}
    for name, fn, n0 in (("nonlinear Hessian", rodstab_threshold, 16),
                         ("linear engine", linear_threshold, 2)):
        n_r, m_r, p, est, rows = richardson_mesh(fn, n0)
        meshes[name] = n_r
        print(f"\nrodstab threshold, {name}, vs elements:")
        for n, m in rows:
            print(f"{n:>5} {m:.7f} {100 * (m / MU_C - 1):+.4f} %")
        print(f"observed order p = {p:.3f}; Richardson estimate at {n_r} elements "
              f"{100 * est:.4f} % (<= {100 * RODSTAB_TOL:g} %), true error "
              f"{100 * abs(m_r / MU_C - 1):.4f} %")
    n_r, n_l = meshes["nonlinear Hessian"], meshes["linear engine"]
    pencil = rodstab_pencil(n_r)
    lin_pencil = linear_pencil(straight_rod(), n_l)
    print(f"cold nonlinear verdict at {n_r} elements, median of 5 (ms): " + ", ".join(
        f"{k} {1e3 * v:.2f}" for k, v in cold_profile(MU_C, n_r).items()))

    print(f"\nRace (rodstab median of 5: nonlinear {n_r} elements -- eig = lowest eigenvalue, "
          f"LDL = inertia, warm = pencil assembled once -- and linear engine {n_l} elements, "
          f"cold and warm (P2's pencil assembled once), both by inertia; "
          f"PyElastica N = {n_e}, 1 run of <= {T:.4f} s simulated, stopped at growth "
          f"{GROWTH_DESIGN:g}):")
    print(f"{'f':>5} {'rodstab':>9} {'linear':>9} {'PyElastica':>11} {'lam 1/s2':>10} "
          f"{'|A|/a0':>7} {'PyEl s':>6} | ms (ratio):  {'eig':>13} {'LDL':>13} {'warm':>14} "
          f"{'linear':>13} {'lin. warm':>13} | same  >=1000x")
    for f in RACE_FACTORS:
        mu = f * MU_C
        s_eig, t_eig = _median_time(lambda mu=mu: rodstab_verdict_eig(mu, n_r))
        s_ldl, t_ldl = _median_time(lambda mu=mu: rodstab_verdict_inertia(mu, n_r))
        s_warm, t_warm = _median_time(lambda mu=mu: rodstab_verdict_warm(mu, pencil))
        s_lin, t_lin = _median_time(lambda mu=mu: rodstab_verdict_linear(mu, n_l))
        s_lw, t_lw = _median_time(lambda mu=mu: rodstab_verdict_linear_warm(mu, lin_pencil))
        assert s_eig == s_ldl == s_warm and s_lin == s_lw
        v_e, t_e, lam, growth = elastica_verdict(mu, n_e, T)
        v_r, v_l = ("stable" if s else "unstable" for s in (s_eig, s_lin))
        times = (t_eig, t_ldl, t_warm, t_lin, t_lw)
        cells = " ".join(f"{1e3 * t:>6.3f} ({t_e / t:>5.0f})" for t in times)
        ok = "/".join("y" if t_e / t >= 1000 else "n" for t in times)
        print(f"{f:>5.2f} {v_r:>9} {v_l:>9} {v_e:>11} {lam:>10.4g} {growth:>7.1f} {t_e:>6.2f} | "
              f"{'':>12}{cells} | {str(v_r == v_l == v_e):>5} {ok}", flush=True)


if __name__ == "__main__":
    race()
