"""Run storage of a continuation: one atomically replaced state file, and the exports.

``state.npz`` holds the state, the stepper (tangent, step), the rows and special points and the
run's arguments (``meta``, with a hash of the design and of the start state). A rerun with the
same ``meta`` resumes from it, losing at most the step in progress; anything else starts afresh
and removes the previous run's files (:data:`OUTPUTS`). ``primary.csv``,
``special_points.json`` and ``branches.csv`` are rebuilt from the run in memory after each step.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path as FsPath

import numpy as np

from ...model import Assembly
from ..discrete import DiscreteRod

#: Output files of a continuation run (removed when a run starts afresh in the directory).
OUTPUTS = ("run.json", "state.npz", "primary.csv", "special_points.json", "branches.csv",
           "diagram.png", "branch.gif", "branch.html")


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


def write_atomic(path: FsPath, text: str) -> None:
    """Replace ``path`` by ``text`` atomically (write a sibling, then rename)."""
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(text)
    tmp.replace(path)


def load_state(path: FsPath) -> dict | None:
    """Return the saved run in ``path``, or None if there is none or it cannot be read."""
    if not path.exists():
        return None
    try:
        st = np.load(path)
        text = json.loads(str(st["text"]))
        return {"x": st["x"], "R_edge": st["R_edge"], "R_joint": st["R_joint"],
                "value": float(st["value"]), "tq": st["tq"], "tp": float(st["tp"]),
                "h": float(st["h"]), "rows": st["rows"].tolist(), "meta": text["meta"],
                "specials": text["specials"]}
    except (OSError, ValueError, KeyError, json.JSONDecodeError):
        return None


def save_state(out: FsPath, rod: DiscreteRod, value: float, tq: np.ndarray, tp: float,
               h: float, rows: list, meta: dict, specials: list) -> None:
    """Write ``state.npz`` atomically."""
    np.savez(out / "state.tmp.npz", x=rod.x, R_edge=rod.R_edge, R_joint=rod.R_joint,
             value=value, tq=tq, tp=tp, h=h, rows=np.array(rows, dtype=float).reshape(-1, 5),
             text=json.dumps({"meta": meta, "specials": specials}))
    (out / "state.tmp.npz").replace(out / "state.npz")


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
