"""The contact model's functions of one gap: the barrier, the soft penalty, the stiffness rule.

Split from :mod:`.contact_model` (which imports them back; :mod:`.contact` gathers the public
names): the IPC log barrier (Li et al. 2020) and its derivatives, the cubic penalty of the soft
stages, and the rule that sets the barrier's stiffness from an expected line load. Each acts
on gaps (length) elementwise.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import RodstabInputError, require_finite, require_positive


class Interpenetration(RodstabInputError):
    """Two capsules overlap (a gap ``<= 0``): the state is outside the contact model."""


def barrier(g: np.ndarray, dhat: float, kappa: float) -> tuple[np.ndarray, np.ndarray,
                                                                np.ndarray]:
    """IPC log barrier ``b(g)`` and its first two derivatives (Li et al. 2020, eq. 6).

    Parameters
    ----------
    g : ndarray
        Gaps (length), all ``> 0``.
    dhat : float
        Activation distance (length): ``b = 0`` for ``g >= dhat``.
    kappa : float
        Stiffness (energy / length^3, so that ``b`` is an energy per unit length).

    Returns
    -------
    b, db, d2b : ndarray
        ``-kappa (g - dhat)^2 ln(g / dhat)`` and its derivatives in ``g``, zero for
        ``g >= dhat``.
    """
    g = np.asarray(g, float)
    if np.any(g <= 0.0):
        raise Interpenetration(f"gap must be > 0, got min gap {float(np.min(g))!r}")
    on = g < dhat
    gs = np.where(on, g, dhat)
    q, lg = gs - dhat, np.log(gs / dhat)
    b = -kappa * q * q * lg
    db = -kappa * (2.0 * q * lg + q * q / gs)
    d2b = -kappa * (2.0 * lg + 4.0 * q / gs - q * q / gs**2)
    return (np.where(on, b, 0.0), np.where(on, db, 0.0), np.where(on, d2b, 0.0))


def stiffness_for_line_load(line_load: float, dhat: float, gap_fraction: float = 0.5) -> float:
    """Barrier stiffness ``kappa`` with which a contact line load is held at a chosen gap.

    Two parallel rods at gap ``g`` carry the energy ``b(g)`` per unit length
    (:mod:`.contact_model`), so they press on one another with the line load ``-b'(g) = kappa
    dhat (f - 1)(2 f ln f + f - 1) / f`` at ``g = f dhat``. The rule: give the expected contact
    load (force / length; its scale is ``B / L^3`` for a rod of bending stiffness ``B`` pressed
    over a length ``L``) and the fraction ``f`` of ``dhat`` at which it should be held. The
    barrier repels without bound as ``g -> 0``, so other loads are held at other gaps in ``(0,
    dhat)``.

    Parameters
    ----------
    line_load : float
        Contact force per unit length (> 0).
    dhat : float
        Activation distance (length, > 0).
    gap_fraction : float
        ``f`` in (0, 1).

    Returns
    -------
    float
        ``kappa`` (force / length^2).
    """
    q = require_positive("line_load", line_load)
    d = require_positive("dhat", dhat)
    f = require_finite("gap_fraction", gap_fraction)
    if not 0.0 < f < 1.0:
        raise RodstabInputError(f"gap_fraction must lie in (0, 1), got {gap_fraction!r}")
    return q / (d * (f - 1.0) * (2.0 * f * math.log(f) + f - 1.0) / f)


def penalty(g: np.ndarray, dhat: float, kappa: float) -> tuple[np.ndarray, np.ndarray,
                                                                np.ndarray]:
    """Cubic penalty ``p(g) = kappa (dhat - g)^3`` on ``g < dhat`` and its two derivatives.

    Finite for every gap, overlaps (``g <= 0``) included, and C2 at ``g = dhat`` (``p, p',
    p''`` vanish there): a soft contact that lets a state outside the barrier's model (a path
    computed without contact) be pushed back into it (:mod:`rodstab.multistable.string_contact`).
    It does not prevent interpenetration: a line load ``q`` is held at ``g = dhat - sqrt(q / 3
    kappa)``, negative for ``q > 3 kappa dhat^2``.
    """
    g = np.asarray(g, float)
    q = np.where(g < dhat, dhat - g, 0.0)
    return kappa * q**3, -3.0 * kappa * q**2, 6.0 * kappa * q
