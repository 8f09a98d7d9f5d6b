"""Figure code (``rodstab.plot.plots``, ``rodstab.plot.ribbons``, ``rodstab.report.figures``).

Importing or using it leaves the user's matplotlib backend and pyplot alone (figures are built
with the object API, :class:`matplotlib.figure.Figure`). The rods' pictures are tested through
their data: the ribbon's corners for known frames, the turn a twist gives them, the equal axes,
the segments' outline colours, the stacking of coinciding rods, and the number of frames the
GIF and the HTML view hold.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys

import numpy as np
import pytest

from rodstab.io.design import load_design
from rodstab.linear.solve import SegmentMode, linear_stability
from rodstab.model import held_frame
from rodstab.nonlinear.discrete import discretise
from rodstab.plot import ribbons
from rodstab.plot.plots import (
    GHOST_EDGE,
    animate_shapes,
    html_view,
    plot_equilibrium,
    plot_mode,
    segment_colours,
)
from rodstab.plot.ribbons import RodLayout
from rodstab.problems import birod
from rodstab.report.figures import sweep_plot
from rodstab.sections import circle

KEEPS_BACKEND = """
import sys
import matplotlib
matplotlib.use("svg")
import numpy as np
import rodstab.plot.plots, rodstab.report.figures
from rodstab.report.figures import sweep_plot
sweep_plot([{"k": 1.0, "load_factor_critical": 2.0, "load_factor_lower": -1.0}], "k", sys.argv[1])
print(matplotlib.get_backend(), "matplotlib.pyplot" in sys.modules)
"""


def test_importing_and_drawing_keeps_the_users_backend(tmp_path):
    """A fresh interpreter selects the svg backend, imports both figure modules and draws:
    the backend is still svg and pyplot was never imported."""
    r = subprocess.run([sys.executable, "-c", KEEPS_BACKEND, str(tmp_path)], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["svg", "False"]
    assert (tmp_path / "sweep.png").stat().st_size > 0


def _turn_about(axis: np.ndarray, phi: float) -> np.ndarray:
    """Rotation matrix by ``phi`` about the unit ``axis`` (Rodrigues, written out here)."""
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(phi) * K + (1 - math.cos(phi)) * K @ K


def _straight(n: int = 4, tangent=(1.0, 0.0)):
    """Nodes along an in-plane tangent, its edges, and the held frames (d3 = e3)."""
    t = np.array(tangent) / np.linalg.norm(tangent)
    x = np.zeros((n + 1, 3))
    x[:, :2] = np.outer(np.linspace(0.0, 1.0, n + 1), t)
    edges = np.stack([np.arange(n), np.arange(1, n + 1)], axis=1)
    return x, edges, np.repeat(held_frame(t)[None], n, axis=0)


def test_ribbon_corners_are_the_nodes_moved_half_the_width_along_d_h():
    """For the held frame of a chord along (3, 4)/5, d_h = d3 = e3: the corners are
    x_i -/+ w/2 e3 and x_j -/+ w/2 e3, in the documented order."""
    x, edges, R = _straight(3, (3.0, 4.0))
    q = ribbons.ribbon_quads(x, edges, R[:, :, 2], 0.2)
    up = np.array([0.0, 0.0, 0.1])
    for e, (i, j) in enumerate(edges):
        np.testing.assert_allclose(q[e], [x[i] - up, x[j] - up, x[j] + up, x[i] + up],
                                   atol=1e-15)


def test_box_faces_are_the_ribbon_moved_by_half_the_thickness():
    """The +d1/-d1 faces are the ribbon (h wide along d3) moved by +-t/2 d1 (d1 = t x e3 =
    (0, -1, 0) for a chord along x); the +d3 face is t wide along d1, moved up by h/2."""
    x, edges, R = _straight(2)
    h, t = np.full(2, 0.4), np.full(2, 0.1)
    f = ribbons.box_faces(x, edges, R, h, t)
    ribbon = ribbons.ribbon_quads(x, edges, R[:, :, 2], h)
    np.testing.assert_allclose(f[:, 0], ribbon + [0.0, -0.05, 0.0], atol=1e-15)
    np.testing.assert_allclose(f[:, 1], ribbon - [0.0, -0.05, 0.0], atol=1e-15)
    np.testing.assert_allclose(f[0, 2], [[0, 0.05, 0.2], [0.5, 0.05, 0.2], [0.5, -0.05, 0.2],
                                         [0, -0.05, 0.2]], atol=1e-15)
    np.testing.assert_allclose(ribbons.face_normals(R)[0], [[0, -1, 0], [0, 1, 0], [0, 0, 1],
                                                            [0, 0, -1]], atol=1e-15)


def test_a_twist_turns_the_ribbon_by_the_frames_rotation():
    """Frames turned about the tangent by phi_e put the ribbon's width along
    cos(phi) e3 + sin(phi) n (n = d1 of the held frame): the ribbon turns with the frame."""
    x, edges, R = _straight(4)
    phis = np.array([0.0, 0.3, -0.7, 1.2])
    along = np.array([1.0, 0.0, 0.0])
    Rt = np.array([_turn_about(along, p) @ r for p, r in zip(phis, R, strict=True)])
    q = ribbons.ribbon_quads(x, edges, Rt[:, :, 2], 1.0)
    across = q[:, 3] - q[:, 0]
    n = R[0, :, 0]
    want = np.cos(phis)[:, None] * [0.0, 0.0, 1.0] + np.sin(phis)[:, None] * n
    np.testing.assert_allclose(across, want, atol=1e-14)


def test_a_modes_twist_turns_its_drawn_sections_by_scale_times_omega():
    """A mode of pure twist omega = 0.5 on a straight segment, drawn at scale 2: each
    section's d3 is e3 turned by 1 rad about the tangent (right-handed), the centreline
    does not move, and the drawn turn is 1 rad."""
    a = birod.build(birod.Params(section=circle()))
    s = np.linspace(0.0, 1.0, 5)
    mode = [SegmentMode(seg.name, s, np.zeros(5), np.full(5, 0.5)) for seg in a.segments]
    md = ribbons.mode_drawing(a, mode, 2.0)
    (x0, R0), (x1, R1) = md.held, md.moved
    np.testing.assert_allclose(x1, x0, atol=1e-15)
    np.testing.assert_allclose(md.turn, 1.0)
    want = math.cos(1.0) * R0[:, :, 2] + math.sin(1.0) * R0[:, :, 0]
    np.testing.assert_allclose(R1[:, :, 2], want, atol=1e-14)
    np.testing.assert_allclose(np.einsum("eij,eik->ejk", R1, R1), np.tile(np.eye(3), (8, 1, 1)),
                               atol=1e-14)


def test_section_sizes_follow_the_aspect_of_the_design():
    """A rectangle of h/t = 4 (the folded six-ring) has sqrt(B1/B3) = 4: drawn h = width,
    t = width/4; a flat section (h/t = 1/2) is drawn t = width, h = width/2."""
    rod = discretise(load_design("examples/folded_six_ring.toml").assembly, 2)
    lay = RodLayout.from_rod(rod)
    np.testing.assert_allclose(lay.aspect, 4.0, rtol=1e-12)
    np.testing.assert_array_equal(lay.edge_segment, np.repeat(np.arange(6), 2))
    h, t = ribbons.section_sizes(np.array([4.0, 0.5]), 0.2)
    np.testing.assert_allclose(h, [0.2, 0.1])
    np.testing.assert_allclose(t, [0.05, 0.2])


def test_edge_twist_of_uniformly_turned_frames_is_the_twist_rate():
    """Frames turned about the tangent by tau s (tau = 0.8) along a straight rod have the rate
    of twist tau at every edge (Cayley measure 2 tan(tau ds / 2) / ds, ds = 1/8)."""
    a = birod.build(birod.Params(section=circle()))
    rod = discretise(a, 8)
    mids = (np.arange(8) + 0.5) / 8
    turned = rod.R_edge.copy()
    upper = rod.edge_segment == 0
    t = rod.R_edge[0, :, 1]
    turned[upper] = [_turn_about(t, 0.8 * s) @ r
                     for s, r in zip(mids, rod.R_edge[upper], strict=True)]
    tw = rod.edge_twist(turned)
    ds = 1 / 8
    np.testing.assert_allclose(tw[upper], 2 / ds * math.tan(0.8 * ds / 2), rtol=1e-12)
    np.testing.assert_allclose(tw[~upper], 0.0, atol=1e-12)


def _axes3d(fig):
    return next(ax for ax in fig.axes if hasattr(ax, "get_zlim"))


def test_birod_mode_picture_has_equal_axes_stacked_rods_and_opposite_twists():
    """plot_mode of the bi-rod: the box aspect is in proportion to the axis ranges (equal
    scale), the camera is oblique to the plane, the lower rod (stacked on the upper) is drawn
    one gap below it, and its drawn turns have the opposite sign (the mode's opposite twists:
    opposite colours)."""
    a = birod.build(birod.Params(section=circle()))
    r = linear_stability(a, 8)
    fig = plot_mode(a, r)
    ax = _axes3d(fig)
    spans = np.array([np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim()), np.ptp(ax.get_zlim())])
    box = np.asarray(ax.get_box_aspect())
    np.testing.assert_allclose(box / box[0], spans / spans[0], rtol=1e-9)
    # Oblique to the plane; seen across the rods (along x): 60 degrees off their axis.
    assert (ax.elev, ax.azim) == pytest.approx((ribbons.CAMERA_ELEVATION,
                                                ribbons.CAMERA_AZIMUTH_OFFSET))
    scale = ribbons.mode_scale(r.mode, 0.25)
    md = ribbons.mode_drawing(a, r.mode, scale)
    upper, lower = md.turn[md.layout.edge_segment == 0], md.turn[md.layout.edge_segment == 1]
    assert np.all(upper * lower <= 1e-12) and np.max(np.abs(upper)) > 0.1
    np.testing.assert_array_equal(ribbons.stack_levels(md.held[0], md.layout, 0.05), [0, 1])
    assert "stacked" in ax.get_title()


def test_each_segment_is_outlined_in_its_own_colour():
    """The edge colours of the moved (mode) faces are their segment's colour, one per segment
    and all distinct (tab10, tab20 past ten)."""
    a = birod.build(birod.Params(section=circle()))
    r = linear_stability(a, 8)
    fig = plot_mode(a, r)
    edge = _axes3d(fig).collections[0].get_edgecolor()
    colours, counts = np.unique(np.round(edge, 6), axis=0, return_counts=True)
    n_faces = 2 * 8 * 4  # 2 segments x 8 edges x 4 faces, in the ghost and in the mode
    want = {tuple(np.round(GHOST_EDGE, 6)): n_faces}
    want |= {tuple(np.round(c, 6)): n_faces // 2 for c in segment_colours(2)}
    assert {tuple(c): int(n) for c, n in zip(colours, counts, strict=True)} == want
    for n in (2, 6, 20):
        assert len(set(segment_colours(n))) == n


def test_equilibrium_picture_and_the_ribbon_of_a_ring_state():
    """plot_equilibrium of the held folded six-ring: six segments stacked 0..5 (drawn one under
    the other), the figure's axes at equal scale, the colour bar labelled."""
    rod = discretise(load_design("examples/folded_six_ring.toml").assembly, 4)
    lay = RodLayout.from_rod(rod)
    assert list(ribbons.stack_levels(rod.x, lay, 0.05)) == [0, 1, 2, 3, 4, 5]
    fig = plot_equilibrium(rod.x, rod.R_edge, lay, edge_values=rod.edge_moments())
    ax = _axes3d(fig)
    spans = np.array([np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim()), np.ptp(ax.get_zlim())])
    box = np.asarray(ax.get_box_aspect())
    np.testing.assert_allclose(box / box[0], spans / spans[0], rtol=1e-9)
    # Stacked 0..5 gaps below the first: the drawing's z range covers them all.
    w = ribbons.default_width(rod.x, None)
    h, _ = ribbons.section_sizes(lay.aspect, w)
    assert spans[2] >= 5 * ribbons.stack_gap(h, w)
    assert "stacked" in ax.get_title()
    assert any(c.get_xlabel() == "|internal moment|" for c in fig.axes)


