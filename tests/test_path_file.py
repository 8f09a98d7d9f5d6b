"""``rodstab barrier --out DIR``: the path written to ``DIR/path.npz`` and its contact check.

The file lets anyone check the path's gaps without rodstab: here the printed verdict is
recomputed from the file alone by sampling points along the elements (no rodstab distance
code), with the judging rule of ``rodstab transitions`` re-derived from the file's elements.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from contact_checks import judged_pairs, segment_gap, separation

from rodstab.io.path_file import read_path_file, write_path_file

H = 0.05  # --contact-thickness, h / L
ARGS = ["barrier", "--elements", "4", "--images", "5", "--shape", "rectangle", "--aspect", "4",
        "--contact-thickness", str(H), "--json"]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The six-ring's folded -> one-loop barrier with --out: (JSON printed, file's arrays)."""
    from conftest import run_cli

    out = tmp_path_factory.mktemp("barrier")
    r = run_cli([*ARGS, "--out", str(out)])
    assert r.exit_code == 0, r.stderr
    payload = json.loads(r.stdout)
    assert payload["path_file"] == str(out / "path.npz")
    return payload, read_path_file(out / "path.npz")


@pytest.mark.slow
def test_path_file_holds_every_state_the_elements_and_the_thickness(run):
    """x: one state per path point (5), every node; edges index those nodes; energies as
    printed; thickness as given; the first and last states are the two minima (the lowest
    energies at the ends, the saddle's the highest)."""
    payload, z = run
    n_states = len(payload["energies"])
    assert z["x"].shape[0] == n_states == 5 and z["x"].shape[2] == 3
    assert z["edges"].min() == 0 and z["edges"].max() == z["x"].shape[1] - 1
    assert z["rest_length"].shape == (len(z["edges"]),)
    # The segment lengths are the rod length 1 (six rods of 4 elements).
    assert z["rest_length"].sum() == pytest.approx(6.0, rel=1e-12)
    np.testing.assert_allclose(z["energy"], payload["energies"], rtol=0, atol=0)
    assert z["thickness"] == H
    assert np.argmax(z["energy"]) == payload["saddle_position"]


@pytest.mark.slow
def test_printed_contact_is_recomputed_from_the_file_alone(run):
    """Judged pairs (elements of rods sharing no node, or of one rod >= 3 elements apart), the
    pairs stacked in the first state (closer than h), and the other pairs' smallest distance
    over h along the path: from the file, by sampling -- within the sampling's error (the
    point spacing, 1/100 of an element of L/4: 0.05 h)."""
    payload, z = run
    x, edges = z["x"], z["edges"]
    judged = judged_pairs(edges, 6)
    stacked = {p for p in judged if segment_gap(x[0], edges, *p) < H}
    assert payload["contact"]["stacked_pairs"] == len(stacked) > 0
    others = [p for p in judged if p not in stacked]
    smallest = min(segment_gap(xs, edges, *p) for xs in x for p in others) / H
    printed = payload["contact"]["min_distance"]
    assert printed <= smallest + 1e-12
    assert smallest - printed <= 0.05 + 1e-12


@pytest.mark.slow
def test_printed_pass_through_has_a_witness_in_the_file(run):
    """The path (5 points, no contact model) is judged to pass rods through each other at
    the point where, from the file alone, a stacked pair's out-of-plane order (its separation's
    height, the folded state lying in a horizontal plane) reverses while the straight path
    from the point before comes within h (sampled at 33 states, 41 points per element). Until
    session 19 only the points were judged, and this 5-point path was called clean."""
    payload, z = run
    x, edges = z["x"], z["edges"]
    assert np.ptp(x[0][:, 2]) < 1e-9  # the folded state is planar, in z = const
    k = int(payload["contact"]["pass_through_at"])
    assert payload["contact"]["pass_through"] is True and k >= 1
    stacked = [p for p in judged_pairs(edges, 6) if segment_gap(x[0], edges, *p) < H]

    def height(xs, p):  # the separation's height between the sampled closest points
        return separation(xs, edges, *p)[2]

    witnesses = [p for p in stacked
                 if height(x[k - 1], p) * height(x[k], p) < 0
                 and min(segment_gap((1 - t) * x[k - 1] + t * x[k], edges, *p, n=41)
                         for t in np.linspace(0.0, 1.0, 33)) < H]
    assert witnesses


def test_write_and_read_round_trip_without_a_thickness(tmp_path):
    """A path without a known thickness has no ``thickness`` array; read gives None."""
    x = np.zeros((2, 3, 3))
    x[:, 1, 0], x[:, 2, 0] = 1.0, 2.0
    p = write_path_file(tmp_path / "p.npz", x, [[0, 1], [1, 2]], [1.0, 1.0], [0.0, 1.0])
    z = read_path_file(p)
    assert z["thickness"] is None and z["x"].shape == (2, 3, 3)


@pytest.mark.parametrize("extra, words", [
    (["--contact-thickness", "0"], "--contact-thickness must be a finite positive number"),
    (["--method", "continuation", "--out", "{tmp}"],
     "--out and --workers are options of --method string"),
    (["--out", "{file}"], "--out"),
])
def test_bad_output_options_exit_2_naming_them(tmp_path, run_cli, extra, words):
    """A zero thickness, --out with the continuation method, --out naming a file: exit 2."""
    f = tmp_path / "a_file"
    f.write_text("x")
    args = [a.format(tmp=tmp_path / "d", file=f) for a in extra]
    r = run_cli(["barrier", "--elements", "4", *args])
    assert r.exit_code == 2, r.stderr
    assert words in r.stderr


def test_read_path_file_refuses_another_file(tmp_path):
    """Not a path file: exit-2 input error naming it."""
    from rodstab.errors import RodstabInputError

    bad = tmp_path / "x.npz"
    np.savez(bad, y=np.zeros(2))
    with pytest.raises(RodstabInputError, match="no x, edges, rest_length"):
        read_path_file(bad)
