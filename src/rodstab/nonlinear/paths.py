"""Pseudo-arclength continuation (Keller) in any parameter, special points, branch switching.

The path ``g(q, p) = 0`` is followed with unit tangents ``t = (t_q, t_p)`` (free unknowns and the
parameter, :mod:`.parameters`): predictor ``(q, p) + h t``, corrector the bordered Newton method

    [ H      dg/dp ] [dq]     [ g                   ]
    [ t_q^T  t_p   ] [dp] = - [ t . (accumulated) - h ]

and the next tangent from ``[H dg/dp; t_prev^T] t = [0; 1]`` (normalised, oriented along
``t_prev``). The step halves when the corrector fails and grows by 1.5 after a success, up to
the initial step. Folds in ``p`` are passed without special treatment (the bordered matrix
stays regular there).

Special points come from the Hessian (lowest eigenvalue of the Jacobi-scaled free Hessian,
rigid motions and the uniform ring's sliding mode left out, :func:`.solve.lowest_modes`):

* a sign change of the lowest eigenvalue together with a sign change of ``t_p`` is a **fold**
  (limit point) of ``p``;
* a sign change without one is a **branch point**: the bracket is re-traced twice with an
  eighth of the step, the zero located by linear interpolation of the eigenvalue in ``p``, and
  the secondary branch is traced from the state at the branch point along the critical mode
  (tangent ``(mode, 0)``; both signs). Its side tells the post-buckling: on the side where the
  primary path is unstable the branch is stable (supercritical); on the stable side it is
  unstable (subcritical: the structure snaps when ``p`` passes the branch point); on both
  sides at first order it is asymmetric (transcritical).

A branch's amplitude is the displacement, along the critical mode, of the node that the mode
moves most (from the branch point's state, in the length unit of the design); the primary
path's is the largest node displacement from the held state.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from ..errors import NotConverged, RodstabInputError
from ..model import Assembly
from ..results import Result
from .continuation import LOAD, _solve_bordered, post_buckling_verdict
from .discrete import PENALTY, DiscreteRod, discretise
from .parameters import Parameter, parameter
from .solve import critical_load_factor, lowest_modes, newton, settle, sliding_mode


def _bordered(H: sp.spmatrix, gp: np.ndarray, tq: np.ndarray, tp: float,
              z: np.ndarray | None) -> sp.spmatrix:
    """``[[H, g_p, z], [t_q^T, t_p, 0], [z^T, 0, 0]]`` (the last row/column only with ``z``)."""
    col = sp.csr_matrix(gp[:, None])
    row = sp.csr_matrix(tq[None, :])
    if z is None:
        return sp.bmat([[H, col], [row, sp.csr_matrix([[tp]])]], format="csc")
    zc = sp.csr_matrix(z[:, None])
    return sp.bmat([[H, col, zc], [row, sp.csr_matrix([[tp]]), None],
                    [zc.T, None, sp.csr_matrix((1, 1))]], format="csc")


def _arclength_correct(rod: DiscreteRod, param: Parameter, tq: np.ndarray, tp: float, h: float,
                       *, phase: np.ndarray | None = None, max_iter: int = 25) -> bool:
    """Corrector: ``g = 0`` and ``t . (accumulated increment) = h`` (in place).

    ``phase``: a fixed vector ``z`` of the free unknowns; adds ``z . (accumulated) = 0`` with a
    multiplier ``sigma`` (``g + sigma z = 0``). It picks one member of a continuous family of
    equilibria (a rotationally symmetric structure: isotropic twisted rod, ring) where the
    bordered matrix alone is singular; a true equilibrium has ``sigma = 0``, which is checked.
    """
    free = rod.free_dofs()
    n = len(free)
    scale = float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))
    acc_q = tq * h  # the predictor already moved by h along t
    acc_p = tp * h
    sigma = 0.0
    for _ in range(max_iter):
        _, g, H = rod.energy_terms()
        gf = g[free] if phase is None else g[free] + sigma * phase
        c = float(tq @ acc_q + tp * acc_p - h)
        c2 = 0.0 if phase is None else float(phase @ acc_q)
        if np.max(np.abs(gf)) <= 1e-9 * scale and abs(c) <= 1e-10 * max(abs(h), 1e-12) \
                and abs(c2) <= 1e-10 * max(abs(h), 1e-12):
            return phase is None or abs(sigma) * np.max(np.abs(phase)) <= 1e-8 * scale
        gp = param.dgrad(rod)[free]
        rhs = -np.concatenate([gf, [c]] + ([] if phase is None else [[c2]]))
        sol = _solve_bordered(_bordered(H[free][:, free], gp, tq, tp, phase), rhs)
        if sol is None:
            return False
        dq = np.zeros(rod.n_dof)
        dq[free] = sol[:n]
        rod.apply(dq)
        param.set(rod, param.get(rod) + float(sol[n]))
        acc_q = acc_q + sol[:n]
        acc_p += float(sol[n])
        if phase is not None:
            sigma += float(sol[n + 1])
    return False


def _tangent(rod: DiscreteRod, param: Parameter, tq_prev: np.ndarray, tp_prev: float,
             phase: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """Unit tangent of the path: ``[H dg/dp; t_prev^T] t = [0; 1]``, normalised, oriented."""
    free = rod.free_dofs()
    n = len(free)
    _, _, H = rod.energy_terms()
    gp = param.dgrad(rod)[free]
    rhs = np.zeros(n + (1 if phase is None else 2))
    rhs[n] = 1.0
    t = _solve_bordered(_bordered(H[free][:, free], gp, tq_prev, tp_prev, phase), rhs)
    if t is None:
        return tq_prev, tp_prev
    t = t[: n + 1] / np.linalg.norm(t[: n + 1])
    if t[:n] @ tq_prev + t[n] * tp_prev < 0:
        t = -t
    return t[:n], float(t[n])


class _Path:
    """A pseudo-arclength path in progress: the state is ``rod`` (updated in place).

    Safeguards: a corrected point farther than ``2 h`` from the start of the step is rejected
    (the corrector jumped to another branch) and the step halved. On a non-circular state of a
    uniform closed ring the material-sliding family of equilibria makes the bordered matrix
    nearly singular: its phase is pinned by the sliding mode (``_arclength_correct``)."""

    def __init__(self, rod: DiscreteRod, param: Parameter, tq: np.ndarray, tp: float,
                 h: float, h_max: float | None = None, phase: np.ndarray | None = None) -> None:
        nrm = math.sqrt(float(tq @ tq) + tp * tp)
        self.rod, self.param, self.phase = rod, param, phase
        self.tq, self.tp = tq / nrm, tp / nrm
        self.h = h
        self.h_min = 1e-4 * h
        self.h_max = h if h_max is None else h_max

    def _phase(self) -> np.ndarray | None:
        z = sliding_mode(self.rod)
        return self.phase if z is None else z / np.linalg.norm(z)

    def step(self) -> bool:
        """One accepted step (halving on failure); False once the step is below ``h_min``."""
        rod, free = self.rod, self.rod.free_dofs()
        phase = self._phase()
        while self.h >= self.h_min:
            saved = rod.copy()
            p0 = self.param.get(rod)
            dq = np.zeros(rod.n_dof)
            dq[free] = self.h * self.tq
            rod.apply(dq)
            self.param.set(rod, p0 + self.h * self.tp)
            if _arclength_correct(rod, self.param, self.tq, self.tp, self.h, phase=phase) \
                    and _distance(rod, saved, self.param.get(rod) - p0) <= 2 * self.h:
                self.tq, self.tp = _tangent(rod, self.param, self.tq, self.tp, phase)
                self.last_h = self.h
                self.h = min(1.5 * self.h, self.h_max)
                return True
            rod.assign(saved)
            self.h *= 0.5
        return False


def _distance(rod: DiscreteRod, other: DiscreteRod, dp: float) -> float:
    """Distance in (positions, rotation increments, p) between two states of one rod."""
    from .solve import _vee_log

    dx = (rod.x - other.x).ravel()
    de = _vee_log(np.swapaxes(other.R_edge, 1, 2) @ rod.R_edge).ravel()
    dj = _vee_log(np.swapaxes(other.R_joint, 1, 2) @ rod.R_joint).ravel()
    return math.sqrt(float(dx @ dx + de @ de + dj @ dj) + dp * dp)


#: |cos(critical mode, dg/dp)| above which a turning point of the parameter is a fold.
FOLD_COS = 1e-3
#: Two lowest eigenvalues at a branch point closer than this (relative to the third) are a
#: double eigenvalue.
DOUBLE_RTOL = 1e-3


def _lowest(rod: DiscreteRod) -> float:
    return float(lowest_modes(rod, 1)[0][0])


def _moved(x: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(x - ref, axis=1)))


# ------------------------------------------------------------------ paths from a bifurcation
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


def arclength_from_bifurcation(a: Assembly, lo: float, hi: float, *, elements_per_segment: int
                               = 24, ds: float = 0.05, n_steps: int = 60,
                               mu_window: tuple[float, float] | None = None) -> ArclengthPath:
    """Pseudo-arclength continuation along the branch leaving the first bifurcation of the held
    state in the load factor (in ``(lo, hi]``).

    Starts at the critical load with the tangent along the critical mode (a symmetric
    pitchfork has ``d mu = 0`` there); steps up to ``4 ds``. Stops after ``n_steps`` or when the
    load leaves ``mu_window``.
    """
    lo, hi = _check_number("lo", lo), _check_number("hi", hi)
    if not lo < hi:
        raise RodstabInputError(f"arclength_from_bifurcation needs lo < hi, got {lo!r}, {hi!r}")
    if _check_number("ds", ds) <= 0:
        raise RodstabInputError(f"ds must be > 0, got {ds!r}")
    n_steps = _check_count("n_steps", n_steps, 1)
    crit = critical_load_factor(a, lo, hi, elements_per_segment=elements_per_segment)
    if not math.isfinite(crit.load_factor_critical):
        raise RodstabInputError(f"the held state does not lose stability for load factors in "
                                f"({lo!r}, {hi!r}]: no bifurcation to start from")
    rod = discretise(a, elements_per_segment, crit.load_factor_critical)
    _, vecs = lowest_modes(rod, 1)
    path = _Path(rod, LOAD, vecs[:, 0], 0.0, ds, 4 * ds)
    out = []

    def record() -> None:
        c = rod.x.mean(axis=0)
        out.append((rod.load_factor, rod.energy(), _lowest(rod),
                    float(np.max(np.linalg.norm(rod.x - c, axis=1))), rod.x.copy()))

    record()
    ok_all = True
    for _ in range(n_steps):
        if not path.step():
            ok_all = False
            break
        record()
        if mu_window and not (mu_window[0] <= rod.load_factor <= mu_window[1]):
            break
    return ArclengthPath(tuple(o[0] for o in out), tuple(o[1] for o in out),
                         tuple(o[2] for o in out), tuple(o[3] for o in out),
                         tuple(o[4] for o in out), ok_all,
                         "pseudo-arclength (Keller), bordered Newton corrector")


# ------------------------------------------------------------------ continuation in any parameter
@dataclasses.dataclass(frozen=True)
class SecondaryBranch(Result):
    """A branch traced from a branch point along the critical mode (both signs)."""

    value_critical: float
    value: tuple[float, ...]
    amplitude: tuple[float, ...]  # signed displacement along the mode (see module doc)
    energy: tuple[float, ...]
    lowest_eigenvalue: tuple[float, ...]
    verdict: str
    converged: bool


@dataclasses.dataclass(frozen=True)
class Continuation(Result):
    """A primary path in one parameter, its special points and secondary branches."""

    key: str
    value: tuple[float, ...]
    energy: tuple[float, ...]
    lowest_eigenvalue: tuple[float, ...]
    amplitude: tuple[float, ...]  # largest node displacement from the held state
    converged: bool
    special_points: tuple[dict, ...]
    branches: tuple[SecondaryBranch, ...]
    resumed_steps: int
    method: str
    branch_shapes: tuple = ()  # node positions along the first branch (this run only)


def _trace_branch(rod: DiscreteRod, param: Parameter, stable_side: float, ds: float,
                  n_steps: int) -> tuple[SecondaryBranch, list]:
    p_c = param.get(rod)
    vals, vecs = lowest_modes(rod, 3)
    # A double critical eigenvalue of a rotationally symmetric structure: the branch is a
    # circle of equilibria; pin its phase by the second mode (see _arclength_correct).
    double = abs(vals[1] - vals[0]) <= DOUBLE_RTOL * abs(vals[2] - vals[0])
    phase = vecs[:, 1] / np.linalg.norm(vecs[:, 1]) if double else None
    ref = rod.x.copy()
    free = rod.free_dofs()
    full = np.zeros(rod.n_dof)
    full[free] = vecs[:, 0]
    disp = full[: 3 * len(rod.x)].reshape(-1, 3)
    k = int(np.argmax(np.linalg.norm(disp, axis=1)))
    u = disp[k] / np.linalg.norm(disp[k])  # amplitude: displacement of node k along the mode
    # The tangent is a unit vector in (positions, rotations, p): scale the step so that the
    # amplitude grows by about ds per step.
    h = ds * float(np.linalg.norm(vecs[:, 0]) / np.linalg.norm(disp[k]))
    pts, shapes, ok_all = [], [rod.x.copy()], True
    for sign in (1.0, -1.0):
        r = rod.copy()
        path = _Path(r, param, sign * vecs[:, 0], 0.0, h, phase=phase)
        for _ in range(n_steps):
            if not path.step():
                ok_all = False
                break
            pts.append((float((r.x[k] - ref[k]) @ u), param.get(r), r.energy(), _lowest(r)))
            if sign > 0:
                shapes.append(r.x.copy())
    pts.sort()
    A = np.array([q[0] for q in pts])
    V = np.array([q[1] for q in pts])
    small = np.abs(A) <= 0.6 * np.max(np.abs(A)) if len(A) else np.zeros(0, bool)
    verdict = post_buckling_verdict(A[small], V[small], p_c, stable_side)[0]
    return SecondaryBranch(p_c, tuple(V), tuple(A), tuple(q[2] for q in pts),
                           tuple(q[3] for q in pts), verdict, ok_all), shapes


def _branch_dict(b: SecondaryBranch) -> dict:
    return {"verdict": b.verdict, "converged": b.converged, "value": list(b.value),
            "amplitude": list(b.amplitude), "energy": list(b.energy),
            "lowest_eigenvalue": list(b.lowest_eigenvalue)}


def _design_hash(a: Assembly) -> str:
    import hashlib

    return hashlib.sha256(repr(a).encode()).hexdigest()[:16]


#: Output files of a continuation run (removed when a run starts afresh in the directory).
OUTPUTS = ("run.json", "state.npz", "primary.csv", "special_points.json", "branches.csv",
           "diagram.png", "branch.gif", "branch.html")


def _write_atomic(path: Path, text: str) -> None:
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(text)
    tmp.replace(path)


def _check_number(name: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) \
            or not math.isfinite(v):
        raise RodstabInputError(f"{name} must be a finite number, got {v!r}")
    return float(v)


def _check_count(name: str, v, minimum: int) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < minimum:
        raise RodstabInputError(f"{name} must be an integer >= {minimum}, got {v!r}")
    return int(v)


def continuation(a: Assembly, key: str, start: float, stop: float, n_steps: int, *,
                 elements_per_segment: int = 16, out_dir: str | Path | None = None,
                 progress=None, branch_steps: int = 8, branch_ds: float | None = None,
                 max_steps_factor: int = 8, rod: DiscreteRod | None = None,
                 stop_at_first: bool = False, critical_out: list | None = None
                 ) -> Continuation:
    """Follow the equilibrium of ``a`` as the parameter ``key`` goes from ``start`` to ``stop``.

    ``key``: ``load_factor``, ``segment.<name>.natural_curvature`` / ``.natural_twist`` or
    ``support.<i>.rotation.<normal|tangent|binormal>`` (:func:`.parameters.parameter`). The
    path starts at ``start``, reached from the design's value by Newton in small steps (the
    path, not the end value, decides: an end rotation of 2 pi is not none), steps about
    ``|stop - start| / n_steps`` in the parameter, ends exactly at ``stop`` and reports folds
    and branch points inside the range (module docstring). It is reported not converged if a
    step fails or ``stop`` is not reached in ``max_steps_factor * n_steps`` steps. From each
    loss of stability at a branch point the secondary branch is traced ``branch_steps`` steps
    each way with step ``branch_ds`` (default 1 % of the total length). ``rod``: start from this
    discretised state instead of the held state of ``a`` (e.g. an imperfect one);
    ``stop_at_first``: stop at the first special point; ``critical_out``: a list that receives
    ``(p, state)`` at each loss of stability.

    With ``out_dir``: after every step one file, ``state.npz``, is replaced atomically (state,
    path, rows, special points, and the run's arguments and design); ``primary.csv`` and
    ``special_points.json`` are exported from it. A rerun with the same design and arguments
    continues from the last completed step (losing at most the step in progress); anything
    else starts afresh and removes the previous run's files.
    """
    start, stop = _check_number("start", start), _check_number("stop", stop)
    if start == stop or not math.isfinite(stop - start):
        raise RodstabInputError(f"continuation needs two different values a finite distance "
                                f"apart, got {start!r}:{stop!r}")
    n_steps = _check_count("n_steps", n_steps, 1)
    n = _check_count("elements_per_segment", elements_per_segment, 2)
    branch_steps = _check_count("branch_steps", branch_steps, 0)
    max_steps_factor = _check_count("max_steps_factor", max_steps_factor, 1)
    param = parameter(a, key, n)
    fresh = rod is None
    rod = discretise(a, n) if rod is None else rod
    held_x = rod.x.copy()
    direction = 1.0 if stop > start else -1.0
    h = abs(stop - start) / n_steps
    branch_ds = 0.01 * a.total_length if branch_ds is None else \
        _check_number("branch_ds", branch_ds)
    rows: list[tuple[float, float, float, float, bool]] = []
    specials: list[dict] = []
    tq, tp = np.zeros(len(rod.free_dofs())), direction
    out = Path(out_dir) if out_dir is not None else None
    resumed = 0
    meta = {"key": key, "start": start, "stop": stop, "n_steps": n_steps,
            "elements_per_segment": n, "branch_steps": branch_steps, "branch_ds": branch_ds,
            "max_steps_factor": max_steps_factor, "design": _design_hash(a),
            "start_state": "held" if fresh else _state_hash(rod)}
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        st = _load_state(out / "state.npz")
        if st is not None and st["meta"] == meta:
            rows = [tuple(r[:4]) + (bool(r[4]),) for r in st["rows"]]
            specials = st["specials"]
            rod.x, rod.R_edge, rod.R_joint = st["x"], st["R_edge"], st["R_joint"]
            param.set(rod, st["value"])
            tq, tp, h = st["tq"], st["tp"], st["h"]
            resumed = len(rows)
        else:
            for name in OUTPUTS:
                (out / name).unlink(missing_ok=True)
            _write_atomic(out / "run.json", json.dumps(meta, indent=1))
    if not rows:
        if fresh:
            settle(rod)
        _reach(rod, param, key, start, h)
        tq, tp = _tangent(rod, param, tq, tp)  # the true tangent (the start is regular)
        # Arclength counts the unknowns too: size the step so that the parameter advances by
        # about |stop - start| / n_steps while the path is the primary one.
        h = h / max(abs(tp), 1e-3)
    path = _Path(rod, param, tq, tp, h)
    branch_shapes: list = []

    def record(ok: bool, lowest: float | None = None) -> None:
        rows.append((param.get(rod), rod.energy(), _lowest(rod) if lowest is None else lowest,
                     _moved(rod.x, held_x), ok))
        if out is not None:
            np.savez(out / "state.tmp.npz", x=rod.x, R_edge=rod.R_edge, R_joint=rod.R_joint,
                     value=param.get(rod), tq=path.tq, tp=path.tp, h=path.h,
                     rows=np.array(rows, dtype=float).reshape(-1, 5),
                     text=json.dumps({"meta": meta, "specials": specials}))
            (out / "state.tmp.npz").replace(out / "state.npz")
            _export(out, rows, specials)
        if progress is not None:
            progress()

    if not rows:
        record(True)
    ok_all, why = True, ""
    budget = max_steps_factor * n_steps + 1
    while (rows[-1][0] - stop) * direction < 0:
        if len(rows) >= budget:
            ok_all, why = False, f"{stop!r} not reached in {budget - 1} steps"
            break
        prev_state, prev_tp = rod.copy(), path.tp
        prev_tq = path.tq.copy()
        if not path.step():
            ok_all, why = False, f"step failed at {key} = {param.get(rod)!r}"
            break
        if (param.get(rod) - stop) * direction > 0:
            # Past the end: land exactly on ``stop`` by Newton from the previous point.
            trial = prev_state.copy()
            param.set(trial, stop)
            if newton(trial)[0]:
                rod.assign(trial)
        prev_h = path.last_h
        e0, e1 = rows[-1][2], _lowest(rod)
        if (e0 > 0) != (e1 > 0) or (prev_tp > 0) != (path.tp > 0):
            point = _special_point(rod, param, prev_state, prev_tq, prev_tp, prev_h, e0, e1,
                                   path.tp, branch_ds, branch_steps, branch_shapes,
                                   critical_out)
            if (point["value"] - stop) * direction <= 0:
                specials.append(point)
                if stop_at_first:
                    record(True, e1)
                    break
        record(True, e1)
    if out is not None:
        _export(out, rows, specials)
    branches = tuple(SecondaryBranch(s["value"], tuple(s["branch"]["value"]),
                                     tuple(s["branch"]["amplitude"]),
                                     tuple(s["branch"]["energy"]),
                                     tuple(s["branch"]["lowest_eigenvalue"]),
                                     s["branch"]["verdict"], s["branch"]["converged"])
                     for s in specials if "branch" in s)
    return Continuation(key, tuple(r[0] for r in rows), tuple(r[1] for r in rows),
                        tuple(r[2] for r in rows), tuple(r[3] for r in rows), ok_all,
                        tuple(specials), branches, resumed,
                        "pseudo-arclength (Keller) with Hessian eigenvalue monitoring"
                        + (f"; STOPPED: {why}" if why else ""), tuple(branch_shapes))


def _state_hash(rod: DiscreteRod) -> str:
    import hashlib

    hsh = hashlib.sha256()
    for arr in (rod.x, rod.R_edge, rod.R_joint, rod.k_held_pairs, rod.k0_links[0]):
        hsh.update(np.ascontiguousarray(arr).tobytes())
    return hsh.hexdigest()[:16]


def _load_state(path: Path) -> dict | None:
    """The saved run in ``path``, or None if there is none or it cannot be read."""
    if not path.exists():
        return None
    try:
        st = np.load(path)
        text = json.loads(str(st["text"]))
        return {"x": st["x"], "R_edge": st["R_edge"], "R_joint": st["R_joint"],
                "value": float(st["value"]), "tq": st["tq"], "tp": float(st["tp"]),
                "h": float(st["h"]), "rows": st["rows"].tolist(), "meta": text["meta"],
                "specials": text["specials"]}
    except (OSError, ValueError, KeyError, json.JSONDecodeError):
        return None


def _export(out: Path, rows: list, specials: list) -> None:
    """primary.csv, special_points.json and branches.csv from the run in memory."""
    lines = ["value,energy,lowest_eigenvalue,amplitude,converged"]
    lines += [",".join(repr(float(v)) for v in r[:4]) + f",{bool(r[4])}" for r in rows]
    _write_atomic(out / "primary.csv", "\n".join(lines) + "\n")
    _write_atomic(out / "special_points.json", json.dumps(specials, indent=1))
    lines = ["branch,value,amplitude,energy,lowest_eigenvalue"]
    for i, sp_ in enumerate(s for s in specials if "branch" in s):
        b = sp_["branch"]
        for row in zip(b["value"], b["amplitude"], b["energy"], b["lowest_eigenvalue"]):
            lines.append(f"{i}," + ",".join(repr(float(v)) for v in row))
    _write_atomic(out / "branches.csv", "\n".join(lines) + "\n")


#: Largest parameter change of one Newton step while reaching the start of a path.
REACH_STEPS_MAX = 200


def _reach(rod: DiscreteRod, param: Parameter, key: str, start: float, h: float) -> None:
    """Bring ``rod`` from its parameter value to ``start`` by Newton in steps of at most ``h``
    (at most REACH_STEPS_MAX steps); raise naming the value where Newton fails."""
    p0 = param.get(rod)
    n = int(math.ceil(abs(start - p0) / h)) if start != p0 else 0
    if n > REACH_STEPS_MAX:
        raise RodstabInputError(
            f"{key} = {start!r} is {n} steps of {h:.3g} from the design's value {p0!r} "
            f"(at most {REACH_STEPS_MAX}): start nearer to it or take fewer, longer steps")
    for p in np.linspace(p0, start, n + 1)[1:]:
        param.set(rod, float(p))
        if not newton(rod)[0]:
            raise NotConverged(f"no equilibrium found at {key} = {float(p)!r} on the way "
                               f"from the design's value {p0!r} to {start!r}")
    param.set(rod, start)
    if not newton(rod)[0]:
        raise NotConverged(f"no equilibrium found at {key} = {start!r}")


def _refine(param: Parameter, prev: DiscreteRod, tq: np.ndarray, tp: float, h: float,
            indicator, v0: float) -> tuple[DiscreteRod, tuple, tuple, float]:
    """Re-trace a bracket twice with an eighth of the step until ``indicator`` changes sign.

    Returns the state at the bracket's start, its (p, indicator) ends and the step used."""
    lo, lo_tq, lo_tp = prev.copy(), tq, tp
    b0, b1 = (param.get(prev), v0), None
    for _ in range(2):
        h = h / 8
        walker = lo.copy()
        path = _Path(walker, param, lo_tq, lo_tp, h)
        last = b0
        for _ in range(24):
            saved = (walker.copy(), path.tq.copy(), path.tp)
            if not path.step():
                break
            v = indicator(walker, path)
            if (v > 0) != (b0[1] > 0):
                b0, b1 = last, (param.get(walker), v)
                lo, lo_tq, lo_tp = saved
                break
            last = (param.get(walker), v)
    return lo, b0, b1, h


def _special_point(rod: DiscreteRod, param: Parameter, prev: DiscreteRod, prev_tq: np.ndarray,
                   prev_tp: float, prev_h: float, e0: float, e1: float, tp_now: float,
                   branch_ds: float, branch_steps: int, shapes_out: list,
                   critical_out: list | None = None) -> dict:
    """Classify and locate the special point between ``prev`` and ``rod`` (module docstring)."""
    if (prev_tp > 0) != (tp_now > 0):
        # Fold. Near it p(s) is a parabola in the arclength s, t_p = dp/ds linear: from the two
        # ends of the refined bracket, s* = ds tp0 / (tp0 - tp1), p_max = p0 + tp0 s* / 2.
        lo, (p0, t0), b1, h = _refine(param, prev, prev_tq, prev_tp, prev_h,
                                      lambda r, path: path.tp, prev_tp)
        if b1 is None:
            p0, t0, p1, t1 = param.get(prev), prev_tp, param.get(rod), tp_now
            h = prev_h
        else:
            p1, t1 = b1
        ds = 2 * (p1 - p0) / (t0 + t1) if abs(t0 + t1) > 1e-3 * abs(t0 - t1) else h
        p_fold = p0 + t0 * (ds * t0 / (t0 - t1)) / 2
        if critical_out is not None:
            critical_out.append((p_fold, lo))
        # A fold has its critical mode transversal to dg/dp; a symmetric branch point (where
        # the path turned onto the secondary branch) has it orthogonal.
        _, vec = lowest_modes(lo, 1)
        gp = param.dgrad(lo)[lo.free_dofs()]
        cos = abs(vec[:, 0] @ gp) / max(np.linalg.norm(vec[:, 0]) * np.linalg.norm(gp), 1e-300)
        kind = "fold" if cos > FOLD_COS else "branch point (path turned onto the branch)"
        return {"kind": kind, "value": float(p_fold), "bracket": sorted([p0, p1]),
                "mode_cosine_with_dg_dp": float(cos)}
    lo, b0, b1, _ = _refine(param, prev, prev_tq, prev_tp, prev_h,
                            lambda r, path: _lowest(r), e0)
    (m0, v0), (m1, v1) = b0, b1 if b1 is not None else (param.get(rod), e1)
    p_c = m0 + (m1 - m0) * v0 / (v0 - v1)
    lost = e0 > 0
    point = {"kind": "branch point (stability lost)" if lost else
             "branch point (stability regained)", "value": float(p_c),
             "bracket": sorted([float(m0), float(m1)])}
    if lost and (branch_steps > 0 or critical_out is not None):
        at = lo.copy()
        param.set(at, p_c)
        ok, _, _ = newton(at)
        if ok and critical_out is not None:
            critical_out.append((p_c, at.copy()))
        if ok and branch_steps > 0:
            stable_side = math.copysign(1.0, m0 - p_c)
            branch, shapes = _trace_branch(at, param, stable_side, branch_ds, branch_steps)
            point["post_buckling"] = branch.verdict
            point["branch"] = _branch_dict(branch)
            if not shapes_out:
                shapes_out.extend(shapes)
    return point


@dataclasses.dataclass(frozen=True)
class PrimaryCritical(Result):
    """First loss of stability along the primary equilibrium path (found by continuation)."""

    load_factor_critical: float
    bracket: tuple[float, float]
    steps: int
    method: str


def critical_along_primary(a: Assembly, mu_start: float, mu_stop: float, *,
                           elements_per_segment: int = 32, ds: float = 0.05) -> PrimaryCritical:
    """Critical load of a primary path that is NOT the held state (e.g. a twisted ring): the
    first branch point or fold of :func:`continuation` in the load factor (no branch traced).
    The bracket is re-traced to ``ds / 64``; the eigenvalue is interpolated linearly in it
    (error well below the discretisation error)."""
    c = continuation(a, "load_factor", mu_start, mu_stop,
                     max(1, int(math.ceil(abs(mu_stop - mu_start) / ds))),
                     elements_per_segment=elements_per_segment, branch_steps=0,
                     stop_at_first=True)
    if c.lowest_eigenvalue[0] <= 0:
        return PrimaryCritical(math.nan, (math.nan, math.nan), 0,
                               "no stable equilibrium at mu_start")
    lost = [s for s in c.special_points if s["kind"] != "branch point (stability regained)"]
    if not lost:
        return PrimaryCritical(math.nan, (math.nan, math.nan), len(c.value),
                               "no loss of stability before mu_stop")
    return PrimaryCritical(float(lost[0]["value"]), tuple(lost[0]["bracket"]), len(c.value),
                           "pseudo-arclength along the primary path, eigenvalue sign change")


# ------------------------------------------------------------------ imperfection sensitivity
@dataclasses.dataclass(frozen=True)
class ImperfectionSensitivity(Result):
    """Limit values of imperfect structures (imperfection ``eps L`` times the critical mode)."""

    key: str
    value_critical: float
    epsilon: tuple[float, ...]
    limit_value: tuple[float, ...]
    paths: tuple[tuple[tuple[float, float], ...], ...]  # per eps: (p, largest displacement)
    exponent: float
    verdict: str
    method: str


def _imperfect(state: DiscreteRod, target: DiscreteRod, vec: np.ndarray, eps: float
               ) -> DiscreteRod:
    """``target`` (a held state) whose natural shape contains ``eps`` times the mode ``vec``
    (free unknowns) of ``state``: every joint's natural curvature changes by the curvature
    change that the displacement ``eps * vec`` causes at ``state``; the supports stay."""
    from .discrete import _held_curvatures

    moved = state.copy()
    dq = np.zeros(state.n_dof)
    dq[state.free_dofs()] = eps * vec
    moved.apply(dq)
    kp0, kl0 = _held_curvatures(state)
    kp1, kl1 = _held_curvatures(moved)
    imp = target.copy()
    imp.k_held_pairs = target.k_held_pairs + (kp1 - kp0)
    a, b = target.k0_links
    imp.k0_links = (a + (kl1 - kl0), b)
    return imp


def imperfection_sensitivity(a: Assembly, key: str, start: float, stop: float, *,
                             epsilons: tuple[float, ...] = (1e-3, 2e-3, 4e-3, 8e-3),
                             elements_per_segment: int = 16,
                             n_steps: int = 20) -> ImperfectionSensitivity:
    """Limit value ``p_max(eps)`` of the parameter ``key`` for imperfections of amplitude
    ``eps L`` (``L``: total length; mode scaled to a largest entry of 1) shaped like the
    critical mode of the perfect structure.

    The perfect path from ``start`` towards ``stop`` gives the critical value ``p_c`` and its
    mode (:func:`continuation`); each imperfect structure is followed from ``start`` by the same
    continuation up to its first fold or loss of stability. No such point before ``stop``
    means imperfection-insensitive at that amplitude (NaN). The exponent is the slope of
    ``log |p_c - p_max|`` against ``log eps`` (2/3 for an unstable symmetric bifurcation, 1/2
    for an asymmetric one).
    """
    n = elements_per_segment
    if not epsilons or any(isinstance(e, bool) or not isinstance(e, (int, float)) or
                           not math.isfinite(e) or e <= 0 for e in epsilons):
        raise RodstabInputError(f"epsilons must be one or more positive numbers, got "
                                f"{epsilons!r}")
    crit: list = []
    continuation(a, key, start, stop, n_steps, elements_per_segment=n, branch_steps=0,
                 stop_at_first=True, critical_out=crit)
    if not crit:
        raise RodstabInputError(f"the perfect structure does not lose stability between "
                                f"{key} = {start!r} and {stop!r}")
    p_c, state = crit[0]
    _, vecs = lowest_modes(state, 1)
    v = vecs[:, 0] / np.max(np.abs(vecs[:, 0]))
    limits, paths = [], []
    for eps in epsilons:
        imp = _imperfect(state, discretise(a, n), v, eps * a.total_length)
        c = continuation(a, key, start, stop, n_steps, elements_per_segment=n, branch_steps=0,
                         stop_at_first=True, rod=imp)
        # An imperfection breaks the bifurcation: the first loss of stability is a fold. A
        # long step may jump past it onto a nearby branch, but the bracket is re-traced with
        # small steps from the stable side, which stops at the fold's zero eigenvalue; a
        # result that does not grow with eps is reported as inconclusive below.
        lost = [s for s in c.special_points if s["kind"] != "branch point (stability regained)"]
        limits.append(float(lost[0]["value"]) if lost else math.nan)
        paths.append(tuple(zip(c.value, c.amplitude)))
    lim = np.array(limits)
    side = math.copysign(1.0, start - p_c)  # the stable side of p_c
    ok = np.isfinite(lim) & ((lim - p_c) * side > 0)
    slope = (np.polyfit(np.log(np.array(epsilons)[ok]), np.log(np.abs(lim[ok] - p_c)), 1)[0]
             if ok.sum() >= 2 else math.nan)
    if ok.sum() >= 2 and slope > 0:
        exponent = float(slope)
        verdict = f"imperfection-sensitive: |p_c - p_max| ~ eps^{exponent:.3f}"
    elif ok.any():
        exponent = math.nan
        verdict = ("inconclusive: limit points found but they do not grow with the "
                   "imperfection (refine n_steps or the mesh)")
    else:
        exponent = math.nan
        verdict = (f"no limit point between {start:g} and {stop:g} for these amplitudes: "
                   "imperfection-insensitive (stable post-buckling)")
    return ImperfectionSensitivity(key, float(p_c), tuple(epsilons), tuple(limits),
                                   tuple(paths), exponent, verdict,
                                   "pseudo-arclength continuation, folds and Hessian eigenvalues")
