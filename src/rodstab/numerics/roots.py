"""Roots of scalar and matrix characteristic equations, and the one multiplicity rule.

* :func:`find_roots` -- roots of a real scalar function on an interval: scan on a uniform grid,
  bracket every sign change and every near-zero local minimum of ``|f|`` (a root of even
  multiplicity, where ``f`` touches zero without changing sign), refine (Brent), and estimate
  each root's multiplicity from the local order of vanishing.
* :func:`matrix_roots` -- values ``x`` where a square matrix ``A(x)`` is singular: scan the
  *smallest singular value* relative to the largest (never only a determinant's sign, which
  misses repeated roots), refine the minimum, polish by the determinant's sign change when there
  is one, and report the multiplicity as the number of (near-)zero singular values.
* :func:`multiplicity_tolerance`, :func:`multiplicity_of` -- the one multiplicity rule, used by
  every method (here and by the eigen solvers of :mod:`.eigen`).

The accuracy statement ("never miss a root") is in :mod:`rodstab.numerics`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import RodstabInputError
from ..results import Result

#: Default number of scan intervals on the search interval.
SCAN_INTERVALS = 400
#: A non-crossing local minimum of |f| is a root when |f| <= TOUCH_TOL * max|f| over the scan.
TOUCH_TOL = 1e-8
#: Relative tolerance of the smallest singular value below which a matrix counts as singular.
SINGULAR_TOL = 1e-8
#: A singular point found without a determinant sign change (even multiplicity) must reach this
#: smaller sigma ratio.
TOUCH_SINGULAR_TOL = 1e-11
#: Relative x-tolerance of the refinement (Brent); the absolute part is this times the span.
XTOL = 1e-14
#: Subintervals per scan interval of the local re-scan around a minimum of |f| or sigma_min.
SUBSCAN = 16
#: Eigenvalues within this relative distance are counted as one repeated eigenvalue when the
#: method states no error of its own (:func:`multiplicity_tolerance`).
MULTIPLICITY_RTOL = 1e-6
#: A complex matrix's determinant (row-scaled) keeps one phase over the scan when its part
#: across that phase is below this times its largest modulus (:func:`matrix_roots`).
COMPLEX_PHASE_TOL = 1e-8
#: Machine epsilon (the round-off floor of :func:`multiplicity_tolerance`).
EPS = float(np.finfo(float).eps)
#: The one multiplicity rule (:func:`multiplicity_tolerance`): two computed eigenvalues (roots)
#: are one multiple eigenvalue when they differ by at most this many times the method's error
#: estimate. A discretisation that breaks a symmetry splits an exact pair by up to the sum of
#: the two values' errors (2x the estimate), and an estimate (Richardson, a-priori bound) is
#: itself good to a factor ~2: hence 4.
MULTIPLICITY_ERROR_FACTOR = 4.0


def _brentq() -> Any:
    """Return scipy's Brent root finder, imported on first use.

    ``scipy.optimize`` costs ~0.3 s to import; an analytic CLI answer needs it only when it
    refines a root (issue 12: start-up time).
    """
    from scipy.optimize import brentq

    return brentq


@dataclasses.dataclass(frozen=True)
class Root(Result):
    """One root of a scalar or matrix characteristic equation.

    Attributes
    ----------
    x : float
        The root.
    multiplicity : int
        Order of vanishing of ``f`` (scalar) or number of zero singular values (matrix).
    residual : float
        ``|f(x)|`` (scalar) or ``sigma_min / sigma_max`` (matrix) at the root.
    bracket : tuple of float
        The scan interval the root was refined in.
    kind : str
        ``"sign-change"``, ``"touching"`` (even order, no sign change) or ``"grid-point"``.
    """

    x: float
    multiplicity: int
    residual: float
    bracket: tuple[float, float]
    kind: str


@dataclasses.dataclass(frozen=True)
class RootSearch(Result):
    """All roots found on an interval, in increasing order, with the scan's diagnostics."""

    roots: tuple[Root, ...]
    interval: tuple[float, float]
    n_scan: int
    converged: bool
    method: str

    @property
    def values(self) -> list[float]:
        """The roots' locations, increasing."""
        return [r.x for r in self.roots]


