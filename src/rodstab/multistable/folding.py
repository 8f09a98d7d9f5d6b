"""The N-loop ring folded from an untwisted one-loop ring: flat layers that swap (issue 21).

Why not the torus curve. A ring's ribbon (its centreline pushed off along a section director)
links its centreline ``Lk = Tw + Wr`` times, an integer that rods which cannot cross keep
(:mod:`.linking`). The untwisted one-loop ring has ``Lk = 0``. The ``(N, 1)`` torus curve with
its strip kept flat (:func:`~.stacking.stack_loops`) has ``Tw ~ 0`` and ``Wr = Lk = -(N - 1)``:
it is the ring *wound* round itself (the paper's footnote 2, a "covered ring"), or the one-loop
ring given ``N - 1`` turns of twist, not the ring folded from it.

What the fold makes. Stack ``N`` strands flat, one spacing ``s`` apart along ``e3``. Going once
round, the layer a strand ends in must be the one the next loop starts in, so the layers are
permuted by an ``N``-cycle; with swaps of neighbouring layers that takes ``N - 1`` swaps at
least, and any number of them has the parity of ``N - 1``. Each swap is a crossing of the
strip over itself seen from the side, adding ``+-1`` to the writhe, so with the strip flat
(``Tw = 0``) ``Lk = Wr`` = the sum of the swaps' signs. **``Lk = 0`` with no twist needs an even
number of swaps: ``N`` odd.** For even ``N`` the writhe is odd, and the untwisted ring folds
only with ``|Tw| >= 1``. This is the paper's statement (Sec. 3.1) that a one-loop ring folds
"without twist when the number of loops is odd", derived here from the stacking.

The construction (:func:`fold_loops`, odd ``N >= 3``). The loops start in layers ``N - 1``
(top), ``0``, ``1``, ..., ``N - 2``. Swap ``k`` (``k = 0 .. N - 2``) exchanges layers ``N - 1 -
k`` and ``N - 2 - k`` over the azimuth window ``[k w, (k + 1) w)``, ``w = 2 pi / (N - 1)``: the
two strands turn by ``pi`` (a C2 quintic smoothstep of the azimuth) about their midpoint in
the plane ``(e_r, e3)``, so they stay ``s`` apart and ``s`` from every other layer; swap ``k``
turns with sense ``(-1)^k`` (the upper strand passes outside for ``+``), so the signs cancel
and ``Lk = 0`` (tested by both evaluations of :mod:`.linking`). Going once round, the top
strand descends to the bottom and the others rise one layer. ``s`` is set so that the
smallest distance between strands on a fine polyline of the curve (:data:`CURVE_POINTS` per
loop) is ``h + g0`` (plus the chords' allowance), the radius so that the length is ``L``.

Measured (3 loops, circle, ``h/L = 0.01``, 32 el. per loop, ``dhat = 0.1 h``, load factor 1,
``benchmarks/folded_three_loops.py --hold``): relaxed with contact, the two swaps settle half a
turn apart from windows of half, a third and a quarter of a turn placed a third or half a turn
apart (178-182 degrees, :func:`layer_swaps`), to energies within 0.12 % of one another.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from ..errors import RodstabInputError, require_positive
from ..nonlinear.contact import ContactModel
from ..nonlinear.discrete import DiscreteRod
from .stacking import (
    CHORD_MARGIN,
    StackedState,
    _strain,
    _traversal,
    check_stacked,
    coincident_loops,
    default_model,
    fit_spacing,
    smoothstep,
)

#: Points per loop of the polyline the construction samples (interpolated at the nodes by
#: arclength: position error ``<= (2 pi R / CURVE_POINTS)^2 kappa / 8``, 1e-7 R).
CURVE_POINTS = 4096
#: Points per loop of the polyline on which the strands' distance is measured.
DISTANCE_POINTS = 1024
#: Fixed-point iterations setting ``s`` and ``R``, and their relative tolerance.
FOLD_MAX_ITER = 40
FOLD_RTOL = 1e-9


def start_layers(loops: int) -> list[int]:
    """Return the layer each loop starts in: ``N - 1`` (top), then ``0, 1, ..., N - 2``."""
    return [loops - 1, *range(loops - 1)]


def alternating(loops: int) -> tuple[int, ...]:
    """Return the folded ring's swap senses: ``+1, -1, +1, ...`` (``N - 1`` of them)."""
    return tuple(1 if k % 2 == 0 else -1 for k in range(loops - 1))


