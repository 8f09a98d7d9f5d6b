"""Continuation of the equilibrium in one parameter.

The primary path, its special points (:mod:`.special`) and the branches leaving its losses of
stability (:mod:`.branches`).
"""

from __future__ import annotations

import contextlib
import json
import math
from collections.abc import Callable
from pathlib import Path as FsPath

import numpy as np

from ...errors import NotConverged, RodstabInputError, require_finite, require_int
from ...io.outputs import run_lock
from ...limits import DEFAULT as DEFAULT_LIMITS
from ...limits import Limits, require_nonlinear, require_steps
from ...model import MAX_END_ROTATION, Assembly
from ...numerics import richardson
from ..contact_model import ContactModel
from ..contact_step import attach_contact, contact_state, type_switch_crossings
from ..discrete import MAX_NATURAL_TURNING, DiscreteRod, check_mesh, discretise
from ..parameters import EndRotation, Parameter, SegmentValue, parameter
from ..solve import newton, settle
from . import storage
from .branches import trace_branch
from .corrector import Stepper, tangent
from .path import Path, SpecialKind, reference_length
from .special import crossed, locate, lowest

#: First step along a branch from a branch point, as a fraction of ``branch_ds``: small
#: amplitudes first, for the post-buckling fit (the steps grow by 1.5 up to 4 branch_ds).
BRANCH_FIRST_STEP = 1 / 8
#: Most Newton steps taken while reaching the start of a path from the design's value.
REACH_STEPS_MAX = 200


def _reach(rod: DiscreteRod, param: Parameter, key: str, start: float, h: float) -> None:
    """Bring ``rod`` from its parameter value to ``start`` by Newton in steps of at most ``h``.

    At most REACH_STEPS_MAX steps; raise naming the value where Newton fails.
    """
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


def _moved(x: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(x - ref, axis=1)))


def _branch_dict(b: Path) -> dict:
    return {"verdict": b.verdict, "converged": b.converged, "value": list(b.value),
            "amplitude": list(b.amplitude), "energy": list(b.energy),
            "lowest_eigenvalue": list(b.lowest_eigenvalue),
            "coefficients": {"a": b.coefficients[0], "b": b.coefficients[1],
                             "definition": "p/p_c = 1 + a xi + b xi^2; " + b.amplitude_definition}}


