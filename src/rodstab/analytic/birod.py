"""Bi-rod of Section 4: closed forms (the admissible test field of P2 (4.4)).

The second, independent method for Sections 4-5 (each straight segment's general solution joined
by ALL joint conditions into one square system) is
:func:`rodstab.transfer.full_system_critical`, applied to the structures by
:func:`rodstab.problems.birod.full_system` and :func:`rodstab.problems.folded_ring.full_system`.

Paper's derivation after (4.6) imposes the natural conditions (4.6) at the clamped end
``x = 0`` as well; at a clamp they do not hold (the clamp reacts), so that solution is confined
to the opening mode ``u(1) = -u(2)`` (a clamped-clamped column, ``lam = 2 pi``). The full system
also has the mode ``u(1) = u(2)``, ``alpha(1) = -alpha(2)`` with ``sin(lam) = 0``: ``lam = pi``.
"""

from __future__ import annotations

import math

import numpy as np

from ..sections import Section


def birod_test_field_energy(section: Section, lam: float, n_quad: int = 2001) -> float:
    """P2 (4.4) of an explicit admissible field of the clamped bi-rod, per ``B1 / L``.

    Field (``x = s/L``, both rods deflect together, opposite twists): ``u1 = u2 = U``,
    ``alpha1 = -alpha2 = D`` with ``U = sin(pi x) - pi x`` and
    ``D = -(k/b2)(U - U(1) x)``, ``k = pi sqrt(b1 b2)`` (the eigenfield at ``lam = pi``;
    ``u``, ``u'``, ``alpha`` vanish at the clamp ``x = 0`` and are continuous at ``x = 1``).
    With ``B3 kappa0 L = lam sqrt(B1 B2)`` (4.4) is ``int {b1 U''^2 + b2 D'^2 +
    2 lam sqrt(b1 b2) D' U'} dx`` (in units of ``B3/L``); it is linear in ``lam`` and negative
    for every ``lam > pi``, so the straight bi-rod is unstable below the paper's ``2 pi``.
    Integrated by the trapezoid rule on ``n_quad`` points (smooth integrand).
    """
    b1, b2 = section.b1, section.b2
    x = np.linspace(0.0, 1.0, n_quad)
    Ud = np.pi * np.cos(np.pi * x) - np.pi  # U'
    Udd = -np.pi**2 * np.sin(np.pi * x)  # U''
    U1 = -np.pi  # U(1)
    k = np.pi * math.sqrt(b1 * b2)
    Dd = -(k / b2) * (Ud - U1)  # D'
    f = b1 * Udd**2 + b2 * Dd**2 + 2 * lam * math.sqrt(b1 * b2) * Dd * Ud
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))