_GOLD = 0.5 * (math.sqrt(5.0) - 1.0)


def golden_min(g: Callable[[float], float], a: float, b: float, xtol: float) -> tuple[float, float]:
    """Minimum of a unimodal ``g`` on ``[a, b]`` by golden-section search, to ``xtol``.

    Used instead of parabolic (Brent) minimisation because the measures minimised here,
    ``|f|`` and ``sigma_min``, are V-shaped at a simple root, where parabolic steps stall far
    from the kink.
    """
    c, d = b - _GOLD * (b - a), a + _GOLD * (b - a)
    gc, gd = g(c), g(d)
    while b - a > xtol:
        if gc <= gd:
            b, d, gd = d, c, gc
            c = b - _GOLD * (b - a)
            gc = g(c)
        else:
            a, c, gc = c, d, gd
            d = a + _GOLD * (b - a)
            gd = g(d)
    x = 0.5 * (a + b)
    return x, g(x)


def refine_root(f: Callable[[float], float], a: float, b: float, *,
                rel_xtol: float = XTOL) -> float:
    """Refine the root of ``f`` in ``[a, b]``, where ``f(a)`` and ``f(b)`` differ in sign.

    The refinement step of :func:`find_roots` alone (Brent, bisection where it stalls), to
    ``rel_xtol * |b - a|``, for a caller that already holds a sign-change bracket (e.g. a
    stability change between two steps of a path, where each evaluation is a Newton solve and
    a scan would cost dozens). Raises :class:`RodstabInputError` if the signs do not differ.
    """
    lo, hi = min(a, b), max(a, b)
    if not (f(lo) * f(hi) < 0):
        raise RodstabInputError(f"refine_root: f has no sign change on [{lo!r}, {hi!r}]")
    return _bracketed_root(f, lo, hi, rel_xtol * (hi - lo))


def _bracketed_root(f: Callable[[float], float], a: float, b: float, xtol: float) -> float:
    """Root in a sign-change bracket: Brent, falling back to bisection where Brent stalls.

    Brent can fail to converge on a root of high odd order (``(x - 1)^3``), where ``f`` is
    flat; bisection on the same bracket always converges (to ``xtol``).
    """
    try:
        return float(_brentq()(f, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=500))
    except RuntimeError:
        fa = f(a)
        while b - a > xtol:
            m = 0.5 * (a + b)
            fm = f(m)
            if fm == 0.0:
                return m
            if (fm < 0) == (fa < 0):
                a, fa = m, fm
            else:
                b = m
        return 0.5 * (a + b)


def _order_of_vanishing(g: Callable[[float], float], x0: float, h: float) -> int:
    """Estimate the order ``m`` in ``|g(x)| ~ c |x - x0|^m`` from two symmetric step sizes."""
    vals = []
    for step in (h, 2 * h):
        vals.append(0.5 * (abs(g(x0 + step)) + abs(g(x0 - step))))
    if vals[0] <= 0 or vals[1] <= 0:
        return 1
    m = math.log(vals[1] / vals[0]) / math.log(2.0)
    return max(1, int(round(m)))


def multiplicity_tolerance(value: float, error: float | None = None) -> float:
    """Distance within which computed eigenvalues (roots) are one multiple eigenvalue at ``value``.

    The one multiplicity rule of rodstab, used by every method (FE, transfer/Bloch, closed
    forms): :data:`MULTIPLICITY_ERROR_FACTOR` times the method's error estimate ``error``
    (absolute, in the units of ``value``: an FE mesh error from a Richardson estimate, a root
    finder's tolerance; never below a few units of round-off), or :data:`MULTIPLICITY_RTOL`
    ``|value|`` when the method states no error (None). Values farther apart are distinct:
    two methods then agree on a multiplicity wherever the split is outside both their
    tolerances, and within a method's tolerance it cannot tell (the near-coincident symmetric
    and antisymmetric roots of a clamped arc near L/R = 2 pi: 1 by a closed form at 1e-12,
    2 by an FE at 1e-7).
    """
    if error is None or not math.isfinite(error):
        return MULTIPLICITY_RTOL * abs(value)
    return max(MULTIPLICITY_ERROR_FACTOR * abs(error), 16.0 * EPS * abs(value))