def _three_states():
    x, edges, R = _straight(4)
    lay = RodLayout(edges, np.zeros(4, dtype=int), ("rod",), np.full(4, 2.0))
    shapes = [x + [0.0, 0.0, 0.1 * k] for k in range(3)]
    frames = [np.array([_turn_about(np.array([1.0, 0, 0]), 0.3 * k) @ r for r in R])
              for k in range(3)]
    return shapes, frames, lay


def test_gif_has_one_frame_per_state(tmp_path):
    from PIL import Image

    shapes, frames, lay = _three_states()
    gif = animate_shapes(shapes, frames, lay, tmp_path / "a.gif", labels=["a", "b", "c"],
                         edge_values=[np.arange(4.0) * k for k in range(3)], value_label="v")
    with Image.open(gif) as im:
        assert im.format == "GIF" and im.n_frames == 3


def test_html_view_has_meshes_per_state_equal_axes_and_a_slider(tmp_path):
    """One frame per state, each with the coloured and the grey Mesh3d; the scene's aspect
    ratio is the ranges' (equal axes); one slider step per state."""
    pytest.importorskip("plotly")
    shapes, frames, lay = _three_states()
    page = html_view(shapes, frames, lay, tmp_path / "v.html", labels=["a", "b", "c"],
                     edge_values=[np.arange(4.0)] * 3, value_label="v", diverging=True
                     ).read_text()
    page = page[page.index("Plotly.newPlot("):]  # the figure, after plotly.js itself
    # The figure's data, then each frame: a coloured mesh (intensity per face) and a grey one.
    assert page.count('"intensitymode":"cell"') == 1 + 3
    assert page.count('"color":"rgb(220,220,220)"') == 1 + 3
    ranges = [json_range(page, ax) for ax in "xyz"]
    ratio = re.search(r'"aspectratio":\{"x":([-\d.e]+),"y":([-\d.e]+),"z":([-\d.e]+)\}', page)
    assert ratio is not None
    spans = np.array([hi - lo for lo, hi in ranges])
    np.testing.assert_allclose(np.array([float(v) for v in ratio.groups()]),
                               spans / spans.max(), rtol=1e-9)
    assert page.count('"method":"animate"') == 3 + 1  # slider steps and the play button


