"""Result objects: JSON and notebook display."""

from __future__ import annotations

import dataclasses
import math

import pytest


def test_results_display_as_html_tables_in_notebooks():
    """Every result has _repr_html_: one row per field, values escaped, long sequences cut."""
    from rodstab.analytic.ring import ring_stability
    from rodstab.multistable.states import closed_states

    r = ring_stability(1.0, 0.75, 3)
    h = r._repr_html_()
    assert h.startswith("<table><caption>RingStability</caption>")
    for f in dataclasses.fields(r):
        assert f"<th style='text-align:left'>{f.name}</th>" in h
    states = closed_states(6)
    h = states._repr_html_()
    assert h.count("<caption>HeldState</caption>") == 8  # the first 8 of 11 states ...
    assert "(11 items)" in h  # ... and how many there are
    assert "&#x27;cusp&#x27;" in h  # strings escaped


def test_plots_return_a_figure_without_a_path(tmp_path):
    """Without a path a plot returns its matplotlib Figure (notebooks show it); with one it
    writes the file and returns its path."""
    from matplotlib.figure import Figure

    from rodstab.multistable.states import state_centrelines, uniform_ring
    from rodstab.plot.plots import plot_ring_states

    ring = uniform_ring(6)
    shapes = [state_centrelines(ring, t) for t in (0.0, 2 * math.pi / 3)]
    fig = plot_ring_states(shapes, ["line", "star"])
    assert isinstance(fig, Figure) and len(fig.axes) == 2
    out = plot_ring_states(shapes, ["line", "star"], tmp_path / "s.png")
    assert out == tmp_path / "s.png" and out.stat().st_size > 0


def test_the_interactive_view_returns_its_plotly_figure_without_a_path():
    """html_view without a path gives the plotly Figure (inline in a notebook): one frame per
    state, the same traces as the written page."""
    go = pytest.importorskip("plotly.graph_objects")
    from rodstab.multistable.states import ring_assembly
    from rodstab.nonlinear.discrete import discretise
    from rodstab.plot.plots import html_view
    from rodstab.plot.ribbons import RodLayout

    rod = discretise(ring_assembly(6, 2 * math.pi / 3), 4, 1.0)
    fig = html_view([rod.x, rod.x], [rod.R_edge, rod.R_edge], RodLayout.from_rod(rod),
                    labels=["a", "b"])
    assert isinstance(fig, go.Figure)
    assert len(fig.frames) == 2 and len(fig.data) > 0