def multiplicity_of(values: Any, value: float, error: float | None = None,
                    errors: Any = None) -> int:
    """Count the ``values`` that are one multiple eigenvalue with ``value`` (the rule above).

    ``values`` are the computed eigenvalues (roots) near ``value``, ``value`` among them; 0 for
    a non-finite ``value`` (no eigenvalue bounds that side). ``errors``, when given, is each
    value's own error estimate (same length as ``values``): a value then joins ``value`` if
    their distance is within the tolerance of the LARGER of the two errors (``error`` being
    ``value``'s). A mesh splits a symmetry pair by the error of its worse-resolved member,
    which can be ten times that of the better one (a 3-rod cusp ring, b1 = 5.2, b2 = 48.6,
    theta = 60 deg: the pair at -25.8007389 is split 2.3e-9 at 64 elements per rod, where
    the lower member's estimate is 2.5e-10 and the upper's 2.3e-9; Bloch: double).
    """
    if not math.isfinite(value):
        return 0
    v = np.asarray(values, dtype=float)
    if errors is None:
        return int(np.sum(np.abs(v - value) <= multiplicity_tolerance(value, error)))
    e = np.asarray(errors, dtype=float)
    if e.shape != v.shape:
        raise ValueError(f"errors has shape {e.shape}, values {v.shape}")
    own = 0.0 if error is None or not math.isfinite(error) else abs(error)
    count = 0
    for x, ex in zip(v, e, strict=True):
        worst = max(own, abs(ex)) if math.isfinite(ex) else error
        count += bool(abs(x - value) <= multiplicity_tolerance(value, worst))
    return count


