"""``barrier``'s contact lines: the path judged, its ends' knots, the saddle into contact."""

from __future__ import annotations

from typing import Any

from .output import fmt


def path_model(a: Any, elements: int, mu: float, order: Any, model: Any, wide: float | None,
               h: float) -> tuple[Any, Any]:
    """Return the barrier path's discrete model and the contact model whose pairs are judged.

    ``(None, None)``: ``a``'s plain model, :func:`~.multistable.transitions.judged_pairs`'
    default. With ``order`` (``--layers``) the stacked model (welds spanning the layers);
    with ``wide`` (``--cusp-width`` as a length) the model with wide cusp welds and every
    pair the contact model sees judged (``model``, else one of capsules ``h``), the cusps'
    two ends included.
    """
    from ..multistable.discover import common_rod

    if order is not None:
        from ..multistable.layered import stacked_model

        return stacked_model(common_rod(a, elements, mu), order, model), None
    if wide is not None:
        from ..nonlinear.equilibrium import rod_contact_model

        return common_rod(a, elements, mu, cusp_width=wide), model or rod_contact_model(a, h)
    return None, None


def into_contact_lines(a: Any, elements: int, mu: float, saddle: Any, ends: dict[str, Any],
                       thickness: float, dhat: float, payload: dict[str, Any],
                       units: Any = None) -> tuple[list[str], bool]:
    """Continue ``saddle`` (a Snapshot of ``a``'s model) into contact; the lines and if any held.

    ``ends``: the barrier's two states (label -> Assembly), the names for the descents' ends
    (matched by shape, :func:`~.multistable.identify.same_state`; others are "new k").
    ``thickness`` ``h / L`` and ``dhat / h`` of the contact model. Puts ``into_contact`` in
    ``payload``: the model, the intersecting pairs and one record per choice of sides
    (:class:`~.multistable.contact_saddle.StiffenedSaddle`, with the states its descents with
    contact end on and their energies, in model units). ``units``: a design's units, to
    print every energy also in J, as the barrier's own lines do.
    """
    from ..multistable.contact_saddle import crossing_pairs, stiffen_all
    from ..multistable.discover import common_rod
    from ..multistable.landscape import Landscape
    from ..nonlinear.equilibrium import rod_contact_model
    from ..nonlinear.newton import newton

    rod = common_rod(a, elements, mu)
    saddle.put(rod)
    model = rod_contact_model(a, thickness, dhat)
    named = []
    for label, asm in ends.items():
        r = common_rod(asm, elements, mu)
        newton(r)
        named.append((label, r))
    land = Landscape.of(named)
    land.new_label = "new "
    pairs = crossing_pairs(rod).tolist()

    def energy(e: float) -> str:
        return fmt(e) + ("" if units is None else f" ({fmt(units.si(e, 'energy'))} J)")

    out: list[dict[str, Any]] = []
    lines = [f"into contact capsules h/L = {fmt(thickness)}, dhat/h = {fmt(dhat)}: "
             f"{len(pairs)} pair(s) of elements intersect at the saddle {pairs}; the saddle "
             f"continued into contact for each choice of sides "
             f"(rodstab.multistable.contact_saddle):"]
    for res, r in stiffen_all(rod, model):
        rec = res.to_dict()
        signs = "".join("+" if s > 0 else "-" for s in res.sides) or "(none)"
        if not res.found or res.energy is None:
            where = "" if not res.distances else (
                f" after {len(res.distances)} stages, closest pair {fmt(res.distances[-1])} h, "
                f"lowest eigenvalues {', '.join(f'{v:.3g}' for v in res.eigenvalues[:2])}")
            lines.append(f"  sides {signs:<4} {res.outcome}{where}")
            out.append(rec)
            continue
        judged = land.judge(r)
        ends_text = ", ".join(
            f"{lab} {energy(e)}" + ("" if ok else " (not converged)") for lab, e, ok in
            zip(judged["descent_ends"], judged["end_energies"], judged["ends_converged"],
                strict=True))
        rec.update(descent_ends=list(judged["descent_ends"]),
                   end_energies=[float(e) for e in judged["end_energies"]],
                   ends_converged=list(judged["ends_converged"]))
        out.append(rec)
        lines.append(f"  sides {signs:<4} saddle index 1, energy {energy(res.energy)}, contact "
                     f"adds {energy(res.energy - float(rod.energy()))}; descents with contact "
                     f"end on {ends_text}")
    payload["into_contact"] = {"thickness": thickness, "dhat": dhat, "pairs": pairs,
                               "branches": out}
    return lines, any(rec.get("outcome") == "saddle" for rec in out)