def fold_offsets(loops: int, theta: np.ndarray, spacing: float,
                 senses: tuple[int, ...] | None = None) -> np.ndarray:
    """Offsets ``(N, k, 2)``: ``(r, z)`` of each loop's strand at azimuths ``theta`` (rad).

    ``r`` radial from the loops' circle, ``z`` along ``e3`` from the stack's middle (length);
    ``theta`` in ``[0, 2 pi)``; the module doc's swaps, swap ``k`` turning with sense
    ``senses[k]`` (the upper strand passes outside for ``+1``; default :func:`alternating`).
    """
    N = int(loops)
    senses = alternating(N) if senses is None else senses
    theta = np.asarray(theta, float)
    w = 2.0 * math.pi / (N - 1)
    mid_layer = 0.5 * (N - 1)
    out = np.zeros((N, len(theta), 2))
    for i, layer in enumerate(start_layers(N)):
        r = np.zeros_like(theta)
        z = np.full_like(theta, spacing * (layer - mid_layer))
        for k in range(N - 1):
            upper, lower = N - 1 - k, N - 2 - k
            if layer not in (upper, lower):
                continue
            after = theta >= k * w
            turn = math.pi * smoothstep((theta - k * w) / w)
            sign = 1.0 if layer == upper else -1.0
            sense = float(senses[k])
            r = np.where(after, sense * sign * 0.5 * spacing * np.sin(turn), r)
            z = np.where(after, spacing * (0.5 * (upper + lower) - mid_layer)
                         + sign * 0.5 * spacing * np.cos(turn), z)
            layer = lower if layer == upper else upper
        out[i, :, 0], out[i, :, 1] = r, z
    return out


def fold_curve(loops: int, radius: float, spacing: float, per_loop: int = CURVE_POINTS,
               senses: tuple[int, ...] | None = None) -> np.ndarray:
    """Return the folded ring's closed polyline ``(N per_loop, 3)``, loops in turn from ``+e1``."""
    theta = np.arange(per_loop) * (2.0 * math.pi / per_loop)
    rz = fold_offsets(loops, theta, spacing, senses)
    rho = radius + rz[:, :, 0]
    return np.stack([rho * np.cos(theta), rho * np.sin(theta), rz[:, :, 1]],
                    axis=-1).reshape(-1, 3)


def _closed_length(C: np.ndarray) -> float:
    return float(np.linalg.norm(np.roll(C, -1, axis=0) - C, axis=1).sum())


def nearest_strands(C: np.ndarray, spacing: float) -> float:
    """Return the strands' distance: the nearest vertices of ``C`` far apart along it (length).

    ``C``: a closed polyline; vertices more than ``4 spacing`` apart along it count (not a
    strand's own neighbours). Vertices only (:data:`DISTANCE_POINTS` per loop: between nearly
    parallel strands that overstates the distance by ``<= step^2 / 8 s``); the built rod's
    elements are then checked segment to segment (:func:`~.stacking.check_stacked`).
    ``inf`` if no two strands come within ``1.1 spacing``.
    """
    step = np.linalg.norm(np.roll(C, -1, axis=0) - C, axis=1)
    along = np.concatenate([[0.0], np.cumsum(step)[:-1]])
    total = float(step.sum())
    P = cKDTree(C).query_pairs(1.1 * spacing, output_type="ndarray")
    if not len(P):
        return math.inf
    sep = np.abs(along[P[:, 0]] - along[P[:, 1]])
    far = np.minimum(sep, total - sep) > 4.0 * spacing
    if not far.any():
        return math.inf
    return float(np.linalg.norm(C[P[far, 0]] - C[P[far, 1]], axis=1).min())


