"""The ``barrier`` command: the energy barrier between two stable states of a ring.

Parsing and printing only.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import click

from ..errors import NotConverged, RodstabInputError
from ..io.outputs import check_output
from ..limits import Limits
from ..model import CONTACT_DHAT_FRACTION
from ..sections import Section
from .barrier_contact import apart_output, judge_path, judged_lines
from .barrier_design import chain_link_text, design_ends, where_k
from .contact_options import (
    check_cusp_width,
    cusp_width_option,
    layers_option,
    parse_layers,
    path_contact_options,
)
from .options import (
    elements_option,
    json_option,
    limit_options,
    load_factor_option,
    ring_and_section,
    section_options,
    string_pool,
    string_workers_option,
    structure_option,
)
from .output import emit, fmt, image_output, section_line, units_line

#: Default ``--from`` / ``--to`` of ``rodstab barrier`` per built-in structure.
_BARRIER_STATES = {"six-ring": ("folded", "one-loop"), "hexagram": ("line", "star")}


@click.command()
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@click.option("--method", type=click.Choice(["string", "continuation", "pull"]),
              default="string", show_default=True,
              help="string: minimum energy path between the two states, saddle refined from "
                   "it; continuation: saddle from the --from state's bifurcation (built-in, "
                   "straight held states only); pull: with --contact --layers, a path inside "
                   "the contact model from the stacked --from state and an upper bound on the "
                   "barrier (not the barrier).")
@structure_option("six-ring", "hexagram", help="Without DESIGN: the structure (six-ring: "
                  "folded, one-loop; hexagram: line, star, daisy, eight).")
@click.option("--from", "from_state", default=None,
              help="The stable state the barrier is climbed from (default: folded for the "
                   "six-ring, line for the hexagram; with a ring DESIGN a label of `rodstab "
                   "states DESIGN`, required; else #k or '#k mirror', a row of `rodstab "
                   "discover DESIGN` or its mirror image, default the lowest).")
@click.option("--to", "to_state", default=None, help="The other state (default: one-loop, "
              "star; with a ring DESIGN required; else the second lowest).")
@load_factor_option(
    default=None,
    help="Without DESIGN kappa_n R0 (six-ring: R0 = L / theta, the one-loop radius; "
         "hexagram: R0 = 3L/2pi); with DESIGN the multiplier of its natural "
         "curvature. Default: the middle of the two states' common stable interval "
         "(Bloch). Both states must be stable there.")
@elements_option(default=8, minimum=4, help="Elements per rod of the discrete rod (>= 4).")
@click.option("--images", type=int, default=None,
              help="Images of the string, ends included (>= 3; default 17). String method.")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write the energy along the path (saddle marked, barriers annotated).")
@click.option("--animation", "animation_path", type=click.Path(dir_okay=False), default=None,
              help="Write a GIF of the path's states (.gif). String method.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default=None,
              help="Write DIR/path.npz: node positions of every state of the path, the "
                   "elements, rest lengths, energies and --contact-thickness, to check the gaps "
                   "independently (rodstab.io.path_file). String method.")
@path_contact_options("The path's contact is judged as a transition's: pairs stacked in "
                      "the --from state may touch but not swap layers, no other pair may pass "
                      "through another (rodstab transitions). With --contact also the "
                      "capsules' diameter.")
@layers_option("Barrier: the --from state is stacked in this order (NAME=U:K: in-plane "
               "offset U and layer K, in units of h + g0; NAME=U:K:S also shifts the rod S "
               "along itself, to stagger welds; straight rods only) and the path runs with "
               "its welds spanning the layers. String method, --contact.")
@click.option("--into-contact", is_flag=True,
              help="Continue the saddle found without contact into contact (capsules "
                   "--contact-thickness, dhat --contact-dhat), one branch per side of each "
                   "pair of rods intersecting at it, and name where each saddle's descents "
                   "with contact end (rodstab.multistable.contact_saddle). String method.")
@cusp_width_option
@string_workers_option
@section_options
@limit_options
@json_option
def barrier(design_file: str | None, section: Section, method: str, structure: str,
            from_state: str | None, to_state: str | None, load_factor: float | None,
            elements: int,
            images: int | None, plot_path: str | None, animation_path: str | None,
            out_dir: str | None, contact: Any, layers: str | None, into_contact: bool,
            cusp_width: float | None, workers: int, limits: Limits, as_json: bool) -> None:
    """Energy barrier between two stable states of a ring: the saddle and the path through it.

    string (default): the minimum energy path between the two states by the string method
    (images relaxed from a path that turns the frames through 3D), the saddle refined from it
    by Newton, index 1, and checked by the steepest descents from it, which must end on the two
    states. continuation: the saddle is the subcritical branch from the --from state's
    bifurcation, traced back to the load; the path is the steepest descent from it on both
    sides; a state curved in its held geometry (the hexagram's) is refused (exit 2). An
    unconverged barrier exits 3 after the output. --contact (string): rods are capsules of
    diameter --contact-thickness that cannot pass through each other along the path; energies
    include the contact energy. pull (--contact --layers): the stacked --from state pulled to
    --to by node springs inside the contact model; its highest energy bounds the barrier.
    """
    from ..errors import require_int
    from ..limits import require_nonlinear

    k = load_factor
    chosen: tuple[float, float] | None = None
    ends = named_states = None  # a design that is no ring: its states, found by deflation
    if method == "continuation" and (images is not None or animation_path is not None
                                     or out_dir is not None or workers != 1):
        raise RodstabInputError("--images, --animation, --out and --workers are options of "
                                "--method string")
    if method == "pull" and (images is not None or animation_path is not None or workers != 1):
        raise RodstabInputError("--images, --animation and --workers are options of --method "
                                "string, not of --method pull")
    from ..multistable.string_method import STRING_IMAGES

    n_img = STRING_IMAGES if images is None else require_int("--images", images, 3)
    plot = None if plot_path is None else image_output("--plot", plot_path)
    gif = None if animation_path is None else check_output("--animation", animation_path,
                                                           directory=False, suffixes={".gif"})
    out = None if out_dir is None else check_output("--out", out_dir, directory=True)
    if design_file is not None:
        if method == "continuation":
            raise RodstabInputError("--method continuation is for the built-in structures "
                                    "(it needs their load range); use --method string with "
                                    f"{design_file}")
        ring, section, name, design = ring_and_section(design_file, structure, 6, section,
                                                       contact_ok=True, any_design=True)
        if ring is None:  # states found by deflation (barrier_design)
            from_state, to_state, ends, named_states = design_ends(
                design, design_file, elements, k, from_state, to_state,
                (contact.on, layers, into_contact, cusp_width, method))
            a, b_asm, others = design.assembly, design.assembly, {}
        elif from_state is None or to_state is None:
            raise RodstabInputError(f"--from and --to name two states of {design_file} (see "
                                    "`rodstab states DESIGN`)")
        else:
            a, b_asm = (ring.held(ring.state(s).theta) for s in (from_state, to_state))
            others = {st.label: ring.held(st.theta) for st in ring.states().states
                      if st.label not in (from_state, to_state)}  # names minima a path passes
        if k is None:
            from ..multistable.atlas import common_load

            k, chosen = common_load(ring, (from_state, to_state))
        mu = k
    else:
        from ..problems.barrier_states import (
            STRUCTURE_STATES,
            check_state,
            model_load_factor,
            state_assembly,
        )

        name = structure
        from_state = from_state or _BARRIER_STATES[structure][0]
        to_state = to_state or _BARRIER_STATES[structure][1]
        check_state(structure, from_state, "--from")
        check_state(structure, to_state, "--to")
        a, b_asm = (state_assembly(structure, section, s) for s in (from_state, to_state))
        others = {s: state_assembly(structure, section, s) for s in STRUCTURE_STATES[structure]
                  if s not in (from_state, to_state)}  # to name the minima a path passes
    if from_state == to_state:
        raise RodstabInputError(f"--to {to_state!r} is the --from state: a barrier joins two "
                                "different states")
    given = None if design_file is None or design.contact is None else design.contact[1]
    into_dhat = contact.dhat or given or CONTACT_DHAT_FRACTION
    if into_contact:
        if method != "string" or contact.on:
            raise RodstabInputError("--into-contact continues the saddle of a barrier "
                                    "computed without contact: --method string, no --contact")
        contact = dataclasses.replace(contact, on=False, dhat=None)
    h, c = contact.judged(None if design_file is None else design.contact)
    if c is not None and method == "continuation":
        raise RodstabInputError("--contact is an option of --method string or pull")
    order = None
    if layers is not None:
        if c is None:
            raise RodstabInputError(f"--layers {layers!r} is a setting of contact, which is off "
                                    "for this run (--contact)")
        parsed = parse_layers(layers, [s.name for s in a.segments])
        if not isinstance(parsed, dict):
            raise RodstabInputError(f"--layers {layers!r}: a barrier takes NAME=K, NAME=U:K or "
                                    "NAME=U:K:S for every segment, not a named stacking")
        order = parsed
    if method == "pull" and (c is None or order is None):
        raise RodstabInputError("--method pull pulls the stacked --from state inside the contact "
                                f"model: it needs --contact and --layers (contact "
                                f"{'on' if c is not None else 'off'}, --layers {layers!r})")
    wide = None
    if cusp_width is not None:
        wide = check_cusp_width(cusp_width, a, h, from_state)
        if method != "string" or order is not None or into_contact:
            raise RodstabInputError(f"--cusp-width {cusp_width!r} is an option of --method "
                                    "string without --layers or --into-contact")
    # Sized before anything is built: the string relaxes its images together.
    string = method == "string"
    require_nonlinear([elements] * len(a.segments), len(a.joints()),
                      f"--images {n_img}, --elements {elements}" if string else
                      f"--elements {elements}", limits, copies=n_img if string else 1)
    if design_file is None:
        from ..problems.barrier_states import model_load_factor, structure_load

        if k is None:
            from ..problems.barrier_states import common_load as structure_common_load

            hexagram_ring = ring_and_section(None, "hexagram", 6, section)[0]
            k, chosen = structure_common_load(structure, hexagram_ring, (from_state, to_state))
        mu = model_load_factor(structure, k)
    assert k is not None  # set above on every path (given, DESIGN's or the structure's default)
    from ..multistable.linking import TopologicallyApart
    from ..nonlinear.contact import Interpenetration
    from ..nonlinear.equilibrium import rod_contact_model

    path: list[Any] = []
    try:
        if method == "string":
            from ..multistable.string_method import string_barrier

            model = None if c is None else rod_contact_model(a, h, c)
            with string_pool(workers) as pool:
                b, path = string_barrier(a, b_asm, mu, elements_per_segment=elements,
                                         images=n_img, name_a=from_state, name_b=to_state,
                                         limits=limits, contact=model, layers=order,
                                         named=others, cusp_width=wide, pool=pool,
                                         ends=ends, named_states=named_states)
        elif method == "pull":
            from .barrier_contact import pull_output

            model = rod_contact_model(a, h, c)
            scale = ("B3 = 1, L = 1" if design_file is None or design.units is not None else
                     "energies in the design's units: stiffness / length")
            where = "kappa_n R0" if design_file is None else "load factor"
            head = [section_line(section), f"{name} at {where} = {fmt(k)}, {elements} elements "
                    f"per rod ({scale}), method pull"]
            pull_output(a, b_asm, mu, head, {"structure": name, "kappa_R0": k,
                                              "section": section.to_dict(), "from": from_state,
                                              "to": to_state}, elements, order, model, h, c,
                        (from_state, to_state), out, as_json, plot)
            return
        else:
            from ..multistable.barrier import barrier_from_bifurcation

            b = barrier_from_bifurcation(a, mu, upper=model_load_factor(structure, 4.0),
                                         elements_per_segment=elements, name=from_state,
                                         named={to_state: b_asm}, limits=limits)
    except TopologicallyApart as exc:  # a certified answer: no path inside the model
        apart_output(exc.verdict, name, k, section, elements, design_file, as_json)
        return
    except Interpenetration as exc:  # a state outside the contact model
        raise RodstabInputError(f"--contact-thickness {h!r}: {exc}") from exc
    except RodstabInputError as exc:
        raise RodstabInputError(f"--load-factor {k!r}, --from {from_state!r}: {exc}") from exc
    payload = b.to_dict()
    payload.update(structure=name, kappa_R0=k, section=section.to_dict(), method=method)
    if chosen is not None:
        payload["load_factor_chosen_in"] = list(chosen)
    if method == "string":
        payload.update(images=b.images)
    units = None if design_file is None else design.units
    joules: dict[str, str] = {}  # " (... J)" after the model energies of the table
    if units is not None:
        payload["units"] = units.block(
            natural_curvature={"value": units.natural_curvature(design.assembly, k),
                               "unit": "1/m"},
            **{key: (getattr(b, key), "energy") for key in (
                "barrier_forward", "barrier_backward", "energy_from", "energy_to",
                "energy_saddle", "energies")})
        joules = {key: f" ({fmt(payload['units'][key]['value'])} J)" for key in (
            "barrier_forward", "barrier_backward", "energy_saddle")}
    # energies: of rods with B3 = L = 1 (built-in, or a design with units, converted to J
    # below), else in the design's own units
    scale = ("B3 = 1, L = 1" if design_file is None or units is not None else
             "energies in the design's units: stiffness / length")
    lines = [section_line(section),
             f"{name} at {'kappa_n R0' if design_file is None else 'load factor'} = {fmt(k)}, "
             f"{elements} elements per rod ({scale}), method {method}"
             + ("" if chosen is None else f" (chosen: the middle of the states' common stable "
                                          f"interval ({fmt(chosen[0])}, {fmt(chosen[1])}))")]
    if units is not None:
        lines[1:1] = [units_line(units), f"physical     load factor {fmt(k)}: natural curvature "
                      f"{fmt(payload['units']['natural_curvature']['value'])} 1/m of segment "
                      f"{units.segment!r}; energies in J = model energy x B3/L"]
    run: Any = b.string_run
    if method == "string":
        refined = f" (refined from {n_img})" if b.images != n_img else ""
        lines.append(f"string       {b.images} images{refined}, {b.iterations} iterations; "
                     f"{'saddle from' if b.converged else 'highest:'} image "
                     f"{b.saddle_position} of the path")
    else:
        lines.append(f"branch       from kappa_n R0 = "
                     f"{fmt(structure_load(structure, b.load_factor_critical))}")
    # an unconverged string reports its highest image, not a saddle (string_barrier)
    top = ("saddle       " if b.converged or method != "string" else
           "highest image (no saddle joining the two states was found): ")
    lines += [
        f"{top}index {b.saddle_index}, energy {fmt(b.energy_saddle)}"
        f"{joules.get('energy_saddle', '')}, descents end on "
        f"{', '.join(b.descent_ends) or 'not run'}",
        f"forward      {b.from_state} -> {b.to_state}: {fmt(b.barrier_forward)}"
        + joules.get("barrier_forward", ""),
        f"backward     {b.to_state} -> {b.from_state}: {fmt(b.barrier_backward)}"
        + joules.get("barrier_backward", ""),
        f"converged    {b.converged} ({len(b.energies)} path points)"]
    if b.chain is not None:  # the string passed other minima: one saddle per step
        ch: Any = b.chain
        steps = " ".join(f"-[{chain_link_text(lk)}]-> {lk.to_state} {fmt(lk.energy_to)}"
                         for lk in ch.links)
        lines.append(f"chain        {ch.states[0]} {fmt(ch.energies[0])} {steps}"
                     + ("" if ch.converged else " (not converged)"))
        lines.append("             (minima and energies; [saddle] between them, [<= the highest "
                     "energy along a path], or [~ a path's highest image] where neither was "
                     "found)")
        if ch.lowest is not None and not ch.lowest["energy"] >= ch.energy_saddle:  # NaN: none
            lines.append(f"lowest       over every saddle found: {fmt(ch.lowest['energy'])} via "
                         f"{' -> '.join(ch.lowest['states'])}")
    for o in b.other_saddles:  # saddles of the string that join other states
        tips = ", ".join(f"{lab} {fmt(e)}{'' if ok else ' (not converged)'}" for lab, e, ok
                         in zip(o["descent_ends"], o["end_energies"], o["ends_converged"],
                                strict=True))
        lines.append(f"other saddle index 1, energy {fmt(o['energy'])}, descents end on {tips}")
    if plot is not None:
        from ..plot.plots import plot_barrier_path

        # a design with units: the energies in J (the units block's), else in B3/L
        energies, axis = ((b.energies, "energy (B3 / L)") if units is None else
                          (payload["units"]["energies"]["value"], "energy [J]"))
        payload["plot"] = str(plot_barrier_path(
            b.path_arclength, energies, b.saddle_position, plot,
            labels=(b.from_state, b.to_state), energy_label=axis,
            title=f"{name}, {where_k(design_file)} = {fmt(k)}, {elements} el./rod, {method}"))
        lines.append(f"wrote {payload['plot']}")
    if path:
        judged = judge_path(payload, a, elements, mu, order, model, wide, h, c is not None,
                            path)
        if wide is not None and cusp_width is not None:
            payload["contact"]["cusp_width"] = {"h": cusp_width, "length": wide}
            lines.append(f"cusp welds   {fmt(cusp_width)} h wide ({fmt(wide)}): every pair "
                         "the contact model sees is judged, the cusps' two ends included")
        if c is not None:
            stages = run.contact_stages
            payload["contact"].update(dhat=c, soft_stages=stages.to_dict())
            lines.append(f"contact      acting: capsules h/L = {fmt(h)}, dhat/h = {fmt(c)}; "
                         f"{len(stages.stiffnesses)} soft stages took the path's closest "
                         f"rods from {fmt(stages.distances[0] / h)} h to "
                         f"{fmt(stages.distances[-1] / h)} h apart "
                         "(rodstab.multistable.string_contact)")
        lines += judged_lines(payload, judged, a, elements, h, c is not None, path,
                              (b.from_state, b.to_state), order, model, b.energies, out)
    if gif is not None:
        from ..plot.animations import barrier_animation

        payload["animation"] = str(barrier_animation(b, path, a, gif, name=name))
        lines.append(f"wrote {payload['animation']}")
    held = True
    if into_contact and b.converged and b.chain is None:
        from .barrier_contact import into_contact_lines

        more, held = into_contact_lines(a, elements, mu, path[b.saddle_position],
                                        {from_state: a, to_state: b_asm}, h, into_dhat, payload,
                                        units)
        lines += more
    elif into_contact:
        lines.append("into contact no saddle joining the two states to continue")
    emit(payload, as_json, lines)
    if not held:
        raise NotConverged("--into-contact: no branch reached a saddle with contact")
    if not b.converged:
        why = ""
        if run is not None and run.too_coarse:
            why = (f": neighbouring images are {fmt(run.largest_gap)} rad apart, more "
                   "--images are needed")
        elif run is not None and getattr(run.contact_stages, "start_crossing", None) is not None:
            k = run.contact_stages.start_crossing
            why = (f": the path the soft stages reached passes rods through each other between "
                   f"its images {k} and {k + 1} (on opposite sides of a rod), which no image "
                   "shows, so the string cannot relax it inside the contact model")
        elif run is not None and run.refused_reparametrisations:
            why = (f": {run.refused_reparametrisations} of the string's reparametrisations "
                   "were refused because the path between neighbouring images passes rods "
                   "through each other, so its images bunched and stalled; more --images "
                   "may join them inside the contact model")
        raise NotConverged(f"the barrier {b.from_state} -> {b.to_state} did not converge"
                           f"{why} (residual {b.residual:.3g}, saddle index "
                           f"{b.saddle_index}, descents end on "
                           f"{', '.join(b.descent_ends) or 'not run'})")