def continuation(a: Assembly, key: str, start: float, stop: float, n_steps: int, *,
                 elements_per_segment: int = 16, out_dir: str | FsPath | None = None,
                 progress: Callable[[], None] | None = None, branch_steps: int = 8,
                 branch_ds: float | None = None, max_steps_factor: int = 8,
                 rod: DiscreteRod | None = None, stop_at_first: bool = False,
                 reference_segment: str | None = None, restart: bool = False,
                 limits: Limits = DEFAULT_LIMITS, contact: ContactModel | None = None) -> Path:
    """Follow the equilibrium of ``a`` as the parameter ``key`` goes from ``start`` to ``stop``.

    ``key``: ``load_factor``, ``segment.<name>.natural_curvature`` / ``.natural_twist``,
    ``support.<i>.rotation.<axis>``, ``welds.<i>,<j>.rotation.<axis>`` or
    ``weld.<i>.moment.<axis>`` (:func:`..parameters.parameter`). The
    path starts at ``start``, reached from the design's value by Newton in small steps (the
    path, not the end value, decides: an end rotation of 2 pi is not none), steps about
    ``|stop - start| / n_steps`` in the parameter, ends exactly at ``stop`` and reports folds
    and branch points inside the range. It is reported not converged if a step fails or
    ``stop`` is not reached in ``max_steps_factor * n_steps`` steps. From each loss of
    stability at a branch point the branch (its most dangerous direction at a multiple
    eigenvalue) is traced ``branch_steps`` steps each way with step ``branch_ds`` (default 1 %
    of the total length); its verdict and the coefficients ``(a, b)`` of
    ``p/p_c = 1 + a xi + b xi^2`` (``xi`` relative to ``reference_segment``'s length, default
    the first segment's) go into the special point. ``rod``: start from this discretised state
    instead of the held state (e.g. an imperfect one); ``stop_at_first``: stop at the first
    special point. The returned :class:`.Path` carries in ``states`` the states
    ``(value, rod)`` at the losses of stability and folds found by this run.

    With ``out_dir``: the run is stored after every step (:mod:`.storage`); a rerun with the
    same design and arguments continues from the last completed step, unless ``restart``. The
    run holds the directory's lock (:func:`rodstab.io.outputs.run_lock`: a concurrent run into it
    raises :class:`~rodstab.errors.RodstabInputError`); a saved state that cannot be used is set
    aside with a :class:`~rodstab.errors.RodstabWarning` and the run starts afresh. A run past
    ``limits`` (steps, unknowns; :mod:`rodstab.limits`) is refused before it starts.

    ``contact``: the rods cannot pass through each other (:mod:`..contact`): the corrector's
    steps are filtered, a predictor outside the model is a failed step (halved), the stability
    is the Hessian's of rod and contact, and the path's ``contact`` gives the model and the
    smallest capsule gap over its points. A held state that already interpenetrates is refused.
    """
    start, stop = require_finite("start", start), require_finite("stop", stop)
    if start == stop or not math.isfinite(stop - start):
        raise RodstabInputError(f"continuation needs two different values a finite distance "
                                f"apart, got {start!r}:{stop!r}")
    n_steps = require_int("n_steps", n_steps, 1)
    n = require_int("elements_per_segment", elements_per_segment, 2)
    require_steps(n_steps, f"{n_steps} steps", "continuation steps", limits)
    require_nonlinear([n] * len(a.segments), len(a.joints()), f"{n} elements per segment",
                      limits)
    if key == "load_factor":  # the natural turning at both ends of the range, before stepping
        check_mesh(a, n, start)
        check_mesh(a, n, stop)
    branch_steps = require_int("branch_steps", branch_steps, 0)
    max_steps_factor = require_int("max_steps_factor", max_steps_factor, 1)
    length = reference_length(a, reference_segment)
    param = parameter(a, key, n)
    for value in (start, stop):  # both ends of the range, before stepping
        if isinstance(param, EndRotation) and abs(value) > MAX_END_ROTATION:
            raise RodstabInputError(
                f"--vary {key}: {value:g} rad is beyond +-{MAX_END_ROTATION:.6g} (a hundred "
                "turns of the end)")
        if isinstance(param, SegmentValue):
            turn = abs(value) * a.segment(param.name).length
            if turn > MAX_NATURAL_TURNING:
                raise RodstabInputError(
                    f"--vary {key}: {value:g} turns the segment by {turn:.3g} rad, above "
                    f"{MAX_NATURAL_TURNING:g}")
    fresh = rod is None
    rod = discretise(a, n) if rod is None else rod
    if contact is not None:
        attach_contact(rod, contact)
    param.prepare(rod)  # a weld parameter holds its welds and takes their reference frames
    held_x = rod.x.copy()
    direction = 1.0 if stop > start else -1.0
    h = abs(stop - start) / n_steps
    branch_ds = 0.01 * a.total_length if branch_ds is None else \
        require_finite("branch_ds", branch_ds)
    rows: list[tuple[float, float, float, float, bool]] = []
    specials: list[dict] = []
    states: list[tuple[float, DiscreteRod]] = []
    branches: list[Path] = []
    tq, tp = np.zeros(len(rod.free_dofs())), direction
    out = FsPath(out_dir) if out_dir is not None else None
    resumed = 0
    meta = {"key": key, "start": start, "stop": stop, "n_steps": n_steps,
            "elements_per_segment": n, "branch_steps": branch_steps, "branch_ds": branch_ds,
            "max_steps_factor": max_steps_factor, "design": storage.design_hash(a),
            "start_state": "held" if fresh else storage.state_hash(rod),
            "reference_length": length}
    if contact is not None:  # a run with contact never resumes one without, nor the reverse
        meta["contact"] = {"radius": contact.radius, "dhat": contact.dhat,
                           "stiffness": contact.stiffness}
    gaps: list[tuple[float, float]] = []  # (value, smallest capsule gap) with contact
    # With contact: where a node's closest point crossed a clamped end of an element between
    # two points of the path (the energy is C1 there, not C2: an event, not a silent jump)
    events: list[dict] = []
    last_x: list[np.ndarray] = []  # the last point's nodes
    with contextlib.ExitStack() as held:
        if out is not None:
            out.mkdir(parents=True, exist_ok=True)
            held.enter_context(run_lock(out))
            st = None
            if not restart:
                try:
                    st = storage.load_state(out / "state.npz")
                    if st is not None and st["meta"] == meta:  # else: another run's, replaced
                        storage.check_fits(st, rod)
                except storage.StateUnreadable as exc:
                    st = None
                    storage.set_aside(out / "state.npz", str(exc))
            storage.remove_temporaries(out)
            if st is not None and st["meta"] == meta:
                rows = [tuple(r[:4]) + (bool(r[4]),) for r in st["rows"]]
                specials = st["specials"]
                rod.x, rod.R_edge, rod.R_joint = st["x"], st["R_edge"], st["R_joint"]
                param.set(rod, st["value"])
                tq, tp, h = st["tq"], st["tp"], st["h"]
                resumed = len(rows)
            else:
                for name in storage.OUTPUTS:
                    (out / name).unlink(missing_ok=True)
                storage.write_atomic(out / "run.json", json.dumps(meta, indent=1))
        if not rows:
            if fresh:
                settle(rod)
            _reach(rod, param, key, start, h)
            tq, tp = tangent(rod, param, tq, tp)  # the true tangent (the start is regular)
            # Arclength counts the unknowns too: size the step so that the parameter advances by
            # about |stop - start| / n_steps while the path is the primary one.
            h = h / max(abs(tp), 1e-3)
        path = Stepper(rod, param, tq, tp, h)

        def record(ok: bool, low: float | None = None) -> None:
            rows.append((param.get(rod), rod.energy(), lowest(rod) if low is None else low,
                         _moved(rod.x, held_x), ok))
            if rod.contact is not None:
                gap = contact_state(rod.contact, rod.x).smallest_gap
                if gap is not None:
                    gaps.append((param.get(rod), gap))
                if last_x:
                    for node, element, end in type_switch_crossings(rod.contact, last_x[0],
                                                                    rod.x):
                        events.append({"kind": "C1 switch", "node": node, "element": element,
                                       "end": "start" if end == 0 else "end",
                                       "bracket": [rows[-2][0], rows[-1][0]]})
                last_x[:] = [rod.x.copy()]
                _mark_events(specials, events)
            if out is not None:
                storage.save_state(out, rod, param.get(rod), path.tq, path.tp, path.h, rows, meta,
                                   specials)
                storage.export(out, rows, specials)
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
            prev, prev_tp, prev_tq = rod.copy(), path.tp, path.tq.copy()
            if not path.step():
                ok_all, why = False, f"step failed at {key} = {param.get(rod)!r}"
                break
            hessian = None if path.terms is None else path.terms[2]
            if (param.get(rod) - stop) * direction > 0:
                # Past the end: land exactly on ``stop`` by Newton from the previous point.
                trial = prev.copy()
                param.set(trial, stop)
                if newton(trial)[0]:
                    rod.assign(trial)
                    hessian = None  # the stepper's is not this point's
            e0, e1 = rows[-1][2], lowest(rod, hessian)
            if crossed(e0, e1, prev_tp, path.tp):
                point, at = locate(rod, param, prev, prev_tq, prev_tp, path.last_h, e0, e1,
                                   path.tp)
                if (point["value"] - stop) * direction <= 0:
                    if at is not None and point["kind"] != SpecialKind.REGAINED.value:
                        states.append((point["value"], at))
                    if point["kind"] == SpecialKind.LOST.value and at is not None \
                            and branch_steps > 0:
                        side = math.copysign(1.0, param.get(prev) - point["value"])
                        b = trace_branch(at, param, side, branch_ds, branch_steps, length=length,
                                         first_step=BRANCH_FIRST_STEP)
                        point["post_buckling"] = b.verdict
                        point["branch"] = _branch_dict(b)
                        branches.append(b)
                    specials.append(point)
                    if stop_at_first:
                        record(True, e1)
                        break
            record(True, e1)
        if out is not None:
            storage.export(out, rows, specials)
        if resumed:  # branches found before the resume: rebuilt from their stored points
            branches = [_from_dict(key, s) for s in specials if "branch" in s]
        return Path(key, tuple(r[0] for r in rows), tuple(r[1] for r in rows),
                    tuple(r[2] for r in rows), tuple(r[3] for r in rows),
                    "largest node displacement from the start state (length unit)", ok_all,
                    "pseudo-arclength (Keller) with Hessian eigenvalue monitoring"
                    + (f"; STOPPED: {why}" if why else ""), special_points=tuple(specials),
                    branches=tuple(branches), resumed_steps=resumed,
                    states=tuple(states), contact=None if contact is None else _contact_block(
                        contact, gaps, resumed, events, specials, len(rows) - resumed))