def json_range(page: str, axis: str) -> tuple[float, float]:
    m = re.search(rf'"{axis}axis":\{{"range":\[([-\d.e]+),([-\d.e]+)\]', page)
    assert m is not None, axis
    return float(m.group(1)), float(m.group(2))


def test_plot_mode_writes_its_file_and_sweep_plot_too(tmp_path):
    a = birod.build(birod.Params(section=circle()))
    r = linear_stability(a, 8)
    assert plot_mode(a, r, tmp_path / "mode.png").stat().st_size > 0
    rows = [{"k": 1.0, "load_factor_critical": 2.0, "load_factor_lower": -1.0},
            {"k": 2.0, "load_factor_critical": 3.0, "load_factor_lower": -2.0}]
    assert sweep_plot(rows, "k", tmp_path).stat().st_size > 0


def test_cli_equilibrium_render_takes_colour_twist_and_refuses_an_unknown_colour(run_cli, tmp_path):
    """equilibrium --render --colour twist writes its picture;
    --colour with another name is a usage error (exit 2) naming the choices."""
    r = run_cli(["equilibrium", "examples/birod.toml", "--elements", "4", "--render",
                 str(tmp_path / "eq.png"), "--colour", "twist", "--json"])
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "eq.png").stat().st_size > 0
    r = run_cli(["equilibrium", "examples/birod.toml", "--elements", "4", "--render",
                 str(tmp_path / "eq2.png"), "--colour", "stress"])
    assert r.exit_code == 2 and "moment" in r.stderr and "twist" in r.stderr
    assert not (tmp_path / "eq2.png").exists()


