"""Exceptions raised for invalid user input.

Every error names the offending parameter and its value, so a CLI can print it as one line.
"""

from __future__ import annotations

import math
from numbers import Integral, Real


class RodstabInputError(ValueError):
    """Invalid user input; the message names the parameter and its value."""


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


def require_positive_int(name: str, value: int) -> int:
    """Return ``value`` if it is an integer >= 1 (bools rejected), else raise naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, Integral) or value < 1:
        raise RodstabInputError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def require_poisson(nu: float) -> float:
    """Return Poisson's ratio if it lies in (-1, 0.5], else raise naming ``nu``."""
    v = require_finite("nu", nu)
    if not (-1.0 < v <= 0.5):
        raise RodstabInputError(f"nu (Poisson's ratio) must lie in (-1, 0.5], got {nu!r}")
    return v