def find_roots(
    f: Callable[[float], float],
    lo: float,
    hi: float,
    *,
    n_scan: int = SCAN_INTERVALS,
    touch_tol: float = TOUCH_TOL,
    method_name: str = "scan+brent",
    rel_xtol: float = XTOL,
) -> RootSearch:
    """Find every root of a real scalar function on ``[lo, hi]``.

    Parameters
    ----------
    f : callable
        Real scalar function of one real variable, continuous on ``[lo, hi]``.
    lo, hi : float
        Search interval, ``lo < hi``.
    n_scan : int
        Number of uniform scan intervals (see the module docstring for what this guarantees).
    touch_tol : float
        A local minimum of ``|f|`` without sign change is accepted as a root when its refined
        value is at most ``touch_tol * max|f|`` over the scan.
    rel_xtol : float
        Roots are refined to ``rel_xtol * (hi - lo)`` (default ``XTOL``); a coarser value saves
        evaluations of an expensive ``f`` whose root is wanted only to a few digits.

    Returns
    -------
    RootSearch
        Roots in increasing order; each with ``|f(x)|`` as its residual. Sign-change roots are
        refined by Brent's method to ``XTOL * (hi - lo)``.
    """
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise RodstabInputError(f"find_roots needs finite lo < hi, got lo={lo!r}, hi={hi!r}")
    xs = np.linspace(lo, hi, n_scan + 1)
    fs = np.array([f(float(x)) for x in xs], dtype=float)
    finite = np.isfinite(fs)
    scale = float(np.max(np.abs(fs[finite]))) if finite.any() else 1.0
    scale = scale if scale > 0 else 1.0
    xtol = rel_xtol * (hi - lo)
    h_order = 1e-4 * (hi - lo) / n_scan
    roots: list[Root] = []
    converged = bool(finite.all())
    sg = np.sign(fs)  # signs, not products: f values may be huge (no overflow)

    def sign_change_root(a: float, b: float, fa: float, fb: float) -> None:
        x = _bracketed_root(f, a, b, xtol)
        fx = abs(f(x))
        # A sign change through a pole is not a root: there |f| grows as the bracket shrinks.
        # A root refined to xtol leaves |f| up to ~slope * xtol (the second bound: a coarse
        # rel_xtol must not turn a root into a "pole").
        slope = abs(fb - fa) / (b - a)
        if fx > max(1e-3 * min(abs(fa), abs(fb)), 10.0 * slope * xtol) \
                and fx > touch_tol * scale:
            return
        m = _order_of_vanishing(f, x, min(h_order, 0.25 * (b - a)))
        m = m if m % 2 == 1 else m + 1  # a sign change has odd order
        roots.append(Root(float(x), m, fx, (float(a), float(b)), "sign-change"))

    def exact_zero(x: float, a: float, b: float) -> None:
        m = _order_of_vanishing(f, x, min(h_order, 0.25 * (b - a)))
        roots.append(Root(float(x), m, 0.0, (float(a), float(b)), "grid-point"))

    regions: list[int] = []  # grid indices around which a finer local scan is needed
    for i in range(n_scan):
        if not (finite[i] and finite[i + 1]):
            continue
        if sg[i] * sg[i + 1] < 0:
            sign_change_root(xs[i], xs[i + 1], fs[i], fs[i + 1])
    for i in range(n_scan + 1):
        if not finite[i]:
            continue
        if fs[i] == 0.0:
            regions.append(i)  # a root on the grid: a close neighbour may hide beside it
        elif 0 < i < n_scan and finite[i - 1] and finite[i + 1] \
                and sg[i - 1] == sg[i] == sg[i + 1] \
                and abs(fs[i]) <= abs(fs[i - 1]) and abs(fs[i]) <= abs(fs[i + 1]):
            regions.append(i)  # |f| dips without a sign change: touching root, or a close pair
    for i in regions:
        a, b = xs[max(i - 1, 0)], xs[min(i + 1, n_scan)]
        # Odd count of sub-intervals: the grid point x_i is not a sub-grid point, so a root on
        # the grid is bracketed like any other.
        sub = np.linspace(a, b, 2 * SUBSCAN + 2)
        fsub = np.array([f(float(t)) for t in sub])
        ssub = np.sign(fsub)
        if fs[i] == 0.0:
            exact_zero(xs[i], a, b)
        before = len(roots)
        for k in range(len(sub) - 1):
            if ssub[k] == 0.0:
                exact_zero(sub[k], sub[max(k - 1, 0)], sub[min(k + 1, len(sub) - 1)])
            elif ssub[k] * ssub[k + 1] < 0:
                sign_change_root(sub[k], sub[k + 1], fsub[k], fsub[k + 1])
        if len(roots) > before or fs[i] == 0.0:
            continue
        x, fx = golden_min(lambda t: abs(f(t)), a, b, xtol)
        if fx <= touch_tol * scale:
            m = _order_of_vanishing(f, x, h_order)
            m = m if m % 2 == 0 else m + 1  # no sign change: even order
            roots.append(Root(float(x), m, float(fx), (float(a), float(b)), "touching"))
    roots.sort(key=lambda r: r.x)
    merged: list[Root] = []
    for r in roots:  # a root found both by the coarse and by a local scan
        if merged and abs(r.x - merged[-1].x) <= 1e3 * xtol:
            # Keep an exact zero's location and label; the larger multiplicity estimate wins.
            keep, other = (merged[-1], r) if merged[-1].kind == "grid-point" else (r, merged[-1])
            merged[-1] = dataclasses.replace(
                keep, multiplicity=max(keep.multiplicity, other.multiplicity))
            continue
        merged.append(r)
    return RootSearch(tuple(merged), (float(lo), float(hi)), n_scan, converged, method_name)


def _sv_ratio(A: np.ndarray) -> tuple[float, np.ndarray]:
    s = np.linalg.svd(A, compute_uv=False)
    return (float(s[-1] / s[0]) if s[0] > 0 else 0.0), s


#: Step (relative to ``max(|x|, 1)``) of the one-sided differences by which
#: :func:`_null_dimension` measures how fast a small singular value vanishes.
NULL_SLOPE_STEP = 1e-4