def test_stack_shift_fades_as_stacked_rods_come_apart():
    """Two coinciding straight rods: full stack shift (weight 1); 10 lengths apart in their
    plane: none (0); halfway through the fade distance: half (0.5)."""
    en = np.array([[0, 1], [1, 2], [3, 4], [4, 5]])
    layout = RodLayout(en, np.array([0, 0, 1, 1]), ("a", "b"), np.ones(4))
    line = np.array([[0.0, 0, 0], [0.5, 0, 0], [1.0, 0, 0]])
    w = 0.05
    near = ribbons.STACK_TOL * w
    for dy, want in ((0.0, 1.0), (10.0, 0.0),
                     (near * (1 + 0.5 * (ribbons.STACK_FADE - 1)), 0.5)):
        x = np.vstack([line, line + [0.0, dy, 0.0]])
        assert ribbons.stack_weights(x, layout, w) == pytest.approx([want, want])


def _branch_result(elements: int, *, shapes: bool = True):
    """A primary path with one branch of two states of ``examples/twisted_rod.toml``: the held
    rod, then its frames twisted and its nodes lifted."""
    from rodstab.nonlinear.continuation.path import Path as Curve

    a = load_design("examples/twisted_rod.toml").assembly
    rod = discretise(a, elements)
    # each frame turned about its tangent d2 by 0.1 more than the last: a uniform twist
    turned = np.array([R @ _turn_about(np.array([0.0, 1, 0]), 0.1 * k)
                       for k, R in enumerate(rod.R_edge)])
    curve = dict(key="load_factor", value=(1.0,), energy=(0.0,), lowest_eigenvalue=(1.0,),
                 amplitude=(0.0,), amplitude_definition="", converged=True, method="test")
    branch = Curve(**curve, value_critical=2.0, shapes=(rod.x, rod.x + [0.0, 0.0, 0.01]),
                   frames=(rod.R_edge, turned), shape_values=(2.0, 2.5),
                   shape_moments=(np.zeros(len(rod.R_edge)), np.ones(len(rod.R_edge))))
    return Curve(**curve, branches=(branch,) if shapes else ()), a, rod, turned


