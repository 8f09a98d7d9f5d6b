"""Every checked statement of the paper, section by section, and beyond it.

:class:`Claim` is one row of the reproduction report; its status is computed by a named rule of
:mod:`.rules`.
"""

from __future__ import annotations

from .core import Claim, Run
from .rules import DIFFERS, REPRODUCED, STATUSES, UNRESOLVED

__all__ = ["Claim", "DIFFERS", "REPRODUCED", "Run", "STATUSES", "UNRESOLVED"]
