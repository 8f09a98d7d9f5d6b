"""Run storage of a continuation: one atomically replaced state file, a lock, and the exports.

``state.npz`` holds the state, the stepper (tangent, step), the rows and special points and the
run's arguments (``meta``, with a hash of the design and of the start state). A rerun with the
same ``meta`` resumes from it, losing at most the step in progress; anything else starts afresh
and removes the previous run's files (:data:`OUTPUTS`). A ``state.npz`` that cannot be read, or
does not fit the design (truncated, another program's file, arrays of other shapes), is set
aside as ``state.npz.corrupt-<n>`` with one :class:`~rodstab.errors.RodstabWarning` and the run
starts afresh (:func:`set_aside`). ``primary.csv``, ``special_points.json`` and
``branches.csv`` are rebuilt from the run in memory after each step. Every file is written to a
uniquely named sibling and renamed over the old one.

``run.lock`` (:func:`rodstab.io.outputs.run_lock`) holds the process id and host of the run
writing into the directory: a second run into the same directory is refused (exit 2) while
that process lives; the lock of a process that is gone (killed) is taken over with a warning.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import warnings
from pathlib import Path as FsPath
from typing import Any

import numpy as np

from ...errors import RodstabWarning
from ...io.outputs import replace_atomic, write_atomic
from ...model import Assembly
from ..discrete import DiscreteRod

#: The pictures ``rodstab continue --out`` draws (``--no-pictures`` removes them instead).
PICTURES = ("diagram.png", "branch.gif", "branch.html")
#: Output files of a continuation run (removed when a run starts afresh in the directory).
OUTPUTS = ("run.json", "state.npz", "primary.csv", "special_points.json", "branches.csv",
           *PICTURES)


#: The arrays of ``state.npz`` (:func:`save_state`).
_ARRAYS = ("x", "R_edge", "R_joint", "value", "tq", "tp", "h", "rows", "text")


class StateUnreadable(Exception):
    """A saved ``state.npz`` that cannot be used; the message says why."""


def design_hash(a: Assembly) -> str:
    """Return a short hash of the whole design (its repr)."""
    return hashlib.sha256(repr(a).encode()).hexdigest()[:16]


def state_hash(rod: DiscreteRod) -> str:
    """Return a short hash of a discrete state and its natural shape (imperfect starts differ)."""
    hsh = hashlib.sha256()
    assert rod.k0_links is not None  # set by discretise
    for arr in (rod.x, rod.R_edge, rod.R_joint, rod.k_held_pairs, rod.k0_links[0]):
        hsh.update(np.ascontiguousarray(arr).tobytes())
    return hsh.hexdigest()[:16]


def load_state(path: FsPath, rod: DiscreteRod | None = None) -> dict | None:
    """Return the saved run in ``path``, or None if there is none.

    Parameters
    ----------
    path : Path
        The ``state.npz`` file.
    rod : DiscreteRod, optional
        The discretised design of the run: the saved arrays must have its shapes
        (:func:`check_fits`).

    Returns
    -------
    dict or None
        The saved state, stepper, rows, special points and ``meta``; None if ``path`` does not
        exist.

    Raises
    ------
    StateUnreadable
        If the file exists but cannot be read as a saved run (not an npz file, truncated,
        missing or malformed arrays, shapes that do not fit ``rod``).
    """
    if not os.path.lexists(path):
        return None
    try:
        with open(path, "rb") as fh:
            magic = fh.read(4)
        if magic != b"PK\x03\x04":
            raise StateUnreadable("it is not an npz (zip) file")
        with np.load(path, allow_pickle=False) as st:
            missing = [k for k in _ARRAYS if k not in st.files]
            if missing:
                raise StateUnreadable(f"it lacks {', '.join(map(repr, missing))} (not a rodstab "
                                      "run)")
            text = json.loads(str(st["text"]))
            out = {"x": st["x"], "R_edge": st["R_edge"], "R_joint": st["R_joint"],
                   "value": float(st["value"]), "tq": st["tq"], "tp": float(st["tp"]),
                   "h": float(st["h"]), "rows": st["rows"], "meta": text["meta"],
                   "specials": text["specials"]}
    except StateUnreadable:
        raise
    except Exception as exc:  # any failure to parse foreign bytes: the file is unusable
        why = " ".join(str(exc).split())
        raise StateUnreadable(f"it cannot be read ({type(exc).__name__}"
                              + (f": {why[:100]}" if why else "") + ")") from None
    if not isinstance(out["meta"], dict) or not isinstance(out["specials"], list):
        raise StateUnreadable("its run description is malformed")
    rows = out["rows"]
    if rows.ndim != 2 or rows.shape[1] != 5 or not np.issubdtype(rows.dtype, np.number):
        raise StateUnreadable(f"its rows have shape {rows.shape}, not (n, 5)")
    for name in ("x", "R_edge", "R_joint", "tq"):
        if not np.issubdtype(out[name].dtype, np.number) or \
                not np.all(np.isfinite(out[name])):
            raise StateUnreadable(f"its {name!r} is not an array of finite numbers")
    out["rows"] = rows.tolist()
    if rod is not None:
        check_fits(out, rod)
    return out


def check_fits(state: dict, rod: DiscreteRod) -> None:
    """Raise :class:`StateUnreadable` unless the saved arrays of ``state`` fit ``rod``'s shapes.

    A rerun with the same arguments (the same ``meta``) discretises the same design, so a
    state that does not fit was damaged or written by something else.
    """
    want = {"x": rod.x.shape, "R_edge": rod.R_edge.shape, "R_joint": rod.R_joint.shape,
            "tq": (len(rod.free_dofs()),)}
    for name, shape in want.items():
        if state[name].shape != shape:
            raise StateUnreadable(f"its {name!r} has shape {state[name].shape}, the design's "
                                  f"{shape}")


def set_aside(path: FsPath, reason: str) -> FsPath:
    """Rename the unusable ``path`` to ``<name>.corrupt-<n>`` and warn once; return the name.

    ``n`` is the smallest integer >= 1 not yet taken, so that earlier ones are kept.
    """
    n = 1
    while os.path.lexists(aside := path.with_name(f"{path.name}.corrupt-{n}")):
        n += 1
    os.replace(path, aside)
    warnings.warn(f"{path} is not a usable saved run: {reason}; set aside as {aside.name}; "
                  "starting afresh", RodstabWarning, stacklevel=3)
    return aside


def save_state(out: FsPath, rod: DiscreteRod, value: float, tq: np.ndarray, tp: float,
               h: float, rows: list, meta: dict, specials: list) -> None:
    """Write ``state.npz`` atomically."""
    arrays: dict[str, Any] = dict(
        x=rod.x, R_edge=rod.R_edge, R_joint=rod.R_joint, value=value, tq=tq, tp=tp, h=h,
        rows=np.array(rows, dtype=float).reshape(-1, 5),
        text=json.dumps({"meta": meta, "specials": specials}))
    replace_atomic(out / "state.npz", lambda fh: np.savez(fh, **arrays))


def export(out: FsPath, rows: list, specials: list) -> None:
    """primary.csv, special_points.json and branches.csv from the run in memory."""
    lines = ["value,energy,lowest_eigenvalue,amplitude,converged"]
    lines += [",".join(repr(float(v)) for v in r[:4]) + f",{bool(r[4])}" for r in rows]
    write_atomic(out / "primary.csv", "\n".join(lines) + "\n")
    write_atomic(out / "special_points.json", json.dumps(specials, indent=1))
    lines = ["branch,value,amplitude,energy,lowest_eigenvalue"]
    for i, sp_ in enumerate(s for s in specials if "branch" in s):
        b = sp_["branch"]
        for row in zip(b["value"], b["amplitude"], b["energy"], b["lowest_eigenvalue"],
                       strict=True):
            lines.append(f"{i}," + ",".join(repr(float(v)) for v in row))
    write_atomic(out / "branches.csv", "\n".join(lines) + "\n")


def remove_temporaries(out: FsPath) -> None:
    """Remove the temporary files of outputs left in ``out`` by a killed run (hold the lock)."""
    for name in OUTPUTS:
        for tmp in out.glob(f".{name}.*.tmp"):
            with contextlib.suppress(OSError):
                tmp.unlink()