def _topology_text(verdict: Any) -> list[str]:
    """Return the ``knots`` and ``linking`` lines of a :class:`~.linking.Topology`."""
    from ..multistable.knots import apart_by_topology, describe
    from ..multistable.linking import apart_by_linking, describe_linking

    (a, b), (ka, kb), (la, lb) = verdict.names, verdict.knots, verdict.linking
    apart = "no path joins them without passing rods through each other"
    knots = ("different knots: " + apart if apart_by_topology(ka, kb)
             else "rods that cannot cross keep the knot type")
    # each invariant judged on its own: ends of different knot types may differ in Lk too
    links = (f"different: {apart}" if apart_by_linking(la, lb)
             else "rods that cannot cross keep it" if la.value is not None
             and lb.value is not None else "no verdict")
    how = ("Gauss's integral and crossings agree" if la.value is not None
           and lb.value is not None else "not certified for both")
    return [f"knots        {describe(a, ka)}; {describe(b, kb)}: {knots}",
            f"linking      ribbons pushed along {la.director} ({how}): "
            f"{describe_linking(a, la)}; {describe_linking(b, lb)}: {links}"]


def topology_lines(payload: dict[str, Any], rod: Any, xs: Any, Rs: Any, a: str,
                   b: str) -> list[str]:
    """Return the knot types and ribbon linking of the path's ends, as printed.

    JSON ``contact.knots`` and ``contact.linking``.
    """
    from ..multistable.linking import topology

    verdict = topology(rod, rod, (a, b), xs[0], xs[-1], Rs[0], Rs[1])
    payload["contact"]["knots"] = {a: verdict.knots[0].to_dict(), b: verdict.knots[1].to_dict()}
    payload["contact"]["linking"] = {a: verdict.linking[0].to_dict(),
                                     b: verdict.linking[1].to_dict()}
    return _topology_text(verdict)


def apart_output(verdict: Any, name: str, k: float, section: Any, elements: int,
                 design_file: str | None, as_json: bool) -> None:
    """Print a barrier whose two states topology keeps apart (JSON ``blocked_by_contact``)."""
    from .output import emit, section_line

    a, b = verdict.names
    payload = {"structure": name, "kappa_R0": k, "section": section.to_dict(),
               "from_state": a, "to_state": b, "blocked_by_contact": verdict.to_dict(),
               "barrier_forward": None, "barrier_backward": None}
    lines = [section_line(section),
             f"{name} at {'kappa_n R0' if design_file is None else 'load factor'} = {fmt(k)}, "
             f"{elements} elements per rod, with contact",
             f"blocked      {a} -> {b}: BLOCKED BY CONTACT ({verdict.why}): no path joins "
             "them without passing rods through each other; no barrier (the string was not "
             "run)"] + _topology_text(verdict)
    emit(payload, as_json, lines)


def contact_line(report: Any, thickness: float, from_state: str, acting: bool) -> str:
    """Return the path's contact verdict as printed (a transition's stretch, over h)."""
    verdict = ("RODS PASS THROUGH at path point "
               f"{report.pass_through_at:g}: not physical as computed"
               + ("" if acting else " (no contact model: --contact)")
               if report.pass_through else "no pass-through")
    overlap = ""
    if report.touching:
        points = ", ".join(f"{a:g}" if a == b else f"{a:g}-{b:g}" for a, b in report.touching)
        overlap = f" (closer than h, the rods overlap: path points {points})"
    return (f"contact      h/L = {fmt(thickness)}, judged at the {report.samples} path points: "
            f"{report.stacked_pairs} element pairs stacked in {from_state} (may touch, not "
            f"swap layers); the others come within {fmt(report.min_distance)} h{overlap}; "
            + verdict)


def judge_path(payload: dict[str, Any], a: Any, elements: int, mu: float, order: Any,
               model: Any, wide: float | None, h: float, acting: bool, path: Any
               ) -> tuple[Any, Any, Any, Any, Any]:
    """Judge a barrier's path for pass-through (JSON ``contact``); return what the lines need.

    Returns ``(report, stacked, xs, edges, rest)``: the
    :func:`~.multistable.barrier.path_contact` report, the path's discrete model (None: ``a``'s
    plain model), node positions, elements and rest lengths.
    """
    import numpy as np

    from ..multistable.barrier import path_contact

    xs = np.stack([s.x for s in path])
    stacked, judge = path_model(a, elements, mu, order, model, wide, h)
    report, edges, rest = path_contact(a, elements, xs, h, rod=stacked, model=judge)
    payload["contact"] = dict(report.to_dict(), thickness=h, acting=acting)
    return report, stacked, xs, edges, rest


