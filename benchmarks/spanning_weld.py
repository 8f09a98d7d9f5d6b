"""Table: the stacked bi-rod's limit with welds that span the layers (issue 21, part 2).

The bi-rod of Section 4 (circle section, one end clamped, B3 = 1, L = 1) with its two rods
lifted apart by the spacing ``h`` (``discretise(layers=)``: the welds' rigid offsets join
them), no contact: the load factor where the lowest Hessian eigenvalue changes sign (Brent in
[1, 12]), for several spacings, meshes and stretch penalties (``PENALTY``, the discrete rod's
stand-in for inextensibility). At ``h = 0`` the planar model's limit. Prints one row per
(h, elements, penalty).

Measured 2026-12-05 (docs/theory/contact.md, "Stacked states: the weld that spans the layers"):
the limit converges to the planar one as h -> 0 (1e-6: equal to 1e-7), and at fixed h it
grows with the penalty and with the mesh (whose stretch stiffness ``PENALTY B / l_e^2`` grows as
the elements shorten): the mode needs the layers to slide over one another at the welds, which
inextensible rods joined by rigid offsets cannot do. With the rods' axial stiffness EA in place
of the penalty (second table) the limit depends on ``s = EA h^2 / B`` alone and converges with
the mesh. Run: ``python benchmarks/spanning_weld.py``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

from scipy.optimize import brentq  # noqa: E402

from rodstab.nonlinear import discrete  # noqa: E402
from rodstab.nonlinear.solve import lowest_modes, newton  # noqa: E402
from rodstab.problems import birod  # noqa: E402
from rodstab.sections import circle  # noqa: E402

BIROD = birod.build(birod.Params(section=circle()))
SPACINGS = (0.0, 1e-6, 1e-4, 1e-3, 1e-2)
MESHES = (24, 48)
PENALTIES = (1e3, 4e3)


#: The laminate's parameter EA h^2 / B of the second table (solid rectangular strips 12, solid
#: round rods touching 16), at spacing H_EA, with and without contact.
LAMINATE = (1.2, 12.0, 16.0, 120.0, 1200.0)
H_EA = 1e-2
EA_MESHES = (24, 48, 96)


def limit(spacing: float, n: int, axial: float | None = None, contact: bool = False) -> float:
    """Load factor of the sign change of the lowest eigenvalue (NaN if none in [1, 12])."""
    def lowest(mu: float) -> float:
        layers = None if spacing == 0 else {"upper": spacing / 2, "lower": -spacing / 2}
        rod = discrete.discretise(BIROD, n, mu, layers=layers, axial_stiffness=axial)
        if contact:  # capsules of diameter 0.9 h: the layers 0.1 h apart, inside dhat
            from rodstab.nonlinear.contact import mesh_of_rod
            from rodstab.nonlinear.equilibrium import rod_contact_model

            rod.contact = mesh_of_rod(rod, rod_contact_model(BIROD, 0.9 * spacing, 0.2))
        newton(rod)
        return float(lowest_modes(rod, 1)[0][0])

    lo, hi = 1.0, 12.0
    if lowest(hi) > 0:
        return float("nan")
    return brentq(lowest, lo, hi, xtol=1e-9)


def main() -> None:
    print(f"{'h/L':>8} {'el.':>4} {'penalty':>8} {'limit mu':>10}")
    for penalty in PENALTIES:
        discrete.PENALTY = penalty
        for n in MESHES:
            for h in SPACINGS:
                print(f"{h:>8g} {n:>4} {penalty:>8g} {limit(h, n):>10.6g}")
    discrete.PENALTY = PENALTIES[0]
    print(f"\nEA = s B / h^2, h = {H_EA:g} L: limit by elements per rod; last: with contact "
          f"({EA_MESHES[0]} el.)")
    print(f"{'s':>8} " + " ".join(f"{n:>9}" for n in EA_MESHES) + f" {'contact':>9}")
    for s in LAMINATE:
        ea = s / H_EA**2  # B = 1
        row = [limit(H_EA, n, ea) for n in EA_MESHES]
        row.append(limit(H_EA, EA_MESHES[0], ea, contact=True))
        print(f"{s:>8g} " + " ".join(f"{v:>9.6g}" for v in row))


if __name__ == "__main__":
    main()
