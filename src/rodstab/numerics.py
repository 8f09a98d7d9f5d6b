"""The one root finder and the one eigen solver of rodstab.

Every characteristic equation and every linear stability pencil in the package goes through
this module, so that the accuracy statement is made once:

* :func:`find_roots` -- roots of a real scalar function on an interval: scan on a uniform grid,
  bracket every sign change and every near-zero local minimum of ``|f|`` (a root of even
  multiplicity, where ``f`` touches zero without changing sign), refine (Brent), and estimate
  each root's multiplicity from the local order of vanishing.
* :func:`matrix_roots` -- values ``x`` where a square matrix ``A(x)`` is singular: scan the
  *smallest singular value* relative to the largest (never only a determinant's sign, which
  misses repeated roots), refine the minimum, polish by the determinant's sign change when there
  is one, and report the multiplicity as the number of (near-)zero singular values.
* :func:`lowest_eigenpairs` -- the lowest eigenpairs of a sparse symmetric matrix (dense
  solver for small ones, shift-invert Lanczos with an inertia-certified shift beyond), each
  pair's residual checked; :func:`jacobi_scaling` is the one diagonal scaling used before it
  and before the sparse pencil solve.
* :func:`pencil_interval` -- for a pencil ``K(p) = A - p C`` with ``A`` symmetric positive
  definite, the open interval of the load parameter ``p`` containing 0 on which ``K(p)`` stays
  positive definite, with the critical modes, their multiplicities and residuals.

"Never miss a root" is stated precisely: every root ``x*`` of ``f`` that is separated from every
other root by more than two scan spacings ``h = (hi - lo) / n_scan`` is found; a pair of simple
roots closer than that is still found when it is separated by more than ``h / SUBSCAN`` (a
local re-scan at every minimum of the scan measure); closer pairs may be returned as one root
whose multiplicity counts both.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .errors import NotConverged, RodstabInputError
from .results import Result

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
#: Converged when every critical eigenvector's relative residual is below this; for a
#: symmetric pencil the eigenvalue error is of the order of the residual squared.
SPARSE_RESIDUAL_TOL = 1e-6
#: Subintervals per scan interval of the local re-scan around a minimum of |f| or sigma_min.
SUBSCAN = 16
#: Eigenvalues within this relative distance are counted as one repeated eigenvalue when the
#: method states no error of its own (:func:`multiplicity_tolerance`).
MULTIPLICITY_RTOL = 1e-6
#: Machine epsilon (the round-off floor of :func:`multiplicity_tolerance`).
EPS = float(np.finfo(float).eps)
#: The one multiplicity rule (:func:`multiplicity_tolerance`): two computed eigenvalues (roots)
#: are one multiple eigenvalue when they differ by at most this many times the method's error
#: estimate. A discretisation that breaks a symmetry splits an exact pair by up to the sum of
#: the two values' errors (2x the estimate), and an estimate (Richardson, a-priori bound) is
#: itself good to a factor ~2: hence 4.
MULTIPLICITY_ERROR_FACTOR = 4.0
#: Up to this many unknowns :func:`lowest_eigenpairs` uses a dense solver; beyond, shift-invert
#: Lanczos (tested against the dense solver, tests/test_paths.py). The dense solve is O(n^3)
#: and, with a multithreaded BLAS on a loaded machine, slow already at a few hundred unknowns
#: (0.85 s at 300 measured on 2 busy cores, 0.006 s sparse).
DENSE_EIG_MAX = 200
#: Largest matrix :func:`lowest_eigenpairs` solves densely when Lanczos does not converge
#: (LAPACK eigh of 4000 unknowns: ~10 s on one core).
DENSE_FALLBACK_MAX = 4000
#: :func:`lowest_eigenpairs` has converged when every pair's residual ``|A v - lam v|`` is
#: below this times ``max |A_ij|`` (ARPACK's own test is relative to the shifted-inverted
#: eigenvalue, which says little about a tiny eigenvalue of a stiff matrix).
EIG_RESIDUAL_TOL = 1e-8
#: The Lanczos shift of :func:`lowest_eigenpairs` lies at least twice this times ``max |A_ij|``
#: below the lowest eigenvalue (when that is ~0): a few units of round-off. (An absolute 1e-12
#: made the lowest eigenvalues of a Jacobi-scaled rod Hessian at 1e-14..1e-17, hundreds of
#: elements per segment, one cluster as seen from the shift: ~7000 Lanczos steps, 15-45 s.)
EIG_SHIFT_FLOOR = 1e-14


def _brentq() -> Any:
    """Return scipy's Brent root finder, imported on first use.

    ``scipy.optimize`` costs ~0.3 s to import; an analytic CLI answer needs it only when it
    refines a root (issue 12: start-up time).
    """
    from scipy.optimize import brentq

    return brentq


def _sla() -> Any:
    """Return ``scipy.linalg``, imported on first use (~0.1-0.4 s to import)."""
    import scipy.linalg

    return scipy.linalg


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


def richardson(coarse: float, fine: float, ratio: float, order: float) -> tuple[float, float]:
    """Richardson extrapolation of a discretisation of error ``~ h^order``: ``(value, error)``.

    ``coarse`` and ``fine`` on meshes ``ratio`` apart (``h_coarse = ratio h_fine``); ``value``
    is the extrapolated value and ``error = |fine - coarse| / (ratio^order - 1)`` the estimate
    of the fine value's error (the leading term). Non-finite inputs give ``(fine, nan)``.
    """
    if not (math.isfinite(coarse) and math.isfinite(fine)):
        return float(fine), math.nan
    step = (fine - coarse) / (ratio ** order - 1.0)
    return float(fine + step), float(abs(step))


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
    mats = [matrix(float(x)) for x in xs]
    square = mats[0].shape[0] == mats[0].shape[1]
    svals = [np.linalg.svd(A, compute_uv=False) for A in mats]
    del mats
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

    def det(x: float) -> float:
        A = matrix(float(x))
        if A.shape[0] != A.shape[1]:
            return 1.0  # rectangular: rank loss is seen by sigma_min only (no sign to polish)
        # Scale rows so the determinant neither under- nor overflows; the sign is unchanged.
        norms = np.linalg.norm(A, axis=1)
        norms[norms == 0] = 1.0
        return float(np.linalg.det(A / norms[:, None]))

    roots: list[Root] = []
    eps4 = 4 * np.finfo(float).eps

    def add_sign_change(xa: float, xb: float) -> None:
        x = float(_brentq()(det, xa, xb, xtol=xtol, rtol=eps4))
        gx = g(x)
        if gx <= singular_tol and not is_pole(x, xa, xb):
            _, s = _sv_ratio(matrix(x))
            mult = _null_dimension(matrix, x, s, max(s[0], s_ref), singular_tol)
            roots.append(Root(x, max(mult, 1), gx, (float(xa), float(xb)), "sign-change"))

    signs = r == 0 and square  # a determinant sign to scan and to polish on
    ds = np.array([det(float(x)) for x in xs]) if signs else np.ones(n_scan + 1)
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
        dsub = [det(float(t)) for t in sub] if signs else [1.0] * len(sub)
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


@dataclasses.dataclass(frozen=True)
class PencilInterval(Result):
    """Stable interval ``(lo, hi)`` of the load ``p`` for the pencil ``A - p C`` (``A`` SPD).

    ``lo`` / ``hi`` are ``-inf`` / ``+inf`` when no eigenvalue bounds that side. ``mode_lo`` and
    ``mode_hi`` are the critical eigenvectors (columns span the repeated eigenspace);
    ``residual`` is the largest ``||A v - p C v|| / ||A v||`` over the critical modes.
    """

    lo: float
    hi: float
    multiplicity_lo: int
    multiplicity_hi: int
    mode_lo: np.ndarray | None
    mode_hi: np.ndarray | None
    residual: float
    converged: bool
    n_dof: int
    method: str
    #: The computed eigenvalues (as loads ``p = 1/theta``) on each side, nearest to 0 first:
    #: a caller with an error estimate of its own (an FE mesh error) re-applies the
    #: multiplicity rule to them (:func:`multiplicity_of`).
    near_lo: tuple[float, ...] = ()
    near_hi: tuple[float, ...] = ()


#: Eigenvalues per side kept in :attr:`PencilInterval.near_lo` / ``near_hi``.
NEAR_VALUES = 12
#: Restarts of one sparse Lanczos run (ARPACK ``maxiter``). The extreme eigenvalues converge in
#: a few (every both-ends run of tests/test_linear.py and test_hexagram.py within 30); a
#: requested value inside an accumulation point of the spectrum (a strongly anisotropic ring
#: accumulates theta at -1/b2 as well as at 0) never does, and ARPACK's default (10 n) then ran
#: 70 s before failing. The converged part is used and certified by the inertia.
LANCZOS_MAXITER = 30
#: Lanczos runs of :func:`pencil_interval_sparse` per end before it gives up certifying it.
LANCZOS_ATTEMPTS = 4

#: Pencils up to this size are reduced in numpy (:func:`pencil_interval`), larger by LAPACK.
SMALL_PENCIL = 8


def pencil_window(theta: float, error_rtol: float | None) -> float:
    """Return the multiplicity window about the load ``p = 1/theta``, in units of ``theta``.

    :func:`multiplicity_tolerance` ``w`` of ``p`` with the relative error estimate
    ``error_rtol`` of the load; ``|1/theta' - 1/theta| <= w`` is ``|theta' - theta| <= w
    theta^2`` to first order.
    """
    p = 1.0 / theta
    err = None if error_rtol is None else error_rtol * abs(p)
    return multiplicity_tolerance(p, err) * theta * theta


def pencil_interval(A: np.ndarray, C: np.ndarray, *,
                    error_rtol: float | None = None) -> PencilInterval:
    """Stable interval of the load ``p`` for the symmetric pencil ``K(p) = A - p C``.

    ``A`` (the second variation at zero load) must be symmetric positive definite; ``C`` is
    symmetric, possibly indefinite or singular. With ``C v = theta A v`` (a definite generalized
    symmetric problem solved by LAPACK ``sygv`` through ``scipy.linalg.eigh``), ``K(p)`` is
    positive definite exactly for ``1/theta_min < p < 1/theta_max`` (``theta_min < 0 <
    theta_max``); a side with no eigenvalue of that sign is unbounded.

    Eigenvalues that are one with the critical one by the multiplicity rule
    (:func:`multiplicity_tolerance`, the caller's relative error estimate ``error_rtol`` of
    the loads: a discretisation splits a symmetric pair by about its own error) count towards
    its multiplicity.

    Raises
    ------
    RodstabInputError
        (a ValueError) If ``A`` is not positive definite (the unloaded state is then not
        stable and no interval about ``p = 0`` exists).
    """
    A = np.asarray(A, dtype=float)
    C = np.asarray(C, dtype=float)
    n = A.shape[0]
    try:
        if n <= SMALL_PENCIL:
            # LAPACK sygv's own reduction (Cholesky A = L L^T, eigh of L^-1 C L^-T), in numpy:
            # the small mode pencils of the analytic modules then import no scipy.linalg
            L = np.linalg.cholesky(A)
            Li = np.linalg.inv(L)
            theta, W = np.linalg.eigh(Li @ C @ Li.T)
            V = Li.T @ W
        else:
            _sla().cholesky(A, lower=True)
            theta, V = _sla().eigh(C, A)
    except np.linalg.LinAlgError as exc:
        raise RodstabInputError("pencil_interval: A (zero-load second variation) is not "
                                "positive definite") from exc
    cnorm = max(float(np.max(np.abs(theta))), 1e-300)
    tol = MULTIPLICITY_RTOL * cnorm

    def side(sel: np.ndarray, pick: float) -> tuple[float, int, tuple | None]:
        if not sel.any():
            return (math.inf if pick > 0 else -math.inf), 0, None
        th = theta[sel]
        t = th.max() if pick > 0 else th.min()
        if abs(t) <= tol:
            return (math.inf if pick > 0 else -math.inf), 0, None
        close = np.abs(theta - t) <= pencil_window(float(t), error_rtol)
        return 1.0 / float(t), int(close.sum()), (V[:, close], theta[close])

    hi, m_hi, vt_hi = side(theta > tol, +1.0)
    lo, m_lo, vt_lo = side(theta < -tol, -1.0)
    residual = 0.0
    for vt in (vt_hi, vt_lo):
        if vt is None:
            continue
        v, th = vt
        for k in range(v.shape[1]):  # each vector with its own eigenvalue
            Av = A @ v[:, k]
            residual = max(residual, float(np.linalg.norm(Av - (C @ v[:, k]) / th[k])
                                           / np.linalg.norm(Av)))
    v_hi = None if vt_hi is None else vt_hi[0]
    v_lo = None if vt_lo is None else vt_lo[0]
    pos, neg = np.sort(theta[theta > tol])[::-1], np.sort(theta[theta < -tol])
    return PencilInterval(lo, hi, m_lo, m_hi, v_lo, v_hi, residual,
                          bool(residual < 1e-8), n, "generalized symmetric eigh (LAPACK sygv)",
                          near_lo=tuple(1.0 / neg[:NEAR_VALUES]),
                          near_hi=tuple(1.0 / pos[:NEAR_VALUES]))


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


def count_below(A: Any, sigma: float) -> int | None:
    """Count the eigenvalues of the sparse symmetric ``A`` below ``sigma`` (Sylvester's inertia).

    ``A - sigma I = P L D L^T P^T`` by SuperLU in symmetric mode (diagonal pivots, the same
    symmetric ordering for rows and columns), so the negative entries of ``U``'s diagonal count
    the eigenvalues below ``sigma``. None when that factorisation is not available (singular,
    or the pivoting left the diagonal).
    """
    return _ldlt(A, sigma)[1]


def _ldlt(A: Any, sigma: float) -> tuple[Any, int | None]:
    """Symmetric factorisation of ``A - sigma I`` and its count of negative pivots.

    ``(lu, count)``: SuperLU in symmetric mode (see :func:`count_below`); ``(None, None)`` when
    it fails, ``(lu, None)`` when the pivoting left the diagonal (no inertia).
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    n = A.shape[0]
    try:
        lu = spla.splu((A - sigma * sp.identity(n)).tocsc(), permc_spec="MMD_AT_PLUS_A",
                       diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:
        return None, None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return lu, None
    d = lu.U.diagonal()
    return lu, (int(np.sum(d < 0)) if np.all(np.isfinite(d)) else None)


def jacobi_scaling(A: Any) -> np.ndarray:
    """Return ``d = 1 / sqrt(|diag A|)`` (1 where the diagonal is 0), shape ``(n,)``.

    ``D A D`` (``D = diag(d)``) has a unit diagonal and, by Sylvester's law, the inertia of
    ``A``: the same stable/unstable verdict and the same load at which it changes. It evens
    out unknowns of different units (an FE displacement ~h^-3 against a slope ~h^-1, a rod's
    stiff stretch penalty against its bending), without which a factorisation loses digits.
    """
    dg = np.abs(np.asarray(A.diagonal(), dtype=float))
    dg[dg == 0] = 1.0
    return 1.0 / np.sqrt(dg)


def lowest_eigenpairs(A: Any, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Return the ``k`` lowest eigenpairs ``(vals (k,), vecs (n, k))`` of sparse symmetric ``A``.

    Dense (LAPACK ``eigh``) up to :data:`DENSE_EIG_MAX` unknowns (``k <= n``); beyond, shift-
    invert Lanczos (ARPACK ``eigsh``, ``k < n``), which returns the eigenvalues NEAREST its
    shift: the shift is therefore moved below the lowest eigenvalue and certified there by the
    inertia (:func:`count_below` = 0), so the nearest are the lowest and none is missed (a
    negative eigenvalue farther from 0 than a small positive one would be missed by a shift
    placed from the eigenvalue nearest 0 alone). Raises :class:`~rodstab.errors.NotConverged`
    when a pair's residual exceeds :data:`EIG_RESIDUAL_TOL` ``max |A_ij|``.
    """
    import warnings

    import scipy.sparse.linalg as spla

    from .errors import NotConverged

    n = A.shape[0]
    if n <= DENSE_EIG_MAX:
        vals, vecs = _sla().eigh(A.toarray(), subset_by_index=[0, min(k, n) - 1])
    else:
        # A fixed start vector: ARPACK's default is random, which makes the last digits -- and
        # so the sign of quantities near zero along a path -- differ from run to run.
        v0 = np.linspace(1.0, 2.0, n)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            lam0 = spla.eigsh(A, k=1, sigma=0.0, which="LM", tol=1e-10, v0=v0)[0][0]
        step = max(abs(lam0), EIG_SHIFT_FLOOR * float(abs(A).max()))
        sigma = min(lam0, 0.0) - 2.0 * step
        for _ in range(80):
            lu, below = _ldlt(A, sigma)
            if below == 0:
                break
            step *= 2.0
            sigma = min(lam0, 0.0) - 2.0 * step
        else:
            raise NotConverged("could not place a Lanczos shift below the lowest eigenvalue "
                               "(no inertia-certified shift in 80 doublings)")
        assert lu is not None  # below == 0 only with a factorisation
        # The certifying factorisation of A - sigma I is the shift-invert operator: no second
        # factorisation inside eigsh.
        op = spla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
        kk = min(k, n - 1)
        vals = vecs = None
        # ARPACK's default basis (2k + 1 vectors) can stall when the shift had to go far below
        # the lowest eigenvalues (an unstable state: the transformed ones 1/(lam - sigma)
        # crowd): a 7-rod cusp ring at 16 elements per rod, 1.03x past its lower limit, ran
        # 20001 iterations (38 s) with 2 of 4 converged, and a 60-vector basis took 20 s.
        # A near-zero cluster (rigid motions, near-neutral modes of a ring) converges slowly
        # at best: a first try with few restarts, then dense where that is cheap.
        tries = ((max(2 * kk + 1, 20), 1000),) if n <= DENSE_FALLBACK_MAX else \
            ((max(2 * kk + 1, 20), 1000), (max(4 * kk, 60), 20000))
        for ncv, iters in tries:
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    vals, vecs = spla.eigsh(A, k=kk, sigma=sigma, which="LM", tol=1e-10,
                                            maxiter=iters, v0=v0, OPinv=op,
                                            ncv=min(ncv, n - 1))
                break
            except spla.ArpackNoConvergence:
                continue
        if vals is None:
            if n > DENSE_FALLBACK_MAX:
                raise NotConverged(f"lowest eigenpairs: shift-invert Lanczos did not converge "
                                   f"({n} unknowns, bases of up to {max(4 * kk, 60)} "
                                   "vectors)")
            vals, vecs = _sla().eigh(A.toarray(), subset_by_index=[0, kk - 1])
        order = np.argsort(vals)
        vals, vecs = vals[order], vecs[:, order]
    scale = float(abs(A).max()) if n else 1.0
    res = np.linalg.norm(A @ vecs - vecs * vals, axis=0)
    if res.size and float(res.max()) > EIG_RESIDUAL_TOL * scale:
        raise NotConverged(f"lowest eigenpairs: residual {float(res.max()):.3g} exceeds "
                           f"{EIG_RESIDUAL_TOL:g} x max|A| = {EIG_RESIDUAL_TOL * scale:.3g}")
    return vals, vecs


#: Entries of one dense block of right-hand sides in :meth:`ConstrainedFactor.of` (8 MB).
SOLVE_BLOCK_ENTRIES = 1_000_000


@dataclasses.dataclass(frozen=True)
class ConstrainedFactor:
    """Factorisation of ``A`` on the constraints ``G v = 0`` by substructuring, with inertia.

    The unknowns after the first ``border`` (``I``; ``A_II`` must be nonsingular) are
    factorised once by a sparse LU in symmetric mode (diagonal pivots, so ``U``'s diagonal is
    the ``D`` of ``P A_II P^T = L D L^T``), and the ``border`` unknowns with the ``m``
    multipliers of ``G`` form a small dense Schur complement ``S`` of the KKT matrix
    ``[A G^T; G 0]``. Its inertia is ``inertia(A | G v = 0) + (m, m, 0)`` (``G`` of full row
    rank) and, by Haynsworth's additivity, ``inertia(A_II) + inertia(S)``: so ``A`` has
    ``n_negative = neg(A_II) + neg(S) - m`` negative directions on the constraints, and a
    zero one when ``S`` is singular.
    """

    n: int
    border: int
    m: int
    lu: Any
    W: Any  # sparse [A_IJ, G_I^T]
    X: Any  # sparse A_II^-1 W
    S: np.ndarray
    n_negative: int
    singular: bool

    @classmethod
    def of(cls, A: Any, G: Any, border: int) -> ConstrainedFactor:
        """Factorise ``A`` (sparse symmetric ``n x n``) on ``G v = 0`` (sparse ``m x n``)."""
        import scipy.sparse as sp
        import scipy.sparse.linalg as spla

        A = sp.csc_matrix(A)
        G = sp.csr_matrix(G)
        n, m, b = A.shape[0], G.shape[0], border
        try:
            lu = spla.splu(A[b:, b:].tocsc(), permc_spec="MMD_AT_PLUS_A",
                           diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise RodstabInputError(f"A_II is singular: {exc}") from None
        d = lu.U.diagonal()
        if not np.array_equal(lu.perm_r, lu.perm_c) or not np.all(np.isfinite(d)):
            raise RodstabInputError("A_II is singular (no symmetric factorisation)")
        # W and X are sparse when A_II is block diagonal (one block per segment of an FE
        # assembly): the solves leave exact zeros outside the blocks a column touches.
        W = sp.hstack([A[b:, :b], G[:, b:].T]).tocsc()
        # In blocks of columns (one SuperLU call per block: a call per column cost ~3 ms of
        # overhead each at 5000 unknowns), each block dense: O(n) memory per block.
        cols = max(1, SOLVE_BLOCK_ENTRIES // max(n - b, 1))
        X = sp.hstack([sp.csc_matrix(lu.solve(W[:, j:j + cols].toarray()))
                       for j in range(0, W.shape[1], cols)], format="csc") \
            if W.shape[1] else sp.csc_matrix((n - b, 0))
        S = np.zeros((b + m, b + m))
        S[:b, :b] = A[:b, :b].toarray()
        S[:b, b:] = G[:, :b].T.toarray()
        S[b:, :b] = G[:, :b].toarray()
        S -= (W.T @ X).toarray()
        S = 0.5 * (S + S.T)
        s_eig = np.linalg.eigvalsh(S) if S.size else np.zeros(0)
        s_scale = max(float(np.abs(s_eig).max()) if s_eig.size else 0.0, 1e-300)
        return cls(n, b, m, lu, W, X, S, int(np.sum(d < 0)) + int(np.sum(s_eig < 0)) - m,
                   bool(np.any(np.abs(s_eig) <= 1e-13 * s_scale)))

    def solve(self, f: np.ndarray) -> np.ndarray:
        """``y`` with ``A y - f`` in the range of ``G^T`` and ``G y = 0``."""
        b = self.border
        z = self.lu.solve(f[b:])
        g = np.concatenate([f[:b], np.zeros(self.m)]) - self.W.T @ z
        yj = np.linalg.solve(self.S, g) if self.S.size else g
        out = np.empty(self.n)
        out[:b] = yj[:b]
        out[b:] = z - self.X @ yj
        return out


def lowest_eigenpairs_on(A: Any, G: Any, border: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Return the ``k`` lowest eigenpairs of sparse symmetric ``A`` on ``G v = 0``.

    ``(vals (k,), vecs (n, k))``, the vectors orthonormal and in the null space of ``G``.

    The eigenvalues of ``N^T A N`` for an orthonormal basis ``N`` of the null space of ``G``
    (``m x n``, full row rank, ``m`` small: its rows may be dense). Dense up to
    :data:`DENSE_EIG_MAX` unknowns; beyond, shift-invert Lanczos on the constrained inverse
    ``f -> y`` (``A y - sigma y - f`` in the range of ``G^T``, ``G y = 0``: a symmetric operator
    on the null space whose largest eigenvalues are ``1 / (lam - sigma)``), by
    :class:`ConstrainedFactor` (``border``: as there). As in :func:`lowest_eigenpairs` the shift
    is placed below the lowest eigenvalue and certified there by the inertia (no negative
    direction of ``A - sigma I`` on the constraints), so no eigenvalue is missed. Raises
    :class:`~rodstab.errors.NotConverged` when a pair's residual (projected on the null space)
    exceeds :data:`EIG_RESIDUAL_TOL` ``max |A_ij|``.
    """
    import warnings

    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from .errors import NotConverged

    A = sp.csc_matrix(A)
    G = sp.csr_matrix(G)
    n = A.shape[0]
    if n <= DENSE_EIG_MAX:
        N = _sla().null_space(G.toarray()) if G.shape[0] else np.eye(n)
        w, V = np.linalg.eigh(N.T @ A.toarray() @ N)
        return w[:k], N @ V[:, :k]
    scale = float(abs(A).max())
    eye = sp.identity(n, format="csc")

    def factor(sigma: float) -> ConstrainedFactor | None:
        try:
            return ConstrainedFactor.of(A - sigma * eye, G, border)
        except RodstabInputError:  # singular at this shift: try another
            return None

    def largest(fac: ConstrainedFactor, kk: int, which: str) -> tuple[np.ndarray, np.ndarray]:
        op = spla.LinearOperator((n, n), matvec=fac.solve, dtype=float)
        v0 = fac.solve(np.linspace(1.0, 2.0, n))  # in the null space, fixed (reproducible)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return spla.eigsh(op, k=kk, which=which, tol=1e-10, v0=v0,
                              maxiter=1000 if n <= DENSE_FALLBACK_MAX else 20000)

    def dense() -> tuple[np.ndarray, np.ndarray]:
        # Lanczos stalled on a crowded near-zero cluster (as in lowest_eigenpairs): dense
        # where that is cheap, else say so
        if n > DENSE_FALLBACK_MAX:
            raise NotConverged(f"lowest eigenvalues on the constraints: shift-invert Lanczos "
                               f"did not converge ({n} unknowns)") from None
        N = _sla().null_space(G.toarray()) if G.shape[0] else np.eye(n)
        w, V = np.linalg.eigh(N.T @ A.toarray() @ N)
        return w[:k], N @ V[:, :k]

    sigma = -EIG_SHIFT_FLOOR * scale
    fac = factor(sigma)
    if fac is None:
        sigma *= -1.0
        fac = factor(sigma)
    if fac is None:
        raise NotConverged("lowest eigenvalues on the constraints: singular at two shifts")
    if fac.n_negative > 0:
        # Nearest eigenvalue to the shift first, then below the lowest (doubling steps).
        try:
            mu = largest(fac, 1, "LM")[0][0]
        except spla.ArpackNoConvergence:
            return dense()
        lam0 = sigma + 1.0 / mu
        step = max(abs(lam0), EIG_SHIFT_FLOOR * scale)
        for _ in range(80):
            sigma = min(lam0, 0.0) - 2.0 * step
            fac = factor(sigma)
            if fac is not None and fac.n_negative == 0:
                break
            step *= 2.0
        else:
            raise NotConverged("could not place a Lanczos shift below the lowest eigenvalue "
                               "on the constraints (80 doublings)")
    assert fac is not None
    try:
        mus, vecs = largest(fac, min(k, n - G.shape[0] - 1), "LA")
    except spla.ArpackNoConvergence:
        return dense()
    order = np.argsort(-mus)
    vals = sigma + 1.0 / mus[order]
    vecs = vecs[:, order]
    # Residual on the null space: A y - lam y minus its least-squares part in range(G^T).
    R = A @ vecs - vecs * vals
    Gd = G.T.toarray()
    if Gd.shape[1]:
        R = R - Gd @ np.linalg.lstsq(Gd, R, rcond=None)[0]
    res = np.linalg.norm(R, axis=0)
    if res.size and float(res.max()) > EIG_RESIDUAL_TOL * scale:
        raise NotConverged(f"lowest eigenvalues on the constraints: residual "
                           f"{float(res.max()):.3g} exceeds {EIG_RESIDUAL_TOL:g} x max|A|")
    return vals, vecs


def definite_on(A: Any, constraints: Any = None, border: int = 0) -> bool:
    """Whether the sparse symmetric ``A`` is positive definite on ``constraints @ v = 0``.

    A stability verdict without an eigen solve: the inertia of :class:`ConstrainedFactor`
    (Sylvester, Haynsworth), or for up to :data:`DENSE_EIG_MAX` unknowns the lowest eigenvalue
    of ``N^T A N`` on a null-space basis ``N``, against ``1e-13 max |eig|`` (a zero eigenvalue
    -- the critical load itself -- is not definite).
    """
    import scipy.sparse as sp

    A = sp.csc_matrix(A)
    n = A.shape[0]
    G = sp.csr_matrix((0, n)) if constraints is None else sp.csr_matrix(constraints)
    if n <= DENSE_EIG_MAX:
        N = _sla().null_space(G.toarray()) if G.shape[0] else np.eye(n)
        ev = np.linalg.eigvalsh(N.T @ A.toarray() @ N)
        return bool(ev.size == 0 or ev[0] > 1e-13 * max(abs(ev[0]), abs(ev[-1])))
    try:
        fac = ConstrainedFactor.of(A, G, border)
    except RodstabInputError:
        return False
    return fac.n_negative == 0 and not fac.singular


def pencil_interval_sparse(A, C, *, constraints=None, border: int = 0,
                           error_rtol: float | None = None,
                           n_eig: int = 6, tol: float = 1e-12) -> PencilInterval:
    """Sparse version of :func:`pencil_interval` for large FE pencils, with linear constraints.

    ``C v = theta A v`` on the subspace ``G v = 0`` (``G = constraints``, ``m x n`` sparse of
    full row rank, or None): the few largest and smallest ``theta`` by Lanczos (ARPACK
    ``eigsh`` in generalized mode, ``A``-inner product, one run per end), to relative
    tolerance ``tol``. The extreme values converge fast; the spectrum accumulates at 0 and, for
    strongly anisotropic sections, at other points too (a requested value there never
    converges: the converged part is used). Each end is certified by the inertia
    (:class:`ConstrainedFactor` of ``A - C / theta'`` for a ``theta'`` between the critical
    cluster and the next found value: the count of eigenvalues beyond it must be the
    cluster's), so no extreme eigenvalue is missed and a multiplicity is not under-counted;
    ``n_eig`` doubles while the found values are all one cluster or the certificate fails.
    Multiplicities by :func:`multiplicity_tolerance` with the caller's relative error
    estimate ``error_rtol``. Raises :class:`~rodstab.errors.NotConverged` (with the reason)
    when an end cannot be certified.

    The constrained solve ``[A G^T; G 0] [y; nu] = [f; 0]`` and the definiteness test of ``A``
    on the constraints are those of :class:`ConstrainedFactor` (substructured on the first
    ``border`` unknowns). Up to :data:`DENSE_EIG_MAX` unknowns: :func:`pencil_interval` on a
    null-space basis of ``G``.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    A = sp.csc_matrix(A)
    C = sp.csc_matrix(C)
    n = A.shape[0]
    G = sp.csr_matrix((0, n)) if constraints is None else sp.csr_matrix(constraints)
    m = G.shape[0]
    if n <= DENSE_EIG_MAX:  # the dense solve is O(n^3) and slow on a busy multithreaded BLAS
        N = _sla().null_space(G.toarray()) if m else np.eye(n)
        res = pencil_interval(N.T @ A.toarray() @ N, N.T @ C.toarray() @ N,
                              error_rtol=error_rtol)
        return dataclasses.replace(
            res, mode_lo=None if res.mode_lo is None else N @ res.mode_lo,
            mode_hi=None if res.mode_hi is None else N @ res.mode_hi, n_dof=n - m)
    fac = ConstrainedFactor.of(A, G, border)
    if fac.n_negative != 0 or fac.singular:
        raise RodstabInputError("pencil_interval_sparse: A is not positive definite on the "
                                f"constraints ({fac.n_negative} negative directions)")
    solve, b = fac.solve, border
    Ainv = spla.LinearOperator((n, n), matvec=solve, dtype=float)

    if C.count_nonzero() == 0 or not np.any(C.data):
        # C = 0 (e.g. no natural curvature anywhere): every theta is 0, the interval is the
        # whole line, as the dense pencil_interval says (ARPACK would stop: "Starting vector
        # is zero", found by benchmarks/fuzz.py).
        return PencilInterval(-math.inf, math.inf, 0, 0, None, None, 0.0, True, n - m,
                              "C = 0: no load-dependent term, every eigenvalue theta is 0")
    # A start vector on the constraints, fixed (ARPACK's default is random: results would
    # vary run to run); the Krylov space then stays on them, as solve() maps into them.
    v_start = solve(C @ np.linspace(1.0, 2.0, n))
    k_max = n - m - 2

    def lanczos(which: str, k: int) -> tuple[np.ndarray, np.ndarray, bool]:
        # k values of ``C v = theta A v`` (the A-inner product) at one end ("LA", "SA") or
        # k/2 at each ("BE"), and whether all k converged (else the converged part, possibly
        # empty: a value asked for inside an accumulation point of the spectrum never does).
        try:
            vals, vecs = spla.eigsh(C, k=k, M=A, Minv=Ainv, which=which, tol=tol,
                                    v0=v_start, maxiter=LANCZOS_MAXITER)
            complete = True
        except spla.ArpackNoConvergence as exc:
            vals, vecs, complete = exc.eigenvalues, exc.eigenvectors, False
        except spla.ArpackError as exc:
            raise NotConverged(f"the sparse Lanczos eigen solve ({n} unknowns) failed: "
                               f"{exc}") from None
        return np.asarray(vals), np.asarray(vecs), complete

    def at_end(vals: np.ndarray, vecs: np.ndarray, sign: float
               ) -> tuple[np.ndarray, np.ndarray]:
        # the values of one sign, from the end inwards
        sel = vals * sign > 0
        order = np.argsort(-sign * vals[sel])
        return vals[sel][order], vecs[:, sel][:, order]

    def negative_directions(t: float) -> int | None:
        # Eigenvalues theta beyond t (theta > t for t > 0, theta < t for t < 0) by Sylvester's
        # inertia of A - C / t on the constraints: n_negative(A - p C) = #{p theta > 1}.
        try:
            f = ConstrainedFactor.of(A - C / t, G, border)
        except RodstabInputError:
            return None
        return None if f.singular else f.n_negative

    def certify(vals: np.ndarray, vecs: np.ndarray, sign: float, complete: bool, k: int
                ) -> tuple[int, np.ndarray | None, str | None]:
        # The end's extreme eigenvalue t = vals[0] with its multiplicity (the values within
        # the multiplicity window of 1/t), certified by the inertia at a theta between that
        # cluster and the next found value: the count beyond it must be the cluster's, so no
        # eigenvalue beyond t or inside its window was missed. (0, None, why) to ask again.
        t = float(vals[0])
        window = pencil_window(t, error_rtol)
        close = np.abs(vals - t) <= window
        if complete and close.all() and k < k_max:
            return 0, None, "the found values were one cluster"
        edge = vals[close][-1]
        nxt = vals[~close]
        probe = 0.5 * (edge + nxt[0]) if nxt.size else edge - sign * window
        count = negative_directions(float(probe))
        if count == int(close.sum()):
            return int(close.sum()), vecs[:, close], None
        return 0, None, (f"the inertia counts {count} eigenvalues beyond theta = {probe:.6g}, "
                         f"Lanczos found {int(close.sum())}")

    # One Lanczos run for both ends first (k/2 from each); an end it does not settle is asked
    # again on its own, k doubling.
    k = min(2 * n_eig, k_max)
    vals, vecs, complete = lanczos("BE", k)
    found = {sign: (*at_end(vals, vecs, sign), complete, k // 2) for sign in (1.0, -1.0)}
    scale = max(float(np.max(np.abs(vals))) if vals.size else 0.0, 1e-300)
    out: dict[float, tuple[float, int, np.ndarray | None]] = {}
    thetas: dict[float, np.ndarray] = {}
    near: dict[float, tuple[float, ...]] = {}
    failures: list[str] = []
    for sign, name in ((1.0, "LA"), (-1.0, "SA")):
        ev, V, done, k_end = found[sign]
        why: str | None = None
        for attempt in range(LANCZOS_ATTEMPTS + 1):
            if attempt:
                k_end = min(max(2 * k_end, n_eig), k_max)
                ev, V, done = lanczos(name, k_end)
                ev, V = at_end(ev, V, sign)
                scale = max(scale, float(np.max(np.abs(ev))) if ev.size else 0.0)
            if ev.size == 0:
                if done:  # every eigenvalue found at this end has the other sign
                    why = None
                    out[sign] = (math.inf * sign, 0, None)
                    break
                why = f"no eigenvalue converged at the {name} end ({k_end} asked)"
                continue
            if abs(ev[0]) <= 1e-14 * scale:
                why = None
                out[sign] = (math.inf * sign, 0, None)
                break
            mult, Vc, why = certify(ev, V, sign, done, k_end)
            if why is None:
                out[sign] = (1.0 / float(ev[0]), mult, Vc)
                thetas[sign] = ev[:mult]  # the cluster: ev runs from the end inwards
                near[sign] = tuple(1.0 / ev[:NEAR_VALUES])
                break
            if k_end >= k_max:
                break
        if why is not None:
            failures.append(why)
    if failures:
        raise NotConverged(f"the sparse Lanczos eigen solve ({n} unknowns) could not certify "
                           f"the extreme eigenvalues: {'; '.join(failures)}")
    residual = 0.0
    for sign in (1.0, -1.0):
        modes = out[sign][2]
        if modes is None:
            continue
        for k in range(modes.shape[1]):  # each vector with its own eigenvalue
            # |A^-1 C v / theta - v| / |v| on the constraints: the inverted problem's residual
            v = modes[:, k]
            residual = max(residual, float(np.linalg.norm(solve(C @ v) / thetas[sign][k] - v)
                                           / np.linalg.norm(v)))
    out_hi, out_lo = out[1.0], out[-1.0]
    hi, m_hi, v_hi = out_hi
    lo, m_lo, v_lo = out_lo
    how = (f"substructured: sparse LU of A_II, {b + m}-square Schur complement" if b + m
           else "sparse LU of A")
    return PencilInterval(lo, hi, m_lo, m_hi, v_lo, v_hi, residual,
                          bool(residual < SPARSE_RESIDUAL_TOL), n - m,
                          f"Lanczos (ARPACK eigsh, generalized, each end certified by the "
                          f"inertia; {how})", near_lo=near.get(-1.0, ()),
                          near_hi=near.get(1.0, ()))
