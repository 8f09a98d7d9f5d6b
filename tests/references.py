"""Independent references shared by several test modules (computed once per session).

Each is computed by a method other than the one the tests check, from closed forms where
there are any; the docstring says which.
"""

from __future__ import annotations

import functools

from scipy.optimize import brentq

#: Bracket of the hexagram's threshold search: h/t in [3, 4] holds the published 3.4.
HEXAGRAM_BRACKET = (3.0, 4.0)
#: Brent's tolerance on h/t (the FE limits it compares are refined to ~2.5e-7 relative).
HEXAGRAM_XTOL = 1e-9


def hexagram_eight_lower_minus_line_upper(aspect: float, nu: float = 1 / 3) -> float:
    """The eight's lower limit by the FE engine less the line's upper one in closed form.

    Rectangle h/t = ``aspect``, exact torsion. The line's upper limit is Section 5's folded
    3-loop finding, kappa_n R0 = sqrt(b1 b2) / 2 (tests/test_hexagram.py checks the Bloch
    method against it); the eight's lower limit is the FE engine's on the whole ring
    (:func:`rodstab.problems.hexagram.fe_interval`, mesh refined to its target error), which
    shares no code with the Bloch transfer method that :func:`hexagram.threshold` uses.
    """
    from rodstab.problems import hexagram as hx
    from rodstab.sections import rectangle

    sec = rectangle(aspect=aspect, nu=nu)
    eight_lower = hx.fe_interval(hx.Params(section=sec, state="eight"))[0]
    return eight_lower - sec.sqrt_b1b2 / 2


@functools.lru_cache(maxsize=None)
def hexagram_threshold_fe(nu: float = 1 / 3) -> float:
    """h/t at which the hexagram's eight (lower limit, FE) meets the line (upper, closed form).

    A bracketed root (Brent on :data:`HEXAGRAM_BRACKET`) of
    :func:`hexagram_eight_lower_minus_line_upper`: the threshold h/t* of the four states'
    common range when these two limits bind (as published, and as tests assert separately).
    """
    return float(brentq(hexagram_eight_lower_minus_line_upper, *HEXAGRAM_BRACKET,
                        args=(nu,), xtol=HEXAGRAM_XTOL))
