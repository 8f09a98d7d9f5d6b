"""Exceptions for the two failures a user can act on: invalid input, and no convergence.

* :class:`RodstabInputError` (a :class:`ValueError`): the input is invalid; the message names
  the offending parameter and its value. The CLI prints it as one line and exits with status 2.
* :class:`NotConverged` (a :class:`RuntimeError`): a solver did not converge where the caller
  needs its answer; the message names what did not converge. The CLI exits with status 3.

:class:`RodstabWarning` (a :class:`UserWarning`) reports what a run recovered from.

Any other exception is a bug in rodstab and is not caught by the CLI (it shows a traceback).
"""

from __future__ import annotations

import math
from numbers import Integral, Real


class RodstabInputError(ValueError):
    """Invalid user input; the message names the parameter and its value."""


class NotConverged(RuntimeError):
    """A solver did not converge where its answer is needed.

    The message names what did not converge (which solve, at which parameter value).

    Solvers that return a result with a ``converged`` flag do not raise this: they report.
    It is raised where no meaningful result exists without convergence (e.g. the start of a
    path that cannot be reached).
    """


class RodstabWarning(UserWarning):
    """Something the user should know that did not stop the run.

    E.g. a resume state set aside, or a stale lock taken over. The CLI prints it as one line
    ``rodstab: warning: ...``.
    """


def require_positive(name: str, value: float) -> float:
    """Return ``value`` as float if it is a finite number > 0, else raise naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise RodstabInputError(f"{name} must be a positive number, got {value!r}")
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise RodstabInputError(f"{name} must be a finite positive number, got {value!r}")
    return v


def require_finite(name: str, value: float) -> float:
    """Return ``value`` as float if it is a finite real number, else raise naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise RodstabInputError(f"{name} must be a finite number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise RodstabInputError(f"{name} must be a finite number, got {value!r}")
    return v


def require_in_range(name: str, value: float, lo: float, hi: float, why: str) -> float:
    """Return ``value`` as float if it is a number in ``[lo, hi]``, else raise.

    The message names ``name``, the value, the range and ``why`` the range is what it is.
    """
    v = require_finite(name, value)
    if not (lo <= v <= hi):
        raise RodstabInputError(f"{name} must lie in [{lo:g}, {hi:g}] ({why}), got {value!r}")
    return v


def require_positive_int(name: str, value: int) -> int:
    """Return ``value`` if it is an integer >= 1 (bools rejected), else raise naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, Integral) or value < 1:
        raise RodstabInputError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def require_int(name: str, value: int, minimum: int) -> int:
    """Return ``value`` if it is an integer >= ``minimum`` (bools rejected), else raise."""
    if isinstance(value, bool) or not isinstance(value, Integral) or value < minimum:
        raise RodstabInputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def require_poisson(nu: float) -> float:
    """Return Poisson's ratio if it lies in (-1, 0.5], else raise naming ``nu``."""
    v = require_finite("nu", nu)
    if not (-1.0 < v <= 0.5):
        raise RodstabInputError(f"nu (Poisson's ratio) must lie in (-1, 0.5], got {nu!r}")
    return v
