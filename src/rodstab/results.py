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

    Non-finite floats become ``None`` (JSON has no NaN/inf); the CLI documents this. A
    dataclass field with ``metadata={"json": False}`` (bulk arrays written to files of their
    own) is left out.
    """
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)
                if f.metadata.get("json", True)}
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

    def _repr_html_(self) -> str:
        """HTML table of the fields for Jupyter (issue 13: notebook friendliness).

        Scalars as they are (floats to 6 significant figures), nested results as nested tables,
        sequences longer than :data:`HTML_MAX_ITEMS` shortened with their length stated.
        """
        return _html_table(type(self).__name__, self)


#: Sequences longer than this are shown by their first items and their length.
HTML_MAX_ITEMS = 8


def _html_value(value: Any) -> str:
    import html

    if isinstance(value, Result):
        return _html_table(type(value).__name__, value)
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, np.ndarray):
        return (f"array{value.shape}" if value.size > HTML_MAX_ITEMS
                else html.escape(np.array2string(value, precision=6)))
    if isinstance(value, (list, tuple)):
        items = [_html_value(v) for v in value[:HTML_MAX_ITEMS]]
        more = f", ... ({len(value)} items)" if len(value) > HTML_MAX_ITEMS else ""
        return "(" + ", ".join(items) + more + ")"
    if isinstance(value, dict):
        return "<br>".join(f"{html.escape(str(k))}: {_html_value(v)}"
                           for k, v in list(value.items())[:HTML_MAX_ITEMS])
    return html.escape(repr(value) if isinstance(value, str) else str(value))


def _html_table(title: str, result: Any) -> str:
    import html

    rows = "".join(f"<tr><th style='text-align:left'>{html.escape(f.name)}</th>"
                   f"<td style='text-align:left'>{_html_value(getattr(result, f.name))}</td></tr>"
                   for f in dataclasses.fields(result))
    return f"<table><caption>{html.escape(title)}</caption>{rows}</table>"