def _null_dimension(matrix: Callable[[float], np.ndarray], x: float, s: np.ndarray,
                    ref: float, singular_tol: float) -> int:
    """Dimension of the null space of ``matrix(x)`` at a root ``x`` (``s``: its singular values).

    A singular value at or below ``singular_tol ref`` (the level at which a root is accepted)
    is null. One between that and ``sqrt(singular_tol) ref`` is null only if it belongs to a
    root within the one multiplicity rule's distance of ``x``: its own root lies at
    ``~ sigma / |d sigma / dx|`` (a singular value of an analytic matrix vanishes linearly at a
    simple root), measured by one-sided differences of :data:`NULL_SLOPE_STEP`. Counting every
    singular value below ``sqrt(singular_tol) ref`` alone made ill-conditioned transfer
    matrices report phantom multiplicities: the Bloch harmonic 3 of an 8-rod cusp ring's eight
    (b1 = 0.096, b2 = 43.9) has two singular values at 9e-6 of the largest, whose roots are
    0.12 away: multiplicity 4 where the FE and the exact symmetry give 2.
    """
    loose, tight = math.sqrt(singular_tol) * ref, singular_tol * ref
    count = int(np.sum(s <= tight))
    unsure = [k for k in range(s.size) if tight < s[k] <= loose]
    if not unsure:
        return count
    step = NULL_SLOPE_STEP * max(abs(x), 1.0)
    near = [np.linalg.svd(matrix(x + d), compute_uv=False) for d in (step, -step)]
    for k in unsure:
        slope = max(abs(float(sv[k]) - float(s[k])) for sv in near) / step
        if slope > 0 and s[k] / slope <= multiplicity_tolerance(x):
            count += 1
    return count


