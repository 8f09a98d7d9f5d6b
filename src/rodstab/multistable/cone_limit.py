"""By how much contact moves a stacked state's limit: the minimum of the form on the cone.

:mod:`.cone` decides whether contact at zero gap keeps a no-contact limit ``mu_c`` or moves it
outward. This module finds where it moves it to: the first load factor past ``mu_c`` at which
P2 (2.12, FE) is no longer positive on the cone ``C = {v : g_i(v) >= 0}`` of perturbations that
close no gap between touching layers (the gaps of :func:`.cone.touching_pairs`, first order,
``n_z (w_a - w_b)``). At each load the question "is ``v^T K(mu) v > 0`` on ``C``" is decided
with a certificate by :func:`rodstab.numerics.copositive.positive_on_cone` (an eigen-split of
``K`` and exact least-distance programmes: positive, or a witness perturbation, or undecided).

Search (scan, then refine; the window from the no-contact interval): loads ``mu_c +- i dmu``,
``dmu`` = :data:`SCAN_STEPS`-th of the no-contact interval's width, out to
:data:`WINDOW_WIDTHS` widths; the first load with a witness and the last certified one bracket
the limit with contact, which bisection shrinks to :data:`XTOL` (relative). The bracket is
certified at both ends: positive on the cone at its inner end (or ``mu_c`` itself, where ``K``
is positive semi-definite), a witness at its outer end. An undecided load (more than two
non-positive directions, or the arcs not certified in the allowed solves) ends the search with
what is certified so far, said so. A load where the form is positive again after a witness,
between two scan points, is not looked for.

What it is exact for: the FE's perturbations are P2's, out of plane (``w`` and the twist); a
gap whose normal has an in-plane part (the torus curve's, the hexagon's) is only tested in its
height component. An in-plane part of a perturbation costs energy but can open such a gap, so
the limit with contact against every perturbation lies between ``mu_c`` and the one given here
(equal where the touching layers' normals are vertical: flat layers).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..errors import require_positive_int
from ..linear.solve import linear_pencil, linear_stability
from ..model import Assembly
from ..numerics.copositive import NOT_POSITIVE, POSITIVE, positive_on_cone
from ..results import Result
from .cone import MAX_DENSE_DOF, gap_changes, touching_pairs

#: Scan step: this fraction of the no-contact interval's width (or of ``max(|mu_c|, 1)`` when
#: the interval is one-sided).
SCAN_STEPS = 40
#: How far past ``mu_c`` the scan goes, in widths.
WINDOW_WIDTHS = 1.0
#: The bracket is refined to this, relative to ``max(|mu|, 1)``.
XTOL = 1e-5


@dataclasses.dataclass(frozen=True)
class ConeLimit(Result):
    """The limit with contact at zero gap on one side of the no-contact interval.

    Attributes
    ----------
    side : str
        ``"lower"`` or ``"upper"``.
    no_contact : float
        ``mu_c``, the no-contact limit (FE of P2).
    status : str
        ``"bracketed"`` (the limit with contact lies in ``bracket``), ``"beyond window"``
        (positive on the cone up to ``bracket[0]``, the window's end) or ``"undecided"``
        (certified up to ``bracket[0]``; ``message`` says what stopped it).
    bracket : tuple of float
        ``(certified positive on the cone, witness of instability)`` in load factor, the first
        nearer ``mu_c``; the second is ``nan`` unless bracketed.
    load_factor : float
        The bracket's midpoint (``nan`` unless bracketed).
    shift : float
        ``load_factor - mu_c`` (outward positive on both sides; ``nan`` unless bracketed).
    decisions : int
        Loads decided.
    message : str
    """

    side: str
    no_contact: float
    status: str
    bracket: tuple[float, float]
    load_factor: float
    shift: float
    decisions: int
    message: str


@dataclasses.dataclass(frozen=True)
class ConeLimits(Result):
    """Both sides' limits with contact at zero gap (:func:`cone_limits`)."""

    interval: tuple[float, float]
    lower: ConeLimit | None
    upper: ConeLimit | None
    elements_per_segment: int
    method: str


def _search(decide: Any, mu_c: float, sign: float, width: float, side: str) -> ConeLimit:
    """Scan outward from ``mu_c``, then bisect the first certified bracket (module doc)."""
    step = width / SCAN_STEPS
    inner, count = mu_c, 0
    for i in range(1, int(math.ceil(SCAN_STEPS * WINDOW_WIDTHS)) + 1):
        mu = mu_c + sign * i * step
        d = decide(mu)
        count += 1
        if d.status == NOT_POSITIVE:
            outer = mu
            break
        if d.status != POSITIVE:
            return ConeLimit(side, mu_c, "undecided", (inner, math.nan), math.nan, math.nan,
                             count, f"at {mu:.6g}: {d.message}")
        inner = mu
    else:
        return ConeLimit(side, mu_c, "beyond window", (inner, math.nan), math.nan, math.nan,
                         count, f"positive on the cone out to {inner:.6g} ({WINDOW_WIDTHS:g} "
                         "widths of the no-contact interval)")
    note = ""
    while abs(outer - inner) > XTOL * max(abs(inner), 1.0):
        mid = 0.5 * (inner + outer)
        d = decide(mid)
        count += 1
        if d.status == NOT_POSITIVE:
            outer = mid
        elif d.status == POSITIVE:
            inner = mid
        else:
            note = f"; refinement stopped at {mid:.6g}: {d.message}"
            break
    mid = 0.5 * (inner + outer)
    return ConeLimit(side, mu_c, "bracketed", (inner, outer), mid, sign * (mid - mu_c), count,
                     "certified: positive on the cone at the inner end (or the no-contact "
                     "limit), a witness at the outer" + note)


def cone_limits(a: Assembly, layers: dict[str, Any] | str, elements_per_segment: int = 24
                ) -> ConeLimits:
    """Limits with contact at zero gap: where P2 stops being positive on the cone (module doc).

    Parameters
    ----------
    a : Assembly
        The planar held state with stacked rods (as for :func:`.cone.contact_cone`).
    layers : dict or "torus"
        The layer order (:func:`.cone.touching_pairs`); not re-checked here for realisability
        (:func:`.cone.contact_cone` does that).
    elements_per_segment : int
        FE mesh of P2.

    Returns
    -------
    ConeLimits
        Per finite side of the no-contact interval, the certified bracket of the limit with
        contact (load factors).
    """
    from scipy.linalg import null_space

    n = require_positive_int("elements_per_segment", elements_per_segment)
    lin = linear_stability(a, n)
    pencil = linear_pencil(a, n)
    if pencil.K0.shape[0] > MAX_DENSE_DOF:
        from ..errors import RodstabInputError

        raise RodstabInputError(f"elements_per_segment = {n}: {pencil.K0.shape[0]} FE unknowns, "
                                f"more than the dense solve's {MAX_DENSE_DOF}")
    pairs = touching_pairs(a, layers, n)
    N = null_space(pencil.G.toarray())
    K0 = N.T @ pencil.K0.toarray() @ N
    K1 = N.T @ pencil.K1.toarray() @ N
    D, _ = gap_changes(pencil, pairs, N)
    norms = np.linalg.norm(D, axis=1)
    D = D[norms > 0] / norms[norms > 0, None]  # side-by-side pairs (n_z = 0): no row

    def decide(mu: float) -> Any:
        return positive_on_cone(K0 + mu * K1, D)

    lo, hi = lin.load_factor_interval
    both = math.isfinite(lo) and math.isfinite(hi)
    out: list[ConeLimit | None] = []
    for mu_c, sign, side in ((lo, -1.0, "lower"), (hi, 1.0, "upper")):
        if not math.isfinite(mu_c):
            out.append(None)
            continue
        width = (hi - lo) if both else max(abs(mu_c), 1.0)
        out.append(_search(decide, float(mu_c), sign, width, side))
    return ConeLimits((float(lo), float(hi)), out[0], out[1], n,
                      "minimum of P2 (2.12, FE) on the cone of gap-keeping perturbations at zero "
                      "gap (out of plane): certified decisions (eigen-split + least-distance "
                      "programmes), scanned and bisected in the load factor")


#: Fourier modes ``j = 0 .. RING_MODES`` of eq. (3.2) in :func:`ring_cone_limits` (``j = N``,
#: the rigid tilt, left out), and samples per loop of the torus's gaps.
RING_MODES = 48
RING_SAMPLES = 192


def ring_cone_limits(b1: float, b2: float, loops: int, modes: int = RING_MODES,
                     samples: int = RING_SAMPLES) -> ConeLimits:
    """Compute the N-loop ring's limits with contact on the torus from eq. (3.2)'s modes.

    An independent discretisation of :func:`cone_limits`' question for the ring: P2 is block
    diagonal in the modes ``omega = A cos(k theta)``, ``beta = B sin(k theta)`` and their
    quarter-period shifts, ``k = j / N`` (:func:`rodstab.analytic.ring.ring_mode_pencil`; one
    prefactor for every ``j >= 1``), and ``w = int beta ds = -(R B / k) cos(k theta)``. The gaps
    are the torus's (:func:`.cone.ring_mode_margin`'s geometry): loop ``m`` at azimuth ``phi``
    sits at ``psi_m = (phi + 2 pi m) / N``, neighbours touch with ``n_z`` the height of their
    unit normal, and the gap changes by ``n_z (w_a - w_b)`` at ``samples`` azimuths per pair.
    Load factor ``mu = R kappa_n = 1 - M`` (the FE's for :func:`rodstab.problems.ring.build`).
    """
    from ..analytic.ring import ring_mode_pencil, ring_stability

    N = require_positive_int("loops", loops)
    js = [j for j in range(1, require_positive_int("modes", modes) + 1) if j != N]
    nb = 2 * len(js)  # (A, B) per phase
    K0 = np.zeros((2 * nb, 2 * nb))
    K1 = np.zeros_like(K0)
    phi = np.linspace(0.0, 2 * math.pi, require_positive_int("samples", samples),
                      endpoint=False)
    pairs = sorted({(min(m, (m + 1) % N), max(m, (m + 1) % N)) for m in range(N)
                    if m != (m + 1) % N})
    rows = []
    for ka, kb in pairs:
        pa, pb = (phi + 2 * math.pi * ka) / N, (phi + 2 * math.pi * kb) / N
        nz = (np.sin(pa) - np.sin(pb)) / np.hypot(np.cos(pa) - np.cos(pb),
                                                  np.sin(pa) - np.sin(pb))
        D = np.zeros((len(phi), 2 * nb))
        for i, j in enumerate(js):
            k = j / N
            A, C = ring_mode_pencil(k, b1, b2)
            for ph in range(2):  # phase 0: cos/sin; phase 1: shifted a quarter period
                sl = slice(ph * nb + 2 * i, ph * nb + 2 * i + 2)
                K0[sl, sl] = A - C  # A - M C with M = 1 - mu: (A - C) + mu C
                K1[sl, sl] = C
                ta, tb = phi + 2 * math.pi * ka, phi + 2 * math.pi * kb
                wa = -np.cos(k * ta) / k if ph == 0 else -np.sin(k * ta) / k
                wb = -np.cos(k * tb) / k if ph == 0 else -np.sin(k * tb) / k
                D[:, ph * nb + 2 * i + 1] = nz * (wa - wb)
        rows.append(D)
    Dm = np.vstack(rows)
    Dm = Dm[np.linalg.norm(Dm, axis=1) > 1e-12]
    Dm = Dm / np.linalg.norm(Dm, axis=1, keepdims=True)
    an = ring_stability(b1, b2, N)
    lo, hi = 1.0 - an.M_interval[1], 1.0 - an.M_interval[0]

    def decide(mu: float) -> Any:
        return positive_on_cone(K0 + mu * K1, Dm)

    out = [_search(decide, mu_c, sign, hi - lo, side)
           for mu_c, sign, side in ((lo, -1.0, "lower"), (hi, 1.0, "upper"))]
    return ConeLimits((lo, hi), out[0], out[1], 0,
                      f"minimum of P2 on the torus's cone in eq. (3.2)'s Fourier modes j <= "
                      f"{modes} (closed-form 2x2 pencils), {samples} azimuths per pair")
