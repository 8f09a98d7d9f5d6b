"""The commands that search a ring's equilibria: discover and transitions.

Parsing and printing only.
"""

from __future__ import annotations

import json
import warnings
from typing import Any

import click

from ..errors import (
    NotConverged,
    RodstabInputError,
)
from ..io.outputs import check_output
from ..limits import Limits, require_steps
from ..results import jsonable
from ..sections import Section
from .contact_options import (
    check_cusp_width,
    contact_options,
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
    structure_option,
)
from .output import (
    emit,
    fmt,
    image_output,
    section_label,
    section_line,
    units_line,
    warnings_as_lines,
    weld_line,
)
from .saddles import saddle_options


@click.command()
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@structure_option("hexagram", "six-ring",
                  help="Without DESIGN: hexagram: six rods of length L, load kappa_n R0 (R0 = "
                       "3L/2pi); six-ring: the ring of Section 5 (unfolded_ring: --segments "
                       "arcs of radius 1 welded at cusps), load kappa_n R0.")
@click.option("--segments", type=int, default=6, show_default=True,
              help="Rods of the six-ring (even, >= 4).")
@click.option("--state", default=None,
              help="Held state the search starts from (a label of `rodstab states`; default "
                   "star).")
@load_factor_option(default=2.0, help="Without DESIGN kappa_n R0; with DESIGN the multiplier "
                    "of its natural curvature.")
@click.option("--starts", type=int, default=8, show_default=True, help="Perturbed starts "
              "(in +/- pairs) besides the seeds.")
@elements_option(default=16, minimum=2, help="Elements per rod.")
@click.option("--seed", "rng_seed", type=int, default=0, show_default=True,
              help="Seed of the random perturbations.")
@click.option("--seed-states/--no-seed-states", default=True, show_default=True,
              help="Also start from the held geometry of every other closed state of the ring "
                   "(rodstab states, |kL| <= 2 pi).")
@click.option("--plot", "plot_path", type=click.Path(dir_okay=False), default=None,
              help="Write a grid of the states found (projected on their best-fit planes).")
@click.option("--morph", default=None, metavar="segment.NAME.length=VALUE[:STEPS]",
              help="First carry every seed to rod NAME of length VALUE in STEPS steps "
                   "(default 10): a ring no design can hold (one rod longer).")