def judged_lines(payload: dict[str, Any], judged: tuple[Any, Any, Any, Any, Any], a: Any,
                 elements: int, h: float, acting: bool, path: Any, names: tuple[str, str],
                 order: Any, model: Any, energies: Any, out: Any) -> list[str]:
    """Return the judged path's lines: contact, knots and linking, welds, the path file."""
    import numpy as np

    from .output import weld_line

    report, stacked, xs, edges, rest = judged
    lines = [contact_line(report, h, names[0], acting)]
    if acting:
        from ..nonlinear.discrete import discretise

        lines += topology_lines(payload, stacked or discretise(a, elements), xs,
                                (path[0].R_edge, path[-1].R_edge), *names)
    if order is not None and stacked is not None and model is not None:
        from ..multistable.layered import weld_spans

        start = stacked.copy()  # the path's first state, as the knots line judges it
        start.x = xs[0]
        welds = weld_spans(start, 2.0 * float(np.max(model.radius)))
        payload["contact"]["welds"] = welds.to_dict()
        lines.append(weld_line(welds))
    if out is not None:
        from ..io.path_file import PATH_FILE, write_path_file

        payload["path_file"] = str(write_path_file(out / PATH_FILE, xs, edges, rest, energies,
                                                   thickness=h))
        lines.append(f"wrote {payload['path_file']}")
    return lines


def pull_output(a: Any, b: Any, mu: float, head: list[str], payload: dict[str, Any],
                elements: int, order: Any, model: Any, h: float, dhat: float,
                names: tuple[str, str], out: Any, as_json: bool, plot: Any = None) -> None:
    """Print ``barrier --method pull``: a path inside the contact model and an upper bound.

    :func:`~.multistable.pulled.stacked_pull` from the stacked ``--from`` state (``order``)
    to ``--to``; the path is judged as the string's (:func:`judge_path`) and written with
    ``--out``. The barrier is not computed: JSON ``barrier_forward`` and
    ``barrier_backward`` are null, ``upper_bound_forward`` / ``upper_bound_backward`` the
    path's highest energy above each end. ``plot``: the energy along the path (chart
    arclength), its highest point and the two bounds marked. Raises NotConverged (after the
    output) when the released state is not ``--to``.
    """
    import numpy as np

    from ..errors import NotConverged
    from ..multistable.pulled import stacked_pull
    from .output import emit

    run = stacked_pull(a, b, mu, order, model, elements_per_segment=elements, names=names)
    top, e_a, e_b = run.highest_energy, run.energies[0], run.energies[-1]
    payload.update(method="pull", pull=run.to_dict(), energy_from=e_a, energy_to=e_b,
                   from_state=names[0], to_state=names[1],
                   barrier_forward=None, barrier_backward=None,
                   upper_bound_forward=top - e_a if run.reached else None,
                   upper_bound_backward=top - e_b if run.reached else None,
                   converged=run.reached)
    k_lo, k_hi = run.stages[0][0], run.stages[-1][0]
    released = ("released after the first stage whose release settled on "
                f"{names[1]}" if run.released_after >= 0 else "then released")
    lines = head + [
        f"pull         {names[0]} (stacked, --layers) pulled towards {names[1]} by node springs "
        f"{fmt(k_lo)} .. {fmt(k_hi)} B3/Lm^3 in {len(run.stages)} stages, each relaxed by "
        f"Newton with contact one filtered step at a time, {released}: "
        f"{len(run.states)} states (rodstab.multistable.pulled)",
        f"reached      {run.reached}: the released state is {fmt(run.end_distance)} (length) "
        f"from {names[1]} (tolerance {fmt(run.tolerance)})"]
    if run.reached:
        lines += [f"upper bound  {names[0]} -> {names[1]}: barrier <= {fmt(top - e_a)}; "
                  f"{names[1]} -> {names[0]}: <= {fmt(top - e_b)} (highest energy "
                  f"{fmt(top)} along the path; {names[0]} {fmt(e_a)}, {names[1]} {fmt(e_b)})",
                  "barrier      not computed: the pulled path is no minimum energy path, its "
                  "highest energy only bounds the barrier from above"]
    judged = judge_path(payload, a, elements, mu, order, model, None, h, True, run.states)
    payload["contact"]["dhat"] = dhat
    lines += judged_lines(payload, judged, a, elements, h, True, run.states, names, order,
                          model, run.energies, out)
    if plot is not None:
        from ..multistable.path_chart import arclength
        from ..plot.plots import plot_barrier_path

        payload["plot"] = str(plot_barrier_path(
            arclength(list(run.states)).tolist(), run.energies, int(np.argmax(run.energies)), plot,
            labels=(names[0], names[1] if run.reached else f"released (not {names[1]})"),
            bound=True, title=f"{head[1]}: pulled path, an upper bound"))
        lines.append(f"wrote {payload['plot']}")
    emit(payload, as_json, lines)
    if not run.reached:
        raise NotConverged(f"--method pull: the pulled {names[0]} did not reach {names[1]} "
                           f"when released ({fmt(run.end_distance)} from it): no path built")
