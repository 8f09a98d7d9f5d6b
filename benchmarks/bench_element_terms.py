"""Benchmark: the discrete rod's element energies in closed form against second-order jets.

``rodstab.nonlinear.element_terms`` gives the stretch/shear and bending energies' value,
gradient and Hessian in closed form; before 2026-12-05 they were second-order jets of the
same expressions (``rodstab.nonlinear.jets``), which the tests keep as the reference. Timed
side by side in one run (medians of ``repeats``), on the folded six-ring and the hexagram:

* ``stretch``: every edge's stretch/shear term (9 local variables);
* ``bend``: bending between consecutive edges (6 local variables);
* ``evaluate``: one ``energy_terms()`` of the whole rod (closed forms, as the engine runs).

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_element_terms.py [elements] [repeats]``.
"""

from __future__ import annotations

import sys

import numpy as np
from bench_analytic import median_time

from rodstab.nonlinear import discrete as D
from rodstab.nonlinear.jets import Jet, rotation_jet, vector_jet
from rodstab.problems import REGISTRY


def stretch_by_jets(rod: D.DiscreteRod) -> Jet:
    """The stretch/shear energies by second-order jets (the former implementation)."""
    i, j = rod.edge_nodes[:, 0], rod.edge_nodes[:, 1]
    le, w = rod.rest_length, 0.5 * D.PENALTY * rod.edge_B.max(axis=1) / rod.rest_length
    xi, xj = vector_jet(rod.x[i], 9, 0), vector_jet(rod.x[j], 9, 3)
    eps = rotation_jet(rod.R_edge, 9, 6).T.apply([(xj[k] - xi[k]) * (1.0 / le)
                                                 for k in range(3)])
    zero = Jet(np.zeros(len(le)), np.zeros((len(le), 9)), np.zeros((len(le), 9, 9)))
    return sum(((eps[k] - D._T0[k]) * (eps[k] - D._T0[k]) for k in range(3)), start=zero) * w


def bend_by_jets(rod: D.DiscreteRod) -> Jet:
    """The bending energies between edges by jets of their relative rotation (former)."""
    a, b = rod.bend_pairs[:, 0], rod.bend_pairs[:, 1]
    le = rod.rest_length
    ds, k0, B = 0.5 * (le[a] + le[b]), rod._k0(rod.k_held_pairs, a, rod.load_factor), \
        rod.edge_B[a]
    P = rotation_jet(rod.R_edge[a], 6, 0).T @ rotation_jet(rod.R_edge[b], 6, 3)
    den = (P.entry(0, 0) + P.entry(1, 1) + P.entry(2, 2) + 1.0).reciprocal()
    vee = [P.entry(2, 1) - P.entry(1, 2), P.entry(0, 2) - P.entry(2, 0),
           P.entry(1, 0) - P.entry(0, 1)]
    t = [vee[c] * den * (2.0 / ds) - k0[:, c] for c in range(3)]
    return sum((t[c] * t[c] * (0.5 * B[:, c] * ds) for c in range(1, 3)),
               start=t[0] * t[0] * (0.5 * B[:, 0] * ds))


def time_structure(name: str, rod: D.DiscreteRod, repeats: int) -> None:
    """Print the jets' and the closed forms' medians for one rod."""
    i, j = rod.edge_nodes[:, 0], rod.edge_nodes[:, 1]
    w = 0.5 * D.PENALTY * rod.edge_B.max(axis=1) / rod.rest_length
    a, b = rod.bend_pairs[:, 0], rod.bend_pairs[:, 1]
    eye = np.broadcast_to(np.eye(3), (len(a), 3, 3))
    M = np.swapaxes(rod.R_edge[a], 1, 2) @ rod.R_edge[b]
    ds = 0.5 * (rod.rest_length[a] + rod.rest_length[b])
    k0 = rod._k0(rod.k_held_pairs, a, rod.load_factor)
    rows = {
        "stretch": (lambda: stretch_by_jets(rod),
                    lambda: D.stretch_jet(rod.R_edge, rod.x[j] - rod.x[i], rod.rest_length,
                                          w, 2)),
        "bend": (lambda: bend_by_jets(rod),
                 lambda: D.bend_jet(eye, M, eye, np.zeros(len(a), bool), ds, rod.edge_B[a],
                                    k0, 2)),
    }
    for term, (old, new) in rows.items():
        t_old, t_new = median_time(old, repeats), median_time(new, repeats)
        print(f"{name:>12} {term:>9} {1e3 * t_old:9.3f} {1e3 * t_new:9.3f} "
              f"{t_old / t_new:7.2f}")
    t = median_time(rod.energy_terms, repeats)
    print(f"{name:>12} {'evaluate':>9} {'':>9} {1e3 * t:9.3f}")


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 15
    print(f"element energies, {n} elements per rod, medians of {repeats} runs (ms)")
    print(f"{'structure':>12} {'term':>9} {'jets':>9} {'closed':>9} {'ratio':>7}")
    rng = np.random.default_rng(0)
    for name in ("folded-ring", "hexagram"):
        p = REGISTRY[name]
        rod = D.discretise(p.build(p.Params()), n, 0.9)
        rod.apply(0.05 * rng.standard_normal(rod.n_dof))
        time_structure(name, rod, repeats)


if __name__ == "__main__":
    main()