def fold_loops(rod: DiscreteRod, thickness: float, gap: float,
               model: ContactModel | None = None, *, chord_allowance: bool = True,
               senses: tuple[int, ...] | None = None) -> StackedState:
    """Build the N-loop ring folded from an untwisted ring (odd ``N``) and check it.

    Parameters
    ----------
    rod : DiscreteRod
        The coincident N-loop ring (``discretise`` of ``rodstab.problems.ring.build``).
    thickness, gap : float
        ``h`` (capsule diameter) and ``g0 > 0`` (the gap between neighbouring strands), length.
    model : ContactModel, optional
        The check's contact model (default :func:`~.stacking.default_model`).
    chord_allowance : bool
        As :func:`~.stacking.stack_loops`: strands ``1.05 l^2 kappa_max / 4`` further apart, so
        the elements (chords) keep the gap ``g0``.
    senses : tuple of int, optional
        Each swap's sense (``+-1``, ``N - 1`` of them; default :func:`alternating`, the
        folded ring). Others build flat stackings of other writhe (the sum of the senses up
        to one sign): all alike is a flat form of the wound ring.

    Returns
    -------
    StackedState
        The layers (module doc), ``layers`` giving each segment's start layer ``(name, 0,
        k)``. Raises :class:`~rodstab.errors.RodstabInputError` for even ``N`` (no flat
        untwisted folding: module doc) and :class:`~.stacking.StackingError` if the check
        fails.
    """
    h = require_positive("thickness", thickness)
    g0 = require_positive("gap", gap)
    ring = coincident_loops(rod, "fold_loops")
    N, L = ring.loops, ring.length
    if senses is not None:
        senses = tuple(int(v) for v in senses)
        if N < 2 or len(senses) != N - 1 or any(v not in (-1, 1) for v in senses):
            raise RodstabInputError(f"senses must be {N - 1} values of +1 or -1 (one per "
                                    f"swap of {N} loops), got {senses!r}")
    elif N < 3 or N % 2 == 0:
        raise RodstabInputError(
            f"fold_loops: {N} loops; an untwisted ring folds flat into an odd number of loops "
            "(3, 5, ...): N layers need N - 1 swaps, whose writhe is odd for even N, so Lk = 0 "
            "would need twist (rodstab.multistable.folding); the wound ring (stack_loops) is "
            "built for any N")
    arcs = np.diff(np.append(ring.t, L))
    R0 = L / (2.0 * math.pi * N)
    target = h + g0
    chord_error = 0.0
    for _ in range(2 if chord_allowance else 1):
        s, R = fit_spacing(
            lambda s, R: nearest_strands(fold_curve(N, R, s, DISTANCE_POINTS, senses), s),
            lambda s, R: _closed_length(fold_curve(N, R, s, senses=senses)),
            target + CHORD_MARGIN * chord_error, L, target + CHORD_MARGIN * chord_error, R0,
            FOLD_RTOL, FOLD_MAX_ITER, f"fold_loops (N = {N}, h / R0 = {h / R0:.3g})")
        C = fold_curve(N, R, s, senses=senses)
        step = np.roll(C, -1, axis=0) - C
        ds = np.linalg.norm(step, axis=1)
        T = step / ds[:, None]
        kappa = np.linalg.norm(T - np.roll(T, 1, axis=0), axis=1) / ds
        chord_error = float(arcs.max()) ** 2 * float(kappa.max()) / 4.0
    if s >= 0.25 * R0:  # as the torus curve's circumradius: strands far off the loops' circle
        raise RodstabInputError(f"fold_loops: layer spacing {s:g} too large for {N} loops of "
                                f"radius {R0:g} (>= R0 / 4)")
    # the polyline's arclength, scaled to L (they differ by the fold's fixed-point tolerance)
    along = np.concatenate([[0.0], np.cumsum(ds)])
    closed = np.vstack([C, C[:1]])
    at = ring.t * (along[-1] / L)
    xyz = np.stack([np.interp(at, along, closed[:, k]) for k in range(3)], axis=1)
    Tn = T + np.roll(T, 1, axis=0)  # the tangent at each polyline point, centred
    Tn = np.vstack([Tn, Tn[:1]])
    tangent = np.stack([np.interp(at, along, Tn[:, k]) for k in range(3)], axis=1)
    new = ring.place(rod, xyz, tangent)
    check = check_stacked(new, default_model(h) if model is None else model, g0,
                          0.0 if chord_allowance else chord_error)
    w = 360.0 / (N - 1)
    sv = alternating(N) if senses is None else senses
    changes = tuple(
        f"layers {N - 1 - k} and {N - 2 - k} swap over azimuth {k * w:.4g}-{(k + 1) * w:.4g} "
        f"deg, the upper passing {'outside' if sv[k] > 0 else 'inside'}"
        for k in range(N - 1))
    # each segment's start layer: that of the loop its first node lies on
    where = np.empty(len(rod.x))
    where[ring.order] = ring.t
    first = [int(rod.edge_nodes[np.flatnonzero(rod.edge_segment == k)[0], 0])
             for k in range(len(rod.assembly.segments))]
    layers = tuple((sg.name, 0.0, float(start_layers(N)[min(int(where[i] * N / L + 1e-9),
                                                             N - 1)]))
                   for sg, i in zip(rod.assembly.segments, first, strict=True))
    return StackedState(
        rod=new, method=(f"folded: {N} flat layers {s:.6g} apart, {N - 1} swaps of "
                         + ("alternating sense (writhe 0)" if senses is None else
                            f"senses {list(senses)}") + f", R = {R:.9g}"),
        thickness=h, gap=g0, layers=layers, changes=changes, chord_error=chord_error,
        max_strain=_strain(new),
        max_offset=float(np.max(np.linalg.norm(new.x - rod.x, axis=1))), check=check)