@saddle_options
@contact_options
@cusp_width_option
@section_options
@limit_options
@json_option
def discover(design_file: str | None, section: Section, structure: str, segments: int,
             state: str | None, load_factor: float, starts: int, elements: int, rng_seed: int,
             seed_states: bool, plot_path: str | None, morph: str | None, saddle_modes: int,
             graph_path: str | None, max_barrier: float | None, climb_steps: int | None,
             strings: int | None, workers: int, contact: Any, cusp_width: float | None,
             limits: Limits, as_json: bool) -> None:
    """Equilibria nobody named: deflated Newton from seeds and perturbed starts.

    On DESIGN (a ring, seeded with its held states of `rodstab states DESIGN`; any other
    design, seeded with its held state) or a built-in structure. With --contact the rods are
    capsules that cannot pass through each other (every step filtered); seeds and starts
    outside the contact model (rods stacked on one curve) are not run and are listed.
    """
    from ..limits import require_nonlinear
    from ..multistable.discover import RUNS_PER_START, search_start, shape_2d
    from ..multistable.discover import discover as search

    plot = None if plot_path is None else image_output("--plot", plot_path)
    graph = None if graph_path is None else image_output("--graph", graph_path)
    mu, n_el = load_factor, elements
    if isinstance(starts, bool) or starts < 0:
        raise RodstabInputError(f"--starts must be an integer >= 0, got {starts!r}")
    from ..multistable.saddle_search import CLIMB_MAX_ITER
    from .saddles import check_saddle_options

    ring, section, name, design = ring_and_section(design_file, structure, segments, section,
                                                   contact_ok=True, any_design=True)
    setting = contact.resolve(None if design is None else design.contact)
    strings = check_saddle_options(saddle_modes, climb_steps, max_barrier, graph_path, strings,
                                   setting is not None)
    n = len(design.assembly.segments) if ring is None else ring.segments
    require_nonlinear([n_el] * n, n, f"--elements {n_el}", limits)
    require_steps((starts + 4 * n) * RUNS_PER_START, f"--starts {starts}",
                  "deflated Newton runs", limits)
    for opt, v in (("state", state), ("cusp-width", cusp_width)):
        if ring is None and v is not None:  # not a ring: its held state is the one seed
            raise RodstabInputError(f"--{opt} {v!r} is a ring's; {design_file} is not a ring "
                                    "(its held state is the seed)")
    start_state = ("held" if ring is None else "star") if state is None else state
    wide = None
    if cusp_width is not None and ring is not None:
        if setting is None:
            raise RodstabInputError(f"--cusp-width {cusp_width!r} is a setting of contact, "
                                    "which is off for this run (--contact)")
        wide = check_cusp_width(cusp_width, ring.held(ring.state(start_state).theta),
                                setting[0], start_state)
    rod, seeds, known, directions = search_start(
        ring, None if design is None else design.assembly, start_state, n_el, mu, seed_states,
        wide)
    if setting is not None:
        from ..nonlinear.contact import attach_contact
        from ..nonlinear.equilibrium import rod_contact_model

        try:
            attach_contact(rod, rod_contact_model(rod.assembly, *setting))
        except RodstabInputError as exc:
            raise RodstabInputError(f"--state {start_state!r}: {exc}") from None
    if morph is not None:  # carried to a ring no design holds (multistable.morph)
        from ..multistable.morph import morph_seeds
        seeds, morphed = morph_seeds(morph, rod, seeds)
    found, snaps = search(rod, seeds, known, starts=starts, seed=rng_seed,
                          directions=directions)
    payload = found.to_dict() | {"structure": name, "segments": n, "start_state": start_state,
                                 "section": section.to_dict()}
    payload["contact"] = {"acting": setting is not None,
                          "thickness": None if setting is None else setting[0],
                          "dhat": None if setting is None else setting[1]}
    if cusp_width is not None:
        payload["contact"]["cusp_width"] = cusp_width
    units = None if design is None else design.units
    if design is not None and units is not None:
        payload["units"] = units.block(
            natural_curvature={"value": units.natural_curvature(design.assembly, mu),
                               "unit": "1/m"},
            energy=([s.energy for s in found.states], "energy"))
    if plot is not None:
        from ..plot.plots import plot_ring_states

        titles = [f"{s.label}: E {s.energy:.4g}, index {s.index}"
                  + ("" if s.invariants.planar else ", 3D") for s in found.states]
        payload["plot"] = str(plot_ring_states([shape_2d(rod, s) for s in snaps], titles, plot))
    load = "kappa_n R0" if design_file is None else "load factor"
    lines = [section_line(section),
             f"{name}, {n} rods, {n_el} elements each, {load} = {fmt(mu)}: "
             f"{len(found.states)} distinct equilibria from {found.runs} deflated Newton runs "
             f"({found.converged_runs} converged); seeds {', '.join(found.seeds)}",
             f"{'label':>14} {'energy':>10} {'index':>5} {'stable':>6} {'welds':>5} "
             f"{'turning':>8} {'max|z|/L':>9}  found from"]
    lines[2:2] = [morphed] if morph is not None else []
    lines[2:2] = [f"seeds        not converged from: {', '.join(found.unconverged_seeds)} "
                  "(a state found before, which deflation repels, or too coarse a mesh for "
                  "their shape: try more --elements)"] if found.unconverged_seeds else []
    joules = None  # the states' energies in J, from the units block
    if units is not None:
        u = payload["units"]
        lines[2:2] = [units_line(units), f"physical     load factor {fmt(mu)}: natural curvature "
                      f"{fmt(u['natural_curvature']['value'])} 1/m of segment "
                      f"{units.segment!r}; energies in J = model energy x B3/L"]
        joules = u["energy"]["value"]
    lines += [f"{s.label:>14} {s.energy:>10.6g} {s.index:>5} {str(s.stable):>6} "
              f"{s.invariants.distinct_weld_points:>5} {s.invariants.turning_number:>8.4g} "
              f"{s.invariants.max_out_of_plane:>9.3g}  {s.found_from}"
              + (f"; a family ({s.zero_modes} zero mode(s) beyond the rigid motions, "
                 f"{s.members} members found)" if s.zero_modes else "")
              + ("" if joules is None else f"  ({fmt(joules[i])} J)")
              for i, s in enumerate(found.states)]
    if setting is not None:
        lines.insert(2, f"contact      acting: capsules h/L = {fmt(setting[0])}, dhat/h = "
                        f"{fmt(setting[1])}"
                        + ("" if cusp_width is None else
                           f", cusp welds {fmt(cusp_width)} h wide")
                        + "; starts outside the model, not run: "
                        f"{', '.join(found.outside_contact) or 'none'}")
    if saddle_modes or strings:
        from .saddles import saddle_lines

        lines += saddle_lines(rod, found, snaps, saddle_modes, directions, payload,
                               CLIMB_MAX_ITER if climb_steps is None else climb_steps, graph,
                               load, max_barrier, strings, workers)
    lines += [f"wrote {payload['plot']}"] if plot is not None else []
    emit(payload, as_json, lines)


