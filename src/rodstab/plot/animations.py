"""Pictures of a sequence of states of a rod: a continuation's branch and a barrier's path.

* :func:`branch_animation`, :func:`branch_html` -- the first secondary branch of a
  continuation (``rodstab continue --out``: ``branch.gif``, ``branch.html``);
* :func:`barrier_animation` -- the states along a barrier's minimum energy path
  (``rodstab barrier --animation``).

Each takes a solver's result and draws it with :func:`.plots.animate_shapes` or
:func:`.plots.html_view`; the rod the states belong to is rebuilt here only for its layout
(edges, segments, sections) and its rates of twist. Only :data:`EDGE_COLOURS` is defined at
import: the command line's ``--colour`` option reads it, and matplotlib, scipy and the solvers
are imported by the functions that draw.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..model import Assembly
    from ..multistable.barrier import Barrier
    from ..multistable.discover import Snapshot
    from ..nonlinear.continuation.path import Path as Curve
    from .ribbons import RodLayout

#: What a rod's edges can be coloured by: key -> (colour bar label, signed). Signed values get
#: a diverging colour scale symmetric about 0 (opposite twists in opposite colours).
EDGE_COLOURS: dict[str, tuple[str, bool]] = {
    "moment": ("|internal moment|", False),
    "twist": ("twist rate (rad/length)", True),
}


def _first_branch(result: Curve, assembly: Assembly, elements_per_segment: int,
                  colour: str) -> tuple[Curve, RodLayout, list[Any]] | None:
    """Return the first branch, its rod's layout and its edge values per shape (None: no shapes)."""
    if colour not in EDGE_COLOURS:
        raise ValueError(f"colour must be one of {sorted(EDGE_COLOURS)}, got {colour!r}")
    if not (result.branches and result.branches[0].shapes):
        return None
    from ..nonlinear.discrete import discretise
    from .ribbons import RodLayout

    first = result.branches[0]
    rod = discretise(assembly, elements_per_segment)
    values = (list(first.shape_moments) if colour == "moment"
              else [rod.edge_twist(R) for R in first.frames])
    return first, RodLayout.from_rod(rod), values


def _branch_title(result: Curve, first: Curve, source: str) -> str:
    return f"{source}: branch from {result.key} = {first.value_critical:.6g}"


def branch_animation(result: Curve, assembly: Assembly, elements_per_segment: int,
                     path: str | Path, *, source: str, colour: str = "moment") -> Path | None:
    """Write a GIF of the first secondary branch of a continuation, one frame per traced shape.

    Parameters
    ----------
    result : rodstab.nonlinear.continuation.path.Path
        The primary path, with its branches (:func:`~rodstab.nonlinear.continuation.continuation`).
    assembly : Assembly
        The continued structure (its rods give the pictures' boxes).
    elements_per_segment : int
        The continuation's mesh: the rod the branch's shapes and frames belong to.
    path : str or Path
        The GIF file.
    source : str
        The design's name, in the title.
    colour : str
        A key of :data:`EDGE_COLOURS`: the branch's internal moments (``moment``) or the rates
        of twist of its frames (``twist``).

    Returns
    -------
    Path or None
        ``path``; None (nothing written) when no branch has shapes (none was traced, or the
        run was resumed: shapes are not saved).
    """
    found = _first_branch(result, assembly, elements_per_segment, colour)
    if found is None:
        return None
    from .plots import animate_shapes

    first, layout, values = found
    label, signed = EDGE_COLOURS[colour]
    return animate_shapes(list(first.shapes), list(first.frames), layout, path,
                          edge_values=values, value_label=label, diverging=signed,
                          labels=[f"{result.key} = {v:.6g}" for v in first.shape_values],
                          title=_branch_title(result, first, source))


def branch_html(result: Curve, assembly: Assembly, elements_per_segment: int,
                path: str | Path, *, source: str, colour: str = "moment") -> Path | None:
    """Write an interactive view (plotly HTML) of the first secondary branch, one step per shape.

    Parameters and return as :func:`branch_animation`; the slider's steps are labelled by the
    parameter's value. Raises :class:`~rodstab.errors.RodstabInputError` when plotly is not
    installed (:func:`.plots.html_view`).
    """
    found = _first_branch(result, assembly, elements_per_segment, colour)
    if found is None:
        return None
    from .plots import html_view

    first, layout, values = found
    label, signed = EDGE_COLOURS[colour]
    return Path(html_view(list(first.shapes), list(first.frames), layout, path,
                          labels=[f"{v:.6g}" for v in first.shape_values], edge_values=values,
                          value_label=label, diverging=signed,
                          title=_branch_title(result, first, source)))


def barrier_animation(barrier: Barrier, path: Sequence[Snapshot], assembly: Assembly,
                      out: str | Path, *, name: str) -> Path:
    """Write a GIF of the states along a barrier's minimum energy path, coloured by twist rate.

    Parameters
    ----------
    barrier : rodstab.multistable.barrier.Barrier
        The string method's barrier (:func:`~rodstab.multistable.string_method.string_barrier`):
        its load factor and mesh give the rod, its arclengths and energies the frames'
        captions.
    path : sequence of Snapshot
        The path's states, one per entry of ``barrier.energies``, from ``from_state`` through
        the saddle to ``to_state``.
    assembly : Assembly
        The ``from_state``'s held structure (the one the string started from): its rod, in
        the model common to both states (:func:`~rodstab.multistable.discover.common_rod`),
        gives the pictures' boxes and the rates of twist.
    out : str or Path
        The GIF file.
    name : str
        The structure's or design's name, in the title.

    Returns
    -------
    Path
        ``out``.
    """
    from ..multistable.discover import common_rod
    from .plots import animate_shapes
    from .ribbons import RodLayout

    rod = common_rod(assembly, barrier.elements_per_segment, barrier.load_factor)
    return animate_shapes(
        [snap.x for snap in path], [snap.R_edge for snap in path], RodLayout.from_rod(rod), out,
        edge_values=[rod.edge_twist(snap.R_edge) for snap in path],
        value_label="rate of twist (rad / length)", diverging=True,
        labels=[f"s = {s:.2f}, E = {e:.5g}"
                for s, e in zip(barrier.path_arclength, barrier.energies, strict=True)],
        title=f"{name}: {barrier.from_state} -> {barrier.to_state}, minimum energy path")