@pytest.mark.parametrize("colour", ["moment", "twist"])
def test_branch_animation_draws_the_first_branch_coloured_by_the_choice(colour, tmp_path,
                                                                        monkeypatch):
    """rodstab.plot.animations.branch_animation hands animate_shapes the branch's shapes and
    frames, its moments (moment) or the rates of twist of its frames (twist, signed), the
    parameter's values as captions; the GIF has a frame per shape."""
    from PIL import Image

    import rodstab.plot.plots as plots
    from rodstab.plot.animations import EDGE_COLOURS, branch_animation

    result, a, rod, turned = _branch_result(4)
    seen = {}
    draw = plots.animate_shapes
    monkeypatch.setattr(plots, "animate_shapes",
                        lambda *args, **kw: seen.update(kw) or draw(*args, **kw))
    gif = branch_animation(result, a, 4, tmp_path / "b.gif", source="rod", colour=colour)
    with Image.open(gif) as im:
        assert im.n_frames == 2
    want = (result.branches[0].shape_moments if colour == "moment"
            else (rod.edge_twist(rod.R_edge), rod.edge_twist(turned)))
    for got, w in zip(seen["edge_values"], want, strict=True):
        np.testing.assert_array_equal(got, w)
    if colour == "twist":
        assert np.all(seen["edge_values"][1] != 0)  # the turned frames are twisted
    assert (seen["value_label"], seen["diverging"]) == EDGE_COLOURS[colour]
    assert seen["labels"] == ["load_factor = 2", "load_factor = 2.5"]
    assert seen["title"] == "rod: branch from load_factor = 2"


def test_branch_pictures_of_a_path_without_branch_shapes_are_none(tmp_path):
    """No branch with shapes (none traced, or a resumed run): nothing is written."""
    from rodstab.plot.animations import branch_animation, branch_html

    result, a, _, _ = _branch_result(4, shapes=False)
    assert branch_animation(result, a, 4, tmp_path / "b.gif", source="rod") is None
    assert branch_html(result, a, 4, tmp_path / "b.html", source="rod") is None
    assert not list(tmp_path.iterdir())


def test_branch_html_has_a_slider_step_per_shape(tmp_path):
    pytest.importorskip("plotly")
    from rodstab.plot.animations import branch_html

    result, a, _, _ = _branch_result(4)
    page = branch_html(result, a, 4, tmp_path / "b.html", source="rod", colour="twist")
    assert page is not None
    assert page.read_text().count('"method":"animate"') == 2 + 1  # steps and the play button


def test_branch_animation_refuses_an_unknown_colour(tmp_path):
    from rodstab.plot.animations import branch_animation

    result, a, _, _ = _branch_result(4)
    with pytest.raises(ValueError, match="colour.*'stress'"):
        branch_animation(result, a, 4, tmp_path / "b.gif", source="rod", colour="stress")