@click.command()
@click.argument("design_file", required=False, type=click.Path(dir_okay=False))
@structure_option("hexagram", help="Without DESIGN: the structure whose states are loaded.")
@load_factor_option(
    default=None,
    help="Load factor at which every state loaded must be stable [default: twice the "
         "star's stress-free load: kappa_n R0 = 2 for the hexagram].")
@elements_option(default=8, minimum=2, help="Elements per rod of the discrete rod.")
@path_contact_options("Without --contact the paths are only judged against it.")
@click.option("--stimulus", "stimuli", multiple=True, metavar="STATE=KEY:STOP",
              help="Load STATE in KEY from 0 (load_factor: from --load-factor) to STOP; "
                   "repeatable, replaces that state's defaults. KEY: load_factor, "
                   "welds.<i>,<j>.rotation.<normal|tangent|binormal> (radians), "
                   "weld.<i>.moment.<normal|tangent|binormal> (B3/L), "
                   "weld.<i>.force.<normal|tangent|binormal> (B3/L^2, dead load), weld indices "
                   "0-5.")
@click.option("--state", "states_", multiple=True, metavar="STATE",
              help="Load only these states (repeatable; labels of `rodstab states`; default: "
                   "the line, star, daisy and eight the ring has).")
@layers_option("Offsets NAME=U:K (in-plane U, layer K) and NAME=U:K:S (also shifted S along "
               "the rod, to stagger welds) also accepted. The one --state "
               "loaded is stacked in this order, its welds spanning the layers, and loaded "
               "in load_factor (needs --contact).")
@cusp_width_option
@click.option("--all", "all_stimuli", is_flag=True,
              help="Try every stimulus of each state, not only up to the first transition.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False), default=None,
              help="Directory for transitions.json, transitions.png (the graph) and a path "
                   "file per edge, path_K_FROM_TO.npz (its sampled states: loading, the "
                   "snap (without --contact its interpolated proxy), release; "
                   "rodstab.io.path_file).")
