"""What a reader sees in the figures of issue 20, tested through the drawn artists (no pixels).

Each test draws a figure under the object API from data shaped as its producer's, then reads
back what matplotlib placed: the hatched overlap's outline in data coordinates, the legend's
entries, the window extents of tick labels, offset texts and titles after a draw.
"""

from __future__ import annotations

import itertools
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from rodstab.multistable import atlas as A
from rodstab.plot.plots import plot_stable_bands
from rodstab.report import figures

GRID = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
#: A's interval (0, p) and B's (ROOT, 10): both stable together for p > ROOT, between grid values.
ROOT = 3.3


def _interval(label: str, lo: float, hi: float) -> A.StateInterval:
    return A.StateInterval(label=label, theta=0.0, stress_free_load=0.5 * (lo + hi),
                           lower=A.Limit(lo, 1, 0, A.ALL_ALIKE),
                           upper=A.Limit(hi, 1, 0, A.ALL_ALIKE), stable_at_stress_free=True,
                           residual=0.0, converged=True, method="transfer")


def _two_state_atlas() -> A.RingAtlas:
    """A RingAtlas of two states whose overlap p - ROOT begins between grid values 3 and 4;
    the range's start refined by the atlas's own root finder (coexistence_ranges)."""
    rows = tuple((_interval("A", 0.0, p), _interval("B", ROOT, 10.0)) for p in GRID)

    def width(p: float) -> float:
        return A.best_overlap({"A": (0.0, p), "B": (ROOT, 10.0)}, 2).width

    both = A.coexistence_ranges(width, GRID, [width(p) for p in GRID], 2)
    return A.RingAtlas(key="p", values=tuple(GRID), states=("A", "B"), intervals=rows,
                       mutual=tuple(A.mutual_sets({r.label: r.interval for r in row})
                                    for row in rows),
                       coexistence=(both,), load_factor=A.LOAD_FACTOR_UNITS, method="transfer")


def _hatches(fig) -> list[PolyCollection]:
    return [c for c in fig.axes[0].collections
            if isinstance(c, PolyCollection) and c.get_hatch() == "//"]


def test_atlas_bands_carry_the_refined_all_stable_range():
    """RingAtlas.bands(): the all-states range's ends, as solved (3.3 to the grid's end)."""
    data = _two_state_atlas().bands()
    assert data["all_stable.start"] == [pytest.approx(ROOT, abs=1e-9)]
    assert data["all_stable.end"] == [6.0]


@pytest.mark.parametrize("source", ["atlas data", "threshold only"])
def test_all_stable_hatch_begins_at_the_computed_root_not_the_next_grid_value(source):
    """The hatch's left edge is the computed start within 1e-9 (data coordinates), not 4.0,
    from the atlas's data (atlas and hexagram charts) or from the threshold alone (the
    report's hexagram figure given data without the range); its right edge is the grid's
    end, and it lies between the binding limits B.lower = 3.3 and A.upper = p."""
    data = _two_state_atlas().bands()
    threshold = None
    if source == "threshold only":
        threshold = data.pop("all_stable.start")[0]
        data.pop("all_stable.end")
    fig = plot_stable_bands(data, ("A", "B"), x_key="value", threshold=threshold)
    (hatch,) = _hatches(fig)
    xy = np.vstack([p.vertices for p in hatch.get_paths()])
    assert xy[:, 0].min() == pytest.approx(ROOT, abs=1e-9)
    assert xy[:, 0].max() == pytest.approx(6.0, abs=1e-12)
    assert np.all(xy[:, 1] >= ROOT - 1e-9) and np.all(xy[:, 1] <= np.maximum(xy[:, 0], ROOT)
                                                       + 1e-9)
    assert "all 2 stable" in [t.get_text() for t in fig.axes[0].get_legend().get_texts()]


