"""What a reader sees in the figures of issue 20, tested through the drawn artists (no pixels).

Each test draws a figure under the object API from data shaped as its producer's, then reads
back what matplotlib placed: the hatched overlap's outline in data coordinates, the legend's
entries, the window extents of tick labels, offset texts and titles after a draw.
"""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.collections import PolyCollection

from rodstab.multistable import atlas as A
from rodstab.plot.plots import plot_stable_bands

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