@section_options
@limit_options
@json_option
def transitions(design_file: str | None, section: Section, structure: str,
                load_factor: float | None, elements: int,
                contact: Any, stimuli: tuple[str, ...], states_: tuple[str, ...],
                layers: str | None, cusp_width: float | None, all_stimuli: bool,
                out_dir: str | None, limits: Limits, as_json: bool) -> None:
    """Transitions between states under a stimulus: the transition graph.

    Each state is loaded until it first loses stability, relaxed past it, unloaded and
    identified. Each edge reports the closest approach of rods over h and whether rods would
    pass through each other (physical: false). With --contact the rods are capsules of
    diameter h that cannot pass through each other throughout; a state whose rods overlap
    (stacked on one curve: the line, the eight) is skipped. On DESIGN's ring (rods welded in
    a cycle, `rodstab states DESIGN`) or the hexagram.
    """
    from ..problems import ring_transitions as rt

    ring, section, name, design = ring_and_section(design_file, structure, 6, section,
                                                   contact_ok=True)
    thickness, dhat = contact.judged(None if design is None else design.contact)
    if load_factor is None:
        load_factor = rt.default_load_factor(ring)
        if load_factor is None:
            raise RodstabInputError(f"{name}: the ring has no star to set the default load "
                                    "factor; give --load-factor")
    labels = tuple(st.label for st in ring.states().states)
    for state in states_:
        if state not in labels:
            raise RodstabInputError(f"--state {state!r} is not one of {labels}")
    chosen: dict[str, list[tuple[str, float]]] = {}
    for text in stimuli:
        state, key, stop = rt.parse_stimulus(text, labels)
        chosen.setdefault(state, []).append((key, stop))
    stim = rt.default_stimuli(ring) | {s: tuple(v) for s, v in chosen.items()}
    order = None
    if layers is not None:
        if dhat is None:
            raise RodstabInputError(f"--layers {layers!r} is a setting of contact, which is off "
                                    "for this run (--contact)")
        if len(states_) != 1:
            raise RodstabInputError(f"--layers {layers!r} stacks one state: name it with one "
                                    f"--state (got {list(states_)})")
        held = ring.held(ring.state(states_[0]).theta)
        parsed = parse_layers(layers, [seg.name for seg in held.segments])
        if not isinstance(parsed, dict):
            raise RodstabInputError(f"--layers {layers!r}: transitions take NAME=K, NAME=U:K or "
                                    "NAME=U:K:S for every segment, not a named stacking")
        order = {states_[0]: parsed}
        if states_[0] not in chosen:  # its default stimuli in the load factor (the others
            # hold welds of the planar model's topology)
            stim[states_[0]] = tuple(p for p in stim.get(states_[0], ()) if p[0] == "load_factor")
        for key, stop in stim.get(states_[0], ()):
            if key != "load_factor":
                raise RodstabInputError(f"--stimulus {states_[0]}={key}:{stop:g}: a state "
                                        "stacked with --layers is loaded in load_factor only")
    if cusp_width is not None:
        if order is not None:
            raise RodstabInputError(f"--cusp-width {cusp_width!r} is not an option of "
                                    "--layers (the stacked model's welds span its layers)")
        first = states_[0] if states_ else "star" if "star" in labels else labels[0]
        check_cusp_width(cusp_width, ring.held(ring.state(first).theta), thickness, first)
    out = None if out_dir is None else check_output("--out", out_dir, directory=True)
    with warnings_as_lines(), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = rt.transitions(ring, load_factor=load_factor, elements=elements,
                             thickness=thickness, stimuli=stim, all_stimuli=all_stimuli,
                             load=tuple(states_) or None, limits=limits, dhat_fraction=dhat,
                             layers=order, cusp_width=cusp_width)
    payload = res.graph.to_json()
    payload["contact"] = {"acting": dhat is not None, "thickness": thickness, "dhat": dhat,
                          "cusp_width": cusp_width}
    payload["structure"] = name
    payload["section"] = section.to_dict()
    units = None if design is None else design.units
    physical: dict[tuple[str, str, str], str] = {}
    if design is not None and units is not None:
        thresholds = rt.threshold_units(units, design.assembly, payload["edges"])
        for q in thresholds:
            what = "" if q["quantity"] == "value" else "natural curvature "
            physical[(q["from"], q["to"], q["stimulus"])] = \
                f" ({what}{fmt(q['value'])} {q['unit']})"
        payload["units"] = units.block(
            natural_curvature={"value": units.natural_curvature(design.assembly, load_factor),
                               "unit": "1/m"},
            contact_thickness=(thickness * ring.length, "length"), thresholds=thresholds)
    load_name = "kappa_n R0" if design_file is None else "load factor"
    load_si = ("" if "units" not in payload else
               f" ({payload['units']['natural_curvature']['value']:.4g} 1/m)")
    if out is not None:
        from ..io.path_file import write_path_file
        from ..plot.transition_graph import plot_transition_graph

        moved = [e for e in res.graph.edges if e.target is not None]
        for k, (e, entry) in enumerate(zip(moved, payload["edges"], strict=True)):
            if e.path is not None:
                entry["path_file"] = str(write_path_file(
                    out / f"path_{k}_{_file_word(e.source)}_{_file_word(str(e.target))}.npz",
                    e.path.x, e.path.edges, e.path.rest_length, thickness=res.graph.thickness))
                entry["path_stretches"] = [list(p) for p in e.path.stretches]
        (out / "transitions.json").write_text(json.dumps(jsonable(payload), allow_nan=False))
        payload["figure"] = str(plot_transition_graph(
            payload, res.shapes, out / "transitions.png",
            title=f"{name}, {section_label(section)}, "
                  f"{load_name} = {load_factor:g}{load_si}, {elements} elements per rod, h/L = "
                  f"{thickness:g}" + ("" if dhat is None else ", contact acting")
                  + ("" if order is None else f", {states_[0]} stacked (--layers)")))
        payload["json_file"] = str(out / "transitions.json")
    lines = [section_line(section),
             f"{name} at {load_name} = {fmt(load_factor)}, {elements} elements per rod, "
             f"contact thickness h/L = {fmt(thickness)}"
             + ("" if dhat is None else f", acting (capsules, dhat/h = {fmt(dhat)})")
             + ("" if cusp_width is None else f"; cusp welds {fmt(cusp_width)} h wide")]
    if units is not None:
        u = payload["units"]
        lines += [units_line(units), f"physical     load factor {fmt(load_factor)}: natural "
                  f"curvature {fmt(u['natural_curvature']['value'])} 1/m of segment "
                  f"{units.segment!r}; contact thickness "
                  f"{units.length_text(u['contact_thickness']['value'])}"]
    for e in payload["edges"]:
        lines.append(f"{e['from']:>6} -> {e['to']:<8} {e['stimulus']} = {fmt(e['threshold'])}"
                     f"{physical.get((e['from'], e['to'], e['stimulus']), '')} ({e['kind']}"
                     f"{', AT A C1 CONTACT EVENT' if e.get('at_contact_event') else ''}"
                     + (f", DOUBLE MODE: reaches {' or '.join(e['reachable'])}"
                        if e.get("double_mode") else "") + "); "
                     + ("no pass-through" if e["physical"] else "RODS PASS THROUGH: not "
                        "physical as computed"))
    lines += [f"{e['from']:>6}    none     {e['stimulus']} up to {fmt(e['stop'])}: "
              f"{e['message']}" for e in payload["no_transition"]]
    lines += [f"{s['state']:>6}    skipped: {s['why']}" for s in payload["skipped"]]
    welds = next((e.welds for e in res.graph.edges if e.welds is not None), None)
    if welds is not None:
        payload["contact"]["welds"] = welds.to_dict()
        lines.append(weld_line(welds))
    if out is not None:
        n_paths = sum("path_file" in e for e in payload["edges"])
        lines += [f"wrote {payload['figure']}, {payload['json_file']} and {n_paths} path "
                  f"files (path_K_FROM_TO.npz) in {out}"]
    emit(payload, as_json, lines)
    unconverged = [f"{e['from']} -> {e['to']}" for e in payload["edges"] if not e["converged"]]
    if unconverged:
        raise NotConverged(f"a relaxation or the path of {', '.join(unconverged)} did not "
                           "converge (those edges are not to be trusted)")


def _file_word(label: str) -> str:
    """Return a state label as part of a file name: letters, digits, '-' and '_'."""
    import re

    return re.sub(r"[^A-Za-z0-9_-]+", "-", label).strip("-") or "state"