def test_without_a_computed_range_the_hatch_covers_the_overlapping_grid_values():
    """No range and no threshold: the hatch is where the grid's bands overlap (4 to 6)."""
    data = {k: v for k, v in _two_state_atlas().bands().items() if not k.startswith("all")}
    (hatch,) = _hatches(plot_stable_bands(data, ("A", "B"), x_key="value"))
    xs = np.vstack([p.vertices for p in hatch.get_paths()])[:, 0]
    assert (xs.min(), xs.max()) == (4.0, 6.0)



def _agg(fig):
    """Draw ``fig`` on an Agg canvas and return its renderer (window extents in pixels)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    return fig.canvas.get_renderer()


def _drawn_tick_labels(axis):
    """The tick labels drawn on ``axis``: a text, and a location inside the view."""
    lo, hi = sorted(axis.get_view_interval())
    return [t.label1 for t in (*axis.get_major_ticks(), *axis.get_minor_ticks())
            if t.label1.get_visible() and t.label1.get_text() and lo <= t.get_loc() <= hi]


def _collisions(fig) -> list[tuple[str, str]]:
    """Pairs of tick labels of one axis whose window extents overlap (after a draw)."""
    renderer = _agg(fig)
    out = []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            boxes = [(t.get_text(), t.get_window_extent(renderer))
                     for t in _drawn_tick_labels(axis)]
            out += [(a, b) for (a, ba), (b, bb) in itertools.combinations(boxes, 2)
                    if ba.overlaps(bb)]
    return out


@pytest.fixture
def drawn(monkeypatch, tmp_path):
    """Call a report figure function; return the figure it wrote (and wrote it to tmp)."""
    figs = []
    save = figures._save

    def keep(fig, out, stem):
        figs.append(fig)
        return save(fig, out, stem)

    monkeypatch.setattr(figures, "_save", keep)

    def draw(fn, data):
        fn(data, tmp_path)
        return figs[-1]
    return draw


def _rings_data() -> dict:
    """As sec3_1.rings_data: 50 aspects log-spaced over [0.5, 8], bands of N = 1, 3, 5."""
    h = np.geomspace(0.5, 8.0, 50)
    return {"h_over_t": h.tolist(), "loops": [1, 3, 5], "overlap_threshold_exact": 1.2144,
            "intervals": {str(n): [[n - 1 - 0.3 * a, n + 0.2 * a] for a in h]
                          for n in (1, 3, 5)}}


def _beyond_data() -> dict:
    """As the beyond_* checks store it, with the report's ranges (imperfections 2.5e-4 to
    4e-3 L: a log axis spanning about a decade, where matplotlib labels the minor ticks)."""
    eps = [0.00025, 0.0005, 0.001, 0.002, 0.004]
    xi = np.linspace(-0.02, 0.02, 21)
    k = np.linspace(0.07, 2.2, 20)
    return {
        "branches": {name: {"amplitude": xi.tolist(), "mu_over_mu_c": (1 + b * xi**2).tolist()}
                     for name, b in (("rod", 1.0), ("bi-rod", 0.1), ("ring", 0.35))},
        "imperfection": {"mu_c": 5.56, "epsilon": [0.001, 0.004],
                         "paths": [[[5.56 * f, 0.3 * f * f] for f in np.linspace(0.2, 1.1, 9)]
                                   for _ in range(2)]},
        "imperfection_folded": {"mu_c": 4.71, "epsilon": eps,
                                "limit": [4.71 * (1 - 0.6 * e ** (2 / 3)) for e in eps]},
        "twisted": {"phi_c": 11.46, "epsilon": eps, "exponent": 0.6657,
                    "limit": [11.46 * (1 - 0.09 * e ** (2 / 3)) for e in eps]},
        "ring_path": {"mu": k.tolist(), "energy": (3 - (k - 2) ** 2).tolist()},
        "six_path": {"theta": 2 * np.pi / 3, "kappa_R0": k.tolist(),
                     "energy": (10 + 3 * k**2).tolist(), "bistable": [0.07, 2.25],
                     "barrier_at_1": 1.1},
    }


@pytest.mark.parametrize("name", ["fig_rings", "fig_beyond"])
@pytest.mark.slow
def test_report_figures_tick_labels_do_not_collide(drawn, name):
    """N-loop rings (log h/t over [0.5, 8]) and the imperfection panel (log eps over a
    decade): no two drawn tick labels of one axis overlap; no offset text is left above any
    panel (the post-buckled panel's '+1': its ticks are written in full)."""
    fig = drawn(getattr(figures, name), _rings_data() if name == "fig_rings" else
                _beyond_data())
    assert _collisions(fig) == []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            assert not axis.get_offset_text().get_text(), (ax.get_title(), axis)


@pytest.fixture
def made(monkeypatch):
    """Every Figure the report's figure module creates (to read back what it drew)."""
    figs: list[Figure] = []

    class Kept(Figure):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            figs.append(self)

    monkeypatch.setattr(figures, "Figure", Kept)
    return figs


def _supercritical_path(eigen_scale: float = 1e-6) -> SimpleNamespace:
    """A continuation result shaped as rodstab.nonlinear.continuation.Path: the bi-rod's
    primary path (lowest eigenvalue ~1e-6 crossing 0 at 2.8388) and its supercritical branch
    p/p_c = 1 + b xi^2, b = 0.132, over |xi| <= 0.02 (a parameter change of 1.5e-4)."""
    value = np.linspace(1.0, 4.0, 13)
    xi = np.array([-0.0203, -0.0119, -0.0062, -0.0025, 0.0, 0.0025, 0.0062, 0.0119, 0.0203])
    pc, b = 2.8388106, 0.132
    branch = SimpleNamespace(value=tuple(pc * (1 + b * xi**2)), amplitude=tuple(xi),
                             value_critical=pc, coefficients=(0.0, b),
                             verdict="stable symmetric (supercritical): the branch lies where "
                                     "the primary is unstable")
    return SimpleNamespace(key="load_factor", value=tuple(value),
                           lowest_eigenvalue=tuple(eigen_scale * (pc - value)),
                           amplitude=tuple(np.zeros_like(value)), branches=(branch,),
                           special_points=({"value": pc},))


def test_continuation_diagram_draws_the_branch_against_its_amplitude(made, tmp_path):
    """A supercritical branch changes the parameter by b p_c xi^2 = 1.5e-4: against the
    parameter it is a vertical line, so a panel draws the parameter's change against xi:
    the line's x data is the branch's amplitude in order, its y data value - value_c."""
    r = _supercritical_path()
    assert figures.continuation_plot(r, tmp_path).stat().st_size > 0
    (fig,) = made
    b = r.branches[0]
    lines = [ln for ax in fig.axes for ln in ax.get_lines()
             if np.array_equal(ln.get_xdata(), np.sort(b.amplitude))]
    assert len(lines) == 1
    np.testing.assert_allclose(lines[0].get_ydata(), np.array(b.value) - b.value_critical,
                               atol=1e-15)
    assert np.ptp(lines[0].get_ydata()) > 1e-4  # not a line along the parameter axis


@pytest.mark.slow
def test_continuation_diagram_has_no_offset_text_on_a_title_and_no_colliding_labels(
        made, tmp_path):
    """Eigenvalues of ~1e-6: the multiplier is in the axis label ('(x1e-6)'), no offset text
    is drawn above a panel, no title overlaps a tick label, axis label or offset text of its
    panel, and no two tick labels of an axis overlap."""
    figures.continuation_plot(_supercritical_path(1e-6), tmp_path)
    (fig,) = made
    renderer = _agg(fig)
    eigen = next(ax for ax in fig.axes if "eigenvalue" in ax.get_ylabel())
    assert eigen.get_ylabel().endswith("(x1e-6)")
    for ax in fig.axes:
        title = ax.title.get_window_extent(renderer)
        others = [t for axis in (ax.xaxis, ax.yaxis)
                  for t in (*_drawn_tick_labels(axis), axis.label, axis.get_offset_text())
                  if t.get_visible() and t.get_text()]
        assert not [t.get_text() for t in others if t.get_window_extent(renderer)
                    .overlaps(title)], ax.get_title()
        for axis in (ax.xaxis, ax.yaxis):
            assert not axis.get_offset_text().get_text(), ax.get_title()
    assert _collisions(fig) == []


def _graph() -> tuple[dict, dict]:
    """Four states on the circle (line at the top), transitions with and without a
    pass-through, and self-loops: two on the top state, one on a side state."""
    def edge(a, b, stimulus, threshold, physical):
        return {"from": a, "to": b, "stimulus": stimulus, "threshold": threshold,
                "physical": physical}

    edges = [edge("line", "star", "load_factor", 2.2533, True),
             edge("eight", "daisy", "load_factor", 1.875, False),
             edge("line", "line", "welds.0,3.rotation.normal", 1.2346, True),
             edge("line", "line", "weld.0.moment.binormal", -0.5, False),
             edge("eight", "eight", "weld.2.force.tangent", 12.5, True)]
    t = np.linspace(0.0, 2 * np.pi, 13)[:-1]
    ring = np.column_stack([np.cos(t), np.sin(t), np.zeros_like(t)])
    return ({"states": ["line", "star", "daisy", "eight"], "edges": edges},
            {s: ring for s in ("line", "star", "daisy", "eight")})


@pytest.fixture
def graph_figure(monkeypatch, tmp_path):
    """The transition graph of :func:`_graph`, drawn to a file; its Figure, read back."""
    from rodstab.plot import transition_graph as tg

    figs: list[Figure] = []

    class Kept(Figure):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            figs.append(self)

    monkeypatch.setattr(tg, "Figure", Kept)
    graph, shapes = _graph()
    assert tg.plot_transition_graph(graph, shapes, tmp_path / "g.png",
                                    title="a title").stat().st_size > 0
    return figs[0]


def _style(artist) -> tuple[tuple[float, ...], str]:
    from matplotlib.colors import to_rgba

    colour = artist.get_color() if hasattr(artist, "get_color") else artist.get_edgecolor()
    return tuple(np.round(to_rgba(colour), 6)), artist.get_linestyle()


def _grey():
    """A line in the states' colour (their drawn shapes are not edges)."""
    from matplotlib.lines import Line2D

    return Line2D([], [], color="0.2")


def test_transition_graph_legend_names_every_edge_style(graph_figure):
    """Every drawn edge style (arrows and loops: colour and line style) has a legend entry,
    and the legend has one entry per style: solid green and dashed red."""
    (ax,) = graph_figure.axes
    arrows = [t.arrow_patch for t in ax.texts if getattr(t, "arrow_patch", None) is not None]
    loops = [ln for ln in ax.get_lines() if _style(ln)[0] != _style(_grey())[0]]
    drawn = {_style(a) for a in (*arrows, *loops)}
    (legend,) = graph_figure.legends
    entries = {_style(h) for h in legend.legend_handles}
    assert len(drawn) == 2 and drawn == entries
    assert len(legend.get_texts()) == 2 and "pass through" in legend.get_texts()[1].get_text()


def test_transition_graph_keeps_every_label_inside_the_figure(graph_figure):
    """Every label (states, edges, the self-loops' stacked labels) lies inside the figure
    after a draw, no two labels overlap, and none overlaps the title or the legend."""
    renderer = _agg(graph_figure)
    (ax,) = graph_figure.axes
    fig_box = graph_figure.bbox
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in ax.texts if t.get_text()]
    assert len(boxes) == 4 + 5
    for text, box in boxes:
        assert (fig_box.x0 <= box.x0 and box.x1 <= fig_box.x1 and fig_box.y0 <= box.y0
                and box.y1 <= fig_box.y1), text
    assert [(a, b) for (a, ba), (b, bb) in itertools.combinations(boxes, 2)
            if ba.overlaps(bb)] == []
    (legend,) = graph_figure.legends
    (title,) = [t for t in graph_figure.texts if t.get_text() == "a title"]
    for other in (title, legend):
        box = other.get_window_extent(renderer)
        assert [t for t, b in boxes if b.overlaps(box)] == []