def layer_swaps(rod: DiscreteRod, samples: int = 720) -> np.ndarray:
    """Azimuths (rad, from the first node's) where a stacked N-loop ring's layer order changes.

    ``rod``: a state of an N-loop ring (its azimuth about the nodes' centre turning ``N``
    times along the traversal). The loops' heights are interpolated on ``samples`` azimuths
    of one turn (nodes in traversal order, azimuth unwrapped); returned: the azimuths at
    which the strands' order in height differs from the one a sample before (a swap's
    middle, to one sample). Going once round, loop ``k`` continues as loop ``k + 1``, which
    the comparison at azimuth 0 accounts for. Empty for a state that does not wind round
    its centre twice or more (a ring snapped open into one loop, or further).
    """
    X = rod.x[_traversal(rod)]
    c = X.mean(axis=0)
    az = np.unwrap(np.arctan2(X[:, 1] - c[1], X[:, 0] - c[0]))
    az = (az - az[0]) * np.sign(az[-1] - az[0])
    N = round(float(az[-1]) / (2.0 * math.pi))
    theta = np.arange(samples) * (2.0 * math.pi / samples)
    if N < 2:  # one turn (or none) about the centre: no layers to swap
        return theta[:0]
    closed_az, closed_z = np.append(az, 2.0 * math.pi * N), np.append(X[:, 2], X[0, 2])
    Z = [np.interp(theta + 2.0 * math.pi * k, closed_az, closed_z) for k in range(N)]
    rank = np.argsort(np.argsort(np.array(Z), axis=0), axis=0)
    changed = np.empty(samples, bool)
    changed[1:] = np.any(rank[:, 1:] != rank[:, :-1], axis=0)
    changed[0] = np.any(rank[:, 0] != np.roll(rank[:, -1], 1))
    return theta[changed]


def flat_foldings(rod: DiscreteRod, thickness: float) -> tuple[int | None, int | None, float]:
    """Return the smallest ``|Lk|`` of the N-loop ring's flat foldings, by both evaluations.

    ``rod``: the coincident N-loop ring (as :func:`fold_loops`); ``thickness``: ``h``
    (length), ``g0 = 0.05 h``. For even ``N`` every sequence of ``N - 1`` swap senses
    (:func:`fold_loops` with ``senses``; ``2^(N-1)`` of them), for odd ``N`` the alternating
    one, is built and its ribbon's linking number taken by Gauss's integral (rounded) and by
    signed crossings (:mod:`.linking`). Returns ``(min |Lk| by Gauss, min |Lk| by crossings of
    the first projection, largest |Tw|)``; ``Tw`` (turns) is the edge frames' own twist,
    summed. A number not given by an evaluation makes its entry None. The module doc's parity
    argument says the minimum is 0 for odd ``N`` and 1 for even ``N``.
    """
    import itertools

    from .linking import self_linking

    N = coincident_loops(rod, "flat_foldings").loops
    h = require_positive("thickness", thickness)
    gauss: list[int | None] = []
    cross: list[int | None] = []
    twist = 0.0
    for senses in (itertools.product((1, -1), repeat=N - 1) if N % 2 == 0
                   else [alternating(N)]):
        built = fold_loops(rod, h, 0.05 * h, senses=senses).rod
        lk = self_linking(built)
        gauss.append(None if lk.gauss is None else abs(round(lk.gauss)))
        cross.append(abs(lk.crossings[0]) if lk.crossings else None)
        twist = max(twist, abs(float(np.sum(built.edge_twist()))) / (2.0 * math.pi))

    def smallest(v: list[int | None]) -> int | None:
        return None if None in v else min(k for k in v if k is not None)

    return smallest(gauss), smallest(cross), twist


def folded_layers(loops: int, theta: np.ndarray) -> np.ndarray:
    """Return each loop's layer at azimuths ``theta`` (rad), the folded ring at zero gap.

    ``(N, k)``: the construction's layers (:func:`start_layers`, swap ``j`` exchanging layers
    ``N - 1 - j`` and ``N - 2 - j``) with every swap shrunk to a point, the middle of its window,
    ``(j + 1/2) 2 pi / (N - 1)``: there the two swapping loops get the mean of their layers (no
    longer one layer apart, so they do not touch at that point). Two loops touch where their
    layers differ by one, the upper one on top (the cone's pairs,
    :func:`~.cone.touching_pairs` with ``"folded"``).
    """
    N = int(loops)
    if N < 2:
        raise RodstabInputError(f"folded layers need 2 or more loops, got {loops!r}")
    theta = np.asarray(theta, float)
    w = 2.0 * math.pi / (N - 1)
    out = np.empty((N, len(theta)))
    for i, layer0 in enumerate(start_layers(N)):
        layer = float(layer0)
        L = np.full(len(theta), layer)
        for j in range(N - 1):
            upper, lower = N - 1 - j, N - 2 - j
            if layer not in (upper, lower):
                continue
            other = float(lower if layer == upper else upper)
            at = (j + 0.5) * w
            L = np.where(np.isclose(theta, at, rtol=0.0, atol=1e-12), 0.5 * (layer + other),
                         np.where(theta > at, other, L))
            layer = other
        out[i] = L
    return out