def _mark_events(specials: list[dict], events: list[dict]) -> None:
    """Set ``"at_contact_event"`` on each special point whose bracket meets an event's.

    Marked as points are recorded, so ``special_points.json`` (written at every point) carries
    the mark; a mark is never cleared (a resumed run has not the events before its resume).
    """
    for sp in specials:
        lo, hi = sorted(sp.get("bracket", (sp["value"], sp["value"])))
        sp["at_contact_event"] = bool(sp.get("at_contact_event")) or any(
            min(ev["bracket"]) <= hi and lo <= max(ev["bracket"]) for ev in events)


def _contact_block(model: ContactModel, gaps: list[tuple[float, float]], resumed: int,
                   events: list[dict], specials: list[dict], checked: int) -> dict:
    """Return the path's ``contact``: the model, the smallest gap over the points run here.

    ``checked``: the points run here (each one's contact checked).
    ``events``: the C1 switches met between two points (:func:`~..contact.type_switch_crossings`);
    a special point whose bracket meets one gets ``"at_contact_event": True`` (its eigenvalue
    sign change may be the Hessian's jump there, not a smooth crossing).
    """
    low = min(gaps, key=lambda vg: vg[1]) if gaps else None
    radius = model.radius if isinstance(model.radius, float) else max(model.radius)
    _mark_events(specials, events)
    return {"thickness": 2.0 * float(radius), "dhat": model.dhat,
            "stiffness": model.stiffness, "smallest_gap": None if low is None else low[1],
            "smallest_gap_value": None if low is None else low[0],
            "points_checked": checked,
            "resumed_points_unchecked": resumed,
            "events": events}