def matrix_roots(
    matrix: Callable[[float], np.ndarray],
    lo: float,
    hi: float,
    *,
    n_scan: int = SCAN_INTERVALS,
    singular_tol: float = SINGULAR_TOL,
    known_nullity: int = 0,
    method_name: str = "scan sigma_min + brent",
    grid: np.ndarray | None = None,
    touch_tol: float = TOUCH_SINGULAR_TOL,
    absolute: bool = False,
) -> RootSearch:
    """Find every ``x`` in ``[lo, hi]`` at which the square matrix ``matrix(x)`` is singular.

    The scan measure is ``g(x) = sigma_min(A) / sigma_max(A)`` (non-negative, zero exactly at a
    root, whatever the multiplicity). Every sign change of the (row-scaled) determinant on the grid
    is refined by Brent's method (full precision) and kept when ``g <= singular_tol`` there.
    At every other local minimum of ``g`` a finer local grid is searched for determinant sign
    changes (two roots closer than a scan spacing); failing that, ``g`` is minimised by
    golden-section search and the point is a root of even multiplicity in the determinant when
    ``g <= singular_tol``. The multiplicity is the number of singular values
    ``<= sqrt(singular_tol)``
    times ``sigma_max`` at the root (the dimension of the null space).

    ``grid`` (optional): the increasing scan points, from ``lo`` to ``hi``, in place of the
    ``n_scan`` uniform intervals -- for a caller that knows where roots crowd (a phase that
    turns fast in one part of the interval), so the guarantee of the module docstring holds
    with the local spacing. ``touch_tol``: the ratio a minimum without a determinant sign
    change must reach (default :data:`TOUCH_SINGULAR_TOL`); a caller whose matrix has no
    ill-conditioned non-roots but a round-off floor above it at its roots may raise it up to
    ``singular_tol``. A rectangular ``matrix(x)`` (rank loss, no determinant) is searched by
    its minima alone. ``absolute=True`` scans ``sigma_min`` over the scan's median
    ``sigma_max`` alone, for a matrix that vanishes as a whole at its roots (every singular
    value together, a mode of multiplicity equal to its column count): there the ratio to the
    local ``sigma_max`` stays finite and shows no dip.

    A complex ``matrix(x)`` is searched the same way; its determinant gives a sign only if it
    keeps one phase over the scan (its part across the phase of the largest value below
    :data:`COMPLEX_PHASE_TOL` of it, as for a Bloch matrix of a self-adjoint problem,
    whose ``rho^(-n/2) det`` is real); otherwise every root is found by the minima alone. The
    multiplicity is the complex null space's dimension.
    """
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise RodstabInputError(f"matrix_roots needs finite lo < hi, got lo={lo!r}, hi={hi!r}")
    r = known_nullity

    if grid is None:
        xs = np.linspace(lo, hi, n_scan + 1)
    else:
        xs = np.asarray(grid, dtype=float)
        if xs.ndim != 1 or xs.size < 3 or not np.all(np.diff(xs) > 0) \
                or xs[0] != lo or xs[-1] != hi:
            raise RodstabInputError("matrix_roots: grid must be increasing, at least 3 points, "
                                    f"from lo={lo!r} to hi={hi!r}")
        n_scan = xs.size - 1
    # One stack: numpy's batched SVD and determinant call LAPACK per matrix as the single
    # calls do (the same numbers), without the Python cost per call; and each scan matrix is
    # formed once, for both.
    mats = np.stack([matrix(float(x)) for x in xs])
    square = mats.shape[1] == mats.shape[2]
    svals = np.linalg.svd(mats, compute_uv=False)
    # Reference size: the median largest singular value over the scan. Dividing by
    # max(sigma_max, s_ref) instead of sigma_max alone keeps the measure relative where A is
    # large, yet still sees a root at which every singular value vanishes together (A = (x-1) I).
    s_ref = float(np.median([sv[0] for sv in svals])) or 1.0

    def _ratio(s: np.ndarray) -> float:
        if absolute:
            return float(s[-1 - r] / s_ref)
        if r == 0:
            return float(s[-1] / max(s[0], s_ref))
        return float(s[-1 - r] / (1.0 + s[0]))

    def _measure(A: np.ndarray) -> tuple[float, np.ndarray]:
        s = np.linalg.svd(A, compute_uv=False)
        return _ratio(s), s

    def g(x: float) -> float:
        return _measure(matrix(float(x)))[0]

    gs = np.array([_ratio(sv) for sv in svals])  # the scan's singular values, not again
    smax_grid = np.array([sv[0] for sv in svals])
    xtol = XTOL * (hi - lo)

    def is_pole(x: float, a: float, b: float) -> bool:
        """sigma_max blowing up between two scan points is a pole of A, not a root."""
        local = max(float(np.max(smax_grid[(xs >= a - 1e-15) & (xs <= b + 1e-15)], initial=0.0)),
                    s_ref)
        return float(np.linalg.svd(matrix(x), compute_uv=False)[0]) > 1e6 * local

    def scaled_det(A: np.ndarray) -> np.ndarray:
        """Return the determinant(s) of the row-scaled matrix or stack ``A`` (1: rectangular)."""
        if A.shape[-2] != A.shape[-1]:
            return np.ones(A.shape[:-2])  # rank loss is seen by sigma_min only (no sign)
        # Scale rows so the determinant neither under- nor overflows; the sign is unchanged.
        norms = np.linalg.norm(A, axis=-1)
        norms[norms == 0] = 1.0
        return np.linalg.det(A / norms[..., None])

    signs = r == 0 and square  # a determinant sign to scan and to polish on
    ds = scaled_det(mats) if signs else np.ones(n_scan + 1)
    phase = 1.0 + 0.0j
    if signs and np.iscomplexobj(ds):
        # A complex matrix: its determinant's sign is taken along the one phase it keeps
        # (a Bloch matrix of a self-adjoint problem, ``rho^(-n/2) det`` real: module
        # docstring); a phase that is not fixed over the scan gives no sign.
        big = int(np.argmax(np.abs(ds)))
        phase = np.conj(ds[big]) / abs(ds[big]) if ds[big] != 0 else phase
        rotated = ds * phase
        if np.max(np.abs(rotated.imag)) > max(COMPLEX_PHASE_TOL * abs(ds[big]), 1e-13):
            signs, ds = False, np.ones(n_scan + 1)
        else:
            ds = rotated.real

    def det(x: float) -> float:
        return float(np.real(scaled_det(matrix(float(x))) * phase))

    roots: list[Root] = []
    eps4 = 4 * np.finfo(float).eps

    def add_sign_change(xa: float, xb: float) -> None:
        x = float(_brentq()(det, xa, xb, xtol=xtol, rtol=eps4))
        gx = g(x)
        if gx <= singular_tol and not is_pole(x, xa, xb):
            _, s = _sv_ratio(matrix(x))
            mult = _null_dimension(matrix, x, s, max(s[0], s_ref), singular_tol)
            roots.append(Root(x, max(mult, 1), gx, (float(xa), float(xb)), "sign-change"))

    del mats
    for i in range(n_scan):
        if np.sign(ds[i]) * np.sign(ds[i + 1]) < 0:
            add_sign_change(xs[i], xs[i + 1])
        elif r == 0 and ds[i] == 0.0 and 0 < i and np.sign(ds[i - 1]) * np.sign(ds[i + 1]) < 0:
            # A simple root exactly on a grid point: the determinant changes sign across it.
            x = float(xs[i])
            _, s = _measure(matrix(x))
            mult = _null_dimension(matrix, x, s, max(s[0], s_ref), singular_tol)
            roots.append(Root(x, max(mult, 1), g(x), (float(xs[i - 1]), float(xs[i + 1])),
                              "sign-change"))
    candidates = [i for i in range(1, n_scan) if gs[i] <= gs[i - 1] and gs[i] <= gs[i + 1]]
    for end in (0, n_scan):
        if gs[end] <= singular_tol:
            candidates.append(end)
    for i in candidates:
        a, b = xs[max(i - 2, 0)], xs[min(i + 2, n_scan)]
        # A root already found explains this minimum only if it lies in the minimum's own
        # basin (the neighbouring scan points): g falls from i - 1 to i, which a root beyond
        # i - 1 does not cause. (Skipping within two spacings lost the second of two roots 2.2
        # spacings apart: a 6-loop ring's upper limit by the Bloch method.)
        if any(xs[max(i - 1, 0)] <= r.x <= xs[min(i + 1, n_scan)] for r in roots):
            continue
        # No sign change of det next to this minimum of g: either a root of even multiplicity,
        # or two simple roots closer than one scan spacing. A finer local grid tells them apart.
        sub = np.linspace(a, b, 4 * SUBSCAN + 1)
        dsub = (np.real(scaled_det(np.stack([matrix(float(t)) for t in sub])) * phase)
                if signs else np.ones(len(sub)))
        n_before = len(roots)
        for k in range(4 * SUBSCAN):
            if np.sign(dsub[k]) * np.sign(dsub[k + 1]) < 0:
                add_sign_change(sub[k], sub[k + 1])
        if len(roots) > n_before:
            continue
        x, gx = golden_min(g, xs[max(i - 1, 0)], xs[min(i + 1, n_scan)], xtol)
        # No sign change to polish on: demand the stricter TOUCH_SINGULAR_TOL, since a merely
        # ill-conditioned matrix (sigma ratio ~1e-9, e.g. a long hyperbolic shooting interval)
        # must not pass for singular; golden search on a genuine zero reaches ~1e-13 or below.
        if gx > min(singular_tol, touch_tol) or is_pole(x, a, b):
            continue
        _, s = _measure(matrix(x))
        ref = max(s[0], s_ref) + (1.0 if r else 0.0)
        mult = _null_dimension(matrix, x, s, ref, singular_tol) - r
        roots.append(Root(x, max(mult, 1), gx, (float(a), float(b)), "touching"))
    roots.sort(key=lambda r: r.x)
    # Merge duplicates found from adjacent candidates.
    merged: list[Root] = []
    for root in roots:
        if merged and abs(root.x - merged[-1].x) <= 1e3 * xtol + 1e-10 * abs(root.x):
            continue
        merged.append(root)
    return RootSearch(tuple(merged), (float(lo), float(hi)), n_scan, True, method_name)


def sigma_min_2x2(a11: np.ndarray, a22: np.ndarray, a12: np.ndarray) -> np.ndarray:
    """Smallest singular values of symmetric 2x2 matrices ``[[a11, a12], [a12, a22]]``.

    Vectorised, in closed form: ``sigma_max^2 = (F + sqrt(F^2 - 4 det^2)) / 2`` (``F`` the
    squared Frobenius norm) and ``sigma_min = |det| / sigma_max``, which keeps its relative
    accuracy at a root of ``det`` (where the difference formula would cancel): the residual
    check of the closed-form mode pencils of the analytic modules.
    """
    det = a11 * a22 - a12 * a12
    F = a11 * a11 + a22 * a22 + 2.0 * a12 * a12
    smax = np.sqrt(0.5 * (F + np.sqrt(np.maximum(F * F - 4.0 * det * det, 0.0))))
    return np.abs(det) / np.maximum(smax, 1e-300)
