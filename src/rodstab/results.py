"""Base class for the small frozen result objects every solver returns.

Results carry values, modes and diagnostics (``converged``, ``residual``, ``method``) and turn
themselves into plain JSON-able dictionaries with :meth:`Result.to_dict` for ``--json``.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np


def jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays, tuples and nested results to JSON-compatible objects.

    Non-finite floats become ``None`` (JSON has no NaN/inf); the CLI documents this.
    """
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    return value


@dataclasses.dataclass(frozen=True)
class Result:
    """Mixin for frozen solver results: ``to_dict()`` gives the JSON form."""

    def to_dict(self) -> dict[str, Any]:
        """Return a JSON-compatible dictionary of every field (recursively)."""
        out = jsonable(self)
        assert isinstance(out, dict)
        return out