def _from_dict(key: str, s: dict) -> Path:
    b = s["branch"]
    co = b.get("coefficients", {})
    return Path(key, tuple(b["value"]), tuple(b["energy"]), tuple(b["lowest_eigenvalue"]),
                tuple(b["amplitude"]), co.get("definition", ""), b["converged"],
                "stored branch", s["value"], (co.get("a", math.nan), co.get("b", math.nan)),
                b["verdict"])


#: Order of the discrete rod's error in the element length (measured on the straightened rod
#: and the clamped arc: critical load factors at 8/16/32/64 elements converge at order
#: 1.98-1.99 to the linear engine's value; ``tests/test_nonlinear.py``).
MESH_ORDER = 2
#: The finer run goes this many coarse steps past the last special point (to cross it).
FINE_MARGIN_STEPS = 2


def special_point_errors(a: Assembly, key: str, start: float, path: Path, n_steps: int, *,
                         elements_per_segment: int, stop: float,
                         limits: Limits = DEFAULT_LIMITS,
                         contact: ContactModel | None = None) -> tuple[dict, ...]:
    """Discretisation error of each special point of ``path`` (a primary path from ``start``).

    The path is continued again on the mesh twice as fine (``2 elements_per_segment``, the
    same step in the parameter, no branches) from ``start`` to just past its last special
    point; the special points of the two runs are matched in order and kind, and each value is
    Richardson-extrapolated with order :data:`MESH_ORDER`: ``v_R = v_f + (v_f - v_c) /
    (2^p - 1)``. Returns one dict per special point of ``path``: ``value_fine``,
    ``value_extrapolated``, ``error_estimate = |value - value_extrapolated|`` (of the coarse
    value the path reports), ``elements_fine``; or ``{"error_estimate": None, "why": ...}``
    when the finer mesh does not have a matching point (a mesh-sensitive path). Values in the
    parameter's units.
    """
    specials = list(path.special_points)
    if not specials:
        return ()
    direction = 1.0 if stop > start else -1.0
    h = abs(stop - start) / n_steps
    last = max((p["value"] for p in specials), key=lambda v: (v - start) * direction)
    end = last + direction * FINE_MARGIN_STEPS * h
    if (end - stop) * direction > 0:
        end = stop
    steps = max(1, math.ceil(abs(end - start) / h))
    fine_n = 2 * elements_per_segment
    fine = continuation(a, key, start, end, steps, elements_per_segment=fine_n,
                        branch_steps=0, limits=limits, contact=contact)
    theirs = list(fine.special_points)
    out: list[dict] = []
    for i, p in enumerate(specials):
        kinds = [q["kind"] for q in specials[: i + 1]]
        match = [q for q in theirs if q["kind"] == p["kind"]]
        k = kinds.count(p["kind"]) - 1
        if k >= len(match):
            out.append({"error_estimate": None, "elements_fine": fine_n,
                        "why": f"no {p['kind']} found on the finer mesh ({fine_n} elements)"})
            continue
        vf = float(match[k]["value"])
        vr = richardson(float(p["value"]), vf, 2.0, MESH_ORDER)[0]
        out.append({"value_fine": vf, "value_extrapolated": vr,
                    "error_estimate": abs(float(p["value"]) - vr), "elements_fine": fine_n})
    return tuple(out)
