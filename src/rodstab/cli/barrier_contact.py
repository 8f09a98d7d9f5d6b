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


def knot_line(payload: dict[str, Any], rod: Any, xs: Any, a: str, b: str) -> str:
    """Return the knot types of the path's two ends (JSON ``contact.knots``), as printed."""
    from ..multistable.knots import apart_by_topology, describe, knot_class, ring_polygon

    ka, kb = (knot_class(ring_polygon(rod, x)) for x in (xs[0], xs[-1]))
    payload["contact"]["knots"] = {a: ka.to_dict(), b: kb.to_dict()}
    verdict = ("different knots: no path joins them without passing rods through each other"
               if apart_by_topology(ka, kb) else "rods that cannot cross keep the knot type")
    return f"knots        {describe(a, ka)}; {describe(b, kb)}: {verdict}"


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
