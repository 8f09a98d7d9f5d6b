"""Figure code (``rodstab.plots``, ``rodstab.report.figures``): smoke tests that files are
written, and that importing or using it leaves the user's matplotlib backend and pyplot alone
(figures are built with the object API, :class:`matplotlib.figure.Figure`)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from rodstab.linear.solve import linear_stability
from rodstab.plots import animate_shapes, plot_equilibrium, plot_mode
from rodstab.problems import birod
from rodstab.report.figures import sweep_plot
from rodstab.sections import circle

KEEPS_BACKEND = """
import sys
import matplotlib
matplotlib.use("svg")
import numpy as np
import rodstab.plots, rodstab.report.figures
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


def test_plots_write_their_files(tmp_path):
    a = birod.build(birod.Params(section=circle()))
    r = linear_stability(a, 8)
    assert plot_mode(a, r, tmp_path / "mode.png").stat().st_size > 0
    x = np.array([[0.0, 0, 0], [1, 0, 0.1], [2, 0.5, 0.2]])
    edges = np.array([[0, 1], [1, 2]])
    assert plot_equilibrium(x, edges, tmp_path / "eq.png",
                            edge_values=np.array([1.0, 2.0])).stat().st_size > 0
    gif = animate_shapes([x, x + 0.1], edges, tmp_path / "a.gif", labels=["a", "b"])
    assert gif.read_bytes()[:3] == b"GIF"
    rows = [{"k": 1.0, "load_factor_critical": 2.0, "load_factor_lower": -1.0},
            {"k": 2.0, "load_factor_critical": 3.0, "load_factor_lower": -2.0}]
    assert sweep_plot(rows, "k", tmp_path).stat().st_size > 0
